//! Shared by the integration tests.

/// SplitMix64 + Box–Muller: a small, fixed generator, so the tests do not
/// depend on a random-number crate's stream.
pub struct Gauss(pub u64);

impl Gauss {
    /// Uniform in (0, 1).
    pub fn uniform(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        ((z >> 11) as f64 + 0.5) / (1u64 << 53) as f64
    }

    /// Standard normal.
    pub fn normal(&mut self) -> f64 {
        let (u1, u2) = (self.uniform(), self.uniform());
        (-2.0 * u1.ln()).sqrt() * (2.0 * std::f64::consts::PI * u2).cos()
    }

    /// `n` white samples of standard deviation `sigma`.
    #[allow(dead_code)]
    pub fn series(seed: u64, n: usize, sigma: f64) -> Vec<f64> {
        let mut g = Gauss(seed);
        (0..n).map(|_| sigma * g.normal()).collect()
    }
}
