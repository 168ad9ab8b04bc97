//! The time stage of reading a log: the time column's unit (given, written
//! or guessed), a wrapping counter unwrapped, a clock running backwards
//! refused, the rate, and the samples placed on the grid of their stamps
//! with the gaps, duplicates and steps back reported.

use std::path::Path;

use super::columns::ColumnKind;
use super::gaps::RowLines;
use super::reader::{RecordingOptions, round_rate};
use crate::error::{ReadError, ReadErrorKind};
use crate::read_report::{Problem, ProblemKind, ReadReport};
use crate::recording::Channel;
use crate::setting::{Setting, Value};
use crate::timing::{Timing, analyze_timestamps, regularize_gapped};
use crate::units::{Quantity, UnitSource, parse_unit};

/// The time column at index `ti` of the file: its raw values, its kind and
/// its header.
pub(super) struct TimeColumn<'a> {
    pub index: usize,
    pub raw: Vec<f64>,
    pub kind: &'a ColumnKind,
    pub header: &'a str,
}

/// Places `channels` on the time of `time`, sets the rate when none was
/// given, and returns the timestamps in seconds from the first (from the
/// first stamp for Unix epoch stamps).
pub(super) fn place_on_time(
    path: &Path,
    time: TimeColumn,
    opts: &RecordingOptions,
    rows: &RowLines,
    channels: &mut [Channel],
    rate_hz: &mut Option<f64>,
    report: &mut ReadReport,
) -> Result<Vec<f64>, ReadError> {
    let scale = time_scale(&time, opts, report);
    let TimeColumn { index, header, .. } = time;
    let mut raw = time.raw;
    note_wraps(&mut raw, scale, header, rows, report);
    refuse_backwards(path, &raw, index, header, rows)?;
    // Epoch stamps (1.7e18 ns) are taken from the first one, so that
    // the steps keep their digits.
    let t0 = raw.iter().copied().find(|v| v.is_finite()).unwrap_or(0.0);
    let epoch = t0.abs() * scale > 1e8;
    let origin_raw = if epoch { t0 } else { 0.0 };
    let mut t: Vec<f64> = raw.iter().map(|v| (v - origin_raw) * scale).collect();
    place_lone_missing_stamps(&mut t, index, rows, report);
    if let Some(timing) = analyze_timestamps(&t) {
        let rate = *rate_hz.get_or_insert(timing.rate_hz);
        if (rate / timing.rate_hz - 1.0).abs() > 1e-3 {
            report.notes.push(format!(
                "the time column's clock runs at {} Hz, not the {} Hz given; samples are placed \
                 by their order and gaps sized on {} Hz",
                round_rate(timing.rate_hz),
                round_rate(rate),
                round_rate(rate)
            ));
        }
        let cols: Vec<Vec<f64>> = channels.iter_mut().map(|c| std::mem::take(&mut c.data)).collect();
        let factor = timing.grid_factor(opts.max_grid_factor, rate);
        let gap_above = timing.gap_above_for(rate);
        let Some((regular, dropped)) = regularize_gapped(&t, rate, gap_above, &cols, factor) else {
            return Err(grid_too_large(path, &t, index, rate, factor));
        };
        let grid = regular.first().map_or(0, Vec::len);
        report.notes.extend(timing.pattern_note(t.len(), grid));
        report_timing(&timing, &dropped, index, rows, report);
        for (c, d) in channels.iter_mut().zip(regular) {
            c.data = d;
        }
        report.dropped_samples = dropped.len();
        report.timing = Some(timing);
    }
    Ok(t)
}

/// Largest departure, as a share of two periods, of the step across a row
/// without a stamp for its neighbours to place it halfway.
const LONE_STAMP_TOLERANCE: f64 = 0.1;

