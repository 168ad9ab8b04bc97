//! The first stage of reading a log: its metadata, what each column holds
//! and in what unit, and which column is the time. Everything here comes
//! from the lines before the first row, so a bad unit or a missing column
//! is refused before the body is read.

use super::columns::{ColumnKind, classify_with_sources, names_column};
use super::reader::{HOST_TIME_COLUMN, RecordingOptions, parse_metadata};
use super::writer::KEY_RATE;
use crate::error::{ReadError, ReadErrorKind};
use crate::header::split_name_unit;
use crate::names::{is_time_name, quantity_of_name};
use crate::read_report::{FileFormat, Problem, ProblemKind};
use crate::recording::Metadata;
use crate::setting::{Setting, Value};
use crate::table::TableReader;
use crate::units::{Quantity, UnitSource};

/// What the header and the metadata say about a log's columns.
pub(super) struct Layout {
    pub meta: Metadata,
    /// The column names as the file writes them.
    pub headers: Vec<String>,
    /// What each column holds, its unit resolved (given, written or assumed).
    pub kinds: Vec<ColumnKind>,
    /// The time column, if any.
    pub time_index: Option<usize>,
    /// What the options changed against the file: a unit given over the
    /// header's, a factor.
    pub notes: Vec<String>,
}

impl Layout {
    /// The metadata and header of `reader`, with the units `opts` gives.
    pub fn read(reader: &TableReader, opts: &RecordingOptions) -> Result<Layout, ReadError> {
        let path = reader.path();
        let mut meta = parse_metadata(reader.comments());
        meta.source = Some(path.to_path_buf());
        let headers: Vec<String> = reader.names().to_vec();
        let from_meta = metadata_units(&meta);
        let mut kinds: Vec<ColumnKind> = headers
            .iter()
            .map(|h| classify_with_sources(h, &opts.units, &from_meta))
            .collect();
        check_units(reader, opts, &headers, &kinds)?;
        let mut notes = overridden_units(opts, &headers, &kinds);
        notes.extend(scale_columns(reader, opts, &headers, &mut kinds)?);
        let time_index = match &opts.time_column {
            Some(name) => Some(
                kinds
                    .iter()
                    .position(|k| k.name.eq_ignore_ascii_case(name))
                    .map_or_else(|| reader.column_index(name), Ok)?,
            ),
            None => (0..headers.len()).find(|&i| is_time_header(&kinds[i], &headers[i])),
        };
        Ok(Layout {
            meta,
            headers,
            kinds,
            time_index,
            notes,
        })
    }
}

/// The format of a file with this metadata and these headers: imutherm's
/// log says so in its `# format:` line; the thesis's log has its own
/// header (its `mpu_gyro_` columns).
pub(super) fn detected_format(meta: &Metadata, headers: &[String]) -> FileFormat {
    if meta.get("format").is_some_and(|f| f.starts_with("imutherm-log")) {
        FileFormat::ImuthermLog
    } else if headers.iter().any(|h| h.starts_with("mpu_gyro_")) {
        FileFormat::ThesisLog
    } else {
        FileFormat::Columns
    }
}

/// Refuses a unit given for a column that is not there (a typo, not a
/// no-op), and a unit imutherm cannot read on a column it knows the meaning
/// of (which would otherwise leave the column out of every analysis in
/// silence).
fn check_units(
    reader: &TableReader,
    opts: &RecordingOptions,
    headers: &[String],
    kinds: &[ColumnKind],
) -> Result<(), ReadError> {
    let path = reader.path();
    if let Some(o) = opts.units.iter().find(|o| {
        !headers
            .iter()
            .zip(kinds)
            .any(|(h, k)| names_column(&o.column, h, &k.name))
    }) {
        return Err(ReadError::new(
            path,
            ReadErrorKind::NoSuchColumn {
                wanted: format!("{} (named by {})", o.column, Setting::UnitOverride),
                available: headers.join(", "),
            },
        ));
    }
    if let Some((i, k)) = kinds.iter().enumerate().find(|(i, k)| {
        k.unknown_unit.is_some() && quantity_of_name(split_name_unit(&headers[*i]).0).is_some()
    }) {
        return Err(ReadError::new(
            path,
            ReadErrorKind::UnknownUnit {
                column: headers[i].clone(),
                unit: k.unknown_unit.clone().unwrap_or_default(),
            },
        )
        .at(1, Some(i + 1)));
    }
    Ok(())
}

