//! The thesis's own reading of an ADEV curve, offered by name beside the
//! two estimators so that its tables can be reproduced and compared:
//! `analyzeAllan.m` in the thesis's analysis code (public repository
//! dyx1994/Temperature-dependency-of-a-low-cost-IMU, `DataAnalysisCode/`)
//! takes the forward differences of log σ against log τ, reads N on the
//! −1/2 line through the point whose slope is nearest −1/2 (anywhere on
//! the curve) at τ = 1 s, and takes σ at the first point where the slope
//! turns positive as 0.664·B.
//!
//! It is no estimator imutherm stands behind: the slope nearest −1/2 may
//! lie past the minimum or on a bump, and the first positive slope may be
//! a wiggle of noise. It is labelled as the thesis's wherever it is shown.

use super::{TermValue, flicker_floor};
use crate::Point;

/// N and B as the thesis's script reads them.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ThesisReading {
    /// N, with the interval of the point it was read at, and its τ.
    pub n: Option<TermValue>,
    /// B = σ/0.664 at the first τ where the slope turns positive.
    pub b: Option<TermValue>,
}

/// Reads `points` (by increasing τ) the thesis's way.
pub fn thesis_reading(points: &[Point]) -> ThesisReading {
    let p: Vec<&Point> = points
        .iter()
        .filter(|p| p.dev.is_finite() && p.dev > 0.0 && p.tau > 0.0)
        .collect();
    if p.len() < 2 {
        return ThesisReading::default();
    }
    let d: Vec<f64> = p
        .windows(2)
        .map(|w| (w[1].dev.ln() - w[0].dev.ln()) / (w[1].tau.ln() - w[0].tau.ln()))
        .collect();
    let n = d
        .iter()
        .enumerate()
        .min_by(|a, b| (a.1 + 0.5).abs().total_cmp(&(b.1 + 0.5).abs()))
        .map(|(i, _)| {
            // On the −1/2 line through point i, read at τ = 1 s.
            let s = p[i].tau.sqrt();
            TermValue {
                value: p[i].dev * s,
                lo: p[i].dev_lo * s,
                hi: p[i].dev_hi * s,
                tau: Some(p[i].tau),
            }
        });
    let f = flicker_floor();
    let b = d.iter().position(|&s| s > 0.0).map(|i| TermValue {
        value: p[i].dev / f,
        lo: p[i].dev_lo / f,
        hi: p[i].dev_hi / f,
        tau: Some(p[i].tau),
    });
    ThesisReading { n, b }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::NoiseIdMethod;

    fn point(tau: f64, dev: f64) -> Point {
        Point {
            tau,
            m: 1,
            dev,
            n: 10,
            edf: 10.0,
            dev_lo: dev * 0.9,
            dev_hi: dev * 1.1,
            alpha: 0,
            noise_id: NoiseIdMethod::Assumed,
        }
    }

    #[test]
    fn reads_like_analyze_allan_m() {
        // σ = 2/√τ to τ = 4, flat after 8, up after: slope −1/2 is exact
        // at the first point; the first positive slope starts at τ = 16.
        let taus = [1.0, 2.0, 4.0, 8.0, 16.0, 32.0];
        let devs = [2.0, 2.0 / 2f64.sqrt(), 1.0, 0.9, 0.9, 1.2];
        let pts: Vec<Point> = taus.iter().zip(devs).map(|(&t, d)| point(t, d)).collect();
        let r = thesis_reading(&pts);
        assert!((r.n.unwrap().value - 2.0).abs() < 1e-12);
        let b = r.b.unwrap();
        assert_eq!(b.tau, Some(16.0));
        assert!((b.value - 0.9 / flicker_floor()).abs() < 1e-12);
    }
}