/// Places each row whose stamp is missing (NaN, or unreadable) halfway
/// between its neighbours where they stand two of the clock's median steps
/// apart: its slot is known, and its samples are kept there rather than
/// counted as a gap before the next line. Each is reported at its line, by
/// its cause; a row its neighbours do not fix keeps the slot after the
/// previous one, as the grid gives it.
fn place_lone_missing_stamps(t: &mut [f64], ti: usize, rows: &RowLines, report: &mut ReadReport) {
    if t.iter().all(|v| v.is_finite()) {
        return;
    }
    let Some(median) = crate::timing::median_step(t) else {
        return;
    };
    for k in 0..t.len() {
        if t[k].is_finite() {
            continue;
        }
        let (before, after) = (k.checked_sub(1).map(|j| t[j]), t.get(k + 1).copied());
        let placed = match (before, after) {
            (Some(a), Some(b)) if a.is_finite() && b.is_finite() => {
                ((b - a) / (2.0 * median) - 1.0).abs() <= LONE_STAMP_TOLERANCE
            }
            _ => false,
        };
        let message = if placed {
            let (a, b) = (t[k - 1], t[k + 1]);
            t[k] = a + (b - a) / 2.0;
            format!(
                "the time is not a number; the row is placed halfway between its neighbours (t = {:.6} s) and its samples kept",
                t[k]
            )
        } else {
            "the time is not a number and its neighbours do not place it: the row takes the slot after the previous one".to_string()
        };
        report.push(Problem {
            kind: ProblemKind::NoStamp,
            line: Some(rows.line(k)),
            column: Some(ti + 1),
            channel: None,
            count: 1,
            message,
        });
    }
}

/// Seconds per unit of the time column: the header's unit, else the one
/// given, else a guess the report's notes name.
fn time_scale(time: &TimeColumn, opts: &RecordingOptions, report: &mut ReadReport) -> f64 {
    let header_unit = Some(time.kind.unit)
        .filter(|u| u.quantity == Quantity::Time && time.kind.unit_source != UnitSource::Assumed);
    let given = opts
        .time_unit
        .as_deref()
        .and_then(parse_unit)
        .filter(|u| u.quantity == Quantity::Time);
    let (scale, origin) = match (header_unit, given) {
        (Some(u), _) => (u.scale, None),
        (None, Some(u)) => (u.scale, None),
        (None, None) => {
            let (scale, why) = guess_time_unit(&time.raw);
            (scale, Some(why))
        }
    };
    if let Some(why) = origin {
        report.notes.push(format!(
            "time column '{}': unit {}, {why}; give {} if that is wrong",
            time.header,
            match scale {
                1.0 => "s",
                1e-3 => "ms",
                1e-6 => "us",
                _ => "ns",
            },
            Setting::TimeUnit
        ));
    }
    scale
}

/// The unit of a time column whose header and flags name none, and why:
/// Unix epoch stamps by their magnitude (s ≈ 1.7e9, ms ≈ 1.7e12, µs ≈
/// 1.7e15, ns ≈ 1.7e18), others by the median step, taking the unit that
/// makes it an IMU's: steps below 2 in seconds, whole-numbered steps and
/// steps up to 2000 in milliseconds, up to 1e5 in microseconds (10 Hz and
/// faster), beyond in nanoseconds.
fn guess_time_unit(raw: &[f64]) -> (f64, &'static str) {
    let first = raw.iter().copied().find(|v| v.is_finite()).unwrap_or(0.0).abs();
    for (lo, scale) in [(1e9, 1.0), (1e12, 1e-3), (1e15, 1e-6), (1e18, 1e-9)] {
        if (lo..lo * 10.0).contains(&first) {
            return (
                scale,
                "guessed from the magnitude of the stamps (Unix epoch time)",
            );
        }
    }
    let mut steps: Vec<f64> = raw.windows(2).map(|w| w[1] - w[0]).filter(|d| *d > 0.0).collect();
    steps.sort_unstable_by(f64::total_cmp);
    let Some(&m) = steps.get(steps.len() / 2) else {
        return (1.0, "guessed (too few steps to tell)");
    };
    let whole = raw.iter().take(1000).all(|v| !v.is_finite() || v.fract() == 0.0);
    let why = "guessed from the median step";
    if m < 2.0 && !whole {
        (1.0, why)
    } else if m < 2000.0 {
        (1e-3, why)
    } else if m < 1e5 {
        (1e-6, why)
    } else {
        (1e-9, why)
    }
}

