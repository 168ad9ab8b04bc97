//! The IEEE Std 952-1997 error terms of one axis, in SI, and the Allan
//! variance they produce (Annex C):
//!
//! σ²(τ) = 3Q²/τ² + N²/τ + (2 ln2/π)·B² + K²·τ/3 + R²·τ²/2
//!
//! | term | unit (gyro / accel) | generated as |
//! | --- | --- | --- |
//! | Q quantization | rad / m/s | differenced white phase noise of σ = Q |
//! | N white noise (ARW/VRW) | rad/√s / m/s/√s | white rate noise of σ = N/√τ0 |
//! | B bias instability | rad/s / m/s² | flicker: a bank of Gauss–Markov processes |
//! | K rate random walk | rad/s/√s / m/s²/√s | random walk with steps of σ = K·√τ0 |
//! | R rate ramp | rad/s² / m/s³ | R·t |

use serde::{Deserialize, Serialize};

use crate::SimError;

/// The five terms of one axis.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct NoiseTerms {
    /// Quantization noise Q.
    #[serde(default)]
    pub q: f64,
    /// White noise N.
    #[serde(default)]
    pub n: f64,
    /// Bias instability B.
    #[serde(default)]
    pub b: f64,
    /// Rate random walk K.
    #[serde(default)]
    pub k: f64,
    /// Rate ramp R.
    #[serde(default)]
    pub r: f64,
}

impl NoiseTerms {
    /// The Allan variance these terms produce at τ (IEEE 952 Annex C).
    pub fn allan_variance(&self, tau: f64) -> f64 {
        let flicker = 2.0 * std::f64::consts::LN_2 / std::f64::consts::PI;
        3.0 * self.q * self.q / (tau * tau)
            + self.n * self.n / tau
            + flicker * self.b * self.b
            + self.k * self.k * tau / 3.0
            + self.r * self.r * tau * tau / 2.0
    }

    /// Checks every term is finite and not negative; `what` names the axis.
    pub fn validate(&self, what: &str) -> Result<(), SimError> {
        for (name, v) in [
            ("q", self.q),
            ("n", self.n),
            ("b", self.b),
            ("k", self.k),
            ("r", self.r),
        ] {
            if !(v.is_finite() && v >= 0.0) {
                return Err(SimError::InvalidParameter {
                    name: format!("{what}.{name}"),
                    value: v,
                    why: "a noise term must be a finite number ≥ 0",
                });
            }
        }
        Ok(())
    }
}
