//! A periodic disturbance: a sinusoid of amplitude A and frequency f0 in
//! the rate data (a vibration, a pump, a heater's cycle, a crosstalk tone)
//! has the Allan variance
//!
//! σ²(τ) = A²·(sin²(πf0τ)/(πf0τ))²
//!
//! (IEEE Std 952-1997 Annex C, C.7; El-Sheimy, Hou & Niu, "Analysis and
//! modeling of inertial sensors using Allan variance", IEEE TIM 57(1),
//! 2008): it rises as τ² below the period, peaks at πf0τ = 1.166 (τ ≈ 0.37
//! of the period) at 0.525·A², and falls as 1/τ² beyond it with zeros at
//! every whole period. No power law or Gauss–Markov process has that
//! bump; without it in the model a GM or a random walk stands for it,
//! bends the white noise beside it, and no candidate keeps the rules.
//!
//! The sinusoid is fitted by backfitting around the selection of the
//! family ([`super::select`]): its Allan variance is taken off the measured
//! points, the family is selected on what remains, the sinusoid is fitted
//! again to the measured points with the family's curve held, and so on
//! ([`refine`]). It is reported as what it is — a periodic disturbance of
//! that period and amplitude — never as a noise term.

use std::f64::consts::PI;

use super::lm::model_avar;
use crate::Point;

/// πf0τ at the sinusoid's Allan variance peak: the root of
/// tan x = 2x beyond 0 (d/dx of sin⁴x/x²).
pub const PEAK_X: f64 = 1.165_561_185_207_211;

/// A periodic disturbance of the rate data.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Periodic {
    /// The sinusoid's amplitude A (its peak, not its RMS), in the unit of
    /// the rate data.
    pub amplitude: f64,
    /// Its frequency f0, Hz.
    pub frequency_hz: f64,
    /// Its period 1/f0, s.
    pub period: f64,
    /// τ of the octave point nearest the Allan variance's peak, s.
    pub peak_tau: f64,
}

impl Periodic {
    fn new(amp2: f64, f0: f64, peak_tau: f64) -> Periodic {
        Periodic {
            amplitude: amp2.sqrt(),
            frequency_hz: f0,
            period: 1.0 / f0,
            peak_tau,
        }
    }

    /// Its Allan variance at τ.
    pub fn avar(&self, tau: f64) -> f64 {
        self.amplitude * self.amplitude * unit_avar(tau, self.frequency_hz)
    }

    /// One sentence naming it.
    pub fn describe(&self, unit: &str) -> String {
        format!(
            "a periodic disturbance of period ≈ {} s ({:.3} Hz), amplitude {:.3e} {unit}: the bump of the curve \
             at τ ≈ {} s, fitted as a sinusoid's Allan variance, not as a noise term",
            super::tau_text(self.period),
            self.frequency_hz,
            self.amplitude,
            super::tau_text(self.peak_tau)
        )
    }
}

/// The Allan variance of a sinusoid of unit amplitude and frequency `f0`
/// at τ.
pub fn unit_avar(tau: f64, f0: f64) -> f64 {
    let x = PI * f0 * tau;
    if x < 1e-4 {
        // sin⁴x/x² → x²: the closed form's digits are lost below.
        return x * x;
    }
    let s = x.sin();
    s * s * s * s / (x * x)
}

/// The least share of a point's measured variance the family must keep
/// there once the sinusoid is taken off for the point to tell anything of
/// the family.
const MIN_LEFT: f64 = 0.1;

/// The measured points with the sinusoid's Allan variance taken off each
/// (and off both ends of its interval), with each one's index in `pts`;
/// the EDF shrinks with the variance left, as the estimate's absolute
/// spread stays. A point the sinusoid leaves less than [`MIN_LEFT`] of is
/// left out: what remains there is the sinusoid's fit error, not the
/// family.
pub(super) fn subtract(pts: &[Point], tone: &Periodic) -> (Vec<Point>, Vec<usize>) {
    pts.iter()
        .enumerate()
        .filter_map(|(i, p)| {
            let v = p.dev * p.dev;
            let left = v - tone.avar(p.tau);
            if left < MIN_LEFT * v {
                return None;
            }
            let off = |d: f64| (d * d - tone.avar(p.tau)).max(MIN_LEFT * d * d).sqrt();
            let point = Point {
                dev: left.sqrt(),
                dev_lo: off(p.dev_lo),
                dev_hi: off(p.dev_hi),
                edf: p.edf * (left / v).powi(2),
                ..*p
            };
            Some((point, i))
        })
        .unzip()
}

