//! Per-sample timestamps: the rate they imply, its jitter, and everything
//! wrong with them (gaps, duplicates, steps backwards).
//!
//! An analysis needs evenly spaced samples; [`regularize`] puts each sample
//! on the grid its timestamp names and leaves NaN (a gap) where samples are
//! missing, so that the Allan statistics skip exactly those spans instead of
//! joining data from both sides of a gap.

/// What the timestamps say.
#[derive(Debug, Clone, PartialEq)]
pub struct Timing {
    /// 1 / median interval, Hz.
    pub rate_hz: f64,
    /// Standard deviation of the intervals that are neither gaps nor
    /// duplicates nor backwards, s.
    pub jitter_s: f64,
    /// (row, missing samples) for every interval longer than 1.5 periods.
    pub gaps: Vec<(usize, usize)>,
    /// Rows whose timestamp repeats the previous one.
    pub duplicates: Vec<usize>,
    /// Rows whose timestamp is earlier than the previous one.
    pub backwards: Vec<usize>,
}

/// Studies timestamps in seconds. `None` with fewer than two finite,
/// increasing timestamps (no rate can be derived).
pub fn analyze_timestamps(t: &[f64]) -> Option<Timing> {
    let mut dts: Vec<f64> = t
        .windows(2)
        .map(|w| w[1] - w[0])
        .filter(|d| d.is_finite() && *d > 0.0)
        .collect();
    if dts.is_empty() {
        return None;
    }
    dts.sort_unstable_by(f64::total_cmp);
    let period = dts[dts.len() / 2];
    let mut gaps = Vec::new();
    let mut duplicates = Vec::new();
    let mut backwards = Vec::new();
    let (mut sum, mut sum2, mut count) = (0.0, 0.0, 0usize);
    // Intervals are measured from the latest timestamp so far, so that one
    // step backwards is reported once, not again as a gap after it.
    let mut latest = t[0];
    for (row, &ti) in t.iter().enumerate().skip(1) {
        let d = ti - latest;
        if ti.is_finite() && ti > latest {
            latest = ti;
        }
        if d == 0.0 {
            duplicates.push(row);
        } else if d < 0.0 {
            backwards.push(row);
        } else if d > 1.5 * period {
            gaps.push((row, ((d / period).round() as usize).saturating_sub(1).max(1)));
        } else if d.is_finite() {
            let r = d - period;
            sum += r;
            sum2 += r * r;
            count += 1;
        }
    }
    let jitter_s = if count > 1 {
        let mean = sum / count as f64;
        ((sum2 / count as f64 - mean * mean).max(0.0) * count as f64 / (count - 1) as f64).sqrt()
    } else {
        0.0
    };
    Some(Timing {
        rate_hz: 1.0 / period,
        jitter_s,
        gaps,
        duplicates,
        backwards,
    })
}

/// Largest grid a time column may ask for, as a multiple of its samples:
/// beyond it the timestamps are wrong (a unit mix-up, a corrupt value), and
/// filling the grid with gaps would only exhaust memory.
pub const MAX_GRID_FACTOR: usize = 16;

/// Places each sample of `columns` on the grid t0 + k/rate named by its
/// timestamp: missing grid points become NaN, a sample whose slot is taken
/// (a duplicate) or lies before the previous one (backwards in time) is
/// dropped. Returns the new columns and the number of samples dropped, or
/// `None` when the grid would exceed [`MAX_GRID_FACTOR`] times the samples.
pub fn regularize(t: &[f64], rate_hz: f64, columns: &[Vec<f64>]) -> Option<(Vec<Vec<f64>>, usize)> {
    let Some(&t0) = t.iter().find(|v| v.is_finite()) else {
        return Some((columns.to_vec(), 0));
    };
    let slot = |v: f64| ((v - t0) * rate_hz).round();
    let last = t
        .iter()
        .filter(|v| v.is_finite())
        .map(|&v| slot(v))
        .fold(0.0, f64::max);
    if !(last.is_finite() && last < (MAX_GRID_FACTOR * t.len() + 1024) as f64) {
        return None;
    }
    let len = (last as usize).saturating_add(1);
    let mut out = vec![vec![f64::NAN; len]; columns.len()];
    let mut dropped = 0;
    let mut previous: Option<usize> = None;
    for (i, &ti) in t.iter().enumerate() {
        if !ti.is_finite() || slot(ti) < 0.0 {
            dropped += 1;
            continue;
        }
        let k = slot(ti) as usize;
        if previous.is_some_and(|p| k <= p) {
            dropped += 1;
            continue;
        }
        previous = Some(k);
        for (dst, src) in out.iter_mut().zip(columns) {
            dst[k] = src.get(i).copied().unwrap_or(f64::NAN);
        }
    }
    Some((out, dropped))
}

#[cfg(test)]
mod tests {
    use super::*;

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
    fn regularize_leaves_gaps_and_drops_out_of_order_samples() {
        let t = [0.0, 0.01, 0.04, 0.04, 0.03, 0.05];
        let col = vec![vec![1.0, 2.0, 3.0, 4.0, 5.0, 6.0]];
        let (out, dropped) = regularize(&t, 100.0, &col).unwrap();
        assert!(regularize(&[0.0, 1e9], 100.0, &col).is_none());
        assert_eq!(dropped, 2);
        let v = &out[0];
        assert_eq!(v.len(), 6);
        assert_eq!((v[0], v[1], v[4], v[5]), (1.0, 2.0, 3.0, 6.0));
        assert!(v[2].is_nan() && v[3].is_nan());
    }
}
