//! # imusim — simulated low-cost IMU recordings whose truth is known
//!
//! Six axes (accelerometer and gyroscope) of an MPU-9250-class sensor with
//! the IEEE Std 952 error terms (quantization Q, white noise N, bias
//! instability B, rate random walk K, rate ramp R; see [`terms`]), a bias
//! that is a polynomial of temperature, noise that scales with temperature,
//! scale-factor errors, gravity for a static orientation, the chip's 16-bit
//! output quantization and clipping and its temperature sensor; the chamber
//! temperature follows a [`thermal::Profile`] (constant, Newton cooling,
//! ramp, heater steps, from a file) and the sensor lags it.
//!
//! Reproducible: the same seed gives the same bytes; each axis draws from
//! its own Xoshiro256++ stream. Streaming: memory does not grow with the
//! duration when writing a log.
//!
//! **What it is not:** not a motion simulator (the sensor is static), and
//! not a register-level chip (that is `mpu9250::sim`, which uses this
//! generator).
//!
//! ```
//! let mut cfg = imusim::presets::preset("white").unwrap();
//! cfg.duration_s = 10.0;
//! let sim = imusim::Simulator::new(cfg).unwrap();
//! let rec = sim.recording(Some("white")).unwrap();
//! assert_eq!(rec.len(), 1000);
//! assert_eq!(rec.meta.get("true.gyro_x.n"), Some("0.00015"));
//! ```

mod error;

pub mod config;
pub mod flicker;
pub mod presets;
pub mod sensor;
pub mod simulate;
pub mod terms;
pub mod thermal;

pub use config::SimConfig;
pub use error::SimError;
pub use simulate::Simulator;
