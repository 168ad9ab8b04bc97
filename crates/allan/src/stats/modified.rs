//! Modified Allan deviation and time deviation (NIST SP 1065 §5.2.5–5.2.6).
//!
//! Mod σ²(τ) = Σ_j [Σ_{i=j}^{j+m−1} (x[i+2m] − 2x[i+m] + x[i])]² / (2 m² τ² n),
//! n = N − 3m + 1 (SP 1065 eq. 15). The inner sums over a sliding window of m
//! second differences are kept as a running sum, so each τ costs O(N) rather
//! than O(N·m); the running sum is recomputed exactly at intervals of at least
//! m steps, which bounds rounding drift while keeping the cost O(N).

use super::Estimate;
use crate::phase::PhaseSeries;

/// Steps between exact recomputations of the running window sum.
const RESYNC: usize = 1024;

/// Modified Allan deviation at averaging factor m.
pub fn mdev(series: &PhaseSeries, m: usize) -> Option<Estimate> {
    let x = series.points();
    if m == 0 || x.len() < 3 * m {
        return None;
    }
    let terms = x.len() - 3 * m + 1;
    // A second difference with a missing phase point counts as zero in the
    // running sum; every window that holds it is skipped below anyway.
    let d = |i: usize| {
        let v = x[i + 2 * m] - 2.0 * x[i + m] + x[i];
        if v.is_nan() { 0.0 } else { v }
    };
    let window = |j: usize| (j..j + m).map(d).sum::<f64>();
    let resync = RESYNC.max(m);
    let gaps = series.gap_index();

    let mut sum = 0.0;
    let mut n = 0usize;
    let mut s = 0.0;
    for j in 0..terms {
        if j % resync == 0 {
            s = window(j);
        } else {
            s += d(j + m - 1) - d(j - 1);
        }
        let usable = match gaps {
            None => true,
            Some(g) => !g.span_has_gap(j, j + 3 * m - 1),
        };
        if usable {
            sum += s * s;
            n += 1;
        }
    }
    (n > 0).then(|| {
        let tau = m as f64 * series.tau0();
        let mf = m as f64;
        Estimate {
            dev: (sum / (2.0 * mf * mf * tau * tau * n as f64)).sqrt(),
            n,
        }
    })
}

/// Time deviation, τ·MDEV/√3 (SP 1065 eq. 16), in seconds of phase (or the
/// integrated unit of the rate data: rad for a gyro, m/s for an accelerometer).
pub fn tdev(series: &PhaseSeries, m: usize) -> Option<Estimate> {
    mdev(series, m).map(|e| Estimate {
        dev: e.dev * m as f64 * series.tau0() / 3f64.sqrt(),
        n: e.n,
    })
}
