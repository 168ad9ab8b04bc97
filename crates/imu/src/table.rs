//! Plain numeric column files: one channel per column, comma, tab or
//! whitespace separated, an optional header line, `#` comment lines.
//!
//! The file is streamed in blocks; each batch of blocks is parsed on all
//! cores, and the blocks' results are joined in order, so line numbers in
//! errors stay exact. Gzip input (by its magic bytes, not its name) is
//! decompressed on the fly. `-` is standard input; pipes, FIFOs and devices
//! are read once, from start to end, never reopened: the trailer is taken
//! from the tail of the stream as it goes by.
//!
//! Limits, so that a hostile file cannot take the machine's memory: a line
//! is at most [`MAX_LINE_BYTES`], the comment lines before the first row at
//! most [`MAX_HEADER_COMMENTS`]; blank and comment lines among the rows are
//! kept as runs, so a file of nothing but newlines costs no memory.

use std::fs::File;
use std::io::{BufRead, BufReader, Read};
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};

use rayon::prelude::*;

use crate::error::{ReadError, ReadErrorKind};

mod short_lines;

/// Bytes per parse block: large enough to amortise the thread hand-off,
/// small enough that a batch of them stays a few MiB.
const BLOCK_BYTES: usize = 1 << 20;

/// The longest line read, in bytes. An IMU row is under 200 bytes; a
/// longer line is not a table (a binary file, a file of NUL bytes, old Mac
/// line endings), and reading on would hold all of it in memory.
pub const MAX_LINE_BYTES: usize = 1 << 20;

/// The most comment lines kept before the header or first row (a
/// recording's metadata is a few dozen).
pub const MAX_HEADER_COMMENTS: usize = 100_000;

/// How much of the end of the stream is kept to find the trailer in (the
/// recorder writes it last).
const TAIL_BYTES: usize = 64 * 1024;

/// How fields are separated.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Delimiter {
    /// `,` (spaces around fields are ignored).
    Comma,
    /// `;`
    Semicolon,
    /// A tab.
    Tab,
    /// Runs of spaces and tabs.
    Whitespace,
}

impl Delimiter {
    fn detect(line: &str) -> Delimiter {
        if line.contains(',') {
            Delimiter::Comma
        } else if line.contains('\t') {
            Delimiter::Tab
        } else if line.contains(';') {
            Delimiter::Semicolon
        } else {
            Delimiter::Whitespace
        }
    }

    /// Splits `line` into `fields` (cleared first), without allocating.
    fn split_into<'a>(self, line: &'a [u8], fields: &mut Vec<&'a [u8]>) {
        fields.clear();
        let sep = match self {
            Delimiter::Comma => b',',
            Delimiter::Semicolon => b';',
            Delimiter::Tab => b'\t',
            Delimiter::Whitespace => {
                fields.extend(line.split(|&b| b == b' ' || b == b'\t').filter(|f| !f.is_empty()));
                return;
            }
        };
        fields.extend(line.split(move |&b| b == sep).map(trim));
    }
}

fn trim(field: &[u8]) -> &[u8] {
    field.trim_ascii()
}

/// Parses one field as a number. `nan` is a gap and is accepted.
fn parse_number(field: &[u8]) -> Option<f64> {
    crate::decimal::parse_field(field)
}

/// Whether a carriage return stands inside `line`, before other text: the
/// mark of lines that end in CR alone (a CR among trailing blanks is only
/// untidy).
fn has_inner_cr(line: &[u8]) -> bool {
    memchr::memchr(b'\r', line.trim_ascii_end()).is_some() && is_text(line)
}

/// Whether `bytes` are UTF-8 text, but for a character cut at their end
/// (a line cut at the length limit).
fn is_text(bytes: &[u8]) -> bool {
    match std::str::from_utf8(bytes) {
        Ok(_) => true,
        Err(e) => e.error_len().is_none(),
    }
}

