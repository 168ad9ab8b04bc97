//! Sums in independent accumulators. One running sum waits on every
//! addition (three to four cycles); four let the additions overlap and
//! still fit the registers beside their operands. They are joined in one
//! fixed tree, so a result has the same bits on every machine.

/// Accumulators per sum.
pub(crate) const LANES: usize = 4;

/// The lanes joined as ((a + b) + (c + d)), then the serial tail added.
#[inline(always)]
pub(crate) fn join(lanes: [f64; LANES], tail: f64) -> f64 {
    let [a, b, c, d] = lanes;
    ((a + b) + (c + d)) + tail
}
