//! The closed-form growth of the horizontal position error of a static,
//! levelled IMU from its IEEE 952 noise terms, per term:
//!
//! | term | horizontal position 1σ, per axis, without the Schuler loop |
//! | --- | --- |
//! | gyro white noise N_g | g·N_g·t^{5/2}/√20 |
//! | accelerometer white noise N_a | N_a·t^{3/2}/√3 |
//! | levelling on N_a over the window T_a | ½·N_a·t²/√T_a |
//! | gyro rate random walk K_g | g·K_g·t^{7/2}/√252, and its lead on the window's mean g·K_g·√(T_a/3)·t³/6 |
//! | gyro bias ε left after alignment | g·ε·t³/6 |
//! | gyro bias taken as the window's mean, from N_g | g·N_g·t³/(6·√T_a) |
//! | accelerometer rate random walk K_a | K_a·t^{5/2}/√20, and its lead on the window's mean ½·K_a·√(T_a/3)·t² |
//! | bias instability B (no closed form) | from its 1/f spectrum, [`crate::spectral`] |
//!
//! (Titterton & Weston, *Strapdown Inertial Navigation Technology*, 2nd
//! ed., §12.3: the error equations of a static system; the integrals of a
//! white rate and a random walk, ∫∫∫ of white noise having variance t⁵/20
//! and of a random walk t⁷/252.) These are the errors of a navigation on a
//! flat, non-rotating Earth, which is what imutherm navigates without a
//! latitude. With one, the navigation carries the transport rate and the
//! Schuler loop closes: each term is then multiplied by its factor of
//! [`crate::schuler`], which bends it away from the power law past about
//! 1/ω_s (13 min) and bounds the oscillating terms.
//!
//! The gyro terms act through the tilt about the other horizontal axis, so
//! each axis's noise is projected onto the local-level frame with the
//! aligned attitude. The terms are independent and are summed in
//! quadrature, over the terms and the two axes: the total is the 2-D rms,
//! DRMS = √(σ_x² + σ_y²), not a 1σ of the horizontal distance (whose median
//! is 0.83 DRMS for equal axes).

use crate::schuler;
use crate::spectral::{self, Kernel};
use crate::strapdown::Alignment;

/// The noise terms of one sensor axis, SI (the gyro's in rad/s, the
/// accelerometer's in m/s²); zero where a term was not identified.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct AxisNoise {
    /// White noise N, unit·√s.
    pub n: f64,
    /// Bias instability B, unit.
    pub b: f64,
    /// Rate random walk K, unit/√s.
    pub k: f64,
}

/// The identified model of the six axes.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct NoiseModel {
    /// The gyro's x, y, z axes (rad/s units).
    pub gyro: [AxisNoise; 3],
    /// The accelerometer's x, y, z axes (m/s² units).
    pub accel: [AxisNoise; 3],
}

/// One term of the prediction.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum PredictedTerm {
    /// The gyro's white noise (angle random walk), through the tilt.
    GyroWhiteNoise,
    /// The accelerometer's white noise (velocity random walk).
    AccelWhiteNoise,
    /// The tilt left by levelling on the accelerometer's white noise over
    /// the alignment window.
    Levelling,
    /// The gyro's rate random walk, through the tilt.
    GyroRateRandomWalk,
    /// The gyro bias left by taking the alignment window's mean out (zero
    /// unless the bias is removed).
    GyroBiasFromAlignment,
    /// The accelerometer's rate random walk.
    AccelRateRandomWalk,
    /// The gyro's bias instability (an upper bound, from its 1/f spectrum).
    GyroBiasInstability,
    /// The accelerometer's bias instability (an upper bound).
    AccelBiasInstability,
}

impl PredictedTerm {
    /// Every term, in the order the documents list them.
    pub const ALL: [PredictedTerm; 8] = [
        PredictedTerm::GyroWhiteNoise,
        PredictedTerm::AccelWhiteNoise,
        PredictedTerm::Levelling,
        PredictedTerm::GyroRateRandomWalk,
        PredictedTerm::GyroBiasFromAlignment,
        PredictedTerm::AccelRateRandomWalk,
        PredictedTerm::GyroBiasInstability,
        PredictedTerm::AccelBiasInstability,
    ];

    /// Its key in imutherm's JSON.
    pub fn key(self) -> &'static str {
        match self {
            PredictedTerm::GyroWhiteNoise => "gyro_white_noise",
            PredictedTerm::AccelWhiteNoise => "accel_white_noise",
            PredictedTerm::Levelling => "levelling",
            PredictedTerm::GyroRateRandomWalk => "gyro_rate_random_walk",
            PredictedTerm::GyroBiasFromAlignment => "gyro_bias_from_alignment",
            PredictedTerm::AccelRateRandomWalk => "accel_rate_random_walk",
            PredictedTerm::GyroBiasInstability => "gyro_bias_instability_bound",
            PredictedTerm::AccelBiasInstability => "accel_bias_instability_bound",
        }
    }
}