fn is_skipped(line: &[u8]) -> bool {
    let t = line.trim_ascii_start();
    t.is_empty() || t[0] == b'#'
}

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
    /// The last bytes of the stream read so far.
    tail: Arc<Mutex<Vec<u8>>>,
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
        if path == Path::new("-") {
            return Self::from_input(path, Box::new(std::io::stdin()), None);
        }
        let file = File::open(&path).map_err(|e| ReadError::new(&path, ReadErrorKind::Io(e)))?;
        Self::from_file(path, file)
    }

    /// [`TableReader::open`] of `file`, already opened from `path` and at
    /// its start (a caller that looked at its first bytes and rewound): the
    /// file is not opened again.
    pub fn from_file(path: impl AsRef<Path>, file: File) -> Result<TableReader, ReadError> {
        let path = path.as_ref().to_path_buf();
        let meta = file
            .metadata()
            .map_err(|e| ReadError::new(&path, ReadErrorKind::Io(e)))?;
        if meta.is_dir() {
            return Err(ReadError::new(&path, ReadErrorKind::IsDirectory));
        }
        let size = meta.is_file().then_some(meta.len());
        Self::from_input(path, Box::new(file), size)
    }

    fn from_input(
        path: PathBuf,
        raw_input: Box<dyn Read + Send>,
        regular_bytes: Option<u64>,
    ) -> Result<TableReader, ReadError> {
        let io_err = |e: std::io::Error| ReadError::new(&path, ReadErrorKind::Io(e));
        let mut buffered = BufReader::with_capacity(1 << 16, raw_input);
        let gz = buffered.fill_buf().map_err(io_err)?.starts_with(&[0x1f, 0x8b]);
        let decoded: Box<dyn Read + Send> = if gz {
            Box::new(GzipMembers::new(buffered))
        } else {
            Box::new(buffered)
        };
        let tail = Arc::new(Mutex::new(Vec::new()));
        let mut input: Box<dyn BufRead + Send> = Box::new(BufReader::with_capacity(
            1 << 16,
            TailKeeper {
                inner: decoded,
                tail: Arc::clone(&tail),
            },
        ));

        let mut comments = Vec::new();
        let mut comment_lines = Vec::new();
        let mut line_no = 0u64;
        let mut raw = Vec::new();
        let (first, terminated) = loop {
            let read = read_line_bounded(&mut input, &mut raw).map_err(io_err)?;
            if raw.is_empty() {
                return Err(ReadError::new(&path, ReadErrorKind::NoData));
            }
            line_no += 1;
            let body = raw.strip_suffix(b"\n").unwrap_or(&raw);
            let body = body.strip_suffix(b"\r").unwrap_or(body);
            if !is_text(body) {
                return Err(ReadError::new(&path, ReadErrorKind::NotText).at(line_no, None));
            }
            // A carriage return inside the line: lines end in CR alone (old
            // Mac OS), which would read as one endless line.
            if has_inner_cr(body) {
                return Err(ReadError::new(&path, ReadErrorKind::CrLineEndings).at(line_no, None));
            }
            if read == LineRead::TooLong {
                return Err(ReadError::new(
                    &path,
                    ReadErrorKind::LineTooLong {
                        limit: MAX_LINE_BYTES,
                    },
                )
                .at(line_no, None));
            }
            let text = std::str::from_utf8(body)
                .map_err(|_| ReadError::new(&path, ReadErrorKind::NotText).at(line_no, None))?
                .trim_start_matches('\u{feff}');
            if is_skipped(text.as_bytes()) {
                if let Some(c) = text.trim_start().strip_prefix('#') {
                    if comments.len() == MAX_HEADER_COMMENTS {
                        return Err(ReadError::new(
                            &path,
                            ReadErrorKind::TooManyComments {
                                limit: MAX_HEADER_COMMENTS,
                            },
                        )
                        .at(line_no, None));
                    }
                    comments.push(c.trim().to_string());
                    comment_lines.push(line_no);
                }
                continue;
            }
            break (text.to_string(), read == LineRead::Whole);
        };
        let delimiter = Delimiter::detect(&first);
        let mut fields = Vec::new();
        delimiter.split_into(first.as_bytes(), &mut fields);
        let numeric = fields.iter().all(|f| parse_number(f).is_some());
        let (names, has_header, pending) = if numeric {
            let names = (1..=fields.len()).map(|i| format!("col{i}")).collect();
            (names, false, Some((line_no, first.clone())))
        } else {
            let names: Vec<String> = fields
                .iter()
                .map(|f| crate::header::clean_cell(&String::from_utf8_lossy(f)).to_string())
                .collect();
            // Two columns of one name: whichever a name picks, the other is
            // lost or mistaken for it.
            for (i, n) in names.iter().enumerate() {
                if let Some(first) = names[..i].iter().position(|m| m == n) {
                    return Err(ReadError::new(
                        &path,
                        ReadErrorKind::DuplicateColumn {
                            name: n.clone(),
                            first: first + 1,
                            second: i + 1,
                        },
                    )
                    .at(line_no, None));
                }
            }
            (names, true, None)
        };
        Ok(TableReader {
            path,
            input,
            names,
            has_header,
            comments,
            comment_lines,
            delimiter,
            pending,
            line_no,
            file_bytes: if gz { None } else { regular_bytes },
            pending_terminated: terminated,
            tail,
        })
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
    pub fn read_with(mut self, select: Option<&[usize]>, policy: &ReadPolicy) -> Result<Table, ReadError> {
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
        let layout = Layout {
            skip_bad_lines: policy.skip_bad_lines,
            ncols,
            delimiter: self.delimiter,
            select: &select,
            spare: Mutex::new(Vec::new()),
        };
        let mut got = Collected {
            columns: vec![Vec::new(); select.len()],
            problems: Vec::new(),
            skipped_lines: SkippedLines::default(),
        };
        let body_start_line = match &self.pending {
            Some((line, _)) => *line,
            None => self.line_no + 1,
        };
        // The file size sizes the columns (see `Merger::merge`).
        let file_bytes = self.file_bytes;

        if let Some((line, text)) = self.pending.take() {
            // Without its newline, the first row is also the last, and cut.
            let out = layout
                .parse_block(text.as_bytes(), !self.pending_terminated)
                .map_err(|f| f.into_error(&self.path, line - 1))?;
            out.append_to(&mut got, &self.path, line - 1, &layout.spare);
        }

        let batch_len = 4 * rayon::current_num_threads().max(1);
        let mut source = BlockSource {
            input: &mut self.input,
            carry: Vec::new(),
            eof: false,
            too_long: false,
            cr_only: false,
            spare: Vec::new(),
        };
        let io_err = |e| ReadError::new(&self.path, ReadErrorKind::Io(e));
        let mut merger = Merger {
            got: &mut got,
            spare: &layout.spare,
            path: &self.path,
            line_no: self.line_no,
            file_bytes,
            bytes_seen: 0,
            sized: false,
        };
        let mut batch = source.next_batch(batch_len).map_err(io_err)?;
        let mut parsed: Option<(Vec<Result<BlockOut, BlockFault>>, u64)> = None;
        loop {
            let last_batch = source.eof;
            // Three stages at once: this batch is parsed on all cores while
            // the previous one is appended to the columns and the next one
            // is read.
            let (results, (merged, next)) = rayon::join(
                || {
                    let last_index = batch.len().wrapping_sub(1);
                    batch
                        .par_iter()
                        .enumerate()
                        .map(|(i, b)| layout.parse_block(b.bytes(), last_batch && i == last_index))
                        .collect::<Vec<Result<BlockOut, BlockFault>>>()
                },
                || {
                    let merged = parsed.take().map_or(Ok(()), |(r, bytes)| merger.merge(r, bytes));
                    let next = (!last_batch).then(|| source.next_batch(batch_len)).transpose();
                    (merged, next)
                },
            );
            merged?;
            parsed = Some((results, batch.iter().map(|b| b.len as u64).sum::<u64>()));
            match next.map_err(io_err)? {
                Some(b) => source.spare.extend(std::mem::replace(&mut batch, b)),
                None => break,
            }
        }
        if let Some((r, bytes)) = parsed {
            merger.merge(r, bytes)?;
        }
        if source.too_long {
            let kind = if source.cr_only {
                ReadErrorKind::CrLineEndings
            } else {
                ReadErrorKind::LineTooLong {
                    limit: MAX_LINE_BYTES,
                }
            };
            return Err(ReadError::new(&self.path, kind).at(merger.line_no + 1, None));
        }
        self.line_no = merger.line_no;
        let trailer = find_trailer(&self.tail.lock().unwrap_or_else(|p| p.into_inner()));
        let Collected {
            columns,
            problems,
            skipped_lines,
        } = got;
        if columns.first().is_none_or(Vec::is_empty) {
            return Err(ReadError::new(&self.path, ReadErrorKind::NoData));
        }
        let names = select.iter().map(|&i| self.names[i].clone()).collect();
        Ok(Table {
            path: self.path,
            names,
            columns,
            has_header: self.has_header,
            comments: self.comments,
            lines: self.line_no,
            problems,
            body_start_line,
            skipped_lines,
            trailer,
        })
    }
}

