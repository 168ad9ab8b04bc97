//! Per-sample timestamps: the rate of the clock that made them, its jitter,
//! and everything wrong with them (gaps, duplicates, steps backwards, a
//! counter that wraps).
//!
//! The rate is the clock's, not the median step's: a chip running 0.3 %
//! fast and stamped in whole milliseconds steps 5 ms almost always and 4 ms
//! now and then, so the median says 200 Hz while the samples come at
//! 200.6 Hz. The period is the mean step over the gap-free stretches (runs
//! of steps within (0.5, 1.5) periods): every real step counts, 4.5 ms
//! steps among 5 ms ones included, and a stamp leaves the clock only where
//! its step leaves that band, against a clock the other stamps hold. The
//! jitter is the stamps' scatter about that clock, all of them. Samples are
//! then placed one slot after another, a step of more than 1.5 periods
//! opening a gap of the size the clock implies: no real sample is dropped
//! and no gap is invented, whatever the stamps' jitter or rounding.
//!
//! Where the steps cluster on several values no one clock makes (4.5, 5
//! and 9 ms: a publisher, not a sensor's clock; see
//! [`crate::clock_pattern`]), the rate is the mean of those steps, and a
//! step is a gap only past [`GAP_FACTOR`] times the longest of them: no
//! sample is counted missing against a clock the steps do not support. A
//! regular duty cycle (bursts) is recognised from its gaps, and its grid
//! may be as large as its pattern asks.

use crate::clock_pattern::{Pattern, and_list, ms};

/// What the timestamps say.
#[derive(Debug, Clone, PartialEq)]
pub struct Timing {
    /// 1 / the mean step over the gap-free stretches, Hz.
    pub rate_hz: f64,
    /// Standard deviation of the stamps of the gap-free stretches about
    /// the clock (a line of the clock's period through each stretch), s.
    pub jitter_s: f64,
    /// (row, missing samples) for every step longer than 1.5 periods.
    pub gaps: Vec<(usize, usize)>,
    /// Rows whose timestamp repeats the previous one.
    pub duplicates: Vec<usize>,
    /// Rows whose timestamp is earlier than the latest one before.
    pub backwards: Vec<usize>,
    /// The median step between stamps, s (what a rate read off the steps
    /// would have been).
    pub median_step_s: f64,
    /// Stamps in the gap-free stretches, which the clock is the mean step of.
    pub fitted_samples: usize,
    /// A step longer than this is a gap, s: [`GAP_FACTOR`] periods, or
    /// [`GAP_FACTOR`] times the longest step of an irregular publisher.
    pub gap_above_s: f64,
    /// From the first finite stamp to the last, s.
    pub span_s: f64,
    /// An irregular publisher or a duty cycle, when the stamps show one.
    pub pattern: Option<Pattern>,
    /// The forward steps between stamps.
    pub steps_read: usize,
}

impl Timing {
    /// The step past which a gap opens on a clock of `rate_hz`: this
    /// timing's own where the rate is its own, else [`GAP_FACTOR`] periods.
    pub fn gap_above_for(&self, rate_hz: f64) -> f64 {
        if (rate_hz / self.rate_hz - 1.0).abs() <= 1e-9 {
            self.gap_above_s
        } else {
            GAP_FACTOR / rate_hz
        }
    }

    /// The largest grid the samples may take, as a multiple of their count:
    /// the one `given`, else what a duty cycle asks for, at least
    /// [`MAX_GRID_FACTOR`].
    pub fn grid_factor(&self, given: Option<usize>, rate_hz: f64) -> usize {
        given.unwrap_or_else(|| {
            let own = self.pattern.as_ref().and_then(|p| p.grid_factor(rate_hz));
            own.unwrap_or(0).max(MAX_GRID_FACTOR)
        })
    }

