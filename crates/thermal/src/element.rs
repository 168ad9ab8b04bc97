//! The sensing element's temperature, as the bias sees it, from the logged
//! one: readouts in coarse steps smoothed, a first-order thermal lag, and
//! the smoothed direction of change a hysteresis follows.
//!
//! A temperature sensor beside (or inside) the MEMS die leads the proof
//! mass when the board heats from outside: the element follows through a
//! thermal resistance and capacity, a first-order lag of time constant τ,
//! so that while heating at r °C/s the element is r·τ colder than the
//! reading. A bias that is a polynomial of the element's temperature is
//! then no polynomial of the logged one, and heating and cooling disagree.
//!
//! Every filter here is causal and runs on the samples in time order, so
//! that firmware (or the C reference of `tcal export --format c`) can run
//! it sample by sample; gaps (NaN) advance the clock and leave the state to
//! continue from the next finite reading.

/// Smallest share of consecutive readings that repeat exactly for the
/// temperature to count as coarsely quantized: a sensor whose readout
/// changes every sample carries its own dither and needs no smoothing.
pub const REPEAT_SHARE: f64 = 0.5;

/// The readout's step where it is coarse (most consecutive readings repeat
/// and every change is a whole number of one step), else `None`.
pub fn coarse_step(temp: &[f64]) -> Option<f64> {
    let mut diffs: Vec<f64> = Vec::new();
    let mut same = 0usize;
    let mut pairs = 0usize;
    let mut last: Option<f64> = None;
    for &t in temp.iter().filter(|t| t.is_finite()) {
        if let Some(p) = last {
            pairs += 1;
            let d = (t - p).abs();
            if d == 0.0 {
                same += 1;
            } else {
                diffs.push(d);
            }
        }
        last = Some(t);
    }
    if pairs < 10 || diffs.is_empty() || (same as f64) < REPEAT_SHARE * pairs as f64 {
        return None;
    }
    let step = diffs.iter().copied().fold(f64::INFINITY, f64::min);
    // Float32 readouts of 1/333.87 °C steps are multiples to a few parts
    // in 1e4 only.
    let whole = diffs
        .iter()
        .filter(|d| {
            let k = *d / step;
            (k - k.round()).abs() < 0.02
        })
        .count();
    (whole as f64 >= 0.95 * diffs.len() as f64).then_some(step)
}

/// A coarse readout as the temperature it stands for: a reading changes
/// when the true temperature crosses the midpoint of two levels, so each
/// change is a point (its time, the two levels' mean) and the temperature
/// is the line through consecutive such points. Before the first change
/// and after the last the reading is kept. NaN stays NaN.
pub fn dequantize(temp: &[f64]) -> Vec<f64> {
    let mut knots: Vec<(usize, f64)> = Vec::new();
    let mut last: Option<f64> = None;
    for (i, &t) in temp.iter().enumerate() {
        if !t.is_finite() {
            continue;
        }
        if let Some(p) = last
            && p != t
        {
            knots.push((i, 0.5 * (p + t)));
        }
        last = Some(t);
    }
    if knots.len() < 2 {
        return temp.to_vec();
    }
    let mut out = temp.to_vec();
    let mut k = 0usize;
    for (i, v) in out.iter_mut().enumerate() {
        if !v.is_finite() || i < knots[0].0 || i >= knots[knots.len() - 1].0 {
            continue;
        }
        while knots[k + 1].0 <= i {
            k += 1;
        }
        let ((i0, t0), (i1, t1)) = (knots[k], knots[k + 1]);
        *v = t0 + (t1 - t0) * (i - i0) as f64 / (i1 - i0) as f64;
    }
    out
}

/// The logged temperature through a first-order lag of `tau_s` seconds:
/// the exact response to the readings joined by straight lines (so a gap
/// is bridged by the line between its two sides), starting at rest at the
/// first finite reading. `tau_s` 0 returns the input. NaN stays NaN.
pub fn lag(temp: &[f64], rate_hz: f64, tau_s: f64) -> Vec<f64> {
    if tau_s.is_nan() || tau_s <= 0.0 {
        return temp.to_vec();
    }
    let dt = 1.0 / rate_hz;
    let mut out = vec![f64::NAN; temp.len()];
    let mut state: Option<(usize, f64, f64)> = None; // (index, input, output)
    for (i, &t) in temp.iter().enumerate() {
        if !t.is_finite() {
            continue;
        }
        let y = match state {
            None => t,
            Some((j, x0, y0)) => {
                let h = (i - j) as f64 * dt;
                let m = (t - x0) / h;
                let e = (-h / tau_s).exp();
                // y' = (x − y)/τ with x = x0 + m·s over the step.
                t - m * tau_s + (y0 - x0 + m * tau_s) * e
            }
        };
        out[i] = y;
        state = Some((i, t, y));
    }
    out
}

/// The smoothed rate of change, °C/s: (T − lag(T, τ))/τ, which on a steady
/// ramp is its slope and relaxes to zero over τ on a plateau. Causal, as
/// the direction a hysteresis remembers. NaN where T is.
pub fn smoothed_rate(temp: &[f64], rate_hz: f64, tau_s: f64) -> Vec<f64> {
    lag(temp, rate_hz, tau_s)
        .iter()
        .zip(temp)
        .map(|(l, t)| (t - l) / tau_s)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_ramp_through_a_lag_trails_by_rate_times_tau() {
        let rate = 0.02; // °C/s
        let temp: Vec<f64> = (0..5000).map(|i| 20.0 + rate * i as f64).collect();
        let y = lag(&temp, 1.0, 100.0);
        // After ten time constants the transient is e^-10 of r·τ.
        let behind = temp[2000] - y[2000];
        assert!((behind - rate * 100.0).abs() < 1e-6, "{behind}");
        let r = smoothed_rate(&temp, 1.0, 100.0);
        assert!((r[3000] - rate).abs() < 1e-9, "{}", r[3000]);
    }

    #[test]
    fn a_gap_is_bridged_by_its_line() {
        let full: Vec<f64> = (0..3000).map(|i| 20.0 + 0.01 * i as f64).collect();
        let mut gappy = full.clone();
        for v in gappy.iter_mut().take(2000).skip(1000) {
            *v = f64::NAN;
        }
        let (a, b) = (lag(&full, 2.0, 60.0), lag(&gappy, 2.0, 60.0));
        assert!(b[1500].is_nan());
        assert!((a[2500] - b[2500]).abs() < 1e-9, "{} {}", a[2500], b[2500]);
    }

    #[test]
    fn whole_degree_readings_are_found_and_smoothed() {
        let truth: Vec<f64> = (0..6000).map(|i| 20.0 + 10.0 * i as f64 / 6000.0).collect();
        let read: Vec<f64> = truth.iter().map(|t| t.floor()).collect();
        assert_eq!(coarse_step(&read), Some(1.0));
        let smooth = dequantize(&read);
        // Between the first and the last change the line through the
        // midpoints is the ramp, half a step below it (floor reads low).
        let worst = (700..5300)
            .map(|i| (smooth[i] + 0.5 - truth[i]).abs())
            .fold(0.0, f64::max);
        assert!(worst < 0.01, "{worst} °C");
        // A readout that moves every sample is left alone.
        assert_eq!(coarse_step(&truth), None);
        let mpu: Vec<f64> = truth.iter().map(|t| (t * 333.87).round() / 333.87).collect();
        assert_eq!(
            coarse_step(&mpu),
            None,
            "6000 samples over 3339 steps mostly change"
        );
    }
}
