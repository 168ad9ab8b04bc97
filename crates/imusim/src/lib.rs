//! # imusim — simulated low-cost IMU recordings whose truth is known
//!
//! Six axes (accelerometer and gyroscope) of an MPU-9250-class sensor with
//! the IEEE Std 952 error terms (quantization Q, white noise N, bias
//! instability B, rate random walk K, rate ramp R; see [`terms`] for their
//! Allan variances), a bias that is a polynomial of temperature, noise that
//! scales with temperature, scale-factor errors, gravity for a static
//! orientation, the chip's 16-bit output quantization and clipping and its
//! temperature sensor ([`sensor`]). The chamber temperature follows a
//! [`thermal::Profile`] (constant with a fluctuation, Newton cooling, ramp,
//! heater steps, a file) and the die lags it by a first-order time constant.
//! Everything is configured by a [`SimConfig`] (TOML, see [`config`]) or a
//! named preset ([`presets`]: `mpu9250-thesis`, calibrated to the thesis
//! *Temperature Dependency of a Low-cost IMU*, and `white`).
//!
//! A production line's units scatter around one configuration
//! ([`population`]): noise terms and bias polynomials drawn per unit id,
//! with planted defects for testing a fleet's screening.
//!
//! Bias instability is a bank of Gauss–Markov processes ([`flicker`]) whose
//! Allan deviation is flat within ±5 % over the configured τ range.
//!
//! Reproducible: the same seed gives the same bytes; every term of every
//! axis draws from its own Xoshiro256++ stream, so adding a term leaves the
//! others' realisations unchanged. Streaming: a [`simulate::Generator`]
//! holds O(1) state and hands out chunks of any size (the simulated chip
//! pulls from one), and [`Simulator::write_log`] writes imutherm's log with
//! every true parameter in its `true.*` metadata (listed in [`simulate`]),
//! so an analysis can be checked against the truth.
//!
//! With a latitude ([`config::SensorConfig::latitude_deg`], off by default)
//! the Earth rotates under the static sensor: its gyros read the Earth's
//! rate for the latitude and heading and its accelerometers the normal
//! gravity there ([`earth`]).
//!
//! **What it is not:** not a motion simulator (the sensor is static: no
//! trajectories, no vibration), not a register-level
//! chip (that is `mpu9250::sim`, which uses this generator), and it does not
//! print: the `imutherm simulate` command adds the progress bar and the
//! messages.
//!
//! ```
//! use imusim::{Simulator, presets};
//!
//! // Ten seconds of the thesis's MPU-9250 cooling from 100 °C.
//! let mut cfg = presets::preset("mpu9250-thesis").unwrap();
//! cfg.duration_s = 10.0;
//! cfg.profile = imusim::thermal::Profile::parse("cooling:100:20:1800").unwrap();
//! let sim = Simulator::new(cfg).unwrap();
//! let rec = sim.recording(Some("mpu9250-thesis")).unwrap();
//! // At the thesis's 20 Hz.
//! assert_eq!(rec.len(), 200);
//! // The truth travels with the data, in SI (rad/√s for the gyro's N).
//! let n: f64 = rec.meta.get("true.gyro_x.n").unwrap().parse().unwrap();
//! assert!((n - 0.0084f64.to_radians()).abs() < 1e-12);
//! // The die starts at the chamber's 100 °C, read by a 333.87 LSB/°C sensor.
//! let temp = &rec.channel("temp").unwrap().data;
//! assert!((temp[0] - 100.0).abs() < 1.0 / 333.87);
//! ```

mod error;

pub mod config;
pub use earth;
pub mod flicker;
pub mod history;
pub mod population;
pub mod presets;
pub mod sensor;
pub mod simulate;
pub mod terms;
pub mod thermal;

pub use config::SimConfig;
pub use error::SimError;
pub use simulate::{Chunk, Generator, Simulator};