/// A note for each column whose header writes a unit that a unit given
/// replaces by another: the values are read in the given one, and both
/// are said.
fn overridden_units(opts: &RecordingOptions, headers: &[String], kinds: &[ColumnKind]) -> Vec<String> {
    let mut notes = Vec::new();
    for (h, k) in headers.iter().zip(kinds) {
        let Some(o) = opts.units.iter().find(|o| names_column(&o.column, h, &k.name)) else {
            continue;
        };
        let written = classify_with_sources(h, &[], &[]);
        if written.unit_source == UnitSource::Header && written.unit != k.unit {
            notes.push(format!(
                "column '{h}': its header says {}, {} reads it as {} instead (×{} against the header)",
                header_unit(h),
                Setting::UnitOverride.given(Value::text(format!("{}={}", o.column, o.unit_text))),
                o.unit_text,
                super::reader::round_rate(k.unit.scale / written.unit.scale),
            ));
        }
    }
    notes
}

/// The unit a header writes, as written.
fn header_unit(header: &str) -> String {
    let (bare, unit) = split_name_unit(header);
    if unit.is_empty() {
        crate::header::split_unit_suffix(bare).map_or_else(String::new, |(_, u)| u.to_string())
    } else {
        unit.to_string()
    }
}

/// Multiplies the conversion of each column a scale names by its factor,
/// with a note each; a scale naming no column is refused, as a unit is.
fn scale_columns(
    reader: &TableReader,
    opts: &RecordingOptions,
    headers: &[String],
    kinds: &mut [ColumnKind],
) -> Result<Vec<String>, ReadError> {
    let mut notes = Vec::new();
    for s in &opts.scales {
        let mut named = false;
        for (h, k) in headers.iter().zip(kinds.iter_mut()) {
            if names_column(&s.column, h, &k.name) {
                k.unit.scale *= s.factor;
                named = true;
                notes.push(format!(
                    "column '{h}': its values are multiplied by {} ({}) before their unit converts them",
                    s.factor,
                    Setting::ColumnScale.given(Value::text(format!("{}={}", s.column, s.factor))),
                ));
            }
        }
        if !named {
            return Err(ReadError::new(
                reader.path(),
                ReadErrorKind::NoSuchColumn {
                    wanted: format!("{} (named by {})", s.column, Setting::ColumnScale),
                    available: headers.join(", "),
                },
            ));
        }
    }
    Ok(notes)
}

/// A `# sample_rate_hz:` that is not a positive number of Hz, as a problem
/// naming its line: ignored, it would otherwise leave the rate to a
/// fallback without a word.
pub(super) fn bad_metadata_rate(reader: &TableReader, file_rate: Option<f64>) -> Option<Problem> {
    if file_rate.is_some() {
        return None;
    }
    // The last line with the key is the one parse_metadata kept.
    let (i, value) = reader.comments().iter().enumerate().rev().find_map(|(i, c)| {
        let (k, v) = c.split_once(':')?;
        (k.trim() == KEY_RATE).then(|| (i, v.trim()))
    })?;
    Some(Problem {
        kind: ProblemKind::BadMetadata,
        line: reader.comment_line(i),
        column: None,
        channel: None,
        count: 1,
        message: format!("'# {KEY_RATE}: {value}' is not a positive number of Hz: ignored"),
    })
}

/// Units of columns written in the metadata as `# unit.<column>: <unit>`.
fn metadata_units(meta: &Metadata) -> Vec<(String, String)> {
    meta.entries
        .iter()
        .filter_map(|(k, v)| Some((k.strip_prefix("unit.")?.to_string(), v.clone())))
        .collect()
}

fn is_time_header(kind: &ColumnKind, header: &str) -> bool {
    let (name, _) = split_name_unit(header);
    let n = name.to_ascii_lowercase();
    if n == HOST_TIME_COLUMN {
        return false;
    }
    kind.quantity == Quantity::Time || is_time_name(&kind.name)
}
