//! Hadamard deviation, non-overlapped and overlapped (NIST SP 1065 §5.2.8–5.2.9).
//!
//! On phase x with step m (τ = mτ0):
//! Hσ²(τ) = Σ (x[j+3m] − 3x[j+2m] + 3x[j+m] − x[j])² / (6 n τ²), with j
//! stepping by m (HDEV, SP 1065 eq. 18) or by 1 (OHDEV, eq. 20). Insensitive to
//! a constant frequency drift, which the Allan deviation is not.

use super::Estimate;
use super::differences::{Order, Terms, sum_squared};
use crate::phase::PhaseSeries;

/// Non-overlapped Hadamard deviation at averaging factor m.
pub fn hdev(series: &PhaseSeries, m: usize) -> Option<Estimate> {
    hadamard(series, m, Terms::NonOverlapped)
}

/// Overlapped Hadamard deviation at averaging factor m.
pub fn ohdev(series: &PhaseSeries, m: usize) -> Option<Estimate> {
    hadamard(series, m, Terms::Overlapped)
}

fn hadamard(series: &PhaseSeries, m: usize, terms: Terms) -> Option<Estimate> {
    Order::Third.deviation(sum_squared(series, m, terms, Order::Third), m, series.tau0())
}
