//! What the first lines tell: the comment lines before the first row, the
//! header or the first row itself, the delimiter, and whether a line is
//! text, a comment, or ends in a carriage return alone.

use std::io::BufRead;
use std::path::Path;

use super::input::{LineRead, read_line_bounded};
use super::{MAX_HEADER_COMMENTS, MAX_LINE_BYTES};
use crate::error::{ReadError, ReadErrorKind};

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
    pub(super) fn detect(line: &str) -> Delimiter {
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
    pub(super) fn split_into<'a>(self, line: &'a [u8], fields: &mut Vec<&'a [u8]>) {
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
pub(super) fn parse_number(field: &[u8]) -> Option<f64> {
    crate::decimal::parse_field(field)
}

/// Whether a carriage return stands inside `line`, before other text: the
/// mark of lines that end in CR alone (a CR among trailing blanks is only
/// untidy).
pub(super) fn has_inner_cr(line: &[u8]) -> bool {
    memchr::memchr(b'\r', line.trim_ascii_end()).is_some() && is_text(line)
}

/// Whether `bytes` are UTF-8 text, but for a character cut at their end
/// (a line cut at the length limit).
pub(super) fn is_text(bytes: &[u8]) -> bool {
    match std::str::from_utf8(bytes) {
        Ok(_) => true,
        Err(e) => e.error_len().is_none(),
    }
}

pub(super) fn is_skipped(line: &[u8]) -> bool {
    let t = line.trim_ascii_start();
    t.is_empty() || t[0] == b'#'
}

/// The lines before the body: comments, then the header or the first row.
pub(super) struct Head {
    /// The `#` comment lines, without the `#`.
    pub comments: Vec<String>,
    /// The line of each comment, 1-based.
    pub comment_lines: Vec<u64>,
    /// Lines consumed.
    pub line_no: u64,
    /// The first line that is not blank or a comment.
    pub first: String,
    /// Whether that line ended with a newline.
    pub terminated: bool,
}

/// Reads up to the first line that is neither blank nor a comment.
pub(super) fn read_head(input: &mut dyn BufRead, path: &Path) -> Result<Head, ReadError> {
    let io_err = |e: std::io::Error| ReadError::new(path, ReadErrorKind::Io(e));
    let mut comments = Vec::new();
    let mut comment_lines = Vec::new();
    let mut line_no = 0u64;
    let mut raw = Vec::new();
    loop {
        let read = read_line_bounded(input, &mut raw).map_err(io_err)?;
        if raw.is_empty() {
            return Err(ReadError::new(path, ReadErrorKind::NoData));
        }
        line_no += 1;
        let body = raw.strip_suffix(b"\n").unwrap_or(&raw);
        let body = body.strip_suffix(b"\r").unwrap_or(body);
        if !is_text(body) {
            return Err(ReadError::new(path, ReadErrorKind::NotText).at(line_no, None));
        }
        // A carriage return inside the line: lines end in CR alone (old
        // Mac OS), which would read as one endless line.
        if has_inner_cr(body) {
            return Err(ReadError::new(path, ReadErrorKind::CrLineEndings).at(line_no, None));
        }
        if read == LineRead::TooLong {
            return Err(ReadError::new(
                path,
                ReadErrorKind::LineTooLong {
                    limit: MAX_LINE_BYTES,
                },
            )
            .at(line_no, None));
        }
        let text = std::str::from_utf8(body)
            .map_err(|_| ReadError::new(path, ReadErrorKind::NotText).at(line_no, None))?
            .trim_start_matches('\u{feff}');
        if is_skipped(text.as_bytes()) {
            if let Some(c) = text.trim_start().strip_prefix('#') {
                if comments.len() == MAX_HEADER_COMMENTS {
                    return Err(ReadError::new(
                        path,
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
        return Ok(Head {
            comments,
            comment_lines,
            line_no,
            first: text.to_string(),
            terminated: read == LineRead::Whole,
        });
    }
}

/// The columns a first line gives: the names, whether it is a header, and
/// the delimiter. A line of numbers is the first row, its columns named
/// `col1`, `col2`, …
pub(super) fn columns_of(
    first: &str,
    line_no: u64,
    path: &Path,
) -> Result<(Vec<String>, bool, Delimiter), ReadError> {
    let delimiter = Delimiter::detect(first);
    let mut fields = Vec::new();
    delimiter.split_into(first.as_bytes(), &mut fields);
    if fields.iter().all(|f| parse_number(f).is_some()) {
        let names = (1..=fields.len()).map(|i| format!("col{i}")).collect();
        return Ok((names, false, delimiter));
    }
    let names: Vec<String> = fields
        .iter()
        .map(|f| crate::header::clean_cell(&String::from_utf8_lossy(f)).to_string())
        .collect();
    // Two columns of one name: whichever a name picks, the other is lost
    // or mistaken for it. A map keeps a wide header linear.
    let mut seen = std::collections::HashMap::with_capacity(names.len());
    for (i, n) in names.iter().enumerate() {
        if let Some(&first) = seen.get(n.as_str()) {
            return Err(ReadError::new(
                path,
                ReadErrorKind::DuplicateColumn {
                    name: n.clone(),
                    first: first + 1,
                    second: i + 1,
                },
            )
            .at(line_no, None));
        }
        seen.insert(n.as_str(), i);
    }
    Ok((names, true, delimiter))
}