    /// What the pattern of the stamps is, with its figures, for the
    /// report's notes; `grid` is the grid's length once placed.
    pub fn pattern_note(&self, samples: usize, grid: usize) -> Option<String> {
        match self.pattern.as_ref()? {
            Pattern::Irregular { steps } => {
                let total = self.steps_read;
                let values: Vec<String> = steps.iter().map(|s| ms(s.step_s)).collect();
                let counts: Vec<String> = steps.iter().map(|s| s.count.to_string()).collect();
                Some(format!(
                    "published irregularly: steps of {} ms ({} of the {total} steps), which no one \
                     clock makes: the samples are placed one after another at their mean step \
                     ({:.4} ms, {} Hz), a sample is counted missing only after a step of more \
                     than {} ms ({GAP_FACTOR} times the longest), and the duration is the \
                     stamps' span ({:.3} s)",
                    and_list(&values),
                    and_list(&counts),
                    1e3 / self.rate_hz,
                    crate::log_file::round_rate(self.rate_hz),
                    ms(self.gap_above_s),
                    self.span_s
                ))
            }
            Pattern::Bursts {
                burst_s,
                period_s,
                bursts,
            } => Some(format!(
                "bursts of {burst_s:.1} s every {period_s:.0} s, {bursts} bursts (a duty cycle): \
                 read with the {} pauses between them as gaps, a grid of {grid} slots for \
                 {samples} samples ({:.1} times)",
                bursts - 1,
                grid as f64 / samples.max(1) as f64
            )),
        }
    }
}

/// A step longer than this many periods is a gap.
pub const GAP_FACTOR: f64 = 1.5;

/// Calls `run(from, to)` for each gap-free stretch of rows `from..to`: at
/// least two rows, every step within the open band `(lo, hi)` (for a
/// clock, (0.5, [`GAP_FACTOR`]) periods).
fn for_each_run_within(t: &[f64], (lo, hi): (f64, f64), mut run: impl FnMut(usize, usize)) {
    let mut start = 0;
    for i in 1..=t.len() {
        let breaks = i == t.len() || {
            let d = t[i] - t[i - 1];
            !(d.is_finite() && d > lo && d < hi)
        };
        if breaks {
            if i - start >= 2 {
                run(start, i);
            }
            start = i;
        }
    }
}

/// The mean step over the gap-free stretches of `step`, and the stamps in
/// them.
fn mean_gap_free_step(t: &[f64], step: f64) -> Option<(f64, usize)> {
    mean_step_within(t, (0.5 * step, GAP_FACTOR * step))
}

/// The mean step over the stretches of steps within `band`, and the stamps
/// in them.
fn mean_step_within(t: &[f64], band: (f64, f64)) -> Option<(f64, usize)> {
    let (mut span, mut steps, mut used) = (0.0, 0usize, 0usize);
    for_each_run_within(t, band, |a, b| {
        span += t[b - 1] - t[a];
        steps += b - 1 - a;
        used += b - a;
    });
    (steps > 0 && span > 0.0).then(|| (span / steps as f64, used))
}

/// What stamps that give no clock are: of the `items` (rows, messages),
/// how many are unusable (`unusable`: NaN, or what the reader made NaN),
/// repeat the previous stamp or step back. Shared by the text and the
/// robot-log readers, so that both say it alike.
pub fn describe_stamps(t: &[f64], items: &str, unusable: &str) -> String {
    let bad = t.iter().filter(|v| !v.is_finite()).count();
    let finite: Vec<f64> = t.iter().copied().filter(|v| v.is_finite()).collect();
    let equal = finite.windows(2).filter(|w| w[1] == w[0]).count();
    let back = finite.windows(2).filter(|w| w[1] < w[0]).count();
    format!(
        "of {} {items}, {bad} {unusable}, {equal} repeat the previous stamp and {back} step back",
        t.len()
    )
}

