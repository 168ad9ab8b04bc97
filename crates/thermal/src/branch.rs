//! Which way the temperature is going: heating or cooling, decided on the
//! temperature smoothed over minutes, and dT/dt over seconds where the
//! samples around a point allow it.
//!
//! A 10 s derivative of a temperature sensor with 0.003 °C steps and some
//! noise flips sign inside a run that only heats; each flip used to make a
//! "cooling" bin of a few samples beside bins of thousands. Here the
//! direction is the slope between the means of the [`HALF_WINDOW_S`] before
//! and after each sample, and it changes only when that slope passes
//! [`SWITCH_RATE_C_PER_S`] the other way (a Schmitt trigger): a plateau or a
//! gap keeps the direction it had.

/// Each side of the smoothing window, s: the direction is the slope of the
/// temperature between the means of the minutes before and after a sample.
pub const HALF_WINDOW_S: f64 = 150.0;

/// Smoothed rate the temperature must pass to change direction, °C/s
/// (0.6 °C per hour): slower than that is a plateau, not a turn.
pub const SWITCH_RATE_C_PER_S: f64 = 1.0 / 6000.0;

/// `true` where the temperature is rising (or has not yet been seen to
/// fall), `false` where it is falling, one per sample. Samples whose
/// temperature is not finite take the direction around them.
pub fn heating(temp: &[f64], rate_hz: f64) -> Vec<bool> {
    let n = temp.len();
    if n == 0 {
        return Vec::new();
    }
    // Prefix sums of the finite temperatures, their count and their index,
    // so that each window's mean and centre cost O(1).
    let mut sum = vec![0.0; n + 1];
    let mut count = vec![0usize; n + 1];
    let mut index = vec![0.0; n + 1];
    for (i, &t) in temp.iter().enumerate() {
        let ok = t.is_finite();
        sum[i + 1] = sum[i] + if ok { t } else { 0.0 };
        count[i + 1] = count[i] + usize::from(ok);
        index[i + 1] = index[i] + if ok { i as f64 } else { 0.0 };
    }
    let window = |a: usize, b: usize| {
        let c = count[b] - count[a];
        (c > 0).then(|| {
            let c = c as f64;
            ((sum[b] - sum[a]) / c, (index[b] - index[a]) / c)
        })
    };
    let h = ((HALF_WINDOW_S * rate_hz).round() as usize).max(1);
    let mut state: Option<bool> = None;
    let mut out: Vec<Option<bool>> = Vec::with_capacity(n);
    for i in 0..n {
        let before = window(i.saturating_sub(h), i);
        let after = window(i, (i + h).min(n));
        if let (Some((t0, i0)), Some((t1, i1))) = (before, after)
            && i1 > i0
        {
            let slope = (t1 - t0) * rate_hz / (i1 - i0);
            if slope > SWITCH_RATE_C_PER_S {
                state = Some(true);
            } else if slope < -SWITCH_RATE_C_PER_S {
                state = Some(false);
            }
        }
        out.push(state);
    }
    // Before the first decision the run goes the way it is first seen to go.
    let first = out.iter().flatten().next().copied().unwrap_or(true);
    out.into_iter().map(|s| s.unwrap_or(first)).collect()
}

/// dT/dt, °C/s, over [`crate::tcal::RATE_WINDOW_S`] around each sample,
/// between the nearest finite temperatures inside the window; NaN where the
/// window holds fewer than two (a gap, an isolated sample).
pub fn dtdt(temp: &[f64], rate_hz: f64, window_s: f64) -> Vec<f64> {
    let n = temp.len();
    let h = ((window_s * rate_hz / 2.0).round() as usize).max(1);
    // next[i]: first finite index ≥ i; prev[i]: last finite index ≤ i.
    let mut next = vec![usize::MAX; n + 1];
    for i in (0..n).rev() {
        next[i] = if temp[i].is_finite() { i } else { next[i + 1] };
    }
    let mut prev = vec![usize::MAX; n];
    let mut last = usize::MAX;
    for (i, t) in temp.iter().enumerate() {
        if t.is_finite() {
            last = i;
        }
        prev[i] = last;
    }
    (0..n)
        .map(|i| {
            let a = next[i.saturating_sub(h)];
            let b = prev[(i + h).min(n - 1)];
            if a != usize::MAX && b != usize::MAX && b > a {
                (temp[b] - temp[a]) * rate_hz / (b - a) as f64
            } else {
                f64::NAN
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 20 → 70 °C heating over 45 min at 10 Hz, with ±0.5 °C noise and
    /// the 0.003 °C steps of an MPU-9250's temperature register.
    fn noisy_heating() -> Vec<f64> {
        let mut state = 1u64;
        (0..27_000)
            .map(|i| {
                state = state
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                let u = (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5;
                let t = 20.0 + 50.0 * i as f64 / 27_000.0 + u;
                (t / 0.003).round() * 0.003
            })
            .collect()
    }

    #[test]
    fn a_noisy_heating_is_heating_throughout() {
        let temp = noisy_heating();
        // The 10 s derivative flips: that is what the smoothing is for.
        let d = dtdt(&temp, 10.0, 10.0);
        assert!(d.iter().any(|r| *r < 0.0));
        assert!(heating(&temp, 10.0).iter().all(|h| *h));
    }

    #[test]
    fn a_heating_then_cooling_run_turns_once() {
        let temp: Vec<f64> = (0..7200)
            .map(|i| {
                let s = i as f64;
                if s < 3600.0 {
                    20.0 + s / 100.0
                } else {
                    56.0 - (s - 3600.0) / 100.0
                }
            })
            .collect();
        let h = heating(&temp, 1.0);
        let turns = h.windows(2).filter(|w| w[0] != w[1]).count();
        assert_eq!(turns, 1);
        assert!(h[0] && !h[7199]);
        let turn = h.iter().position(|x| !x).unwrap();
        assert!((3500..3700).contains(&turn), "{turn}");
    }

    #[test]
    fn gaps_keep_the_direction_and_give_nan_rates_only_where_nothing_is_left() {
        // A cooling run logged in bursts of 5 s every 305 s at 2 Hz.
        let temp: Vec<f64> = (0..2 * 305 * 20)
            .map(|i| {
                let s = i as f64 / 2.0;
                if s % 305.0 < 5.0 {
                    24.0 - s / 900.0
                } else {
                    f64::NAN
                }
            })
            .collect();
        assert!(heating(&temp, 2.0).iter().all(|h| !h));
        let d = dtdt(&temp, 2.0, 10.0);
        for (t, r) in temp.iter().zip(&d) {
            if t.is_finite() {
                assert!(r.is_finite() && *r < 0.0, "{r}");
            }
        }
        assert!(d.iter().any(|r| r.is_nan()));
        let lone = [f64::NAN, 30.0, f64::NAN];
        assert!(dtdt(&lone, 1.0, 2.0).iter().all(|r| r.is_nan()));
    }
}