/// The value of the last `# trailer:` line in `tail`.
fn find_trailer(tail: &[u8]) -> Option<String> {
    String::from_utf8_lossy(tail)
        .lines()
        .rev()
        .find_map(|l| l.trim().strip_prefix("# trailer:").map(|v| v.trim().to_string()))
}

/// How a bounded line read ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum LineRead {
    /// At its newline.
    Whole,
    /// At the end of the input, without a newline (or nothing was left).
    Unterminated,
    /// At [`MAX_LINE_BYTES`], without a newline.
    TooLong,
}

/// Reads one line into `raw` (cleared first), newline included, stopping
/// at [`MAX_LINE_BYTES`].
fn read_line_bounded(input: &mut dyn BufRead, raw: &mut Vec<u8>) -> std::io::Result<LineRead> {
    raw.clear();
    loop {
        let buf = input.fill_buf()?;
        if buf.is_empty() {
            return Ok(LineRead::Unterminated);
        }
        let room = MAX_LINE_BYTES + 1 - raw.len();
        let (take, done) = match memchr::memchr(b'\n', buf) {
            Some(nl) if nl < room => (nl + 1, Some(LineRead::Whole)),
            _ if buf.len() >= room => (room, Some(LineRead::TooLong)),
            _ => (buf.len(), None),
        };
        raw.extend_from_slice(&buf[..take]);
        input.consume(take);
        if let Some(how) = done {
            return Ok(how);
        }
    }
}

/// Passes a stream through, keeping its last [`TAIL_BYTES`]: the trailer
/// is found there without reading the input a second time (which a pipe
/// cannot give, and a live stream would lose bytes to).
struct TailKeeper {
    inner: Box<dyn Read + Send>,
    tail: Arc<Mutex<Vec<u8>>>,
}

impl Read for TailKeeper {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        let n = self.inner.read(buf)?;
        let mut tail = self.tail.lock().unwrap_or_else(|p| p.into_inner());
        // Only the last TAIL_BYTES of a read can still be the tail: a block
        // read of a megabyte copies 64 KiB, not all of it (the copy was a
        // tenth of the reading time).
        let keep = &buf[n.saturating_sub(TAIL_BYTES)..n];
        if keep.len() == TAIL_BYTES {
            tail.clear();
        }
        tail.extend_from_slice(keep);
        if tail.len() > 2 * TAIL_BYTES {
            let cut = tail.len() - TAIL_BYTES;
            tail.drain(..cut);
        }
        Ok(n)
    }
}

/// Gzip members one after another, as `gzip -d` reads them: a file of
/// several members is their concatenation, and zero bytes after the last
/// member (padding a tape or a block device adds) are ignored. Other bytes
/// after it are an error rather than data dropped unseen.
struct GzipMembers<R: BufRead> {
    member: Option<flate2::bufread::GzDecoder<R>>,
}

impl<R: BufRead> GzipMembers<R> {
    fn new(input: R) -> Self {
        GzipMembers {
            member: Some(flate2::bufread::GzDecoder::new(input)),
        }
    }
}

impl<R: BufRead> Read for GzipMembers<R> {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        loop {
            let Some(member) = self.member.as_mut() else {
                return Ok(0);
            };
            let n = member.read(buf)?;
            if n > 0 || buf.is_empty() {
                return Ok(n);
            }
            // The member ended (its CRC and length checked): what follows?
            let Some(member) = self.member.take() else {
                return Ok(0);
            };
            let mut rest = member.into_inner();
            let mut padding = false;
            loop {
                let next = rest.fill_buf()?;
                if next.is_empty() {
                    return Ok(0);
                }
                if !padding && next[0] == 0x1f {
                    // gzip(1) reads a member's magic byte by byte too.
                    self.member = Some(flate2::bufread::GzDecoder::new(rest));
                    break;
                }
                // Zero padding runs to the end, or it is not padding.
                if next.iter().any(|&b| b != 0) {
                    return Err(std::io::Error::new(
                        std::io::ErrorKind::InvalidData,
                        "data after the end of the gzip stream that is neither another member nor zero padding",
                    ));
                }
                let n = next.len();
                rest.consume(n);
                padding = true;
            }
        }
    }
}

/// Cuts the input into blocks of whole lines.
struct BlockSource<'a> {
    input: &'a mut Box<dyn BufRead + Send>,
    /// The partial line at the end of the previous block.
    carry: Vec<u8>,
    eof: bool,
    /// A line longer than [`MAX_LINE_BYTES`] stopped the reading.
    too_long: bool,
    /// That line holds carriage returns: CR-only line endings.
    cr_only: bool,
    /// Blocks already parsed, whose memory the next ones reuse: fresh
    /// megabyte buffers would cost page faults on every block.
    spare: Vec<Block>,
}

/// Whole lines of the input: the first `len` bytes of `buf`. The buffer
/// keeps its length between uses, so a reused block is read into without
/// being zeroed again (a `Vec` cleared and refilled through a `dyn Read`
/// was zeroed on every block).
#[derive(Default)]
struct Block {
    buf: Vec<u8>,
    len: usize,
}

impl Block {
    fn bytes(&self) -> &[u8] {
        &self.buf[..self.len]
    }
}