/// The median of the finite forward steps of `t`; `None` without one.
pub fn median_step(t: &[f64]) -> Option<f64> {
    let mut dts: Vec<f64> = t
        .windows(2)
        .map(|w| w[1] - w[0])
        .filter(|d| d.is_finite() && *d > 0.0)
        .collect();
    if dts.is_empty() {
        return None;
    }
    let mid = dts.len() / 2;
    Some(*dts.select_nth_unstable_by(mid, f64::total_cmp).1)
}

/// Studies timestamps in seconds. `None` with fewer than two finite,
/// increasing timestamps (no rate can be derived).
pub fn analyze_timestamps(t: &[f64]) -> Option<Timing> {
    let median = median_step(t)?;
    // The stretches are cut on the median step first, then again on the
    // clock it gives: where the steps are mixed (5 ms and 4.5 ms), the
    // median is one of them and the clock lies between.
    let (first, _) = mean_gap_free_step(t, median)?;
    let irregular = crate::clock_pattern::irregular_steps(t);
    // An irregular publisher's steps are all its own up to the longest
    // value they cluster on: the band takes them all.
    let band = |period: f64| match &irregular {
        Some(steps) => (0.0, GAP_FACTOR * steps.last().map_or(period, |s| s.longest_s)),
        None => (0.5 * period, GAP_FACTOR * period),
    };
    let (period, fitted) = mean_step_within(t, band(first)).unwrap_or((first, 0));
    let gap_above_s = band(period).1;
    let jitter_s = {
        let (mut sum2, mut n, mut runs) = (0.0, 0usize, 0usize);
        for_each_run_within(t, band(period), |a, b| {
            let offset = (a..b).map(|k| t[k] - t[a] - (k - a) as f64 * period).sum::<f64>() / (b - a) as f64;
            for k in a..b {
                sum2 += (t[k] - t[a] - (k - a) as f64 * period - offset).powi(2);
            }
            n += b - a;
            runs += 1;
        });
        if n > runs {
            (sum2 / (n - runs) as f64).sqrt()
        } else {
            0.0
        }
    };

    let mut gaps = Vec::new();
    let mut duplicates = Vec::new();
    let mut backwards = Vec::new();
    // Steps are measured from the latest timestamp so far, so that one step
    // backwards is reported once, not again as a gap after it.
    // Rows with a stamp that is not new take the slots after the latest
    // good one (see [`regularize`]), so they fill part of a later step.
    let mut latest = t[0];
    let mut since_latest = 0usize;
    for (row, &ti) in t.iter().enumerate().skip(1) {
        let d = ti - latest;
        if ti.is_finite() && ti > latest {
            latest = ti;
        }
        if d == 0.0 {
            duplicates.push(row);
            since_latest += 1;
        } else if d < 0.0 {
            backwards.push(row);
            since_latest += 1;
        } else {
            if d > gap_above_s {
                let missing = missing_before(d, period).saturating_sub(since_latest);
                if missing > 0 {
                    gaps.push((row, missing));
                }
            }
            since_latest = 0;
        }
    }
    let finite = || t.iter().copied().filter(|v| v.is_finite());
    let span_s = finite().fold(f64::NEG_INFINITY, f64::max) - finite().fold(f64::INFINITY, f64::min);
    let steps_read = t.windows(2).filter(|w| w[1] - w[0] > 0.0).count();
    let gap_rows: Vec<usize> = gaps.iter().map(|g| g.0).collect();
    let pattern = irregular
        .map(|steps| Pattern::Irregular { steps })
        .or_else(|| crate::clock_pattern::bursts(t, &gap_rows));
    Some(Timing {
        rate_hz: 1.0 / period,
        jitter_s,
        gaps,
        duplicates,
        backwards,
        median_step_s: median,
        fitted_samples: fitted,
        gap_above_s,
        span_s,
        pattern,
        steps_read,
    })
}

/// A counter of 32 bits wraps after 2³² ticks: a `micros()` clock after
/// 4294.967296 s (71.6 min), a millisecond one after 49.7 days.
pub const U32_WRAP: f64 = 4_294_967_296.0;

