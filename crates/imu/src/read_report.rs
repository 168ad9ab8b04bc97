//! Everything found wrong in a file while reading it, each with its line.

use std::fmt;

use crate::error::{ReadError, ReadErrorKind};
use crate::timing::Timing;

/// Most problems listed one by one; past this they are counted only, so a
/// file full of NaN cannot flood a terminal.
pub const MAX_LISTED: usize = 1000;

/// The kind of a problem.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ProblemKind {
    /// A malformed row skipped as a gap (`--skip-bad-lines`).
    BadLine,
    /// A last line cut short, dropped.
    TruncatedLastLine,
    /// Text before the table (a terminal's banner, boot messages), skipped.
    Preamble,
    /// A first row cut short (a capture begun inside a line), dropped.
    CutFirstRow,
    /// A run of NaN samples (gaps in the file itself).
    NanRun,
    /// Infinite values, turned into gaps.
    Infinite,
    /// Missing samples according to the time column.
    TimeGap,
    /// A timestamp repeating the previous one; the sample is dropped.
    DuplicateTime,
    /// A timestamp earlier than the previous one; the sample is dropped.
    BackwardsTime,
    /// A metadata line whose value cannot be used; it is ignored.
    BadMetadata,
    /// A message of a binary log without a usable stamp (zero, negative
    /// or NaN).
    NoStamp,
    /// A stretch of a binary log skipped as undecodable.
    SkippedData,
}

impl ProblemKind {
    /// Snake-case name for JSON.
    pub fn name(self) -> &'static str {
        match self {
            ProblemKind::BadLine => "bad_line",
            ProblemKind::TruncatedLastLine => "truncated_last_line",
            ProblemKind::Preamble => "preamble",
            ProblemKind::CutFirstRow => "cut_first_row",
            ProblemKind::NanRun => "nan",
            ProblemKind::Infinite => "infinite",
            ProblemKind::TimeGap => "time_gap",
            ProblemKind::DuplicateTime => "duplicate_time",
            ProblemKind::BackwardsTime => "backwards_time",
            ProblemKind::BadMetadata => "bad_metadata",
            ProblemKind::NoStamp => "no_stamp",
            ProblemKind::SkippedData => "skipped_data",
        }
    }
}

/// One problem.
#[derive(Debug, Clone, PartialEq)]
pub struct Problem {
    /// What it is.
    pub kind: ProblemKind,
    /// The (first) line concerned.
    pub line: Option<u64>,
    /// The column concerned, 1-based.
    pub column: Option<usize>,
    /// The channel concerned.
    pub channel: Option<String>,
    /// How many samples (or lines) it concerns.
    pub count: usize,
    /// A sentence for people.
    pub message: String,
}

impl fmt::Display for Problem {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if let Some(l) = self.line {
            write!(f, "line {l}: ")?;
        }
        f.write_str(&self.message)
    }
}

impl Problem {
    pub(crate) fn from_read_error(e: &ReadError) -> Problem {
        let kind = match e.kind {
            ReadErrorKind::TruncatedLastLine { .. } => ProblemKind::TruncatedLastLine,
            ReadErrorKind::Preamble { .. } => ProblemKind::Preamble,
            ReadErrorKind::CutFirstRow { .. } => ProblemKind::CutFirstRow,
            _ => ProblemKind::BadLine,
        };
        let action = match kind {
            ProblemKind::TruncatedLastLine | ProblemKind::CutFirstRow => "dropped",
            ProblemKind::Preamble => "skipped",
            _ => "skipped as a gap",
        };
        let col = e.column.map(|c| format!("column {c}: ")).unwrap_or_default();
        let count = match e.kind {
            ReadErrorKind::Preamble { lines, .. } => lines as usize,
            _ => 1,
        };
        Problem {
            kind,
            line: e.line,
            column: e.column,
            channel: None,
            count,
            message: format!("{col}{} ({action})", e.kind),
        }
    }
}

/// Which format a reader found a file in.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub enum FileFormat {
    /// imutherm's log: `# format: imutherm-log/…` among its metadata.
    ImuthermLog,
    /// The thesis's log: its `mpu_accel_1[m/^2], …` header, no metadata.
    ThesisLog,
    /// Any other table of numeric columns under a header.
    #[default]
    Columns,
}

impl FileFormat {
    /// As `imutherm info` names it.
    pub fn name(self) -> &'static str {
        match self {
            FileFormat::ImuthermLog => "imutherm log",
            FileFormat::ThesisLog => "thesis log",
            FileFormat::Columns => "numeric columns",
        }
    }
}

/// What reading a file found.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ReadReport {
    /// The format the file was found in.
    pub format: FileFormat,
    /// Problems, at most [`MAX_LISTED`], in file order within each kind.
    pub problems: Vec<Problem>,
    /// Problems not listed beyond [`MAX_LISTED`].
    pub unlisted: usize,
    /// Lines in the file.
    pub lines: u64,
    /// Rows read (bad rows skipped as gaps included).
    pub rows: usize,
    /// The time column's verdict, when the file has one.
    pub timing: Option<Timing>,
    /// Rows dropped because they repeat the previous row, stamp and values
    /// alike (a line written twice).
    pub dropped_samples: usize,
    /// What the reader guessed or found suspicious without it being a
    /// problem of a line: a time unit guessed, a clock that disagrees with
    /// the given rate, an accelerometer that looks like g.
    pub notes: Vec<String>,
}

impl ReadReport {
    pub(crate) fn push(&mut self, p: Problem) {
        if self.problems.len() < MAX_LISTED {
            self.problems.push(p);
        } else {
            self.unlisted += 1;
        }
    }

    /// Number of problems of a kind (listed ones).
    pub fn count(&self, kind: ProblemKind) -> usize {
        self.problems.iter().filter(|p| p.kind == kind).count()
    }
}