/// A bump of the measured curve above the line of white noise read at
/// its shortest τ: the interior point where the excess over that line is
/// largest and, the lower end of its interval against the upper ends of
/// its neighbours', [`BUMP_RISE`] times theirs, with the excess there at
/// least [`BUMP_SHARE`] of the point. Its sinusoid (f0 at the peak, A² from
/// the excess) starts [`refine`].
pub(super) fn bump(pts: &[Point]) -> Option<Periodic> {
    let n = pts.len();
    if n < 5 {
        return None;
    }
    let white = white_line(pts);
    let excess: Vec<f64> = pts.iter().map(|p| p.dev * p.dev - white / p.tau).collect();
    // The rise is read between the ends of the points' intervals: the
    // scatter of a long-τ point is no bump.
    let low = |i: usize| pts[i].dev_lo * pts[i].dev_lo - white / pts[i].tau;
    let high = |i: usize| pts[i].dev_hi * pts[i].dev_hi - white / pts[i].tau;
    (2..n - 1)
        .filter(|&i| low(i) > BUMP_RISE * high(i - 1).max(high(i + 1)))
        .filter(|&i| excess[i] >= BUMP_SHARE * pts[i].dev * pts[i].dev)
        .max_by(|&a, &b| {
            let share = |i: usize| excess[i] / (pts[i].dev * pts[i].dev);
            share(a).total_cmp(&share(b))
        })
        .map(|i| {
            let f0 = PEAK_X / (PI * pts[i].tau);
            Periodic::new(excess[i] / unit_avar(pts[i].tau, f0), f0, pts[i].tau)
        })
}

/// N² of the white line through the lowest σ²τ of the first three points
/// past the first (which a sensor's filter pulls down); at least 5 points.
fn white_line(pts: &[Point]) -> f64 {
    pts[1..4]
        .iter()
        .map(|p| p.dev * p.dev * p.tau)
        .fold(f64::INFINITY, f64::min)
}

/// Share of a point's variance the bump must carry over the white line:
/// as a process of the family must to enter a model.
const BUMP_SHARE: f64 = super::SHOW_SHARE;

/// How far the excess at the bump must stand over its larger neighbour's:
/// a flicker floor or a random walk over white noise rises or levels off,
/// and rounding makes a level floor's excess jitter.
const BUMP_RISE: f64 = 1.2;

/// The sinusoid that, added to the family's curve `family(τ)`, fits the
/// measured points best (least squares on ln σ̂², each point weighed by
/// its EDF as the family's fit weighs it): f0 searched over an octave each
/// side of `start`'s in steps of 1/32 octave, A² for each f0 by golden
/// section on ln A² over ±4 e-folds of `start`'s.
pub(super) fn fit(pts: &[Point], family: &dyn Fn(f64) -> f64, start: &Periodic) -> Periodic {
    let cost = |amp2: f64, f0: f64| -> f64 {
        pts.iter()
            .map(|p| {
                let m = family(p.tau) + amp2 * unit_avar(p.tau, f0);
                let r = (p.dev * p.dev).ln() - m.ln();
                // Var(ln σ̂²) ≈ 2/ν.
                r * r * p.edf.min(super::MAX_FIT_EDF) / 2.0
            })
            .sum()
    };
    let base = start.amplitude * start.amplitude;
    let mut best = (f64::INFINITY, base, start.frequency_hz);
    for k in -32..=32 {
        let f0 = start.frequency_hz * 2f64.powf(k as f64 / 32.0);
        let (lo, hi) = (base.ln() - 4.0, base.ln() + 4.0);
        let a = golden(lo, hi, |la| cost(la.exp(), f0));
        let c = cost(a.exp(), f0);
        if c < best.0 {
            best = (c, a.exp(), f0);
        }
    }
    let (_, amp2, f0) = best;
    let peak = pts
        .iter()
        .map(|p| p.tau)
        .min_by(|a, b| {
            (a * f0 * PI / PEAK_X)
                .ln()
                .abs()
                .total_cmp(&(b * f0 * PI / PEAK_X).ln().abs())
        })
        .unwrap_or(start.peak_tau);
    Periodic::new(amp2, f0, peak)
}

/// The minimum of a unimodal `f` on [lo, hi] by golden-section search, to
/// 1e-4 of the interval.
fn golden(mut lo: f64, mut hi: f64, f: impl Fn(f64) -> f64) -> f64 {
    let r = (5f64.sqrt() - 1.0) / 2.0;
    let (mut a, mut b) = (hi - r * (hi - lo), lo + r * (hi - lo));
    let (mut fa, mut fb) = (f(a), f(b));
    while hi - lo > 1e-4 {
        if fa < fb {
            hi = b;
            b = a;
            fb = fa;
            a = hi - r * (hi - lo);
            fa = f(a);
        } else {
            lo = a;
            a = b;
            fa = fb;
            b = lo + r * (hi - lo);
            fb = f(b);
        }
    }
    (lo + hi) / 2.0
}

