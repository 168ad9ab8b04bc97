//! Plain numeric column files: one channel per column, comma, tab or
//! whitespace separated, an optional header line, `#` comment lines.
//!
//! - [`input`]: the bytes, from a file, a pipe or gzip, read once;
//! - [`sniff`]: the comments, the header or first row, the delimiter;
//! - [`blocks`] and [`rows`]: the body, in blocks parsed on all cores;
//! - [`budget`]: how much memory the columns may take.
//!
//! Limits, so that a hostile file cannot take the machine's memory: a line
//! is at most [`MAX_LINE_BYTES`], the comment lines before the first row at
//! most [`MAX_HEADER_COMMENTS`], the columns at most what the input's bytes
//! can hold, a fixed cap for a stream and half the memory the process may
//! use (see [`budget`]); blank and comment lines among the rows are kept as
//! runs, so a file of nothing but newlines costs no memory.

use std::io::{BufRead, Read};
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};

use crate::error::{ReadError, ReadErrorKind};

mod blocks;
mod budget;
mod input;
mod preamble;
mod rows;
mod short_lines;
mod sniff;

#[cfg(test)]
use blocks::BLOCK_BYTES;
pub use budget::{BYTES_PER_BYTE_READ, FLOOR, STREAM_CAP, column_limit};
pub use sniff::Delimiter;

/// The longest line read, in bytes. An IMU row is under 200 bytes; a
/// longer line is not a table (a binary file, a file of NUL bytes, old Mac
/// line endings), and reading on would hold all of it in memory.
pub const MAX_LINE_BYTES: usize = 1 << 20;

/// The most comment lines kept before the header or first row (a
/// recording's metadata is a few dozen).
pub const MAX_HEADER_COMMENTS: usize = 100_000;

/// A numeric column file, opened: the header and layout are known, the body
/// not yet read.
pub struct TableReader {
    path: PathBuf,
    input: Box<dyn BufRead + Send>,
    names: Vec<String>,
    has_header: bool,
    comments: Vec<String>,
    /// The line of each comment, 1-based.
    comment_lines: Vec<u64>,
    delimiter: Delimiter,
    /// The first data row when the file has no header (it was read to find out).
    pending: Option<(u64, String)>,
    /// Lines consumed so far.
    line_no: u64,
    /// The file's size when it is a regular, uncompressed file (a pipe's
    /// or a gzip file's size says nothing of the data).
    file_bytes: Option<u64>,
    /// Whether the first data row (when there is no header) ended with a
    /// newline.
    pending_terminated: bool,
    /// What of the stream has gone by: its last bytes, its length.
    seen: Arc<input::Seen>,
    /// What was passed before the table: a preamble, rows cut short.
    passed: Vec<ReadError>,
}

impl std::fmt::Debug for TableReader {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("TableReader")
            .field("path", &self.path)
            .field("names", &self.names)
            .field("delimiter", &self.delimiter)
            .finish_non_exhaustive()
    }
}

/// The columns read from a file.
#[derive(Debug)]
pub struct Table {
    /// The file.
    pub path: PathBuf,
    /// Names of the columns read (from the header, else `col1`, `col2`, …).
    pub names: Vec<String>,
    /// One vector per column read, all of the same length.
    pub columns: Vec<Vec<f64>>,
    /// Whether the file had a header line.
    pub has_header: bool,
    /// The `#` comment lines before the first data row, without the `#`.
    pub comments: Vec<String>,
    /// Number of lines in the file, comments and header included.
    pub lines: u64,
    /// What was skipped (rows made gaps under
    /// [`ReadPolicy::skip_bad_lines`]) or dropped (a truncated last line),
    /// each with its line.
    pub problems: Vec<ReadError>,
    /// The line of the first row (after the header).
    pub body_start_line: u64,
    /// Blank and comment lines among the rows.
    pub skipped_lines: SkippedLines,
    /// The value of the last `# trailer:` line in the stream's last 64 KiB
    /// (what `imutherm record` counted), if any.
    pub trailer: Option<String>,
}

/// Line numbers of blank and comment lines, ascending, kept as runs of
/// consecutive lines: a million blank lines are one run.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct SkippedLines {
    /// (first line, lines, skipped lines before this run).
    runs: Vec<(u64, u64, u64)>,
}

impl SkippedLines {
    /// Adds `line`, after every line added so far.
    pub fn push(&mut self, line: u64) {
        self.push_run(line, 1);
    }

    fn push_run(&mut self, first: u64, count: u64) {
        match self.runs.last_mut() {
            Some((start, n, _)) if *start + *n == first => *n += count,
            last => {
                let before = last.map_or(0, |&mut (_, n, b)| b + n);
                self.runs.push((first, count, before));
            }
        }
    }

    /// Number of skipped lines.
    pub fn len(&self) -> u64 {
        self.runs.last().map_or(0, |&(_, n, b)| b + n)
    }

    /// Whether there are none.
    pub fn is_empty(&self) -> bool {
        self.runs.is_empty()
    }

    /// Whether `line` is one of them.
    pub fn contains(&self, line: u64) -> bool {
        let i = self.runs.partition_point(|&(s, _, _)| s <= line);
        i > 0 && {
            let (s, n, _) = self.runs[i - 1];
            line < s + n
        }
    }