/// Unwraps a 32-bit counter in place, noting where it wrapped.
fn note_wraps(raw: &mut [f64], scale: f64, header: &str, rows: &RowLines, report: &mut ReadReport) {
    let wraps = crate::timing::unwrap_u32(raw);
    if let Some(&first) = wraps.first() {
        report.notes.push(format!(
            "time column '{}': a 32-bit counter wrapping every 2^32 ticks ({:.3} s, {:.1} min), at line{} {}{}: unwrapped",
            header,
            crate::timing::U32_WRAP * scale,
            crate::timing::U32_WRAP * scale / 60.0,
            if wraps.len() == 1 { "" } else { "s" },
            rows.line(first),
            wraps
                .iter()
                .skip(1)
                .take(9)
                .map(|&r| format!(", {}", rows.line(r)))
                .collect::<String>()
        ));
    }
}

/// A clock that mostly runs backwards is no clock to place samples on
/// (rows in reverse order, a countdown): refused at its first step back,
/// not read as a pile of out-of-order rows.
fn refuse_backwards(
    path: &Path,
    raw: &[f64],
    ti: usize,
    header: &str,
    rows: &RowLines,
) -> Result<(), ReadError> {
    let (back, forth) = raw.windows(2).fold((0usize, 0usize), |(b, f), w| {
        (b + usize::from(w[1] < w[0]), f + usize::from(w[1] > w[0]))
    });
    if back > forth
        && let Some(row) = raw.windows(2).position(|w| w[1] < w[0]).map(|k| k + 1)
    {
        return Err(ReadError::new(
            path,
            ReadErrorKind::TimeColumn(format!(
                "'{}' runs backwards: {back} of its {} steps go back, from this line on; \
                 sort the rows by time, or name the true time column with {}",
                header,
                back + forth,
                Setting::TimeColumn
            )),
        )
        .at(rows.line(row), Some(ti + 1)));
    }
    Ok(())
}

/// The refusal of a time column whose span would make a grid of more than
/// `factor` times its samples.
fn grid_too_large(path: &Path, t: &[f64], ti: usize, rate: f64, factor: usize) -> ReadError {
    let finite = || t.iter().copied().filter(|v| v.is_finite());
    let span = finite().fold(f64::NEG_INFINITY, f64::max) - finite().fold(f64::INFINITY, f64::min);
    let needed = (span * rate / t.len() as f64).ceil() + 1.0;
    ReadError::new(
        path,
        ReadErrorKind::TimeColumn(format!(
            "column {} spans {span:.6e} s, more than {factor} times its {} samples at {rate} Hz: \
             check the time unit ({}) or the values; a duty-cycled log is read \
             with its gaps by raising the limit ({})",
            ti + 1,
            t.len(),
            Setting::TimeUnit,
            Setting::MaxGridFactor.given(Value::number(needed))
        )),
    )
}

/// Reports the time gaps, duplicate stamps and steps back the timing
/// found, each at its line.
fn report_timing(timing: &Timing, dropped: &[usize], ti: usize, rows: &RowLines, report: &mut ReadReport) {
    for &(row, missing) in &timing.gaps {
        report.push(Problem {
            kind: ProblemKind::TimeGap,
            line: Some(rows.line(row)),
            column: Some(ti + 1),
            channel: None,
            count: missing,
            message: format!(
                "{missing} missing sample{} before this line (a step in time, filled as a gap)",
                if missing == 1 { "" } else { "s" }
            ),
        });
    }
    let action = |row: usize| {
        if dropped.binary_search(&row).is_ok() {
            "the whole row repeats the previous one: dropped"
        } else {
            "sample kept, in the slot after the previous one"
        }
    };
    for (rows_of, kind, what) in [
        (
            &timing.duplicates,
            ProblemKind::DuplicateTime,
            "duplicate timestamp",
        ),
        (
            &timing.backwards,
            ProblemKind::BackwardsTime,
            "timestamp earlier than the previous one",
        ),
    ] {
        for &row in rows_of {
            report.push(Problem {
                kind,
                line: Some(rows.line(row)),
                column: Some(ti + 1),
                channel: None,
                count: 1,
                message: format!("{what} ({})", action(row)),
            });
        }
    }
}