/// Whether the sinusoid carries [`super::SHOW_SHARE`] of the measured
/// variance at a point or more holding [`super::MIN_TERM_EDF`] degrees of
/// freedom: its bump spans about one octave, so on octave points one point
/// is all it can hold the most of (a process of the family must show at
/// [`super::MIN_POINTS`]).
fn shows(pts: &[Point], tone: &Periodic) -> bool {
    let (count, edf) = pts
        .iter()
        .filter(|p| tone.avar(p.tau) >= super::SHOW_SHARE * p.dev * p.dev)
        .fold((0usize, 0.0), |(c, e), p| (c + 1, e + p.edf));
    count >= 1 && edf >= super::MIN_TERM_EDF
}

/// Rounds of backfitting: family, sinusoid, family, …
const ROUNDS: usize = 3;

/// The family's fit of `pts` with a sinusoid beside it, where the curve
/// has a bump ([`bump`]): alternately the family, over the τ range
/// [`range::search`](super::range::search) finds on the points with the
/// sinusoid taken off, and the sinusoid, fitted to the measured points of
/// that range with the family's curve held; until the two describe the
/// range and the sinusoid shows ([`shows`]), or [`ROUNDS`] are done.
/// `None` where there is no bump or no round describes a range.
pub(super) fn search(
    pts: &[Point],
    plain: &dyn Fn(&[Point], f64) -> super::Attempt,
) -> Option<super::range::Found> {
    let mut tone = first_guess(pts)?;
    let mut described = None;
    for _ in 0..ROUNDS {
        let (left, index) = subtract(pts, &tone);
        if left.len() <= super::range::MIN_POINTS {
            break;
        }
        let found = super::range::search(&left, plain);
        let found = back(pts, &index, found, tone);
        let Some(best) = &found.attempt.sel.best else {
            break;
        };
        let (comps, theta) = (best.components.clone(), best.theta.clone());
        let range = &pts[found.start..found.end];
        if found.attempt.describes() && shows(range, &tone) {
            described = Some(found);
            break;
        }
        tone = fit(range, &|tau| model_avar(&comps, &theta, tau), &tone);
    }
    let found = described?;
    // The sinusoid fitted once more with the family of the range, and the
    // family again on the range: kept where the two still describe it.
    let best = found.attempt.sel.best.as_ref()?;
    let (comps, theta) = (best.components.clone(), best.theta.clone());
    let range = &pts[found.start..found.end];
    let again = fit(range, &|tau| model_avar(&comps, &theta, tau), &tone);
    let (left, index) = subtract(range, &again);
    if found.skipped.is_empty() && index.len() == range.len() {
        let attempt = plain(&left, found.slack);
        let with = super::Attempt {
            tone: Some(again),
            left_out: found.attempt.left_out.clone(),
            ..attempt
        };
        if with.describes() && shows(range, &again) {
            return Some(super::range::Found {
                attempt: with,
                ..found
            });
        }
    }
    Some(found)
}

/// The sinusoid's first reading where the points have a bump: against the
/// white line alone, over the points up to four times the bump's τ, so the
/// bump's own reading takes all the excess there for the sinusoid.
fn first_guess(pts: &[Point]) -> Option<Periodic> {
    let start = bump(pts)?;
    let white = white_line(pts);
    let near: Vec<Point> = pts
        .iter()
        .filter(|p| p.tau <= 4.0 * start.peak_tau)
        .copied()
        .collect();
    Some(fit(&near, &|tau| white / tau, &start))
}

/// The family's fit of one window of points with a sinusoid beside it,
/// backfitted as [`search`] does but on the window alone: where the
/// sinusoid read over the whole curve describes no range, each window of
/// [`range::search`](super::range::search) fits its own. `None` where the
/// window has no bump or no round describes it.
pub(super) fn on_window(
    pts: &[Point],
    slack: f64,
    plain: &dyn Fn(&[Point], f64) -> super::Attempt,
) -> Option<super::Attempt> {
    let mut tone = first_guess(pts)?;
    for _ in 0..ROUNDS {
        let (left, index) = subtract(pts, &tone);
        if left.len() <= super::range::MIN_POINTS {
            return None;
        }
        let attempt = plain(&left, slack);
        let best = attempt.sel.best.as_ref()?;
        let (comps, theta) = (best.components.clone(), best.theta.clone());
        let mut left_out = attempt.left_out.clone();
        left_out.extend((0..pts.len()).filter(|i| !index.contains(i)).map(|i| pts[i].tau));
        left_out.sort_unstable_by(f64::total_cmp);
        let with = super::Attempt {
            tone: Some(tone),
            left_out,
            ..attempt
        };
        if with.describes() && shows(pts, &tone) {
            return Some(with);
        }
        tone = fit(pts, &|tau| model_avar(&comps, &theta, tau), &tone);
    }
    None
}

