//! Thermal histories whose bias is not a polynomial of the logged
//! temperature: a generator independent of the [`crate::Simulator`]'s
//! assumption (and of `thermal::dynamics`'s model), to check a
//! compensation against what real MEMS do.
//!
//! - The element's temperature lags the logged die temperature through a
//!   first-order lag of 60–200 s, integrated here by sub-stepped Euler
//!   (not the exact response the model uses).
//! - The bias is a cubic of the element's temperature, plus a hysteresis:
//!   the element reads as if `X/2` °C warmer while it has been heating and
//!   cooler while cooling (X, 2.5–15 °C, "worth X °C of the slope"), through
//!   a direction state that relaxes towards the sign of the element's rate
//!   over its own time constant, so it saturates and fades on a plateau.
//! - MPU-9250 noise: white (0.01 °/s/√Hz, 300 µg/√Hz), a Gauss–Markov
//!   bias wander, 16-bit output steps (±500 °/s, ±8 g), and the
//!   temperature register's 1/333.87 °C steps (or whole °C, as Bosch parts
//!   report to PX4).
//! - A scale factor that moves with temperature (on the accelerometer
//!   axis that carries gravity).

use rand::{RngExt, SeedableRng};
use rand_distr::{Distribution, Normal};
use rand_xoshiro::Xoshiro256PlusPlus;

/// The axes, in imutherm's channel order.
pub const AXES: [&str; 6] = ["gyro_x", "gyro_y", "gyro_z", "accel_x", "accel_y", "accel_z"];
/// Temperature the cubics are written about, °C.
pub const T_MID_C: f64 = 40.0;
/// The MPU-9250's temperature register step, °C.
pub const MPU9250_TEMP_STEP_C: f64 = 1.0 / 333.87;
const G: f64 = earth::STANDARD_GRAVITY;

/// What one sensor does, drawn from a seed.
#[derive(Debug, Clone, PartialEq)]
pub struct Truth {
    /// The element's lag behind the logged temperature, s.
    pub lag_s: f64,
    /// Hysteresis: the element reads as if this many °C apart between
    /// heating and cooling.
    pub hysteresis_c: f64,
    /// Time constant of the direction state, s.
    pub direction_s: f64,
    /// Per axis, c0 + c1·d + c2·d² + c3·d³ with d = T_element − 40 °C, SI.
    pub cubic: [[f64; 4]; 6],
    /// The accelerometer's scale factor change per °C on the axis that
    /// carries gravity (z), 1/°C.
    pub scale_per_c: f64,
    /// Readout step of the temperature, °C.
    pub temp_step_c: f64,
    /// Scale every thermal effect but the cubic to zero: a pure cubic of
    /// the logged temperature.
    pub pure_cubic: bool,
}

impl Truth {
    /// A sensor drawn from `seed`: lag 60–200 s, hysteresis 2.5–15 °C.
    pub fn draw(seed: u64) -> Truth {
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed ^ 0x7468_6572_6d61_6c21);
        let mut cubic = [[0.0; 4]; 6];
        for (i, c) in cubic.iter_mut().enumerate() {
            let (slope, unit) = if i < 3 { (4e-4, 1.0) } else { (8e-3, 1.0) };
            let sign = if rng.random::<bool>() { 1.0 } else { -1.0 };
            *c = [
                rng.random_range(-1.0..1.0) * slope * 10.0 * unit,
                sign * rng.random_range(0.3..1.0) * slope,
                rng.random_range(-1.0..1.0) * slope / 20.0,
                rng.random_range(-1.0..1.0) * slope / 1000.0,
            ];
        }
        Truth {
            lag_s: rng.random_range(60.0..200.0),
            hysteresis_c: rng.random_range(2.5..15.0),
            direction_s: rng.random_range(60.0..240.0),
            cubic,
            scale_per_c: rng.random_range(-2e-4..2e-4),
            temp_step_c: MPU9250_TEMP_STEP_C,
            pure_cubic: false,
        }
    }

    fn bias(&self, axis: usize, t: f64) -> f64 {
        let d = t - T_MID_C;
        let c = &self.cubic[axis];
        c[0] + d * (c[1] + d * (c[2] + d * c[3]))
    }
}