impl BlockSource<'_> {
    /// Reads up to `count` blocks; the last block of the input may end
    /// without a newline.
    fn next_batch(&mut self, count: usize) -> std::io::Result<Vec<Block>> {
        let mut blocks = Vec::with_capacity(count);
        while blocks.len() < count && !self.eof {
            let mut block = self.spare.pop().unwrap_or_default();
            let carried = self.carry.len();
            let end = carried + BLOCK_BYTES;
            if block.buf.len() < end {
                block.buf.resize(end, 0);
            }
            block.buf[..carried].copy_from_slice(&self.carry);
            block.len = carried;
            self.carry.clear();
            let mut got = 0;
            while block.len < end {
                match self.input.read(&mut block.buf[block.len..end]) {
                    Ok(0) => break,
                    Ok(n) => {
                        block.len += n;
                        got += n;
                    }
                    Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
                    Err(e) => return Err(e),
                }
            }
            if got == 0 {
                self.eof = true;
                if block.len > 0 {
                    blocks.push(block);
                }
                break;
            }
            // Keep the partial last line for the next block.
            match memchr::memrchr(b'\n', block.bytes()) {
                Some(nl) => {
                    self.carry.extend_from_slice(&block.bytes()[nl + 1..]);
                    block.len = nl + 1;
                    blocks.push(block);
                }
                None if block.len > MAX_LINE_BYTES => {
                    self.too_long = true;
                    self.cr_only = has_inner_cr(block.bytes());
                    self.eof = true;
                }
                None => {
                    self.carry.extend_from_slice(block.bytes());
                    self.spare.push(block);
                }
            }
        }
        Ok(blocks)
    }
}

struct Layout<'a> {
    skip_bad_lines: bool,
    ncols: usize,
    delimiter: Delimiter,
    select: &'a [usize],
    /// Column buffers of blocks already merged, for the next blocks to
    /// parse into (see [`BlockSource::spare`]).
    spare: Mutex<Vec<Vec<f64>>>,
}

/// Appends parsed batches to the columns in file order, turning faults into
/// errors with their absolute line numbers.
struct Merger<'a> {
    got: &'a mut Collected,
    spare: &'a Mutex<Vec<Vec<f64>>>,
    path: &'a Path,
    line_no: u64,
    file_bytes: Option<u64>,
    bytes_seen: u64,
    sized: bool,
}

impl Merger<'_> {
    fn merge(&mut self, results: Vec<Result<BlockOut, BlockFault>>, bytes: u64) -> Result<(), ReadError> {
        self.bytes_seen += bytes;
        for r in results {
            let out = r.map_err(|f| f.into_error(self.path, self.line_no))?;
            let lines = out.lines;
            out.append_to(self.got, self.path, self.line_no, self.spare);
            self.line_no += lines;
        }
        // Sizing the columns from the file size keeps memory near the data:
        // doubling growth would peak at up to three times it. The margin is
        // wide because running short is dear: the huge-page hint splits a
        // column's mapping, so the kernel cannot move it to grow it (mremap
        // fails with EFAULT), and the allocator copies the column instead.
        // On an 8-hour run whose first blocks had slightly longer lines than
        // the rest, 1 % fell 0.08 % short and each column was copied at the
        // end, one at a time: a peak of 1.16 times the data. Capacity not
        // written is never touched, so a wide margin costs address space,
        // not memory.
        if !self.sized
            && let Some(total) = self.file_bytes
        {
            self.sized = true;
            let rows = self.got.columns.first().map_or(0, Vec::len) as u64;
            if self.bytes_seen > 0 && rows > 0 && total > self.bytes_seen {
                let estimate = (rows as f64 * total as f64 / self.bytes_seen as f64 * 1.10) as usize;
                for c in &mut self.got.columns {
                    c.reserve_exact(estimate.saturating_sub(c.len()));
                    hugepages::advise(c);
                }
            }
        }
        Ok(())
    }
}

/// Everything gathered from the blocks, in file order.
struct Collected {
    columns: Vec<Vec<f64>>,
    problems: Vec<ReadError>,
    skipped_lines: SkippedLines,
}

struct BlockOut {
    columns: Vec<Vec<f64>>,
    lines: u64,
    /// Lines skipped (as gaps) or dropped (a truncated last line).
    problems: Vec<BlockFault>,
    /// Blank and comment lines among the rows (block-relative).
    skipped: SkippedLines,
}

impl BlockOut {
    fn append_to(self, into: &mut Collected, path: &Path, lines_before: u64, spare: &Mutex<Vec<Vec<f64>>>) {
        into.problems.extend(
            self.problems
                .into_iter()
                .map(|p| p.into_error(path, lines_before)),
        );
        into.skipped_lines.append(&self.skipped, lines_before);
        let columns = &mut into.columns;
        let mut spare = spare.lock().unwrap_or_else(|p| p.into_inner());
        for (dst, src) in columns.iter_mut().zip(self.columns) {
            if dst.is_empty() {
                *dst = src;
            } else {
                dst.extend_from_slice(&src);
                spare.push(src);
            }
        }
    }
}

/// A fault inside a block, with its line relative to the block.
struct BlockFault {
    line: u64,
    column: Option<usize>,
    kind: ReadErrorKind,
}

impl BlockFault {
    /// A carriage return inside line `line`: the file's lines end in CR
    /// alone from there on, and no row can be read from it.
    fn cr_line_endings(line: u64) -> Self {
        BlockFault {
            line,
            column: None,
            kind: ReadErrorKind::CrLineEndings,
        }
    }

    fn into_error(self, path: &Path, lines_before: u64) -> ReadError {
        ReadError::new(path, self.kind).at(lines_before + self.line, self.column)
    }
}