/// A range found on the points `index` keeps of `pts`, in the indices of
/// `pts`, with the sinusoid: the points inside it that the sinusoid holds
/// alone are left out of the family's fit, and said.
fn back(pts: &[Point], index: &[usize], found: super::range::Found, tone: Periodic) -> super::range::Found {
    let (start, end) = (index[found.start], index[found.end - 1] + 1);
    let mut left_out = found.attempt.left_out;
    left_out.extend((start..end).filter(|i| !index.contains(i)).map(|i| pts[i].tau));
    left_out.sort_unstable_by(f64::total_cmp);
    super::range::Found {
        start,
        end,
        skipped: found.skipped.iter().map(|&i| index[i]).collect(),
        attempt: super::Attempt {
            tone: Some(tone),
            left_out,
            ..found.attempt
        },
        ..found
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_peak_is_where_its_derivative_vanishes() {
        // d/dx (sin⁴x/x²) = 0 ⇔ tan x = 2x.
        assert!((PEAK_X.tan() - 2.0 * PEAK_X).abs() < 1e-9);
        let f0 = 1.0;
        let at = |x: f64| unit_avar(x / (PI * f0), f0);
        assert!(at(PEAK_X) > at(PEAK_X * 1.01) && at(PEAK_X) > at(PEAK_X * 0.99));
        assert!((at(PEAK_X) - 0.5246).abs() < 1e-3, "{}", at(PEAK_X));
    }

    #[test]
    fn a_sampled_sinusoid_has_this_allan_variance() {
        // The overlapping AVAR of y(t) = A sin(2πf0t + φ), sampled at 1 kHz
        // over many periods, computed directly from the samples.
        let (a, f0, rate) = (0.3f64, 2.5f64, 1000.0f64);
        let n = 200_000;
        let y: Vec<f64> = (0..n)
            .map(|i| a * (2.0 * PI * f0 * i as f64 / rate + 0.4).sin())
            .collect();
        let mut cum = vec![0.0; n + 1];
        for i in 0..n {
            cum[i + 1] = cum[i] + y[i];
        }
        for m in [10usize, 60, 150, 333, 1000] {
            let tau = m as f64 / rate;
            let count = n + 1 - 2 * m;
            let s: f64 = (0..count)
                .map(|i| {
                    let d = (cum[i + 2 * m] - 2.0 * cum[i + m] + cum[i]) / m as f64;
                    d * d
                })
                .sum();
            let measured = s / (2.0 * count as f64);
            // The average over a window of m samples is the sinc of the
            // sampled signal, to within (πf0/rate)² of the continuous one.
            let want = a * a * unit_avar(tau, f0);
            assert!(
                (measured - want).abs() <= 2e-3 * want.max(a * a * 1e-3),
                "τ = {tau}: {measured} vs {want}"
            );
        }
    }

    fn point(tau: f64, avar: f64, edf: f64) -> Point {
        let dev = avar.sqrt();
        Point {
            tau,
            m: 1,
            n: 1000,
            dev,
            dev_lo: dev * 0.99,
            dev_hi: dev * 1.01,
            edf,
            alpha: 0,
            noise_id: crate::NoiseIdMethod::Assumed,
        }
    }

    #[test]
    fn a_bump_on_white_noise_is_found_and_fitted() {
        let (n2, a2, f0) = (1e-4f64, 4e-4f64, 0.6f64);
        let pts: Vec<Point> = (0..14)
            .map(|k| {
                let tau = 0.01 * 2f64.powi(k);
                point(tau, n2 / tau + a2 * unit_avar(tau, f0), 1e4)
            })
            .collect();
        let start = bump(&pts).expect("a bump");
        assert!((start.peak_tau - 0.64).abs() < 1e-9, "{start:?}");
        let tone = fit(&pts, &|tau| n2 / tau, &start);
        assert!((tone.frequency_hz / f0 - 1.0).abs() < 0.03, "{tone:?}");
        assert!((tone.amplitude / a2.sqrt() - 1.0).abs() < 0.03, "{tone:?}");
        // Taken off, it leaves the white noise.
        let (left, index) = subtract(&pts, &tone);
        assert!(index.len() >= 12, "{index:?}");
        for p in &left {
            assert!((p.dev * p.dev * p.tau / n2 - 1.0).abs() < 0.1, "{p:?}");
        }
    }

    #[test]
    fn white_noise_alone_has_no_bump() {
        let pts: Vec<Point> = (0..14)
            .map(|k| {
                let tau = 0.01 * 2f64.powi(k);
                point(tau, 1e-4 / tau + 1e-7, 1e4)
            })
            .collect();
        assert!(bump(&pts).is_none());
    }
}