/// The prediction at one time since alignment.
#[derive(Debug, Clone, PartialEq)]
pub struct Prediction {
    /// Time since alignment, s.
    pub t_s: f64,
    /// Horizontal position 1σ of each term (both axes in quadrature), m.
    pub terms: Vec<(PredictedTerm, f64)>,
    /// All the terms in quadrature, m: the horizontal 2-D rms (DRMS).
    pub total_m: f64,
    /// The height's 1σ, m: the vertical accelerometer's white noise, the
    /// error of its window mean taken as gravity, its random walk and its
    /// bias instability. No Schuler loop and no gravity gradient act on it
    /// in the navigation, so none here; nor the Coriolis acceleration of
    /// the horizontal velocity error (2Ω·cos L·v_west), which takes over
    /// once that error reaches metres per second.
    pub vertical_m: f64,
}

/// What the prediction needs besides the noise.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PredictionSetup {
    /// The gravity navigated with, m/s².
    pub gravity: f64,
    /// Alignment window, s.
    pub align_s: f64,
    /// Whether the gyro's window mean was taken out (then its white noise
    /// leaves a bias, the `gyro_bias_from_alignment` term).
    pub gyro_bias_removed: bool,
    /// The sensor-to-level rotation (row-major) the noise is projected with.
    pub attitude: [[f64; 3]; 3],
    /// The Schuler rate of the position along level x (north) and y (west),
    /// rad/s, when the navigation closes the loop (a latitude given).
    pub schuler_rate: Option<[f64; 2]>,
}

impl PredictionSetup {
    /// For an alignment (its roll and pitch).
    pub fn from_alignment(a: &Alignment, gravity: f64, align_s: f64, gyro_bias_removed: bool) -> Self {
        PredictionSetup {
            gravity,
            align_s,
            gyro_bias_removed,
            attitude: earth::body_to_level(a.roll, a.pitch, 0.0),
            schuler_rate: None,
        }
    }

    /// Level, for a model with the same noise on x and y.
    pub fn level(gravity: f64, align_s: f64, gyro_bias_removed: bool) -> Self {
        PredictionSetup {
            gravity,
            align_s,
            gyro_bias_removed,
            attitude: earth::body_to_level(0.0, 0.0, 0.0),
            schuler_rate: None,
        }
    }

    /// With the Schuler loop the navigation closes at `latitude_deg` (none:
    /// a flat Earth, no loop): north positions tilt through the meridian
    /// radius, west positions through the prime-vertical radius, as the
    /// transport rate of [`crate::strapdown::Navigator`] does.
    pub fn with_latitude(mut self, latitude_deg: Option<f64>) -> Self {
        self.schuler_rate = latitude_deg.map(|l| {
            let (meridian, prime) = earth::radii(l.to_radians());
            [
                schuler::schuler_rate(self.gravity, meridian),
                schuler::schuler_rate(self.gravity, prime),
            ]
        });
        self
    }
}

