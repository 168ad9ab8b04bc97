//! What the steps between stamps say beyond the clock: a publisher whose
//! steps cluster on several values that no one clock makes (an irregular
//! publisher, not a lossy sensor), and a regular duty cycle (bursts of
//! samples with long, equal pauses between them).
//!
//! A clock's steps are one value with jitter, or whole multiples of it
//! where samples were not logged; a clock stamped in whole units steps by
//! its period rounded either way (4 and 5 ms at 200.6 Hz), values one unit
//! of the stamps apart. Steps that cluster on values further apart than
//! that and are not multiples of the shortest (4.5, 5 and 9 ms) come from
//! no clock: counting samples "missing" against their mean would invent
//! them.

/// Steps within this ratio of their sorted neighbour are one value.
const CLUSTER_RATIO: f64 = 1.02;

/// A value the steps cluster on holds at least this share of them.
const CLUSTER_SHARE: f64 = 0.05;

/// A value within this share of a whole multiple of the shortest is that
/// multiple (samples not logged).
const MULTIPLE_TOLERANCE: f64 = 0.03;

/// The fewest steps a pattern is read from.
const MIN_STEPS: usize = 100;

/// The least share of the steps the values together hold: steps spread
/// over a range (jitter) fall into chance clusters that hold few.
const CLUSTERED_SHARE: f64 = 0.9;

/// Burst periods (start to start) within this share of their median are
/// one period.
const PERIOD_TOLERANCE: f64 = 0.02;

/// Bursts (first to last stamp) within this share of their median are one
/// length; the last may be shorter (the log stopped).
const BURST_TOLERANCE: f64 = 0.10;

/// The fewest bursts that make a duty cycle.
const MIN_BURSTS: usize = 4;

/// The largest grid a duty cycle may ask for, as a multiple of its
/// samples (a burst of 0.4 % of its period), whatever its pattern says.
pub const MAX_BURST_GRID_FACTOR: usize = 256;

/// A pattern the stamps follow.
#[derive(Debug, Clone, PartialEq)]
pub enum Pattern {
    /// Steps clustered on several values no one clock makes, shortest first.
    Irregular {
        /// The values.
        steps: Vec<StepValue>,
    },
    /// A regular duty cycle.
    Bursts {
        /// The median burst, first to last stamp, s.
        burst_s: f64,
        /// The median period, burst start to burst start, s.
        period_s: f64,
        /// Bursts in the recording.
        bursts: usize,
    },
}

/// One value the steps cluster on.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepValue {
    /// The median step of the cluster, s.
    pub step_s: f64,
    /// Steps in it.
    pub count: usize,
    /// Its shortest step, s.
    pub shortest_s: f64,
    /// Its longest step, s.
    pub longest_s: f64,
}

/// The values the forward steps of `t` cluster on, when they are several
/// that no one clock makes; `None` for a clock (one value with jitter, its
/// multiples, or values one unit of the stamps apart).
pub fn irregular_steps(t: &[f64]) -> Option<Vec<StepValue>> {
    let mut d: Vec<f64> = t
        .windows(2)
        .map(|w| w[1] - w[0])
        .filter(|d| d.is_finite() && *d > 0.0)
        .collect();
    if d.len() < MIN_STEPS {
        return None;
    }
    d.sort_unstable_by(f64::total_cmp);
    let resolution = stamp_unit(&d);
    let mut clusters: Vec<&[f64]> = Vec::new();
    let mut start = 0;
    for i in 1..=d.len() {
        let split = i == d.len() || (d[i] > d[i - 1] * CLUSTER_RATIO && d[i] - d[i - 1] > 1.5 * resolution);
        if split {
            clusters.push(&d[start..i]);
            start = i;
        }
    }
    let least = (CLUSTER_SHARE * d.len() as f64).max(3.0);
    let values: Vec<StepValue> = clusters
        .iter()
        .filter(|c| c.len() as f64 >= least)
        .map(|c| StepValue {
            step_s: c[c.len() / 2],
            count: c.len(),
            shortest_s: c[0],
            longest_s: c[c.len() - 1],
        })
        .collect();
    // Values are apart: each neighbour further from it than either is wide.
    let width = |v: &StepValue| v.longest_s - v.shortest_s;
    let apart = values
        .windows(2)
        .all(|w| w[1].shortest_s - w[0].longest_s >= width(&w[0]).max(width(&w[1])));
    let held: usize = values.iter().map(|v| v.count).sum();
    if !apart || (held as f64) < CLUSTERED_SHARE * d.len() as f64 {
        return None;
    }
    let shortest = values.first()?.step_s;
    let multiples = values.iter().all(|v| {
        let k = (v.step_s / shortest).round();
        (v.step_s / shortest - k).abs() <= MULTIPLE_TOLERANCE * k
    });
    (values.len() >= 2 && !multiples).then_some(values)
}

