//! Plain numeric column files: one channel per column, comma, tab or
//! whitespace separated, an optional header line, `#` comment lines.
//!
//! The file is streamed in blocks; each batch of blocks is parsed on all
//! cores, and the blocks' results are joined in order, so line numbers in
//! errors stay exact. Gzip input (by its magic bytes, not its name) is
//! decompressed on the fly.

use std::fs::File;
use std::io::{BufRead, BufReader, Read};
use std::path::{Path, PathBuf};

use rayon::prelude::*;

use crate::error::{ReadError, ReadErrorKind};

/// Bytes per parse block: large enough to amortise the thread hand-off,
/// small enough that a batch of them stays a few MiB.
const BLOCK_BYTES: usize = 1 << 20;

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
    if field.is_empty() {
        return None;
    }
    fast_float2::parse::<f64, _>(field).ok()
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
    /// Whether the file is gzip-compressed (its size says nothing of the data).
    gzip: bool,
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
    /// Blank and comment lines among the rows, ascending.
    pub skipped_lines: Vec<u64>,
}

impl Table {
    /// The 1-based line of row `row` (0-based): where to look in the file.
    pub fn line_of_row(&self, row: usize) -> u64 {
        // Skipped line i (ascending) lies before the row's line when
        // s_i ≤ base + row + i, that is s_i − i ≤ base + row; s_i − i never
        // decreases (the lines are distinct), so a binary search counts them
        // in O(log n), which matters for files with many gap comments.
        let target = self.body_start_line + row as u64;
        let (mut lo, mut hi) = (0, self.skipped_lines.len());
        while lo < hi {
            let mid = lo + (hi - lo) / 2;
            if self.skipped_lines[mid].saturating_sub(mid as u64) <= target {
                lo = mid + 1;
            } else {
                hi = mid;
            }
        }
        target + lo as u64
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
    /// Opens `path`, reads its comments and header, and works out the layout.
    pub fn open(path: impl AsRef<Path>) -> Result<TableReader, ReadError> {
        let path = path.as_ref().to_path_buf();
        let io_err = |e: std::io::Error| ReadError::new(&path, ReadErrorKind::Io(e));
        let file = File::open(&path).map_err(io_err)?;
        let mut buffered = BufReader::with_capacity(1 << 16, file);
        let gz = buffered.fill_buf().map_err(io_err)?.starts_with(&[0x1f, 0x8b]);
        let mut input: Box<dyn BufRead + Send> = if gz {
            Box::new(BufReader::with_capacity(
                1 << 16,
                flate2::read::MultiGzDecoder::new(buffered),
            ))
        } else {
            Box::new(buffered)
        };

        let mut comments = Vec::new();
        let mut comment_lines = Vec::new();
        let mut line_no = 0u64;
        let mut raw = Vec::new();
        let first = loop {
            raw.clear();
            let got = input.read_until(b'\n', &mut raw).map_err(io_err)?;
            if got == 0 {
                return Err(ReadError::new(&path, ReadErrorKind::NoData));
            }
            line_no += 1;
            let text = std::str::from_utf8(&raw)
                .map_err(|_| ReadError::new(&path, ReadErrorKind::NotText).at(line_no, None))?
                .trim_end_matches(['\n', '\r']);
            if is_skipped(text.as_bytes()) {
                if let Some(c) = text.trim_start().strip_prefix('#') {
                    comments.push(c.trim().to_string());
                    comment_lines.push(line_no);
                }
                continue;
            }
            break text.to_string();
        };
        let delimiter = Delimiter::detect(&first);
        let mut fields = Vec::new();
        delimiter.split_into(first.as_bytes(), &mut fields);
        let numeric = fields.iter().all(|f| parse_number(f).is_some());
        let (names, has_header, pending) = if numeric {
            let names = (1..=fields.len()).map(|i| format!("col{i}")).collect();
            (names, false, Some((line_no, first.clone())))
        } else {
            let names = fields
                .iter()
                .map(|f| String::from_utf8_lossy(f).trim().to_string())
                .collect();
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
            gzip: gz,
        })
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
        };
        let mut got = Collected {
            columns: vec![Vec::new(); select.len()],
            problems: Vec::new(),
            skipped_lines: Vec::new(),
        };
        let body_start_line = match &self.pending {
            Some((line, _)) => *line,
            None => self.line_no + 1,
        };
        // The file size sizes the columns (see `Merger::merge`).
        let file_bytes = if self.gzip {
            None
        } else {
            std::fs::metadata(&self.path).ok().map(|m| m.len())
        };