/// The horizontal position 1σ at `t` seconds since alignment, per term.
pub fn predict(model: &NoiseModel, setup: &PredictionSetup, t: f64) -> Prediction {
    let c = setup.attitude;
    // The noise of the sensor's axes seen along level axis `i`.
    let along = |axes: &[AxisNoise; 3], i: usize, f: fn(&AxisNoise) -> f64| -> f64 {
        (0..3)
            .map(|j| (c[i][j] * f(&axes[j])).powi(2))
            .sum::<f64>()
            .sqrt()
    };
    let g = setup.gravity;
    let ta = setup.align_s;
    let mut terms = Vec::with_capacity(PredictedTerm::ALL.len());
    for term in PredictedTerm::ALL {
        // Position along level x comes from the tilt about y and the
        // specific force along x; along y, from the tilt about x.
        let per_axis = |pos: usize| -> f64 {
            let tilt_axis = 1 - pos;
            let x = setup.schuler_rate.map_or(0.0, |w| w[pos] * t);
            let ng = along(&model.gyro, tilt_axis, |a| a.n);
            let na = along(&model.accel, pos, |a| a.n);
            match term {
                PredictedTerm::GyroWhiteNoise => {
                    g * ng * t.powf(2.5) / 20f64.sqrt() * schuler::gyro_white(x).sqrt()
                }
                PredictedTerm::AccelWhiteNoise => {
                    na * t.powf(1.5) / 3f64.sqrt() * schuler::accel_white(x).sqrt()
                }
                PredictedTerm::Levelling => 0.5 * na * t * t / ta.sqrt() * schuler::constant_accel(x),
                PredictedTerm::GyroRateRandomWalk => {
                    let k = along(&model.gyro, tilt_axis, |a| a.k);
                    let walk = g * k * t.powf(3.5) / 252f64.sqrt() * schuler::gyro_random_walk(x).sqrt();
                    // The walk has left the window's mean by K·√(T_a/3)
                    // when the navigation starts: a bias, independent of
                    // the walk after it (taken out only with the mean).
                    let left = if setup.gyro_bias_removed {
                        g * k * (ta / 3.0).sqrt() * t.powi(3) / 6.0 * schuler::constant_gyro(x)
                    } else {
                        0.0
                    };
                    walk.hypot(left)
                }
                PredictedTerm::GyroBiasFromAlignment if setup.gyro_bias_removed => {
                    g * ng * t.powi(3) / (6.0 * ta.sqrt()) * schuler::constant_gyro(x)
                }
                PredictedTerm::GyroBiasFromAlignment => 0.0,
                PredictedTerm::AccelRateRandomWalk => {
                    let k = along(&model.accel, pos, |a| a.k);
                    let walk = k * t.powf(2.5) / 20f64.sqrt() * schuler::gyro_white(x).sqrt();
                    // Levelling takes out the window's mean; the walk has
                    // left it by K·√(T_a/3) when the navigation starts.
                    walk.hypot(0.5 * k * (ta / 3.0).sqrt() * t * t * schuler::constant_accel(x))
                }
                PredictedTerm::GyroBiasInstability => {
                    let b = along(&model.gyro, tilt_axis, |a| a.b);
                    if setup.gyro_bias_removed {
                        let kernel = Kernel::Gyro {
                            gravity: g,
                            schuler_rate: setup.schuler_rate.map(|w| w[pos]),
                        };
                        spectral::bias_instability_variance(kernel, b, t, ta).sqrt()
                    } else {
                        // Without the window's mean taken out the 1/f power
                        // below 1/t has no bound: the bias is taken as one of
                        // size B, as IEEE 952 reads B.
                        g * b * t.powi(3) / 6.0 * schuler::constant_gyro(x)
                    }
                }
                PredictedTerm::AccelBiasInstability => {
                    let kernel = Kernel::Accel {
                        schuler_rate: setup.schuler_rate.map(|w| w[pos]),
                    };
                    spectral::bias_instability_variance(kernel, along(&model.accel, pos, |a| a.b), t, ta)
                        .sqrt()
                }
            }
        };
        terms.push((term, per_axis(0).hypot(per_axis(1))));
    }
    let total_m = terms.iter().map(|(_, v)| v * v).sum::<f64>().sqrt();
    let nz = along(&model.accel, 2, |a| a.n);
    let vertical = [
        nz * t.powf(1.5) / 3f64.sqrt(),
        0.5 * nz * t * t / ta.sqrt(),
        along(&model.accel, 2, |a| a.k) * t.powf(2.5) / 20f64.sqrt(),
        0.5 * along(&model.accel, 2, |a| a.k) * (ta / 3.0).sqrt() * t * t,
        spectral::bias_instability_variance(
            Kernel::Accel { schuler_rate: None },
            along(&model.accel, 2, |a| a.b),
            t,
            ta,
        )
        .sqrt(),
    ];
    Prediction {
        t_s: t,
        terms,
        total_m,
        vertical_m: vertical.iter().map(|v| v * v).sum::<f64>().sqrt(),
    }
}

/// A gyro bias ε (rad/s) constant after alignment moves the position by
/// g·ε·t³/6 along the axis it tilts: the deterministic law, m.
pub fn gyro_bias_drift(gravity: f64, bias: f64, t: f64) -> f64 {
    gravity * bias * t.powi(3) / 6.0
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn level_white_noise_is_the_closed_form_on_two_axes() {
        let n = AxisNoise {
            n: 2e-4,
            b: 0.0,
            k: 0.0,
        };
        let a = AxisNoise {
            n: 3e-3,
            b: 0.0,
            k: 0.0,
        };
        let model = NoiseModel {
            gyro: [n; 3],
            accel: [a; 3],
        };
        let setup = PredictionSetup::level(9.8, 10.0, false);
        let p = predict(&model, &setup, 60.0);
        // Written out by hand from the table, per axis, then √2 for two.
        let axis = ((9.8 * 2e-4 * 60f64.powf(2.5) / 20f64.sqrt()).powi(2)
            + (3e-3 * 60f64.powf(1.5) / 3f64.sqrt()).powi(2)
            + (0.5 * 3e-3 * 3600.0 / 10f64.sqrt()).powi(2))
        .sqrt();
        assert!((p.total_m - axis * 2f64.sqrt()).abs() < 1e-12 * axis);
        // A rotation about the vertical leaves the level prediction as it was.
        let mut turned = setup;
        turned.attitude = earth::body_to_level(0.0, 0.0, 0.7);
        assert!((predict(&model, &turned, 60.0).total_m - p.total_m).abs() < 1e-9 * axis);
    }
}
