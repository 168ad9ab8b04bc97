//! The body, read in blocks of whole lines: a batch of blocks is parsed on
//! all cores while the previous one is appended to the columns and the
//! next one is read; the blocks' results are joined in file order, so line
//! numbers in errors stay exact.

use std::io::BufRead;
use std::path::Path;
use std::sync::Mutex;

use rayon::prelude::*;

use super::budget::Budget;
use super::rows::Layout;
use super::sniff::has_inner_cr;
use super::{MAX_LINE_BYTES, SkippedLines};
use crate::error::{ReadError, ReadErrorKind};

/// Bytes per parse block: large enough to amortise the thread hand-off,
/// small enough that a batch of them stays a few MiB.
pub(super) const BLOCK_BYTES: usize = 1 << 20;

/// Where the body starts.
pub(super) struct Start<'a> {
    /// Lines before the body.
    pub line_no: u64,
    /// The first row when it was read to find the layout (no header):
    /// its line, text, and whether it ended with a newline.
    pub pending: Option<(u64, &'a str, bool)>,
    /// The size of a regular, uncompressed file, which sizes the columns.
    pub file_bytes: Option<u64>,
}

/// What a block's column takes beyond its values: the `Vec`, the
/// allocator's header and the first reserve of four values, bytes.
const COLUMN_BOOKKEEPING: usize = 72;

/// The most the blocks in flight may take in columns' bookkeeping: in a
/// table of 400 000 columns a block of a megabyte holds one row, and 24
/// blocks in flight would hold 0.7 GB of it beyond the columns' budget.
const BOOKKEEPING_BYTES: usize = 48 << 20;

/// How many blocks a batch of a table of `columns` read holds: a few per
/// core, parsed at once, fewer where the columns' bookkeeping of three
/// batches (two parsed, and the spare columns they leave) would pass
/// [`BOOKKEEPING_BYTES`].
pub(super) fn batch_len(columns: usize) -> usize {
    let cores = 4 * rayon::current_num_threads().max(1);
    let wide = BOOKKEEPING_BYTES / (3 * COLUMN_BOOKKEEPING * columns.max(1));
    cores.min(wide).max(1)
}

/// Reads the rest of `input` into `got`: the lines read in all.
pub(super) fn read_body(
    input: &mut Box<dyn BufRead + Send>,
    path: &Path,
    layout: &Layout,
    start: Start,
    got: &mut Collected,
) -> Result<u64, ReadError> {
    if let Some((line, text, terminated)) = start.pending {
        // Without its newline, the first row is also the last, and cut.
        let out = layout
            .parse_block(text.as_bytes(), !terminated)
            .map_err(|f| f.into_error(path, line - 1))?;
        out.append_to(got, path, line - 1, &layout.spare)?;
    }

    let batch_len = batch_len(layout.select.len());
    let mut source = BlockSource {
        input,
        carry: Vec::new(),
        eof: false,
        too_long: false,
        cr_only: false,
        spare: Vec::new(),
    };
    let io_err = |e| ReadError::new(path, ReadErrorKind::Io(e));
    let mut merger = Merger {
        got,
        spare: &layout.spare,
        path,
        line_no: start.line_no,
        file_bytes: start.file_bytes,
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
        return Err(ReadError::new(path, kind).at(merger.line_no + 1, None));
    }
    Ok(merger.line_no)
}

/// Cuts the input into blocks of whole lines.
pub(super) struct BlockSource<'a> {
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
pub(super) struct Block {
    buf: Vec<u8>,
    len: usize,
}

impl Block {
    pub(super) fn bytes(&self) -> &[u8] {
        &self.buf[..self.len]
    }
}

impl BlockSource<'_> {
    /// Reads up to `count` blocks; the last block of the input may end
    /// without a newline.
    pub(super) fn next_batch(&mut self, count: usize) -> std::io::Result<Vec<Block>> {
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
    pub(super) fn merge(
        &mut self,
        results: Vec<Result<BlockOut, BlockFault>>,
        bytes: u64,
    ) -> Result<(), ReadError> {
        self.bytes_seen += bytes;
        for r in results {
            let out = r.map_err(|f| f.into_error(self.path, self.line_no))?;
            let lines = out.lines;
            out.append_to(self.got, self.path, self.line_no, self.spare)?;
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
                // An estimate past the budget, or one the system refuses,
                // leaves the columns to grow step by step, counted.
                let columns = self.got.columns.len() as u64;
                let bytes = (estimate as u64).saturating_mul(columns * size_of::<f64>() as u64);
                if self.got.budget.fits(bytes) {
                    for c in &mut self.got.columns {
                        if self.got.budget.reserve_exact(c, estimate).is_err() {
                            break;
                        }
                        hugepages::advise(c);
                    }
                }
            }
        }
        Ok(())
    }
}

/// Everything gathered from the blocks, in file order.
pub(super) struct Collected {
    pub columns: Vec<Vec<f64>>,
    pub problems: Vec<ReadError>,
    pub skipped_lines: SkippedLines,
    /// What the columns hold, against what they may.
    pub budget: Budget,
}

pub(super) struct BlockOut {
    pub columns: Vec<Vec<f64>>,
    pub lines: u64,
    /// Lines skipped (as gaps) or dropped (a truncated last line).
    pub problems: Vec<BlockFault>,
    /// Blank and comment lines among the rows (block-relative).
    pub skipped: SkippedLines,
}

impl BlockOut {
    /// Appends the block's rows, unless they would take the columns past
    /// their budget or the system refuses the memory: then the error names
    /// the block's last line.
    pub(super) fn append_to(
        self,
        into: &mut Collected,
        path: &Path,
        lines_before: u64,
        spare: &Mutex<Vec<Vec<f64>>>,
    ) -> Result<(), ReadError> {
        let too_big = |kind| ReadError::new(path, kind).at(lines_before + self.lines.max(1), None);
        let rows = self.columns.first().map_or(0, Vec::len);
        if rows == 0 {
            // Comments or blank lines alone: nothing to hold.
        } else if into.columns.iter().all(Vec::is_empty) {
            for (dst, src) in into.columns.iter().zip(&self.columns) {
                into.budget
                    .adopt(dst.capacity(), src.capacity())
                    .map_err(too_big)?;
            }
        } else {
            let extra: Vec<usize> = self.columns.iter().map(Vec::len).collect();
            into.budget.grow(&mut into.columns, &extra).map_err(too_big)?;
        }
        into.problems.extend(
            self.problems
                .into_iter()
                .map(|p| p.into_error(path, lines_before)),
        );
        into.skipped_lines.append(&self.skipped, lines_before);
        let columns = &mut into.columns;
        let mut spare = spare.lock().unwrap_or_else(|p| p.into_inner());
        for (dst, src) in columns.iter_mut().zip(self.columns) {
            if dst.is_empty() && rows > 0 {
                *dst = src;
            } else {
                dst.extend_from_slice(&src);
                spare.push(src);
            }
        }
        Ok(())
    }
}

/// A fault inside a block, with its line relative to the block.
pub(super) struct BlockFault {
    pub line: u64,
    pub column: Option<usize>,
    pub kind: ReadErrorKind,
}

impl BlockFault {
    /// A carriage return inside line `line`: the file's lines end in CR
    /// alone from there on, and no row can be read from it.
    pub(super) fn cr_line_endings(line: u64) -> Self {
        BlockFault {
            line,
            column: None,
            kind: ReadErrorKind::CrLineEndings,
        }
    }

    pub(super) fn into_error(self, path: &Path, lines_before: u64) -> ReadError {
        ReadError::new(path, self.kind).at(lines_before + self.line, self.column)
    }
}