/// One leg of a temperature profile.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Leg {
    /// A steady ramp to `to_c` at `c_per_min` (positive).
    Ramp {
        /// Target, °C.
        to_c: f64,
        /// Rate, °C/min.
        c_per_min: f64,
    },
    /// Newton's law towards `to_c` with time constant `tau_s`, for `s`.
    Newton {
        /// Ambient, °C.
        to_c: f64,
        /// Time constant, s.
        tau_s: f64,
        /// Duration, s.
        s: f64,
    },
    /// Held for `s`, with a slow drift of `c_per_min`.
    Hold {
        /// Duration, s.
        s: f64,
        /// Drift, °C/min.
        c_per_min: f64,
    },
}

/// A recording: the logged temperature and six channels, and the true
/// bias of each channel (gravity on accel_z included, noise excluded).
#[derive(Debug, Clone)]
pub struct Recording {
    /// Sample rate, Hz.
    pub rate_hz: f64,
    /// The logged temperature, °C, in the readout's steps.
    pub temp: Vec<f64>,
    /// The channels, in [`AXES`] order.
    pub channels: Vec<Vec<f64>>,
    /// The true bias of each channel.
    pub truth: Vec<Vec<f64>>,
}

/// The logged temperature of a profile starting at rest at `start_c`.
fn profile(start_c: f64, legs: &[Leg], rate_hz: f64) -> Vec<f64> {
    let dt = 1.0 / rate_hz;
    let mut t = start_c;
    let mut out = vec![t];
    for leg in legs {
        match *leg {
            Leg::Ramp { to_c, c_per_min } => {
                let step = c_per_min / 60.0 * dt * (to_c - t).signum();
                while (to_c - t).abs() > step.abs() {
                    t += step;
                    out.push(t);
                }
            }
            Leg::Newton { to_c, tau_s, s } => {
                let k = (-dt / tau_s).exp();
                for _ in 0..(s * rate_hz) as usize {
                    t = to_c + (t - to_c) * k;
                    out.push(t);
                }
            }
            Leg::Hold { s, c_per_min } => {
                for _ in 0..(s * rate_hz) as usize {
                    t += c_per_min / 60.0 * dt;
                    out.push(t);
                }
            }
        }
    }
    out
}

/// Records `legs` from `start_c` at `rate_hz` with noise from `seed`.
pub fn record(truth: &Truth, start_c: f64, legs: &[Leg], rate_hz: f64, seed: u64) -> Recording {
    let die = profile(start_c, legs, rate_hz);
    let n = die.len();
    let dt = 1.0 / rate_hz;
    // The element and the direction state, sub-stepped Euler.
    let sub = ((dt / 1.0).ceil() as usize).max(4);
    let h = dt / sub as f64;
    let (mut el, mut dir) = (die[0], 0.0f64);
    let mut element = Vec::with_capacity(n);
    let mut direction = Vec::with_capacity(n);
    for i in 0..n {
        let (a, b) = (die[i.saturating_sub(1)], die[i]);
        for j in 0..sub {
            let x = a + (b - a) * (j + 1) as f64 / sub as f64;
            let rate = (x - el) / truth.lag_s;
            el += h * rate;
            // Saturates at a twentieth of a °C/min.
            let target = (rate / (0.05 / 60.0)).tanh();
            dir += h * (target - dir) / truth.direction_s;
        }
        element.push(el);
        direction.push(dir);
    }
    let (lag_on, hyst_on) = if truth.pure_cubic {
        (false, false)
    } else {
        (true, true)
    };
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed);
    let gyro_white = 0.01f64.to_radians() * rate_hz.sqrt();
    let accel_white = 300e-6 * G * rate_hz.sqrt();
    let gyro_lsb = (1.0f64 / 65.5).to_radians();
    let accel_lsb = G / 4096.0;
    // Bias wander: Gauss–Markov, 300 s, 10 °/h and 50 µg.
    let corr = 300.0;
    let phi = (-dt / corr).exp();
    let wander = [(10.0f64 / 3600.0).to_radians(), 50e-6 * G];
    let mut gm = [0.0f64; 6];
    let unit = Normal::new(0.0, 1.0).expect("unit normal");
    let mut channels = (0..6).map(|_| Vec::with_capacity(n)).collect::<Vec<Vec<f64>>>();
    let mut truths = (0..6).map(|_| Vec::with_capacity(n)).collect::<Vec<Vec<f64>>>();
    for i in 0..n {
        let te = if lag_on { element[i] } else { die[i] };
        let shift = if hyst_on {
            0.5 * truth.hysteresis_c * direction[i]
        } else {
            0.0
        };
        for axis in 0..6 {
            let gyro = axis < 3;
            let mut b = truth.bias(axis, te + shift);
            if axis == 5 {
                b += G * (1.0 + truth.scale_per_c * (te - T_MID_C));
            }
            let (white, lsb, w) = if gyro {
                (gyro_white, gyro_lsb, wander[0])
            } else {
                (accel_white, accel_lsb, wander[1])
            };
            gm[axis] = phi * gm[axis] + w * (1.0 - phi * phi).sqrt() * unit.sample(&mut rng);
            let x = b + gm[axis] + white * unit.sample(&mut rng);
            channels[axis].push((x / lsb).round() * lsb);
            truths[axis].push(b);
        }
    }
    let noise = Normal::new(0.0, 0.02).expect("temperature noise");
    let temp = die
        .iter()
        .map(|t| {
            let read = t + noise.sample(&mut rng);
            (read / truth.temp_step_c).round() * truth.temp_step_c
        })
        .collect();
    Recording {
        rate_hz,
        temp,
        channels,
        truth: truths,
    }
}

