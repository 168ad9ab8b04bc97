//! # ins — what the noise and the temperature cost in metres
//!
//! Strapdown inertial navigation of a **static** IMU recording, and the
//! error it accumulates against the static truth (at rest, where it
//! started, in the attitude it was aligned in):
//!
//! - coarse alignment by levelling ([`strapdown::align`]): roll and pitch
//!   from the mean specific force over an alignment window, heading 0
//!   because a MEMS gyro cannot gyrocompass (the horizontal Earth rate is
//!   far below its bias and noise), and the gyro's window mean taken as its
//!   bias, as a filter at rest estimates it;
//! - attitude by quaternion integration with a coning correction, velocity
//!   and position in a local-level frame (x north, y west, z up) with
//!   Somigliana's normal gravity, and the Earth's rate, the transport rate
//!   and Coriolis when a latitude is given ([`strapdown::Navigator`]);
//! - the horizontal position and velocity, tilt, heading and height errors
//!   over many start points of a recording ([`drift::drift_over_windows`]);
//! - their prediction in closed form from the IEEE 952 noise terms, term by
//!   term ([`prediction`]), with the Schuler loop when the latitude is given
//!   ([`schuler`]) and the bias instability from its 1/f spectrum
//!   ([`spectral`]). The Monte Carlo of the same model through the same
//!   navigation lives in `analysis::monte_carlo`, above the simulator; this
//!   crate does not link it.
//!
//! **What it is not:** not a navigation filter (no Kalman filter, no aiding,
//! no bias estimation beyond the alignment window), not a trajectory
//! integrator for a moving vehicle (the truth it compares with is static),
//! and it does no I/O: the `imutherm ins` command reads the recordings and
//! prints.
//!
//! ```
//! use ins::drift::{drift_over_windows, report_times};
//! use ins::strapdown::{ImuData, NavOptions};
//!
//! // Two minutes of a level sensor at 100 Hz with a small gyro bias
//! // appearing after the first ten seconds (the alignment window).
//! let n = 13_000;
//! let zero = vec![0.0; n];
//! let g = vec![earth::STANDARD_GRAVITY; n];
//! let gyro_x: Vec<f64> = (0..n).map(|i| if i < 1000 { 0.0 } else { 1e-4 }).collect();
//! let imu = ImuData { gyro: [&gyro_x, &zero, &zero], accel: [&zero, &zero, &g], rate_hz: 100.0 };
//! let drift = drift_over_windows(&imu, &NavOptions::default(), 10.0, &report_times(120.0)).unwrap();
//! assert_eq!(drift.windows, 1);
//! // g·ε·t³/6 at 60 s: 35 m.
//! let at60 = drift.curve[3].horizontal_position_m.rms;
//! assert!((at60 - earth::STANDARD_GRAVITY * 1e-4 * 60f64.powi(3) / 6.0).abs() < 0.01 * at60);
//! ```

#![deny(missing_docs)]

mod error;

pub mod drift;
pub mod prediction;
pub mod quaternion;
pub mod schuler;
pub mod spectral;
pub mod strapdown;

pub use error::InsError;
