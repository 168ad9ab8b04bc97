//! Allan deviation, non-overlapped and overlapped (NIST SP 1065 §5.2.2–5.2.4).
//!
//! On phase x with step m (τ = mτ0):
//! σ²(τ) = Σ (x[j+2m] − 2x[j+m] + x[j])² / (2 n τ²), with j stepping by m
//! (ADEV, SP 1065 eq. 7) or by 1 (OADEV, eq. 11).

use super::Estimate;
use super::differences::{Order, Terms, sum_squared};
use crate::phase::PhaseSeries;

/// Non-overlapped Allan deviation at averaging factor m.
pub fn adev(series: &PhaseSeries, m: usize) -> Option<Estimate> {
    allan(series, m, Terms::NonOverlapped)
}

/// Overlapped Allan deviation at averaging factor m.
pub fn oadev(series: &PhaseSeries, m: usize) -> Option<Estimate> {
    allan(series, m, Terms::Overlapped)
}

fn allan(series: &PhaseSeries, m: usize, terms: Terms) -> Option<Estimate> {
    Order::Second.deviation(sum_squared(series, m, terms, Order::Second), m, series.tau0())
}