/// Unwraps a time column of raw ticks that a 32-bit counter wrote: where a
/// stamp falls from the top hundredth of the counter's range to its bottom
/// hundredth, 2³² ticks are added from there on. Returns the rows where it
/// wrapped; none (and `raw` untouched) unless every finite stamp is a whole
/// number within [0, 2³²).
pub fn unwrap_u32(raw: &mut [f64]) -> Vec<usize> {
    let finite = || raw.iter().copied().filter(|v| v.is_finite());
    if !finite().all(|v| (0.0..U32_WRAP).contains(&v) && v.fract() == 0.0) {
        return Vec::new();
    }
    let near = U32_WRAP / 100.0;
    let mut wraps = Vec::new();
    let mut offset = 0.0;
    let mut prev: Option<f64> = None;
    for (row, v) in raw.iter_mut().enumerate() {
        if !v.is_finite() {
            continue;
        }
        if let Some(p) = prev
            && *v < near
            && p - offset >= U32_WRAP - near
        {
            offset += U32_WRAP;
            wraps.push(row);
        }
        *v += offset;
        prev = Some(*v);
    }
    wraps
}

/// Samples missing in a step of `d` seconds on a clock of `period`.
fn missing_before(d: f64, period: f64) -> usize {
    ((d / period).round() as usize).saturating_sub(1).max(1)
}

/// Largest grid a time column may ask for by default, as a multiple of its
/// samples: beyond it the timestamps are more likely wrong (a unit mix-up,
/// a corrupt value) than gaps, and filling the grid would only exhaust
/// memory. A duty-cycled log (5 s logged every 305 s is 61 times its
/// samples) is read by raising it ([`crate::RecordingOptions::max_grid_factor`]).
pub const MAX_GRID_FACTOR: usize = 16;

/// Places the samples of `columns` one slot after another on the clock of
/// `rate_hz`: a step of more than [`GAP_FACTOR`] periods leaves the slots
/// it spans empty (NaN). A sample whose stamp repeats the previous one or
/// lies before it is kept in the next slot (its stamp is wrong, not its
/// value), unless the whole row repeats the previous row — a line written
/// twice — which is dropped. Returns the new columns and the rows dropped,
/// or `None` when the grid would exceed `max_factor` times the samples
/// ([`MAX_GRID_FACTOR`] unless the caller lifts it).
pub fn regularize(
    t: &[f64],
    rate_hz: f64,
    columns: &[Vec<f64>],
    max_factor: usize,
) -> Option<(Vec<Vec<f64>>, Vec<usize>)> {
    regularize_gapped(t, rate_hz, GAP_FACTOR / rate_hz, columns, max_factor)
}

