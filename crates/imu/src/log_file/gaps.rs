//! The channels stage of reading a log: each column's gaps reported as
//! runs (NaN where the logger lost samples, infinities made gaps), then its
//! values converted to SI.

use std::collections::HashSet;

use rayon::prelude::*;

use super::columns::ColumnKind;
use crate::read_report::{Problem, ProblemKind, ReadReport};
use crate::recording::Channel;
use crate::table::Table;

/// The file line of each row, and the rows already reported as bad lines.
pub(super) struct RowLines<'a> {
    table: &'a Table,
    bad_lines: HashSet<u64>,
}

impl<'a> RowLines<'a> {
    pub fn new(table: &'a Table) -> Self {
        let bad_lines = table.problems.iter().filter_map(|p| p.line).collect();
        RowLines { table, bad_lines }
    }

    /// The file line of `row`.
    pub fn line(&self, row: usize) -> u64 {
        self.table.line_of_row(row)
    }

    /// Rows skipped as bad are reported as that already: a NaN run is
    /// reported from its first row that is not one of them.
    fn beyond_bad(&self, start: usize, count: usize) -> Option<(usize, usize)> {
        let first = (start..start + count)
            .find(|&r| self.bad_lines.is_empty() || !self.bad_lines.contains(&self.line(r)))?;
        Some((first, count - (first - start)))
    }
}

/// Reports the rows that are NaN in every column once for the row range,
/// rather than once per channel; returns them as (first row, rows).
pub(super) fn report_whole_row_gaps(
    columns: &[(usize, Vec<f64>)],
    rows: &RowLines,
    report: &mut ReadReport,
) -> Vec<(usize, usize)> {
    let whole_rows = whole_row_gaps(columns);
    for &(start, count) in &whole_rows {
        let Some((start, count)) = rows.beyond_bad(start, count) else {
            continue;
        };
        report.push(Problem {
            kind: ProblemKind::NanRun,
            line: Some(rows.line(start)),
            column: None,
            channel: None,
            count,
            message: format!(
                "{count} row{} of NaN in every channel from here (a gap)",
                if count == 1 { "" } else { "s" }
            ),
        });
    }
    whole_rows
}

/// Runs of rows that are NaN in every column (a logger's gaps), as
/// (first row, rows). Empty with fewer than two columns, or when a column
/// has no NaN.
fn whole_row_gaps(columns: &[(usize, Vec<f64>)]) -> Vec<(usize, usize)> {
    if columns.len() < 2 || columns.iter().any(|(_, c)| !c.par_iter().any(|v| v.is_nan())) {
        return Vec::new();
    }
    let rows = columns.iter().map(|(_, c)| c.len()).min().unwrap_or(0);
    let all_nan = |r: usize| columns.iter().all(|(_, c)| c[r].is_nan());
    let mut runs = Vec::new();
    let mut r = 0;
    while r < rows {
        if all_nan(r) {
            let start = r;
            while r < rows && all_nan(r) {
                r += 1;
            }
            runs.push((start, r - start));
        } else {
            r += 1;
        }
    }
    runs
}

/// The channels of `columns` (each with its index among the headers), in
/// SI, their gaps reported except the whole-row ones already reported.
pub(super) fn into_channels(
    columns: Vec<(usize, Vec<f64>)>,
    kinds: &[ColumnKind],
    headers: &[String],
    whole_rows: &[(usize, usize)],
    rows: &RowLines,
    report: &mut ReadReport,
) -> Vec<Channel> {
    let is_whole_row = |start: usize, count: usize| whole_rows.binary_search(&(start, count)).is_ok();
    let mut channels = Vec::with_capacity(columns.len());
    for (i, mut data) in columns {
        let kind = &kinds[i];
        // Most recordings have no gap, which a parallel look tells at once.
        let all_finite = data.par_chunks(1 << 16).all(|c| c.iter().all(|v| v.is_finite()));
        let mut row = if all_finite { data.len() } else { 0 };
        while row < data.len() {
            if data[row].is_finite() {
                row += 1;
                continue;
            }
            let infinite = data[row].is_infinite();
            let start = row;
            while row < data.len() && !data[row].is_finite() && data[row].is_infinite() == infinite {
                if infinite {
                    data[row] = f64::NAN;
                }
                row += 1;
            }
            let count = row - start;
            if !infinite && is_whole_row(start, count) {
                continue;
            }
            let Some((start, count)) = rows.beyond_bad(start, count) else {
                continue;
            };
            report.push(Problem {
                kind: if infinite {
                    ProblemKind::Infinite
                } else {
                    ProblemKind::NanRun
                },
                line: Some(rows.line(start)),
                column: Some(i + 1),
                channel: Some(kind.name.clone()),
                count,
                message: format!(
                    "{}: {count} {} sample{} from here{}",
                    kind.name,
                    if infinite { "infinite" } else { "NaN" },
                    if count == 1 { "" } else { "s" },
                    if infinite { ", treated as gaps" } else { " (gaps)" }
                ),
            });
        }
        if !kind.unit.is_identity() {
            data.iter_mut().for_each(|v| *v = kind.unit.to_si(*v));
        }
        channels.push(Channel {
            name: kind.name.clone(),
            source_name: headers[i].clone(),
            quantity: kind.quantity,
            axis: kind.axis,
            unit: kind.unit_label.clone(),
            unit_source: kind.unit_source,
            data,
        });
    }
    channels
}
