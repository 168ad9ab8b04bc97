//! One block of whole lines into columns: well-formed rows in one pass
//! over their bytes, anything else on a careful path that names what is
//! wrong, or skips it as a gap under the policy.

use std::sync::Mutex;

use super::SkippedLines;
use super::blocks::{BlockFault, BlockOut};
use super::short_lines;
use super::sniff::{Delimiter, has_inner_cr, is_skipped, parse_number};
use crate::error::ReadErrorKind;

pub(super) struct Layout<'a> {
    pub skip_bad_lines: bool,
    pub ncols: usize,
    pub delimiter: Delimiter,
    pub select: &'a [usize],
    /// Column buffers of blocks already merged, for the next blocks to
    /// parse into (see [`BlockSource::spare`]).
    pub spare: Mutex<Vec<Vec<f64>>>,
    /// The most the columns of the whole read may take (the ceiling of
    /// [`super::budget::Limit`]), `None` for no bound.
    pub column_limit: Option<(u64, crate::error::LimitBound)>,
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
    /// A skipped line is a row of NaN as wide as the selection however
    /// short the line, so the gaps of a block are not bounded by its bytes
    /// as its rows are (a row of n values takes at least 2n bytes): a few
    /// kilobytes of short bad lines in a wide table would be gigabytes of
    /// gaps before the columns' budget sees them at the merge. Each block
    /// of a batch in flight may hold an even share of half the columns'
    /// limit in gaps; past it the read is refused as the budget refuses it.
    fn gaps_too_large(&self, gap_rows: u64, line: u64) -> Option<BlockFault> {
        let (limit, bound) = self.column_limit?;
        let in_flight = 2 * super::blocks::batch_len(self.select.len()) as u64;
        let bytes = gap_rows
            .saturating_mul(self.select.len() as u64)
            .saturating_mul(size_of::<f64>() as u64);
        (bytes > limit / in_flight).then(|| BlockFault {
            line,
            column: None,
            kind: ReadErrorKind::TooLarge {
                held_mib: bytes.saturating_mul(in_flight).div_ceil(1 << 20),
                limit_mib: limit >> 20,
                bound,
            },
        })
    }

    pub(super) fn parse_block(&self, block: &[u8], last: bool) -> Result<BlockOut, BlockFault> {
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
        let mut gap_rows = 0u64;
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
                    gap_rows += 1;
                    if let Some(fault) = self.gaps_too_large(gap_rows, lines) {
                        return Err(fault);
                    }
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