impl Layout<'_> {
    /// Parses a well-formed row of `ncols` numbers at the start of `rest`
    /// in one pass over its bytes, the line's end found on the way (no
    /// separate newline search): the bytes taken, newline included. `None`
    /// for anything else (comments, blank lines, bad cells, wrong field
    /// counts, a last line without its newline), which the careful path
    /// then handles.
    #[inline]
    fn parse_row_fast(&self, rest: &[u8], values: &mut [f64]) -> Option<usize> {
        self.parse_row_with(rest, values, crate::decimal::parse_prefix)
    }

    /// [`Layout::parse_row_fast`] with each cell's digits found and folded
    /// in SSSE3/SSE4.1 registers (`crate::decimal_x86::plain_digits`), the
    /// scalar reader deciding whatever that form leaves to it.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "ssse3,sse4.1")]
    fn parse_row_sse41(&self, rest: &[u8], values: &mut [f64]) -> Option<usize> {
        self.parse_row_with(rest, values, |s| match crate::decimal_x86::plain_digits(s) {
            Some((negative, w, frac_digits, used)) => {
                Some((crate::decimal::plain_value(negative, w, frac_digits), used))
            }
            None => crate::decimal::parse_prefix(s),
        })
    }

    /// Whether this CPU runs [`Layout::parse_row_sse41`].
    fn row_simd() -> bool {
        #[cfg(target_arch = "x86_64")]
        return crate::decimal_x86::available();
        #[cfg(not(target_arch = "x86_64"))]
        false
    }

    /// A row, read with the cell parse it is given.
    #[inline(always)]
    fn parse_row_with(
        &self,
        rest: &[u8],
        values: &mut [f64],
        cell: impl Fn(&[u8]) -> Option<(f64, usize)>,
    ) -> Option<usize> {
        let is_blank = |b: u8| b == b' ' || (b == b'\t' && self.delimiter != Delimiter::Tab);
        let sep = match self.delimiter {
            Delimiter::Comma => Some(b','),
            Delimiter::Semicolon => Some(b';'),
            Delimiter::Tab => Some(b'\t'),
            Delimiter::Whitespace => None,
        };
        let n = rest.len();
        let mut pos = 0;
        for (k, slot) in values.iter_mut().enumerate() {
            while pos < n && is_blank(rest[pos]) {
                pos += 1;
            }
            let (v, used) = cell(&rest[pos..])?;
            *slot = v;
            pos += used;
            while pos < n && is_blank(rest[pos]) {
                pos += 1;
            }
            let last_field = k + 1 == self.ncols;
            match sep {
                // One carriage return before the newline is the line's end
                // in a CRLF file.
                _ if last_field => {
                    return match rest.get(pos..pos + 2) {
                        Some([b'\n', _]) => Some(pos + 1),
                        Some(b"\r\n") => Some(pos + 2),
                        _ => (rest.get(pos) == Some(&b'\n')).then_some(pos + 1),
                    };
                }
                Some(c) => {
                    if pos < n && rest[pos] == c {
                        pos += 1;
                    } else {
                        return None;
                    }
                }
                // Whitespace-separated: the blanks skipped above were the
                // separator, and there must have been some.
                None => {
                    if pos == n || !is_blank(rest[pos - 1]) {
                        return None;
                    }
                }
            }
        }
        None
    }

    /// Parses whole lines. `last` marks the end of the file, where a line
    /// without its newline is a truncated write if it is short.
    fn parse_block(&self, block: &[u8], last: bool) -> Result<BlockOut, BlockFault> {
        let mut problems = Vec::new();
        let mut skipped = SkippedLines::default();
        let est_rows = block.len() / (8 * self.ncols.max(1)) + 1;
        let mut columns: Vec<Vec<f64>> = {
            let mut spare = self.spare.lock().unwrap_or_else(|p| p.into_inner());
            (0..self.select.len())
                .map(|_| {
                    let mut c = spare.pop().unwrap_or_default();
                    c.clear();
                    c.reserve(est_rows);
                    c
                })
                .collect()
        };
        let mut lines = 0u64;
        let unterminated = !block.is_empty() && !block.ends_with(b"\n");
        let mut fields: Vec<&[u8]> = Vec::with_capacity(self.ncols);
        let mut values: Vec<f64> = vec![0.0; self.ncols];
        let mut rest = block;
        let single = self.ncols == 1 && self.select == [0];
        let row_simd = Self::row_simd();
        while !rest.is_empty() {
            // A run of empty lines is skipped at once: a file of nothing but
            // newlines costs one run and a pass over its bytes.
            if rest[0] == b'\n' {
                let n = rest.iter().position(|&b| b != b'\n').unwrap_or(rest.len());
                skipped.push_run(lines + 1, n as u64);
                lines += n as u64;
                rest = &rest[n..];
                continue;
            }
            if single {
                // One plain decimal and a newline, the most common row of
                // all (one gyro axis), without the general row machinery.
                let column = &mut columns[0];
                let (pos, n) = short_lines::read(rest, column);
                lines += n;
                rest = &rest[pos..];
                while let Some((v, used)) = crate::decimal::parse_plain(rest) {
                    if rest.get(used) != Some(&b'\n') {
                        break;
                    }
                    column.push(v);
                    lines += 1;
                    rest = &rest[used + 1..];
                }
                if rest.is_empty() {
                    break;
                }
            }
            let fast = if row_simd {
                #[cfg(target_arch = "x86_64")]
                // SAFETY: `row_simd` is `decimal_x86::available()`, which
                // found SSSE3 and SSE4.1 on this CPU.
                unsafe {
                    self.parse_row_sse41(rest, &mut values)
                }
                #[cfg(not(target_arch = "x86_64"))]
                None
            } else {
                self.parse_row_fast(rest, &mut values)
            };
            if let Some(used) = fast {
                for (dst, &i) in columns.iter_mut().zip(self.select) {
                    dst.push(values[i]);
                }
                lines += 1;
                rest = &rest[used..];
                continue;
            }
            let (line, next) = match memchr::memchr(b'\n', rest) {
                Some(nl) => (&rest[..nl], &rest[nl + 1..]),
                None => (rest, &rest[rest.len()..]),
            };
            rest = next;
            lines += 1;
            let line = line.strip_suffix(b"\r").unwrap_or(line);
            // A last line without its newline was cut by a write that did
            // not finish, even when what is left reads as a (shorter)
            // number: it is dropped and reported.
            if last && unterminated && rest.is_empty() && !is_skipped(line) {
                if has_inner_cr(line) {
                    return Err(BlockFault::cr_line_endings(lines));
                }
                self.delimiter.split_into(line, &mut fields);
                problems.push(BlockFault {
                    line: lines,
                    column: None,
                    kind: ReadErrorKind::TruncatedLastLine {
                        expected: self.ncols,
                        found: fields.len(),
                    },
                });
                continue;
            }
            if is_skipped(line) {
                skipped.push(lines);
                continue;
            }
            if has_inner_cr(line) {
                return Err(BlockFault::cr_line_endings(lines));
            }
            // The careful path: find out exactly what is wrong, or handle
            // what the fast path does not (non-numeric unselected cells).
            self.delimiter.split_into(line, &mut fields);
            let fault = |column, kind| BlockFault {
                line: lines,
                column,
                kind,
            };
            let problem = if fields.len() != self.ncols {
                Some(fault(
                    None,
                    ReadErrorKind::FieldCount {
                        expected: self.ncols,
                        found: fields.len(),
                    },
                ))
            } else {
                self.select.iter().find_map(|&i| {
                    parse_number(fields[i]).is_none().then(|| {
                        let text = String::from_utf8_lossy(fields[i]).into_owned();
                        fault(Some(i + 1), ReadErrorKind::NotANumber { text })
                    })
                })
            };
            match problem {
                None => {
                    for (dst, &i) in columns.iter_mut().zip(self.select) {
                        dst.push(parse_number(fields[i]).unwrap_or(f64::NAN));
                    }
                }
                // Skipped lines become gaps so that sample indices (and so
                // time) stay right.
                Some(p) if self.skip_bad_lines => {
                    for dst in columns.iter_mut() {
                        dst.push(f64::NAN);
                    }
                    problems.push(p);
                }
                Some(p) => return Err(p),
            }
        }
        Ok(BlockOut {
            columns,
            lines,
            problems,
            skipped,
        })
    }
}

