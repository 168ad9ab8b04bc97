//! Errors of the readers: always with the file, and the line and column when
//! the problem is in the content.

use std::fmt;
use std::path::PathBuf;

/// Which bound limits the memory of a table's columns.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LimitBound {
    /// Half the machine's memory, a quarter of the address-space limit.
    Machine,
    /// What a regular file of `bytes` can hold.
    FileSize {
        /// The file's size.
        bytes: u64,
    },
    /// What the `bytes` a compressed or piped input has given so far can
    /// hold.
    BytesRead {
        /// The bytes given so far, decompressed.
        bytes: u64,
    },
    /// The most any compressed or piped input may take.
    StreamCap,
    /// What any read may take, however few its bytes.
    Floor,
}

impl std::fmt::Display for LimitBound {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let per = crate::table::BYTES_PER_BYTE_READ;
        match self {
            LimitBound::Machine => f.write_str(
                "half the machine's memory, a quarter of the process's address-space limit",
            ),
            LimitBound::FileSize { bytes } => {
                write!(f, "{per} bytes for each of the file's {bytes} bytes")
            }
            LimitBound::BytesRead { bytes } => write!(
                f,
                "{per} bytes for each of the {bytes} bytes the compressed or piped input has given so far"
            ),
            LimitBound::StreamCap => f.write_str(
                "the most a compressed or piped input may take, on any machine: its size says nothing of its data",
            ),
            LimitBound::Floor => f.write_str("what any read may take, however few its bytes"),
        }
    }
}

/// What went wrong.
#[derive(Debug, thiserror::Error)]
pub enum ReadErrorKind {
    /// The file could not be opened or read.
    #[error("{0}")]
    Io(#[from] std::io::Error),
    /// The file holds no data row (it is empty, or only comments/header).
    #[error("no data rows (the file is empty or holds only comments and a header)")]
    NoData,
    /// A cell that is not a number.
    #[error("cannot read '{text}' as a number")]
    NotANumber {
        /// The cell's text.
        text: String,
    },
    /// A row with another number of fields than the first row.
    #[error("expected {expected} fields, found {found}")]
    FieldCount {
        /// Fields of the first row.
        expected: usize,
        /// Fields of this row.
        found: usize,
    },
    /// The last line ends without a newline and is incomplete: what a logger
    /// killed mid-write leaves.
    #[error(
        "truncated last line (no newline at the end: a write that did not finish; {found} of {expected} fields)"
    )]
    TruncatedLastLine {
        /// Fields of the first row.
        expected: usize,
        /// Fields found on the last line.
        found: usize,
    },
    /// Text lines before the table that are not of it: a terminal's banner
    /// (PuTTY's `=~=~=~= PuTTY log … =~=~=~=`), a firmware's boot messages.
    #[error(
        "{} of text before the table, not of it ({}'{first}')",
        if *lines == 1 { "a line".to_string() } else { format!("{lines} lines") },
        if *lines == 1 { "" } else { "the first: " }
    )]
    Preamble {
        /// How many lines.
        lines: u64,
        /// The first one's text (at most 80 characters).
        first: String,
    },
    /// A row at the table's start with fewer or more fields than the rows
    /// after it: what a capture that began inside a line leaves.
    #[error(
        "a first row of {found} fields where the rows have {expected}: a capture that began inside a line"
    )]
    CutFirstRow {
        /// Fields of most rows.
        expected: usize,
        /// Fields of this row.
        found: usize,
    },
    /// A column asked for that the file does not have.
    #[error("no column '{wanted}' (the file has: {available})")]
    NoSuchColumn {
        /// The name or index asked for.
        wanted: String,
        /// The columns there are.
        available: String,
    },
    /// A unit imutherm does not know, given for a column.
    #[error(
        "unknown unit '{unit}' for column '{column}' (known: {})", crate::units::KNOWN_UNITS.join(", ")
    )]
    UnknownUnit {
        /// The column.
        column: String,
        /// The unit text.
        unit: String,
    },
    /// A time column that cannot be trusted.
    #[error("time column: {0}")]
    TimeColumn(String),
    /// A line that is not valid UTF-8 text.
    #[error("the line is not UTF-8 text")]
    NotText,
    /// A line longer than the readers' limit: not a table.
    #[error(
        "a line longer than {limit} bytes: not a table of numbers (a binary file, or a line that never ends)"
    )]
    LineTooLong {
        /// The limit, bytes.
        limit: usize,
    },
    /// Lines that end in a carriage return alone.
    #[error(
        "lines end in a carriage return alone (old Mac OS line endings); convert them first: tr '\\r' '\\n'"
    )]
    CrLineEndings,
    /// More comment lines before the first row than the readers keep.
    #[error("more than {limit} comment lines before the first row")]
    TooManyComments {
        /// The limit, lines.
        limit: usize,
    },
    /// Two columns of one name.
    #[error(
        "columns {first} and {second} are both named '{name}': rename one, or every use of the name is ambiguous"
    )]
    DuplicateColumn {
        /// The name.
        name: String,
        /// 1-based column of its first use.
        first: usize,
        /// 1-based column of its second use.
        second: usize,
    },
    /// A directory given where a file is read.
    #[error("is a directory, not a file")]
    IsDirectory,
    /// The columns read would take more memory than a read may: what the
    /// input's bytes can hold, at most a fixed cap for a stream, and half
    /// of what the process may use.
    #[error(
        "the columns read would need {held_mib} MiB by this line, more than the {limit_mib} MiB a read may take ({bound}); read fewer columns or a shorter part of the file"
    )]
    TooLarge {
        /// What the columns would hold, MiB.
        held_mib: u64,
        /// What they may hold, MiB.
        limit_mib: u64,
        /// Which bound that is.
        bound: LimitBound,
    },
    /// The system refused the memory to grow the columns.
    #[error(
        "the system refused the memory for the columns read by this line ({needed_mib} MiB a column); read fewer columns or a shorter part of the file"
    )]
    OutOfMemory {
        /// The size a column needed, MiB.
        needed_mib: u64,
    },
}

/// A reading error with its place.
#[derive(Debug)]
pub struct ReadError {
    /// The file.
    pub path: PathBuf,
    /// 1-based line number, when the problem is on a line.
    pub line: Option<u64>,
    /// 1-based column (field) number, when the problem is in a field.
    pub column: Option<usize>,
    /// What went wrong.
    pub kind: ReadErrorKind,
}

impl ReadError {
    pub(crate) fn new(path: impl Into<PathBuf>, kind: ReadErrorKind) -> Self {
        ReadError {
            path: path.into(),
            line: None,
            column: None,
            kind,
        }
    }

    pub(crate) fn at(mut self, line: u64, column: Option<usize>) -> Self {
        self.line = Some(line);
        self.column = column;
        self
    }
}

impl fmt::Display for ReadError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.path.display())?;
        if let Some(line) = self.line {
            write!(f, ":{line}")?;
            if let Some(col) = self.column {
                write!(f, ": column {col}")?;
            }
        }
        write!(f, ": {}", self.kind)
    }
}

// No source: the system's error is already in the message, and a chain
// printer (`{:#}`) would print it twice.
impl std::error::Error for ReadError {}