    fn append(&mut self, other: &SkippedLines, offset: u64) {
        for &(s, n, _) in &other.runs {
            self.push_run(s + offset, n);
        }
    }
}

impl Table {
    /// The 1-based line of row `row` (0-based): where to look in the file.
    pub fn line_of_row(&self, row: usize) -> u64 {
        // Skipped line i (ascending) lies before the row's line when
        // s_i ≤ base + row + i, that is s_i − i ≤ base + row; s_i − i never
        // decreases (the lines are distinct), so a binary search counts them
        // in O(log n), which matters for files with many gap comments.
        // Within a run s_i − i is constant (the run's start less the lines
        // skipped before it), so the search runs over the runs.
        let target = self.body_start_line + row as u64;
        let runs = &self.skipped_lines.runs;
        let k = runs.partition_point(|&(s, _, before)| s.saturating_sub(before) <= target);
        target + k.checked_sub(1).map_or(0, |i| runs[i].1 + runs[i].2)
    }
}

/// What to do with bad rows.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct ReadPolicy {
    /// Skip malformed rows instead of failing: each becomes a row of NaN (a
    /// gap, so later samples keep their index) and is reported.
    pub skip_bad_lines: bool,
}

impl Table {
    /// Number of rows.
    pub fn rows(&self) -> usize {
        self.columns.first().map_or(0, Vec::len)
    }
}
impl TableReader {
    /// Opens `path` (`-`: standard input), reads its comments and header,
    /// and works out the layout.
    pub fn open(path: impl AsRef<Path>) -> Result<TableReader, ReadError> {
        let path = path.as_ref().to_path_buf();
        let input = input::open(&path)?;
        Self::from_input(path, input)
    }

    /// [`TableReader::open`] of `file`, already opened from `path` and at
    /// its start (a caller that looked at its first bytes and rewound): the
    /// file is not opened again.
    pub fn from_file(path: impl AsRef<Path>, file: std::fs::File) -> Result<TableReader, ReadError> {
        let path = path.as_ref().to_path_buf();
        let input = input::from_file(&path, file)?;
        Self::from_input(path, input)
    }

    /// [`TableReader::open`] of bytes read through `reader` (a file or a
    /// stream the caller opened and wraps, to see the bytes as they are
    /// read); `regular_bytes` is the file's size when it is a regular file.
    pub fn from_reader(
        path: impl AsRef<Path>,
        reader: Box<dyn std::io::Read + Send>,
        regular_bytes: Option<u64>,
    ) -> Result<TableReader, ReadError> {
        let path = path.as_ref().to_path_buf();
        let input = input::from_raw(&path, reader, regular_bytes)?;
        Self::from_input(path, input)
    }

    fn from_input(path: PathBuf, mut input: input::Input) -> Result<TableReader, ReadError> {
        let mut head = sniff::read_head(&mut input.reader, &path)?;
        let mut ahead = preamble::Ahead::read(&mut input.reader);
        let settled = preamble::settle(&head.first, head.line_no, &ahead);
        let mut passed = Vec::new();
        if let Some(i) = settled.first {
            let line = &ahead.lines[i];
            head.first = line.text.clone().unwrap_or_default();
            head.terminated = line.terminated;
            head.line_no += i as u64 + 1;
            for (text, line) in settled.comments {
                head.comments.push(text);
                head.comment_lines.push(line);
            }
            if let Some(&line) = settled.preamble.first() {
                let kind = ReadErrorKind::Preamble {
                    lines: settled.preamble.len() as u64,
                    first: settled.preamble_text,
                };
                passed.push(ReadError::new(&path, kind).at(line, None));
            }
            for (line, found) in settled.cut_rows {
                let kind = ReadErrorKind::CutFirstRow {
                    expected: settled.fields,
                    found,
                };
                passed.push(ReadError::new(&path, kind).at(line, None));
            }
        }
        // The bytes read ahead, after the header or first row, are the
        // body's first.
        let rest = std::io::Cursor::new(ahead.rest_after(settled.first));
        let reader: Box<dyn BufRead + Send> = match ahead.error.take() {
            Some(e) => Box::new(rest.chain(preamble::Failed(Some(e)))),
            None => Box::new(rest.chain(input.reader)),
        };
        let (names, has_header, delimiter) = sniff::columns_of(&head.first, head.line_no, &path)?;
        let pending = (!has_header).then_some((head.line_no, head.first));
        Ok(TableReader {
            path,
            input: reader,
            names,
            has_header,
            comments: head.comments,
            comment_lines: head.comment_lines,
            delimiter,
            pending,
            line_no: head.line_no,
            file_bytes: input.file_bytes,
            pending_terminated: head.terminated,
            seen: input.seen,
            passed,
        })
    }

    /// What was skipped before the table (a terminal's banner, a firmware's
    /// boot messages, rows cut where a capture began), each with its line.
    pub fn passed(&self) -> &[ReadError] {
        &self.passed
    }