#[cfg(test)]
mod tests {

    use super::*;
    use std::io::Write;

    fn file(content: &[u8]) -> tempfile::NamedTempFile {
        let mut f = tempfile::NamedTempFile::new().unwrap();
        f.write_all(content).unwrap();
        f
    }

    #[test]
    fn reads_headerless_whitespace_columns() {
        let f = file(b"# x\n1 2\n\n3\t4\n# mid comment\n5 6\n");
        let t = TableReader::open(f.path()).unwrap().read(None).unwrap();
        assert_eq!(t.names, ["col1", "col2"]);
        assert!(!t.has_header);
        assert_eq!(t.columns, vec![vec![1.0, 3.0, 5.0], vec![2.0, 4.0, 6.0]]);
        assert_eq!(t.comments, ["x"]);
        assert_eq!(t.lines, 6);
        let lines: Vec<u64> = (0..3).map(|r| t.line_of_row(r)).collect();
        assert_eq!(lines, [2, 4, 6]);
    }

    #[test]
    fn reads_thesis_style_header_and_selects() {
        let f = file(b"a[m/^2], b[rad/s],c\r\n1.5, -2e-3, 7\r\n2.5,nan,8\r\n");
        let r = TableReader::open(f.path()).unwrap();
        assert_eq!(r.names(), ["a[m/^2]", "b[rad/s]", "c"]);
        let idx = r.column_index("B[RAD/S]").unwrap();
        assert_eq!(r.column_index("3").unwrap(), 2);
        assert_eq!(r.column_index("a").unwrap(), 0);
        assert!(r.column_index("zz").is_err());
        let t = r.read(Some(&[idx])).unwrap();
        assert_eq!(t.columns[0][0], -2e-3);
        assert!(t.columns[0][1].is_nan());
    }

    #[test]
    fn errors_name_line_and_column() {
        let f = file(b"a,b\n1,2\n3,x7\n");
        let e = TableReader::open(f.path()).unwrap().read(None).unwrap_err();
        assert_eq!((e.line, e.column), (Some(3), Some(2)));
        assert!(e.to_string().contains(":3: column 2: cannot read 'x7'"), "{e}");

        let f = file(b"1,2\n3\n");
        let e = TableReader::open(f.path()).unwrap().read(None).unwrap_err();
        assert_eq!(e.line, Some(2));
        assert!(matches!(
            e.kind,
            ReadErrorKind::FieldCount {
                expected: 2,
                found: 1
            }
        ));

        let f = file(b"1,2\n3,4\n5");
        let t = TableReader::open(f.path()).unwrap().read(None).unwrap();
        assert_eq!(t.columns[0], vec![1.0, 3.0]);
        assert_eq!(t.problems.len(), 1);
        assert_eq!(t.problems[0].line, Some(3));
        assert!(matches!(
            t.problems[0].kind,
            ReadErrorKind::TruncatedLastLine { .. }
        ));
        let f = file(b"1,2\n3,4\n5,-");
        let t = TableReader::open(f.path()).unwrap().read(None).unwrap();
        assert_eq!((t.rows(), t.problems.len()), (2, 1));

        let f = file(b"");
        let e = TableReader::open(f.path()).unwrap_err();
        assert!(matches!(e.kind, ReadErrorKind::NoData));
        let f = file(b"# only\nname\n");
        let e = TableReader::open(f.path()).unwrap().read(None).unwrap_err();
        assert!(matches!(e.kind, ReadErrorKind::NoData));
    }

    #[test]
    fn one_column_rows_leave_the_quick_loop_where_they_must() {
        // Plain decimals run through the one-column loop; an exponent, a
        // leading blank, CRLF, a blank line and a comment each leave it and
        // come back; the bad cell is still named by its line.
        let f = file(b"1.5\n2e-3\n\n# c\n 3\n4\r\n-0.25\n5\n");
        let t = TableReader::open(f.path()).unwrap().read(None).unwrap();
        assert_eq!(t.columns[0], vec![1.5, 2e-3, 3.0, 4.0, -0.25, 5.0]);
        assert_eq!(t.line_of_row(4), 7);
        let f = file(b"1.5\n2.5\n3.5x\n4\n");
        let e = TableReader::open(f.path()).unwrap().read(None).unwrap_err();
        assert_eq!((e.line, e.column), (Some(3), Some(1)));
        let f = file(b"1.5\n2.5\n3.5");
        let t = TableReader::open(f.path()).unwrap().read(None).unwrap();
        assert_eq!(
            (t.columns[0].clone(), t.problems[0].line),
            (vec![1.5, 2.5], Some(3))
        );
    }