        if let Some((line, text)) = self.pending.take() {
            let out = layout
                .parse_block(text.as_bytes(), false)
                .map_err(|f| f.into_error(&self.path, line - 1))?;
            out.append_to(&mut got, &self.path, line - 1);
        }

        let batch_len = 4 * rayon::current_num_threads().max(1);
        let mut source = BlockSource {
            input: &mut self.input,
            carry: Vec::new(),
            eof: false,
        };
        let io_err = |e| ReadError::new(&self.path, ReadErrorKind::Io(e));
        let mut merger = Merger {
            got: &mut got,
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
                        .map(|(i, b)| layout.parse_block(b, last_batch && i == last_index))
                        .collect::<Vec<Result<BlockOut, BlockFault>>>()
                },
                || {
                    let merged = parsed.take().map_or(Ok(()), |(r, bytes)| merger.merge(r, bytes));
                    let next = (!last_batch).then(|| source.next_batch(batch_len)).transpose();
                    (merged, next)
                },
            );
            merged?;
            parsed = Some((results, batch.iter().map(|b| b.len() as u64).sum::<u64>()));
            match next.map_err(io_err)? {
                Some(b) => batch = b,
                None => break,
            }
        }
        if let Some((r, bytes)) = parsed {
            merger.merge(r, bytes)?;
        }
        self.line_no = merger.line_no;
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
        })
    }
}

/// Cuts the input into blocks of whole lines.
struct BlockSource<'a> {
    input: &'a mut Box<dyn BufRead + Send>,
    /// The partial line at the end of the previous block.
    carry: Vec<u8>,
    eof: bool,
}