    /// The file, as it was named (`-` for standard input).
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Column names: the header's, or `col1`, `col2`, … without one.
    pub fn names(&self) -> &[String] {
        &self.names
    }

    /// Whether the file has a header line.
    pub fn has_header(&self) -> bool {
        self.has_header
    }

    /// The delimiter found on the first line.
    pub fn delimiter(&self) -> Delimiter {
        self.delimiter
    }

    /// The `#` comment lines before the header or first row.
    pub fn comments(&self) -> &[String] {
        &self.comments
    }

    /// The line (1-based) of the `i`-th of [`TableReader::comments`].
    pub fn comment_line(&self, i: usize) -> Option<u64> {
        self.comment_lines.get(i).copied()
    }

    /// Finds a column by name (exact, then case-insensitive, then without its
    /// `[unit]`) or by 1-based
    /// index, returning its 0-based index.
    pub fn column_index(&self, wanted: &str) -> Result<usize, ReadError> {
        let w = wanted.trim();
        self.names
            .iter()
            .position(|n| n == w)
            .or_else(|| self.names.iter().position(|n| n.eq_ignore_ascii_case(w)))
            .or_else(|| {
                self.names
                    .iter()
                    .position(|n| crate::header::split_name_unit(n).0.eq_ignore_ascii_case(w))
            })
            .or_else(|| {
                w.parse::<usize>()
                    .ok()
                    .filter(|&i| i >= 1 && i <= self.names.len())
                    .map(|i| i - 1)
            })
            .ok_or_else(|| {
                ReadError::new(
                    &self.path,
                    ReadErrorKind::NoSuchColumn {
                        wanted: w.to_string(),
                        available: self.names.join(", "),
                    },
                )
            })
    }

    /// Reads the body: the columns `select` (0-based indices, in that order),
    /// or all columns when `None`. Every row must have as many fields as the
    /// first; only the selected cells are parsed. A bad row is an error; a
    /// truncated last line is dropped and reported in [`Table::problems`].
    pub fn read(self, select: Option<&[usize]>) -> Result<Table, ReadError> {
        self.read_with(select, &ReadPolicy::default())
    }

    /// [`TableReader::read`] under a policy for bad rows.
    pub fn read_with(self, select: Option<&[usize]>, policy: &ReadPolicy) -> Result<Table, ReadError> {
        let limit = budget::Limit::of_input(self.file_bytes, &self.seen);
        self.read_limited(select, policy, limit)
    }

    /// [`TableReader::read_with`], the columns held to `limit` bytes.
    #[cfg(test)]
    fn read_within(
        self,
        select: Option<&[usize]>,
        policy: &ReadPolicy,
        limit: Option<u64>,
    ) -> Result<Table, ReadError> {
        self.read_limited(select, policy, budget::Limit::fixed(limit))
    }

    fn read_limited(
        self,
        select: Option<&[usize]>,
        policy: &ReadPolicy,
        limit: budget::Limit,
    ) -> Result<Table, ReadError> {
        let ncols = self.names.len();
        let select: Vec<usize> = match select {
            Some(s) => s.to_vec(),
            None => (0..ncols).collect(),
        };
        if let Some(&bad) = select.iter().find(|&&i| i >= ncols) {
            return Err(ReadError::new(
                &self.path,
                ReadErrorKind::NoSuchColumn {
                    wanted: (bad + 1).to_string(),
                    available: self.names.join(", "),
                },
            ));
        }
        let layout = rows::Layout {
            skip_bad_lines: policy.skip_bad_lines,
            ncols,
            delimiter: self.delimiter,
            select: &select,
            spare: Mutex::new(Vec::new()),
            column_limit: limit.ceiling(),
        };
        let mut got = blocks::Collected {
            columns: vec![Vec::new(); select.len()],
            problems: Vec::new(),
            skipped_lines: SkippedLines::default(),
            budget: budget::Budget::within(limit),
        };
        let body_start_line = match &self.pending {
            Some((line, _)) => *line,
            None => self.line_no + 1,
        };
        let TableReader {
            path,
            mut input,
            names,
            has_header,
            comments,
            pending,
            line_no,
            file_bytes,
            pending_terminated,
            seen,
            passed,
            ..
        } = self;
        let start = blocks::Start {
            line_no,
            pending: pending
                .as_ref()
                .map(|(l, t)| (*l, t.as_str(), pending_terminated)),
            file_bytes,
        };
        let lines = blocks::read_body(&mut input, &path, &layout, start, &mut got)?;
        let trailer = input::find_trailer(&seen.tail.lock().unwrap_or_else(|p| p.into_inner()));
        let blocks::Collected {
            columns,
            problems: body_problems,
            skipped_lines,
            ..
        } = got;
        let mut problems = passed;
        problems.extend(body_problems);
        if columns.first().is_none_or(Vec::is_empty) {
            return Err(ReadError::new(&path, ReadErrorKind::NoData));
        }
        let names = select.iter().map(|&i| names[i].clone()).collect();
        Ok(Table {
            path,
            names,
            columns,
            has_header,
            comments,
            lines,
            problems,
            body_start_line,
            skipped_lines,
            trailer,
        })
    }
}

#[cfg(test)]
mod tests;
