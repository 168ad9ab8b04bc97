//! # thermal — how an IMU's noise and bias move with temperature
//!
//! Three tools on top of `allan` and `imu`:
//! - [`surface`]: the Allan deviation over temperature (the thesis's
//!   "3D ADEV"), per temperature bin or per sliding time window, with the
//!   noise terms of each slice;
//! - [`dynamic_adev`]: the sliding time windows themselves, each window's
//!   OADEV labelled by its mean temperature (the thesis's dynamic ADEV);
//! - [`tcal`]: a polynomial compensation of the bias over temperature,
//!   fitted on binned means with the order chosen by cross-validation,
//!   applied as the thesis does, `x_comp = x − (p(T) − p(T_ref))`, never
//!   extrapolated beyond the fitted range; a model is checked before use
//!   ([`ModelError`] names the field at fault);
//! - [`branch`] and [`hysteresis`]: heating or cooling on the temperature
//!   smoothed over minutes, and the two branches' difference where the
//!   data show one;
//! - [`element`] and [`dynamics`]: the element's temperature behind the
//!   logged one (a coarse readout smoothed, a first-order lag) and the search
//!   for lag and hysteresis on held-out cells;
//! - [`firmware`]: a model as PX4's and ArduPilot's parameter files, and
//!   those files applied to samples exactly as the firmware applies them;
//! - [`evaluation`]: what a compensation leaves on a run, the bias over
//!   1 °C bins and the ADEV minimum per temperature slice.
//!
//! **What it is not:** no recordings read or written (`imu`), no printing
//! (the `imutherm` binary), no plots (`report`); the one file it reads is a
//! model ([`tcal::Model::read`]).
//!
//! ```
//! use thermal::tcal::{fit, FitOptions, Order, Run, TcalChannel};
//! // A gyro whose bias is 1e-3 + 2e-5·(T − 40) over a 20 → 60 °C ramp.
//! let temp: Vec<f64> = (0..4000).map(|i| 20.0 + i as f64 * 0.01).collect();
//! let gyro: Vec<f64> = temp.iter().map(|t| 1e-3 + 2e-5 * (t - 40.0)).collect();
//! let channels = vec![TcalChannel::new("gyro_x", "rad/s", gyro.as_slice())];
//! let run = Run { channels: &channels, temp: &temp, rate_hz: 1.0 };
//! let model = fit(&[run], &FitOptions { order: Order::Fixed(1), ..FitOptions::default() }).unwrap();
//! let c = model.channel("gyro_x").unwrap();
//! assert!((c.bias(&model, 50.0) - (1e-3 + 2e-4)).abs() < 1e-9);
//! ```

mod error;
mod model_check;

pub mod branch;
pub mod c_header;
pub mod dynamic_adev;
pub mod dynamics;
pub mod element;
pub mod evaluation;
pub mod firmware;
pub mod hysteresis;
pub mod surface;
pub mod tcal;
pub mod weights;

pub use error::ThermalError;
pub use model_check::{ModelError, ModelFileError};