/// [`regularize`] with gaps opened only by steps longer than
/// `gap_above_s` ([`Timing::gap_above_for`]: an irregular publisher's steps
/// are all its own).
pub fn regularize_gapped(
    t: &[f64],
    rate_hz: f64,
    gap_above_s: f64,
    columns: &[Vec<f64>],
    max_factor: usize,
) -> Option<(Vec<Vec<f64>>, Vec<usize>)> {
    if !t.iter().any(|v| v.is_finite()) {
        return Some((columns.to_vec(), Vec::new()));
    }
    let value = |c: &Vec<f64>, i: usize| c.get(i).copied().unwrap_or(f64::NAN);
    let same_row = |i: usize, j: usize| {
        columns
            .iter()
            .all(|c| value(c, i).to_bits() == value(c, j).to_bits())
    };
    // First pass: the slot of each row (None = dropped).
    let mut slots: Vec<Option<usize>> = Vec::with_capacity(t.len());
    let mut dropped = Vec::new();
    let mut last: Option<(usize, usize)> = None; // (slot, row) of the latest well-stamped row
    let mut used: Option<usize> = None;
    for (i, &ti) in t.iter().enumerate() {
        if i > 0 && ti.is_finite() && t[i - 1] == ti && same_row(i, i - 1) {
            dropped.push(i);
            slots.push(None);
            continue;
        }
        // Slots only ever rise: a row never takes the slot of one before it,
        // even the first well-stamped row after rows without a stamp.
        let next = used.map_or(0, |u| u + 1);
        let slot = match (last, used) {
            (Some((s, r)), Some(_)) if ti.is_finite() => {
                let d = ti - t[r];
                let step = (d * rate_hz).round();
                if d > gap_above_s && step.is_finite() {
                    (s as f64 + step).max(next as f64) as usize
                } else {
                    next
                }
            }
            _ => next,
        };
        if slot > max_factor.saturating_mul(t.len()).saturating_add(1024) {
            return None;
        }
        if ti.is_finite() && last.is_none_or(|(_, r)| ti > t[r]) {
            last = Some((slot, i));
        }
        used = Some(slot);
        slots.push(Some(slot));
    }
    let len = used.map_or(0, |u| u + 1);
    let mut out = vec![vec![f64::NAN; len]; columns.len()];
    for (i, s) in slots.iter().enumerate() {
        if let Some(k) = *s {
            for (dst, src) in out.iter_mut().zip(columns) {
                dst[k] = value(src, i);
            }
        }
    }
    Some((out, dropped))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rows_without_a_stamp_before_the_first_stamped_one_keep_their_slots() {
        // Found by fuzzing the readers: the first finite stamp after NaN
        // stamps took slot 0 again, and the rows before it fell off the grid.
        let t = [f64::NAN, f64::NAN, 0.0, 0.01, 0.05];
        let col = vec![1.0, 2.0, 3.0, 4.0, 5.0];
        let (out, dropped) = regularize(&t, 100.0, std::slice::from_ref(&col), MAX_GRID_FACTOR).unwrap();
        assert!(dropped.is_empty());
        let kept: Vec<f64> = out[0].iter().copied().filter(|v| !v.is_nan()).collect();
        assert_eq!(kept, col, "every row keeps a slot, in order");
        // 0.01 → 0.05 is a gap of three samples after slot 3.
        assert_eq!(out[0].len(), 8);
    }

    #[test]
    fn finds_rate_jitter_gaps_duplicates_and_backwards_steps() {
        let t = [0.0, 0.01, 0.02, 0.05, 0.05, 0.06, 0.055, 0.065];
        let tm = analyze_timestamps(&t).unwrap();
        assert!((tm.rate_hz - 100.0).abs() < 1e-9);
        assert_eq!(tm.gaps, vec![(3, 2)]);
        assert_eq!(tm.duplicates, vec![4]);
        assert_eq!(tm.backwards, vec![6]);
        assert!(analyze_timestamps(&[1.0]).is_none());
    }

    #[test]
    fn regularize_leaves_gaps_and_keeps_samples_with_bad_stamps() {
        // A gap of two slots after row 1; row 3 repeats row 2's stamp with
        // another value (kept, next slot); row 4 steps back (kept, next
        // slot); row 5 is a line written twice (dropped).
        let t = [0.0, 0.01, 0.04, 0.04, 0.03, 0.03, 0.07];
        let col = vec![vec![1.0, 2.0, 3.0, 4.0, 5.0, 5.0, 7.0]];
        let (out, dropped) = regularize(&t, 100.0, &col, MAX_GRID_FACTOR).unwrap();
        assert!(regularize(&[0.0, 1e9], 100.0, &col, MAX_GRID_FACTOR).is_none());
        // Lifted, the same stamps are a long gap.
        assert_eq!(
            regularize(&[0.0, 1e3], 100.0, &col[..1], 1 << 20).unwrap().0[0].len(),
            100_001
        );
        assert_eq!(dropped, [5]);
        let v = &out[0];
        assert_eq!(v.len(), 8);
        assert_eq!(
            (v[0], v[1], v[4], v[5], v[6], v[7]),
            (1.0, 2.0, 3.0, 4.0, 5.0, 7.0)
        );
        assert!(v[2].is_nan() && v[3].is_nan());
    }

    /// A fixed pseudo-random sequence in [0, 1).
    fn uniforms(mut state: u64) -> impl FnMut() -> f64 {
        move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64
        }
    }

    /// An FMUv5 `sensor_combined` as logged: 1,737 stamps stepping 5 ms
    /// with stretches of 4.5 ms (20 steps in every 100: a true mean of
    /// 4.9 ms), 101 messages not logged, 20 µs of jitter: the case where a
    /// clock fit that leaves out stamps off its line drops the 4.5 ms
    /// steps.
    fn fmuv5_clock() -> Vec<f64> {
        let mut u = uniforms(0x9e37_79b9_7f4a_7c15);
        let mut t = Vec::new();
        let mut now = 0.0;
        for k in 0..1737 + 101 {
            now += if k % 100 >= 80 { 4.5e-3 } else { 5.0e-3 };
            t.push(now + 20e-6 * (u() - 0.5));
        }
        let mut removed = 0;
        while removed < 101 {
            let k = 1 + (u() * (t.len() - 2) as f64) as usize;
            t.remove(k);
            removed += 1;
        }
        t
    }

    #[test]
    fn an_irregular_clock_keeps_its_real_steps() {
        let t = fmuv5_clock();
        assert_eq!(t.len(), 1737);
        let tm = analyze_timestamps(&t).unwrap();
        // The mean gap-free step, read here without imutherm's code: every
        // step shorter than 7 ms (an unlogged message makes 9.5 to 10 ms).
        let short: Vec<f64> = t.windows(2).map(|w| w[1] - w[0]).filter(|d| *d < 7e-3).collect();
        let mean_step = short.iter().sum::<f64>() / short.len() as f64;
        assert!(
            (tm.rate_hz * mean_step - 1.0).abs() < 0.002,
            "{} Hz, mean step {mean_step}",
            tm.rate_hz
        );
        assert!((mean_step - 4.9e-3).abs() < 0.01e-3, "{mean_step}");
        // No stamp of the gap-free stretches is left out of the clock: all
        // but those alone between two unlogged messages.
        let alone = (0..t.len())
            .filter(|&k| {
                let gap_before = k == 0 || t[k] - t[k - 1] >= 7e-3;
                let gap_after = k + 1 == t.len() || t[k + 1] - t[k] >= 7e-3;
                gap_before && gap_after
            })
            .count();
        assert_eq!(tm.fitted_samples, t.len() - alone);
        // The jitter is the stamps' spread about the clock reported,
        // recomputed here stretch by stretch.
        let period = 1.0 / tm.rate_hz;
        let (mut sum2, mut n, mut runs) = (0.0, 0usize, 0usize);
        let mut start = 0;
        for i in 1..=t.len() {
            if i == t.len() || t[i] - t[i - 1] >= 7e-3 {
                let r: Vec<f64> = (start..i).map(|k| t[k] - (k - start) as f64 * period).collect();
                let m = r.iter().sum::<f64>() / r.len() as f64;
                sum2 += r.iter().map(|x| (x - m).powi(2)).sum::<f64>();
                n += r.len();
                runs += 1;
                start = i;
            }
        }
        let spread = (sum2 / (n - runs) as f64).sqrt();
        assert!(
            (tm.jitter_s / spread - 1.0).abs() < 1e-6,
            "{} vs {spread}",
            tm.jitter_s
        );
        // Every unlogged message is a gap of one sample.
        assert_eq!(tm.gaps.iter().map(|g| g.1).sum::<usize>(), 101, "{:?}", tm.gaps);
    }

    #[test]
    fn a_publisher_on_several_steps_misses_no_sample_its_steps_do_not_say() {
        // The shape of an FMUv5 `sensor_combined`: 1,737 messages stepping
        // 5 ms, with stretches of 4.5 ms and 102 steps of 9 ms, 20 µs of
        // jitter. Against a 4.9 ms clock the 9 ms steps would be 102
        // "missing" samples, the grid 1,839 slots and its duration longer
        // than the stamps' span (the log: 1,838 slots, 101
        // missing, 9.019 s against a span of 8.937 s).
        let mut u = uniforms(0x2545_f491_4f6c_dd1d);
        let mut t = vec![0.0];
        for k in 0..1736 {
            let step = match k % 100 {
                0..=5 if k / 100 < 17 => 9.0e-3,
                80.. => 4.5e-3,
                _ => 5.0e-3,
            };
            let last = t[k];
            t.push(last + step);
        }
        let nines = t.windows(2).filter(|w| w[1] - w[0] > 8e-3).count();
        assert_eq!(nines, 102);
        for v in &mut t {
            *v += 20e-6 * (u() - 0.5);
        }
        let tm = analyze_timestamps(&t).unwrap();
        let Some(Pattern::Irregular { steps }) = &tm.pattern else {
            panic!("{:?}", tm.pattern);
        };
        let values: Vec<String> = steps.iter().map(|s| ms(s.step_s)).collect();
        assert_eq!(values, ["4.5", "5", "9"]);
        assert!(tm.gaps.is_empty(), "{:?}", tm.gaps);
        // The rate is the mean of every step; the grid is the messages.
        let mean = (t[1736] - t[0]) / 1736.0;
        assert!((tm.rate_hz * mean - 1.0).abs() < 1e-9, "{}", tm.rate_hz);
        assert!((tm.span_s - (t[1736] - t[0])).abs() < 1e-12);
        let (grid, _) = regularize_gapped(
            &t,
            tm.rate_hz,
            tm.gap_above_s,
            &[vec![1.0; t.len()]],
            MAX_GRID_FACTOR,
        )
        .unwrap();
        assert_eq!(grid[0].len(), 1737);
        let note = tm.pattern_note(1737, 1737).unwrap();
        assert!(
            note.starts_with("published irregularly: steps of 4.5, 5 and 9 ms"),
            "{note}"
        );
        // A step past 1.5 times the longest is still a gap.
        t.push(t[1736] + 30e-3);
        let tm = analyze_timestamps(&t).unwrap();
        assert_eq!(tm.gaps.len(), 1);
    }

    #[test]
    fn a_duty_cycles_grid_may_be_as_large_as_its_pattern_asks_and_no_larger() {
        // 5 s of 50 Hz every 305 s, eight bursts: a grid 61 times the
        // samples, past the default limit.
        let t: Vec<f64> = (0..8)
            .flat_map(|b| (0..250).map(move |k| b as f64 * 305.0 + k as f64 * 0.02))
            .collect();
        let tm = analyze_timestamps(&t).unwrap();
        assert!(
            matches!(tm.pattern, Some(Pattern::Bursts { bursts: 8, .. })),
            "{:?}",
            tm.pattern
        );
        let col = [vec![1.0; t.len()]];
        let factor = tm.grid_factor(None, tm.rate_hz);
        assert!(factor > MAX_GRID_FACTOR && factor <= 80, "{factor}");
        let (grid, _) = regularize(&t, tm.rate_hz, &col, factor).unwrap();
        assert_eq!(grid[0].len(), 7 * 15_250 + 250);
        assert!(regularize(&t, tm.rate_hz, &col, MAX_GRID_FACTOR).is_none());
        // A limit given is kept.
        assert_eq!(tm.grid_factor(Some(16), tm.rate_hz), 16);
    }

    #[test]
    fn a_micros_counter_that_wraps_is_unwrapped() {
        // An Arduino's micros() at 100 Hz across its wrap at 2^32 µs.
        let start = U32_WRAP - 50_000.0;
        let mut raw: Vec<f64> = (0..20)
            .map(|k| (start + k as f64 * 10_000.0) % U32_WRAP)
            .collect();
        assert_eq!(unwrap_u32(&mut raw), [5]);
        assert!(raw.windows(2).all(|w| w[1] - w[0] == 10_000.0), "{raw:?}");
        // A column of seconds, or one that merely steps back, is left as is.
        let mut secs = vec![0.5, 0.25, 1.0];
        assert!(unwrap_u32(&mut secs).is_empty());
        let mut back = vec![3_000_000.0, 1_000_000.0];
        assert!(unwrap_u32(&mut back).is_empty());
        assert_eq!(back, [3_000_000.0, 1_000_000.0]);
    }

    proptest::proptest! {
        /// For any clock whose steps stay within (0.7, 1.3) of its period,
        /// with messages lost here and there: the rate is one over the mean
        /// step between the stamps that have no loss between them, and the
        /// grid holds every sample plus the gaps reported (the duration is
        /// count / rate plus the gaps).
        #[test]
        fn the_rate_is_the_mean_gap_free_step_and_the_grid_holds_the_gaps(
            period in 1e-3f64..1.0,
            steps in proptest::collection::vec((0.7f64..1.3, 0usize..40), 10..400),
        ) {
            let mut t = vec![0.0];
            let mut lost_steps = Vec::new();
            for (k, &(f, lose)) in steps.iter().enumerate() {
                // Now and then (1 in 40) a message or two is not logged.
                let lost = if lose == 0 { 1 + k % 2 } else { 0 };
                let d: f64 = (0..=lost).map(|j| if j == 0 { f } else { 1.0 } * period).sum();
                t.push(t[k] + d);
                lost_steps.push(lost > 0);
            }
            let tm = analyze_timestamps(&t).unwrap();
            // Steps drawn all alike with losses among them (every step 0.7
            // periods, a loss 1.7) are two values no one clock makes: a
            // publisher, which `clock_pattern`'s tests cover, not a clock.
            proptest::prop_assume!(!matches!(tm.pattern, Some(Pattern::Irregular { .. })));
            let kept: Vec<f64> = t
                .windows(2)
                .zip(&lost_steps)
                .filter(|(_, l)| !**l)
                .map(|(w, _)| w[1] - w[0])
                .collect();
            proptest::prop_assume!(!kept.is_empty());
            let mean = kept.iter().sum::<f64>() / kept.len() as f64;
            proptest::prop_assert!((tm.rate_hz * mean - 1.0).abs() < 1e-9, "{} vs {}", tm.rate_hz, 1.0 / mean);
            let (grid, dropped) = regularize(&t, tm.rate_hz, &[vec![1.0; t.len()]], MAX_GRID_FACTOR).unwrap();
            let missing: usize = tm.gaps.iter().map(|g| g.1).sum();
            proptest::prop_assert!(dropped.is_empty());
            proptest::prop_assert_eq!(grid[0].len(), t.len() + missing);
        }
    }

    #[test]
    fn the_rate_is_the_clocks_not_the_median_steps() {
        // 200 Hz nominal, the chip 0.3 % fast, stamped in whole ms.
        let rate = 200.0 * 1.003;
        let t: Vec<f64> = (0..20_000)
            .map(|k| (k as f64 / rate * 1e3).floor() * 1e-3)
            .collect();
        let tm = analyze_timestamps(&t).unwrap();
        assert!((tm.median_step_s - 0.005).abs() < 1e-12);
        assert!((tm.rate_hz / rate - 1.0).abs() < 5e-4, "{}", tm.rate_hz);
        assert!(tm.gaps.is_empty() && tm.duplicates.is_empty());
        let (out, dropped) = regularize(&t, tm.rate_hz, &[vec![1.0; t.len()]], MAX_GRID_FACTOR).unwrap();
        assert_eq!((dropped.len(), out[0].len()), (0, t.len()));
        assert!(out[0].iter().all(|v| *v == 1.0));
    }
}