/// The decimal unit the steps `d` are whole multiples of (1 ms for stamps
/// in whole milliseconds), 0 where there is none down to 1 ns.
fn stamp_unit(d: &[f64]) -> f64 {
    let sample = &d[..d.len().min(4096)];
    (0..=9)
        .map(|k| 10f64.powi(-k))
        .find(|&u| {
            sample.iter().all(|&x| {
                let n = x / u;
                (n - n.round()).abs() <= 1e-3
            })
        })
        .filter(|&u| u > 1e-9)
        .unwrap_or(0.0)
}

/// A regular duty cycle in the stamps `t`, whose gaps (rows after a step
/// past the clock) are `gap_rows`: at least [`MIN_BURSTS`] bursts starting
/// one period apart, each as long as the others (the last no longer), and
/// pauses longer than the bursts.
pub fn bursts(t: &[f64], gap_rows: &[usize]) -> Option<Pattern> {
    if gap_rows.len() + 1 < MIN_BURSTS || t.len() < 2 {
        return None;
    }
    let starts: Vec<usize> = std::iter::once(0).chain(gap_rows.iter().copied()).collect();
    let ends: Vec<usize> = gap_rows
        .iter()
        .map(|&r| r - 1)
        .chain(std::iter::once(t.len() - 1))
        .collect();
    let finite = |k: usize| t[k].is_finite();
    if !starts.iter().chain(&ends).all(|&k| finite(k)) {
        return None;
    }
    let periods: Vec<f64> = starts.windows(2).map(|w| t[w[1]] - t[w[0]]).collect();
    let lengths: Vec<f64> = starts.iter().zip(&ends).map(|(&a, &b)| t[b] - t[a]).collect();
    let period = median(&periods)?;
    let burst = median(&lengths[..lengths.len() - 1])?;
    let within = |x: f64, m: f64, tol: f64| (x / m - 1.0).abs() <= tol;
    let regular = periods.iter().all(|&p| within(p, period, PERIOD_TOLERANCE))
        && lengths[..lengths.len() - 1]
            .iter()
            .all(|&l| within(l, burst, BURST_TOLERANCE))
        && lengths[lengths.len() - 1] <= burst * (1.0 + BURST_TOLERANCE)
        && burst > 0.0
        && period > 2.0 * burst;
    regular.then_some(Pattern::Bursts {
        burst_s: burst,
        period_s: period,
        bursts: starts.len(),
    })
}

fn median(x: &[f64]) -> Option<f64> {
    let mut v: Vec<f64> = x.to_vec();
    if v.is_empty() {
        return None;
    }
    let mid = v.len() / 2;
    Some(*v.select_nth_unstable_by(mid, f64::total_cmp).1)
}

impl Pattern {
    /// The grid a duty cycle of `rate_hz` asks for, as a multiple of its
    /// samples, with a quarter to spare; at most [`MAX_BURST_GRID_FACTOR`].
    pub fn grid_factor(&self, rate_hz: f64) -> Option<usize> {
        match *self {
            Pattern::Bursts {
                burst_s, period_s, ..
            } => {
                let per_burst = burst_s + 1.0 / rate_hz;
                Some(((1.25 * period_s / per_burst).ceil() as usize).min(MAX_BURST_GRID_FACTOR))
            }
            Pattern::Irregular { .. } => None,
        }
    }
}

