//! What comes before the table in a file captured from a serial port: a
//! terminal's banner (PuTTY's `=~=~=~= PuTTY log … =~=~=~=`), the lines a
//! firmware prints at boot, and a first row cut short because the capture
//! began in the middle of a line.
//!
//! The first lines are read ahead, up to [`AHEAD_BYTES`]: the rows among
//! them (lines of numbers only) give the table's delimiter and its number
//! of fields, the most common one. Leading text lines that do not share
//! the rows' shape are a preamble; without a header, leading rows of
//! another width before the first row of the common width were cut. Both
//! are skipped and reported with their lines; what follows is read as
//! before. The bytes read ahead are handed back to the body's reader.

use std::io::{BufRead, Read};

use super::sniff::{Delimiter, has_inner_cr, is_skipped, is_text, parse_number};

/// How much is read ahead: hundreds of IMU rows.
pub(super) const AHEAD_BYTES: usize = 64 * 1024;

/// The rows' shape, found from the lines read ahead.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) struct Shape {
    pub delimiter: Delimiter,
    pub fields: usize,
}

/// One whole line read ahead: its text (without its line end) and where
/// its bytes end in the buffer.
pub(super) struct AheadLine {
    pub text: Option<String>,
    pub end: usize,
    pub terminated: bool,
}

/// Bytes read ahead of the body, cut into lines.
pub(super) struct Ahead {
    pub bytes: Vec<u8>,
    pub lines: Vec<AheadLine>,
    /// The error that stopped the reading ahead: the body's reader meets it
    /// after these bytes, where it would have without the look.
    pub error: Option<std::io::Error>,
}

/// A reader that fails once with the error it holds, then ends.
pub(super) struct Failed(pub Option<std::io::Error>);

impl Read for Failed {
    fn read(&mut self, _: &mut [u8]) -> std::io::Result<usize> {
        self.0.take().map_or(Ok(0), Err)
    }
}

impl BufRead for Failed {
    fn fill_buf(&mut self) -> std::io::Result<&[u8]> {
        self.0.take().map_or(Ok(&[]), Err)
    }

    fn consume(&mut self, _: usize) {}
}

impl Ahead {
    /// Reads up to [`AHEAD_BYTES`] from `input` (fewer at its end, or
    /// where it fails).
    pub(super) fn read(input: &mut dyn BufRead) -> Ahead {
        let mut bytes = Vec::new();
        let error = Read::take(input, AHEAD_BYTES as u64)
            .read_to_end(&mut bytes)
            .err();
        let at_end = bytes.len() < AHEAD_BYTES && error.is_none();
        let mut lines = Vec::new();
        let mut start = 0;
        while start < bytes.len() {
            let (end, terminated) = match memchr::memchr(b'\n', &bytes[start..]) {
                Some(nl) => (start + nl + 1, true),
                // A part of a line at the buffer's end is not looked at,
                // unless it is the input's last.
                None if at_end => (bytes.len(), false),
                None => break,
            };
            let body = &bytes[start..end];
            let body = body.strip_suffix(b"\n").unwrap_or(body);
            let body = body.strip_suffix(b"\r").unwrap_or(body);
            let text = (is_text(body) && !has_inner_cr(body))
                .then(|| std::str::from_utf8(body).ok().map(str::to_string))
                .flatten();
            lines.push(AheadLine {
                text,
                end,
                terminated,
            });
            start = end;
        }
        Ahead { bytes, lines, error }
    }

    /// The bytes after line `i`, for the body's reader.
    pub(super) fn rest_after(&self, i: Option<usize>) -> Vec<u8> {
        let from = i.map_or(0, |i| self.lines[i].end);
        self.bytes[from..].to_vec()
    }
}

/// The fields of `line` under its own delimiter, if every one is a number.
fn row_shape(line: &str) -> Option<Shape> {
    let delimiter = Delimiter::detect(line);
    let mut fields = Vec::new();
    delimiter.split_into(line.as_bytes(), &mut fields);
    (!fields.is_empty() && fields.iter().all(|f| parse_number(f).is_some())).then_some(Shape {
        delimiter,
        fields: fields.len(),
    })
}

/// The most common shape of the rows among `lines` (the first seen of
/// equally common ones), or `None` without a row.
pub(super) fn common_shape<'a>(lines: impl Iterator<Item = &'a str>) -> Option<Shape> {
    let mut counts: Vec<(Shape, usize)> = Vec::new();
    for shape in lines.filter(|l| !is_skipped(l.as_bytes())).filter_map(row_shape) {
        match counts.iter_mut().find(|(s, _)| *s == shape) {
            Some((_, n)) => *n += 1,
            None => counts.push((shape, 1)),
        }
    }
    let most = counts.iter().map(|&(_, n)| n).max()?;
    counts.iter().find(|&&(_, n)| n == most).map(|&(s, _)| s)
}

/// Whether `line`, a line before the first row, is not of the table: a
/// header shares the rows' delimiter (or, between blanks, their number of
/// fields); a banner or a boot message does not.
pub(super) fn is_preamble(line: &str, shape: Shape) -> bool {
    if row_shape(line).is_some() {
        return false;
    }
    let mut fields = Vec::new();
    shape.delimiter.split_into(line.as_bytes(), &mut fields);
    match shape.delimiter {
        Delimiter::Whitespace => fields.len() != shape.fields,
        _ => fields.len() < 2 && shape.fields >= 2,
    }
}