    #[test]
    fn odd_but_valid_cells_take_the_careful_path() {
        // A text column that is not selected, tabs with empty-free cells,
        // signs, exponents and spaces around separators.
        let f = file(b"time\tv\n2026-01-01T00:00:00\t+1.5e-3\nt2\t -2 \n");
        let r = TableReader::open(f.path()).unwrap();
        let t = r.read(Some(&[1])).unwrap();
        assert_eq!(t.columns[0], vec![1.5e-3, -2.0]);
        let f = file(b"1  2\n3 4e\n");
        let e = TableReader::open(f.path()).unwrap().read(None).unwrap_err();
        assert_eq!((e.line, e.column), (Some(2), Some(2)));
        let f = file(b"1,2\n3,,\n");
        let e = TableReader::open(f.path()).unwrap().read(None).unwrap_err();
        assert!(
            matches!(
                e.kind,
                ReadErrorKind::FieldCount {
                    expected: 2,
                    found: 3
                }
            ),
            "{e}"
        );
    }

    #[test]
    fn line_of_row_counts_the_skipped_lines_before_it() {
        // Rows and comment lines interleaved in a known pattern: line L is a
        // comment when L % 3 == 0 or L % 7 == 0 (from line 3 on).
        let body_start_line = 2;
        let skipped: Vec<u64> = (3..400).filter(|l| l % 3 == 0 || l % 7 == 0).collect();
        let row_lines: Vec<u64> = (2..400).filter(|l| !skipped.contains(l)).collect();
        let t = Table {
            path: PathBuf::new(),
            has_header: true,
            comments: Vec::new(),
            names: Vec::new(),
            columns: Vec::new(),
            lines: 400,
            problems: Vec::new(),
            body_start_line,
            skipped_lines: {
                let mut s = SkippedLines::default();
                skipped.iter().for_each(|&l| s.push(l));
                s
            },
            trailer: None,
        };
        for (row, &line) in row_lines.iter().enumerate() {
            assert_eq!(t.line_of_row(row), line, "row {row}");
        }
    }

    #[test]
    fn skipped_lines_become_gaps_and_are_reported() {
        let f = file(b"a,b\n1,2\n3\n5,x\n7,8\n");
        let policy = ReadPolicy { skip_bad_lines: true };
        let t = TableReader::open(f.path())
            .unwrap()
            .read_with(None, &policy)
            .unwrap();
        assert_eq!(t.rows(), 4);
        assert!(t.columns[0][1].is_nan() && t.columns[1][2].is_nan());
        assert_eq!(t.columns[1][3], 8.0);
        let lines: Vec<_> = t.problems.iter().map(|p| (p.line, p.column)).collect();
        assert_eq!(lines, [(Some(3), None), (Some(4), Some(2))]);
    }

    #[test]
    fn a_last_line_without_newline_is_cut_even_when_it_reads() {
        // "3.14159" cut after "3.1" reads as a shorter number: the missing
        // newline is the only sign, and it is enough.
        for content in [&b"a,b\n1,2\n3,4"[..], b"a,b\n1,2\n3.1,4.1", b"1,2"] {
            let f = file(content);
            let r = TableReader::open(f.path()).unwrap().read(None);
            let text = String::from_utf8_lossy(content);
            let lines = text.lines().count() as u64;
            match r {
                Ok(t) => {
                    assert_eq!(t.rows() as u64, lines - 2, "{text}");
                    assert_eq!(t.problems.len(), 1);
                    assert_eq!(t.problems[0].line, Some(lines));
                    assert!(matches!(
                        t.problems[0].kind,
                        ReadErrorKind::TruncatedLastLine {
                            expected: 2,
                            found: 2
                        }
                    ));
                }
                // The only row was the cut one.
                Err(e) => assert!(matches!(e.kind, ReadErrorKind::NoData) && lines == 1, "{e}"),
            }
        }
        // A comment or a blank last line without newline loses nothing.
        let f = file(b"1,2\n3,4\n# end");
        let t = TableReader::open(f.path()).unwrap().read(None).unwrap();
        assert_eq!((t.rows(), t.problems.len()), (2, 0));
    }

    #[test]
    fn large_file_keeps_order_and_line_numbers() {
        let mut content = Vec::new();
        let rows = 300_000;
        for i in 0..rows {
            writeln!(content, "{i}, {}", i as f64 * 0.5).unwrap();
        }
        writeln!(content, "1, oops").unwrap();
        let f = file(&content);
        let e = TableReader::open(f.path()).unwrap().read(None).unwrap_err();
        assert_eq!(e.line, Some(rows as u64 + 1));
        content.truncate(content.len() - "1, oops\n".len());
        let f = file(&content);
        let t = TableReader::open(f.path()).unwrap().read(None).unwrap();
        assert_eq!(t.rows(), rows);
        assert!(t.columns[0].iter().enumerate().all(|(i, &v)| v == i as f64));
        // Cut after many blocks: the last row alone is dropped, at its line.
        content.pop();
        let f = file(&content);
        let t = TableReader::open(f.path()).unwrap().read(None).unwrap();
        assert_eq!(t.rows(), rows - 1);
        assert_eq!(t.problems.len(), 1);
        assert_eq!(t.problems[0].line, Some(rows as u64));
    }