/// `s` seconds in ms, to the tenth (hundredth below 1 ms), without a
/// trailing zero: 4.5, 5, 9.
pub fn ms(s: f64) -> String {
    let v = s * 1e3;
    let text = if v >= 1.0 {
        format!("{v:.1}")
    } else {
        format!("{v:.2}")
    };
    text.trim_end_matches('0').trim_end_matches('.').to_string()
}

/// `a, b and c`.
pub fn and_list(items: &[String]) -> String {
    match items {
        [] => String::new(),
        [one] => one.clone(),
        [head @ .., last] => format!("{} and {last}", head.join(", ")),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Stamps stepping `steps` in turn, `n` steps.
    fn stepping(steps: &[f64], n: usize) -> Vec<f64> {
        let mut t = vec![0.0];
        for k in 0..n {
            let last = t[k];
            t.push(last + steps[k % steps.len()]);
        }
        t
    }

    #[test]
    fn steps_on_several_values_no_clock_makes_are_irregular() {
        let t = stepping(&[4.5e-3, 5e-3, 5e-3, 9e-3], 400);
        let v = irregular_steps(&t).unwrap();
        let got: Vec<(String, usize)> = v.iter().map(|s| (ms(s.step_s), s.count)).collect();
        assert_eq!(got, [("4.5".into(), 100), ("5".into(), 200), ("9".into(), 100)]);
    }

    #[test]
    fn a_clock_its_losses_and_its_rounding_are_not_irregular() {
        // One value with jitter.
        let jitter: Vec<f64> = (0..400)
            .map(|k| k as f64 * 5e-3 + 1e-5 * ((k * 7919) % 13) as f64)
            .collect();
        assert!(irregular_steps(&jitter).is_none());
        // Whole multiples: samples not logged.
        assert!(irregular_steps(&stepping(&[4e-3, 4e-3, 8e-3], 400)).is_none());
        // A 200.6 Hz clock stamped in whole ms: 4 and 5 ms, one unit apart.
        let rounded: Vec<f64> = (0..2000)
            .map(|k| (k as f64 / 200.6 * 1e3).floor() * 1e-3)
            .collect();
        assert!(irregular_steps(&rounded).is_none());
        // A few odd steps are not a value the steps cluster on.
        assert!(
            irregular_steps(&stepping(
                &[5e-3; 99].iter().copied().chain([7e-3]).collect::<Vec<_>>(),
                400
            ))
            .is_none()
        );
    }

    #[test]
    fn a_regular_duty_cycle_is_bursts_and_irregular_pauses_are_not() {
        // 5 s of 50 Hz every 305 s, eight bursts, the last cut to 2 s.
        let mut t = Vec::new();
        let mut gaps = Vec::new();
        for b in 0..8 {
            if b > 0 {
                gaps.push(t.len());
            }
            let n = if b == 7 { 100 } else { 250 };
            t.extend((0..n).map(|k| b as f64 * 305.0 + k as f64 * 0.02));
        }
        let Some(Pattern::Bursts {
            burst_s,
            period_s,
            bursts: n,
        }) = bursts(&t, &gaps)
        else {
            panic!("not bursts");
        };
        assert_eq!(n, 8);
        assert!((burst_s - 4.98).abs() < 1e-9 && (period_s - 305.0).abs() < 1e-9);
        let factor = bursts(&t, &gaps).unwrap().grid_factor(50.0).unwrap();
        assert_eq!(factor, (1.25f64 * 305.0 / 5.0).ceil() as usize);
        // One pause twice as long: not a duty cycle.
        let mut odd = t.clone();
        for v in &mut odd[gaps[3]..] {
            *v += 305.0;
        }
        assert!(bursts(&odd, &gaps).is_none());
        // Too few bursts to be a pattern.
        assert!(bursts(&t[..gaps[2]], &gaps[..2]).is_none());
    }
}
