//! Total deviation (NIST SP 1065 §5.2.11, eq. 25).
//!
//! The phase series of N points is extended by reflection at both ends,
//! x*[1−j] = 2x[1] − x[1+j] and x*[N+j] = 2x[N] − x[N−j] for j = 1…N−2, and
//! Totvar(τ) = Σ_{i=2}^{N−1} (x*[i−m] − 2x*[i] + x*[i+m])² / (2τ²(N−2)).
//! This is the doubly reflected form that Stable32 and AllanTools reproduce
//! (Riley's web paper prints different values; they are not used). The
//! extension is indexed, never materialised.

use super::Estimate;
use crate::phase::PhaseSeries;

/// Total deviation at averaging factor m (1 ≤ m ≤ N − 1).
pub fn totdev(series: &PhaseSeries, m: usize) -> Option<Estimate> {
    let x = series.points();
    let n = x.len();
    if m == 0 || n < 3 || m > n - 1 {
        return None;
    }
    let last = n - 1;
    // 0-based reflection: index k may run from −(N−2) to 2N−3.
    let at = |k: isize| -> f64 {
        if k < 0 {
            2.0 * x[0] - x[k.unsigned_abs()]
        } else if (k as usize) > last {
            2.0 * x[last] - x[2 * last - k as usize]
        } else {
            x[k as usize]
        }
    };
    let mi = m as isize;
    let sum: f64 = (1..last)
        .map(|i| {
            let i = i as isize;
            let v = at(i - mi) - 2.0 * at(i) + at(i + mi);
            v * v
        })
        .sum();
    let terms = n - 2;
    let tau = m as f64 * series.tau0();
    Some(Estimate {
        dev: (sum / (2.0 * tau * tau * terms as f64)).sqrt(),
        n: terms,
    })
}