    #[test]
    fn reads_gzip_by_content() {
        let mut gz = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::fast());
        gz.write_all(b"v\n1\n2\n").unwrap();
        let f = file(&gz.finish().unwrap());
        let t = TableReader::open(f.path()).unwrap().read(None).unwrap();
        assert_eq!(t.columns[0], vec![1.0, 2.0]);
    }

    fn gzip(content: &[u8]) -> Vec<u8> {
        let mut gz = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::fast());
        gz.write_all(content).unwrap();
        gz.finish().unwrap()
    }

    #[test]
    fn gzip_members_and_zero_padding_read_as_gzip_reads_them() {
        let mut bytes = gzip(b"v\n1\n");
        bytes.extend(gzip(b"2\n"));
        bytes.extend([0u8; 700]);
        let f = file(&bytes);
        let t = TableReader::open(f.path()).unwrap().read(None).unwrap();
        assert_eq!(t.columns[0], vec![1.0, 2.0]);
        // gzip -d cross-checks the same bytes when it is installed.
        if let Ok(out) = std::process::Command::new("gzip")
            .arg("-dc")
            .arg(f.path())
            .output()
        {
            assert!(out.status.success());
            assert_eq!(out.stdout, b"v\n1\n2\n");
        }
        let mut garbage = gzip(b"v\n1\n");
        garbage.extend(b"\0\0junk");
        let f = file(&garbage);
        let e = TableReader::open(f.path()).unwrap().read(None).unwrap_err();
        assert!(e.to_string().contains("zero padding"), "{e}");
    }

    #[test]
    fn comments_before_the_first_row_are_bounded() {
        let mut content = "#\n".repeat(MAX_HEADER_COMMENTS).into_bytes();
        content.extend(b"v\n1\n");
        let f = file(&content);
        assert_eq!(
            TableReader::open(f.path()).unwrap().comments().len(),
            MAX_HEADER_COMMENTS
        );
        let mut content = "#\n".repeat(MAX_HEADER_COMMENTS + 1).into_bytes();
        content.extend(b"v\n1\n");
        let f = file(&content);
        let e = TableReader::open(f.path()).unwrap_err();
        assert!(matches!(e.kind, ReadErrorKind::TooManyComments { .. }), "{e}");
        assert_eq!(e.line, Some(MAX_HEADER_COMMENTS as u64 + 1));
    }

    #[test]
    fn cr_only_line_endings_are_refused_by_name() {
        let f = file(b"a,b\r1,2\r3,4\r");
        let e = TableReader::open(f.path()).unwrap_err();
        assert!(matches!(e.kind, ReadErrorKind::CrLineEndings), "{e}");
        assert_eq!(e.line, Some(1));
        // From the second line on, short or beyond the line limit.
        let mut long = b"a,b\n".to_vec();
        long.extend("1,2\r".repeat(MAX_LINE_BYTES / 4 + 10).bytes());
        for content in [&b"a,b\n1,2\r3,4\r"[..], &long] {
            let f = file(content);
            let e = TableReader::open(f.path()).unwrap().read(None).unwrap_err();
            assert!(matches!(e.kind, ReadErrorKind::CrLineEndings), "{e}");
            assert_eq!(e.line, Some(2));
        }
    }

    #[test]
    fn duplicate_header_names_are_refused() {
        let f = file(b"gyro_x,gyro_x,temp\n1,2,3\n");
        let e = TableReader::open(f.path()).unwrap_err();
        assert!(
            matches!(&e.kind, ReadErrorKind::DuplicateColumn { name, first: 1, second: 2 } if name == "gyro_x"),
            "{e}"
        );
    }

    #[test]
    fn an_endless_line_stops_at_the_limit() {
        // NUL bytes with no newline, first in the file and after rows.
        let nul = vec![0u8; MAX_LINE_BYTES + 10];
        let f = file(&nul);
        let e = TableReader::open(f.path()).unwrap_err();
        assert!(matches!(e.kind, ReadErrorKind::LineTooLong { .. }), "{e}");
        let mut content = b"a\n1\n2\n".to_vec();
        content.extend(&nul);
        for bytes in [content.clone(), gzip(&content)] {
            let f = file(&bytes);
            let e = TableReader::open(f.path()).unwrap().read(None).unwrap_err();
            assert!(matches!(e.kind, ReadErrorKind::LineTooLong { .. }), "{e}");
            assert_eq!(e.line, Some(4));
        }
    }

    #[test]
    fn blank_lines_cost_no_memory_per_line() {
        let mut content = b"a\n1\n".to_vec();
        content.extend(std::iter::repeat_n(b'\n', 3 * BLOCK_BYTES + 17));
        content.extend(b"2\n");
        let f = file(&gzip(&content));
        let t = TableReader::open(f.path()).unwrap().read(None).unwrap();
        assert_eq!(t.columns[0], vec![1.0, 2.0]);
        assert_eq!(t.skipped_lines.runs.len(), 1);
        assert_eq!(t.skipped_lines.len(), 3 * BLOCK_BYTES as u64 + 17);
        assert_eq!(t.line_of_row(1), 3 * BLOCK_BYTES as u64 + 17 + 3);
        assert!(t.skipped_lines.contains(3) && !t.skipped_lines.contains(2));
    }

    #[test]
    fn the_trailer_comes_from_the_stream_tail_of_any_input() {
        let mut content = b"v\n".to_vec();
        for i in 0..20_000 {
            writeln!(content, "{i}").unwrap();
        }
        writeln!(content, "# trailer: samples=20000 gaps=0").unwrap();
        let want = Some("samples=20000 gaps=0".to_string());
        for bytes in [content.clone(), gzip(&content)] {
            let f = file(&bytes);
            let t = TableReader::open(f.path()).unwrap().read(None).unwrap();
            assert_eq!(t.trailer, want);
        }
        // A FIFO is read once: every value arrives, the trailer too.
        let dir = tempfile::tempdir().unwrap();
        let fifo = dir.path().join("fifo");
        let made = std::process::Command::new("mkfifo").arg(&fifo).status();
        if !made.is_ok_and(|s| s.success()) {
            return;
        }
        let writer = {
            let (fifo, content) = (fifo.clone(), content.clone());
            std::thread::spawn(move || std::fs::write(fifo, content).unwrap())
        };
        let t = TableReader::open(&fifo).unwrap().read(None).unwrap();
        writer.join().unwrap();
        assert_eq!(t.trailer, want);
        assert_eq!(t.rows(), 20_000);
        assert!(t.columns[0].iter().enumerate().all(|(i, &v)| v == i as f64));
    }
}