impl BlockSource<'_> {
    /// Reads up to `count` blocks; the last block of the input may end
    /// without a newline.
    fn next_batch(&mut self, count: usize) -> std::io::Result<Vec<Vec<u8>>> {
        let mut blocks = Vec::with_capacity(count);
        while blocks.len() < count && !self.eof {
            let mut block = std::mem::take(&mut self.carry);
            block.reserve(BLOCK_BYTES);
            let got = (&mut *self.input)
                .take(BLOCK_BYTES as u64)
                .read_to_end(&mut block)?;
            if got == 0 {
                self.eof = true;
                if !block.is_empty() {
                    blocks.push(block);
                }
                break;
            }
            // Keep the partial last line for the next block.
            match memchr::memrchr(b'\n', &block) {
                Some(nl) => {
                    self.carry = block[nl + 1..].to_vec();
                    block.truncate(nl + 1);
                    blocks.push(block);
                }
                None => self.carry = block,
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
}

/// Appends parsed batches to the columns in file order, turning faults into
/// errors with their absolute line numbers.
struct Merger<'a> {
    got: &'a mut Collected,
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
            out.append_to(self.got, self.path, self.line_no);
            self.line_no += lines;
        }
        // Sizing the columns from the file size keeps memory near the data:
        // doubling growth would peak at up to three times it.
        if !self.sized
            && let Some(total) = self.file_bytes
        {
            self.sized = true;
            let rows = self.got.columns.first().map_or(0, Vec::len) as u64;
            if self.bytes_seen > 0 && rows > 0 && total > self.bytes_seen {
                let estimate = (rows as f64 * total as f64 / self.bytes_seen as f64 * 1.01) as usize;
                for c in &mut self.got.columns {
                    c.reserve_exact(estimate.saturating_sub(c.len()));
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
    skipped_lines: Vec<u64>,
}

struct BlockOut {
    columns: Vec<Vec<f64>>,
    lines: u64,
    /// Lines skipped (as gaps) or dropped (a truncated last line).
    problems: Vec<BlockFault>,
    /// Blank and comment lines among the rows (block-relative).
    skipped: Vec<u64>,
}

impl BlockOut {
    fn append_to(self, into: &mut Collected, path: &Path, lines_before: u64) {
        into.problems.extend(
            self.problems
                .into_iter()
                .map(|p| p.into_error(path, lines_before)),
        );
        into.skipped_lines
            .extend(self.skipped.iter().map(|l| l + lines_before));
        let columns = &mut into.columns;
        for (dst, src) in columns.iter_mut().zip(self.columns) {
            if dst.is_empty() {
                *dst = src;
            } else {
                dst.extend_from_slice(&src);
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
    fn into_error(self, path: &Path, lines_before: u64) -> ReadError {
        ReadError::new(path, self.kind).at(lines_before + self.line, self.column)
    }
}

impl Layout<'_> {
    /// Parses a well-formed line of `ncols` numbers in one pass over its
    /// bytes. Returns false for anything else (comments, blank lines, bad
    /// cells, wrong field counts), which the careful path then handles.
    fn parse_line_fast(&self, line: &[u8], values: &mut [f64]) -> bool {
        let is_blank = |b: u8| b == b' ' || (b == b'\t' && self.delimiter != Delimiter::Tab);
        let sep = match self.delimiter {
            Delimiter::Comma => Some(b','),
            Delimiter::Semicolon => Some(b';'),
            Delimiter::Tab => Some(b'\t'),
            Delimiter::Whitespace => None,
        };
        let n = line.len();
        let mut pos = 0;
        for (k, slot) in values.iter_mut().enumerate() {
            while pos < n && is_blank(line[pos]) {
                pos += 1;
            }
            let Ok((v, used)) = fast_float2::parse_partial::<f64, _>(&line[pos..]) else {
                return false;
            };
            if used == 0 {
                return false;
            }
            *slot = v;
            pos += used;
            while pos < n && is_blank(line[pos]) {
                pos += 1;
            }
            let last_field = k + 1 == self.ncols;
            match sep {
                _ if last_field => return pos == n,
                Some(c) => {
                    if pos < n && line[pos] == c {
                        pos += 1;
                    } else {
                        return false;
                    }
                }
                // Whitespace-separated: the blanks skipped above were the
                // separator, and there must have been some.
                None => {
                    if pos == n || !is_blank(line[pos - 1]) {
                        return false;
                    }
                }
            }
        }
        false
    }

    /// Parses whole lines. `last` marks the end of the file, where a line
    /// without its newline is a truncated write if it is short.
    fn parse_block(&self, block: &[u8], last: bool) -> Result<BlockOut, BlockFault> {
        let mut problems = Vec::new();
        let mut skipped = Vec::new();
        let est_rows = block.len() / (8 * self.ncols.max(1)) + 1;
        let mut columns: Vec<Vec<f64>> = (0..self.select.len())
            .map(|_| Vec::with_capacity(est_rows))
            .collect();
        let mut lines = 0u64;
        let unterminated = !block.is_empty() && !block.ends_with(b"\n");
        let mut fields: Vec<&[u8]> = Vec::with_capacity(self.ncols);
        let mut values: Vec<f64> = vec![0.0; self.ncols];
        let mut rest = block;
        while !rest.is_empty() {
            let (line, next) = match memchr::memchr(b'\n', rest) {
                Some(nl) => (&rest[..nl], &rest[nl + 1..]),
                None => (rest, &rest[rest.len()..]),
            };
            rest = next;
            lines += 1;
            let line = line.strip_suffix(b"\r").unwrap_or(line);
            if self.parse_line_fast(line, &mut values) {
                for (dst, &i) in columns.iter_mut().zip(self.select) {
                    dst.push(values[i]);
                }
                continue;
            }
            if is_skipped(line) {
                skipped.push(lines);
                continue;
            }
            // The careful path: find out exactly what is wrong, or handle
            // what the fast path does not (non-numeric unselected cells).
            self.delimiter.split_into(line, &mut fields);
            let fault = |column, kind| BlockFault {
                line: lines,
                column,
                kind,
            };
            let truncated = last && unterminated && rest.is_empty();
            let problem = if fields.len() != self.ncols {
                let kind = if truncated && fields.len() < self.ncols {
                    ReadErrorKind::TruncatedLastLine {
                        expected: self.ncols,
                        found: fields.len(),
                    }
                } else {
                    ReadErrorKind::FieldCount {
                        expected: self.ncols,
                        found: fields.len(),
                    }
                };
                Some(fault(None, kind))
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
                // A logger that lost power leaves a partial last line: it is
                // dropped and reported, the rest of the file kept.
                Some(mut p) if truncated => {
                    if !matches!(p.kind, ReadErrorKind::TruncatedLastLine { .. }) {
                        p.kind = ReadErrorKind::TruncatedLastLine {
                            expected: self.ncols,
                            found: fields.len(),
                        };
                        p.column = None;
                    }
                    problems.push(p);
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
            skipped_lines: skipped,
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
    fn complete_last_line_without_newline_is_kept() {
        let f = file(b"1,2\n3,4");
        let t = TableReader::open(f.path()).unwrap().read(None).unwrap();
        assert_eq!(t.columns[1], vec![2.0, 4.0]);
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
    }

    #[test]
    fn reads_gzip_by_content() {
        let mut gz = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::fast());
        gz.write_all(b"v\n1\n2\n").unwrap();
        let f = file(&gz.finish().unwrap());
        let t = TableReader::open(f.path()).unwrap().read(None).unwrap();
        assert_eq!(t.columns[0], vec![1.0, 2.0]);
    }
}
