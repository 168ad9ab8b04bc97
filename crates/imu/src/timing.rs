//! Per-sample timestamps: the rate of the clock that made them, its jitter,
//! and everything wrong with them (gaps, duplicates, steps backwards).
//!
//! The rate is the clock's, not the median step's: a chip running 0.3 %
//! fast and stamped in whole milliseconds steps 5 ms almost always and 4 ms
//! now and then, so the median says 200 Hz while the samples come at
//! 200.6 Hz. The period is the least-squares slope of time against sample
//! index over the stretches without gaps, refitted without stamps that sit
//! far off the line. Samples are then placed one slot after another, a
//! step of more than 1.5 periods opening a gap of the size the clock
//! implies: no real sample is dropped and no gap is invented, whatever the
//! stamps' jitter or rounding.

/// What the timestamps say.
#[derive(Debug, Clone, PartialEq)]
pub struct Timing {
    /// 1 / the clock's period, fitted over the stretches without gaps, Hz.
    pub rate_hz: f64,
    /// Standard deviation of the stamps about the fitted clock, s.
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
    /// Samples the fit of the clock used.
    pub fitted_samples: usize,
}

/// A step longer than this many periods is a gap.
pub const GAP_FACTOR: f64 = 1.5;

/// Stamps further from the fitted clock than this many robust standard
/// deviations are left out of the refit (a late write, a clock glitch).
const OUTLIER_SIGMAS: f64 = 6.0;

/// Least-squares slope and residual scale of `t` against the row index,
/// over runs of rows whose steps all lie within (0.5, 1.5) × `step`; rows
/// for which `keep` is false end a run.
fn fit_period(t: &[f64], step: f64, keep: &dyn Fn(usize, f64) -> bool) -> Option<(f64, usize)> {
    let (mut sxy, mut sxx, mut used) = (0.0, 0.0, 0usize);
    let mut run_start = 0;
    let flush = |from: usize, to: usize, sxy: &mut f64, sxx: &mut f64, used: &mut usize| {
        // Rows from..to (exclusive) form one run: centred sums, in two
        // passes over the rows kept rather than a list of them, so that a
        // long run costs no memory.
        let kept = || (from..to).filter(|&i| keep(i, t[i]));
        let n = kept().count();
        if n < 2 {
            return;
        }
        let n_f = n as f64;
        let mi = kept().map(|i| i as f64).sum::<f64>() / n_f;
        // Stamps are taken relative to the run's first one so that epoch
        // magnitudes (1.7e18 ns) do not eat the digits of the step.
        let Some(first) = kept().next() else { return };
        let t0 = t[first];
        let mt = kept().map(|i| t[i] - t0).sum::<f64>() / n_f;
        for i in kept() {
            let di = i as f64 - mi;
            *sxy += di * (t[i] - t0 - mt);
            *sxx += di * di;
        }
        *used += n;
    };
    for i in 1..=t.len() {
        let breaks = i == t.len() || {
            let d = t[i] - t[i - 1];
            !(d.is_finite() && d > 0.5 * step && d < GAP_FACTOR * step)
        };
        if breaks {
            flush(run_start, i, &mut sxy, &mut sxx, &mut used);
            run_start = i;
        }
    }
    (sxx > 0.0 && sxy > 0.0).then(|| (sxy / sxx, used))
}

/// Studies timestamps in seconds. `None` with fewer than two finite,
/// increasing timestamps (no rate can be derived).
pub fn analyze_timestamps(t: &[f64]) -> Option<Timing> {
    // Memory is a few series the length of `t`, one at a time: the
    // recordings are long, and the samples themselves are already held.
    let median = {
        let mut dts: Vec<f64> = t
            .windows(2)
            .map(|w| w[1] - w[0])
            .filter(|d| d.is_finite() && *d > 0.0)
            .collect();
        if dts.is_empty() {
            return None;
        }
        let mid = dts.len() / 2;
        *dts.select_nth_unstable_by(mid, f64::total_cmp).1
    };
    let (first, _) = fit_period(t, median, &|_, v| v.is_finite())?;
    // Residuals about the first fit, per run (NaN for rows in no run), to
    // find the stamps that sit off the clock and the jitter of the others.
    let residuals = run_residuals(t, median, first);
    let mad = {
        let mut abs: Vec<f64> = residuals
            .iter()
            .filter(|r| !r.is_nan())
            .map(|r| r.abs())
            .collect();
        let mid = abs.len() / 2;
        if abs.is_empty() {
            0.0
        } else {
            *abs.select_nth_unstable_by(mid, f64::total_cmp).1 * 1.4826
        }
    };
    let limit = (OUTLIER_SIGMAS * mad).max(1e-3 * median);
    let (period, fitted) = fit_period(t, median, &|i, v| {
        v.is_finite() && (residuals[i].is_nan() || residuals[i].abs() <= limit)
    })
    .unwrap_or((first, 0));
    drop(residuals);
    let final_res = run_residuals(t, median, period);
    let kept = || {
        final_res
            .iter()
            .copied()
            .filter(|r| !r.is_nan() && r.abs() <= limit)
    };
    let n_kept = kept().count();
    let jitter_s = if n_kept > 1 {
        let m = kept().sum::<f64>() / n_kept as f64;
        (kept().map(|r| (r - m).powi(2)).sum::<f64>() / (n_kept - 1) as f64).sqrt()
    } else {
        0.0
    };
    drop(final_res);

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
            if d > GAP_FACTOR * period {
                let missing = missing_before(d, period).saturating_sub(since_latest);
                if missing > 0 {
                    gaps.push((row, missing));
                }
            }
            since_latest = 0;
        }
    }
    Some(Timing {
        rate_hz: 1.0 / period,
        jitter_s,
        gaps,
        duplicates,
        backwards,
        median_step_s: median,
        fitted_samples: fitted,
    })
}

/// Samples missing in a step of `d` seconds on a clock of `period`.
fn missing_before(d: f64, period: f64) -> usize {
    ((d / period).round() as usize).saturating_sub(1).max(1)
}

/// Each row's distance from the straight line of `period` through its run
/// (runs as in [`fit_period`]); NaN for rows in no run (the stamps of a run
/// are finite, so no residual is NaN otherwise).
fn run_residuals(t: &[f64], step: f64, period: f64) -> Vec<f64> {
    let mut out = vec![f64::NAN; t.len()];
    let mut start = 0;
    for i in 1..=t.len() {
        let breaks = i == t.len() || {
            let d = t[i] - t[i - 1];
            !(d.is_finite() && d > 0.5 * step && d < GAP_FACTOR * step)
        };
        if breaks {
            if i - start >= 2 {
                let t0 = t[start];
                let n = (i - start) as f64;
                let offset = (start..i)
                    .map(|k| t[k] - t0 - (k - start) as f64 * period)
                    .sum::<f64>()
                    / n;
                for k in start..i {
                    out[k] = t[k] - t0 - (k - start) as f64 * period - offset;
                }
            }
            start = i;
        }
    }
    out
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
    if !t.iter().any(|v| v.is_finite()) {
        return Some((columns.to_vec(), Vec::new()));
    }
    let period = 1.0 / rate_hz;
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
                if d > GAP_FACTOR * period && step.is_finite() {
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