/// The calibration runs: a heating ramp at 1.1 °C/min from 20 to 60 °C,
/// and a Newton cooling from a 60 °C soak (τ 1500 s, 90 min).
pub fn calibration_runs() -> [(f64, Vec<Leg>); 2] {
    [
        (
            20.0,
            vec![Leg::Ramp {
                to_c: 60.0,
                c_per_min: 1.1,
            }],
        ),
        (
            60.0,
            vec![Leg::Newton {
                to_c: 20.0,
                tau_s: 1500.0,
                s: 5400.0,
            }],
        ),
    ]
}

/// A held-out run at another rate, flight-like: heating twice as fast,
/// a warm plateau drifting slowly, then a cooling.
pub fn held_out_run() -> (f64, Vec<Leg>) {
    (
        22.0,
        vec![
            Leg::Ramp {
                to_c: 58.0,
                c_per_min: 2.2,
            },
            Leg::Hold {
                s: 1200.0,
                c_per_min: 0.05,
            },
            Leg::Newton {
                to_c: 22.0,
                tau_s: 900.0,
                s: 3000.0,
            },
        ],
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_element_lags_and_the_branches_part() {
        let truth = Truth::draw(3);
        let (start, legs) = held_out_run();
        let r = record(&truth, start, &legs, 1.0, 9);
        assert_eq!(r.temp.len(), r.channels[0].len());
        // Late in the ramp (lag and direction settled), the true bias is
        // that of an element r·τ colder, read X/2 warmer.
        let i = 900;
        let d = (r.temp[i] - 22.0) - 2.2 / 60.0 * i as f64;
        assert!(d.abs() < 0.1, "the ramp is logged: {d}");
        let (lag, half) = (2.2 / 60.0 * truth.lag_s, 0.5 * truth.hysteresis_c);
        let t = r.temp[i];
        let lagged = truth.bias(0, t - lag + half);
        let slope = (truth.bias(0, t + 0.01) - truth.bias(0, t - 0.01)) / 0.02;
        let err = (r.truth[0][i] - lagged).abs();
        assert!(
            err < 0.1 * slope.abs() * (lag + half),
            "{} vs {lagged}",
            r.truth[0][i]
        );
        // The readout is in the register's steps.
        let k = r.temp[10] / MPU9250_TEMP_STEP_C;
        assert!((k - k.round()).abs() < 1e-6);
    }
}