/// Whether `line` is a row of another width than the shape's, in its
/// delimiter or a lone number: a row cut where the capture began.
pub(super) fn is_cut_row(line: &str, shape: Shape) -> bool {
    row_shape(line)
        .is_some_and(|s| s.fields != shape.fields && (s.delimiter == shape.delimiter || s.fields == 1))
}

/// Where the table starts, once a preamble and cut rows are passed.
#[derive(Debug, Default)]
pub(super) struct Settled {
    /// The line read ahead that is the header or first row (`None`: the
    /// first line read before, as it was).
    pub first: Option<usize>,
    /// The preamble's lines.
    pub preamble: Vec<u64>,
    /// Its first line's text.
    pub preamble_text: String,
    /// The rows cut short: line, fields.
    pub cut_rows: Vec<(u64, usize)>,
    /// The rows' width.
    pub fields: usize,
    /// Comment lines passed on the way: text without `#`, line.
    pub comments: Vec<(String, u64)>,
}

/// Passes the preamble and cut rows at the start of `first` (line
/// `first_line`) and the lines read ahead after it.
pub(super) fn settle(first: &str, first_line: u64, ahead: &Ahead) -> Settled {
    let texts: Vec<Option<&str>> = std::iter::once(Some(first))
        .chain(ahead.lines.iter().map(|l| l.text.as_deref()))
        .collect();
    let Some(shape) = common_shape(texts.iter().map_while(|t| *t)) else {
        return Settled::default();
    };
    let mut settled = Settled {
        fields: shape.fields,
        ..Settled::default()
    };
    let line_of = |i: usize| first_line + i as u64;
    let mut at = 0;
    let mut comments = Vec::new();
    // Text lines not of the table, and the comments among them.
    while let Some(Some(text)) = texts.get(at) {
        if is_skipped(text.as_bytes()) {
            if let Some(c) = text.trim_start().strip_prefix('#') {
                comments.push((c.trim().to_string(), line_of(at)));
            }
        } else if is_preamble(text, shape) {
            if settled.preamble.is_empty() {
                settled.preamble_text = text.chars().take(80).collect();
            }
            settled.preamble.push(line_of(at));
        } else {
            break;
        }
        at += 1;
    }
    // Without a header, rows of another width before the first of the
    // common width.
    let mut cut = Vec::new();
    let mut row = at;
    while let Some(Some(text)) = texts.get(row) {
        if is_skipped(text.as_bytes()) {
            row += 1;
        } else if is_cut_row(text, shape) {
            cut.push((line_of(row), row_shape(text).map_or(0, |s| s.fields)));
            row += 1;
        } else {
            break;
        }
    }
    let first_row = texts
        .get(row)
        .copied()
        .flatten()
        .and_then(row_shape)
        .is_some_and(|s| s == shape);
    if first_row && !cut.is_empty() {
        at = row;
        settled.cut_rows = cut;
    }
    match texts.get(at) {
        Some(Some(_)) if at > 0 => {
            settled.first = Some(at - 1);
            settled.comments = comments;
            settled
        }
        // Nothing passed, or nothing readable after it: as it was.
        _ => Settled::default(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const COMMA7: Shape = Shape {
        delimiter: Delimiter::Comma,
        fields: 7,
    };

    #[test]
    fn the_rows_most_common_width_wins() {
        let lines = [
            "banner line",
            "0,1,2,3,4,5",
            "1,2,3,4,5,6,7",
            "# c",
            "1,2,3,4,5,6,7",
        ];
        assert_eq!(common_shape(lines.into_iter()), Some(COMMA7));
        assert_eq!(common_shape(["a b", "x"].into_iter()), None);
        // Equally common: the first seen.
        let two = Shape {
            delimiter: Delimiter::Comma,
            fields: 2,
        };
        assert_eq!(common_shape(["1,2", "3"].into_iter()), Some(two));
    }

    #[test]
    fn banners_are_preamble_and_headers_are_not() {
        let banner = "=~=~=~=~=~=~=~=~=~=~=~= PuTTY log 2026.05.08 15:02:51 =~=~=~=~=~=~=~=~=~=~=~=";
        assert!(is_preamble(banner, COMMA7));
        assert!(is_preamble("BMI270 Chip ID Detected: 0x24", COMMA7));
        assert!(!is_preamble("t,ax,ay,az,gx,gy,gz", COMMA7));
        // A header of another width is still a header: its count is an error.
        assert!(!is_preamble("t,ax,ay", COMMA7));
        assert!(!is_preamble("1,2,3", COMMA7));
        let ws3 = Shape {
            delimiter: Delimiter::Whitespace,
            fields: 3,
        };
        assert!(!is_preamble("time gx gy", ws3));
        assert!(is_preamble("Resetting sensor...", ws3));
    }

    #[test]
    fn a_short_row_of_the_same_delimiter_is_cut() {
        assert!(is_cut_row("0,0.003,-0.032,0.73,0.12,-1.10", COMMA7));
        assert!(is_cut_row("-1.10", COMMA7));
        assert!(!is_cut_row("1,2,3,4,5,6,7", COMMA7));
        assert!(!is_cut_row("a,b", COMMA7));
    }
}
