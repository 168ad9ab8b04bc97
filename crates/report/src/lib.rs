//! # report — plots and the HTML report of an imutherm experiment
//!
//! SVG plots drawn with plotters and an embedded DejaVu Sans (no system
//! fonts needed): Allan deviations on log-log axes with their confidence
//! bands, the ADEV over temperature as a heat map (log colour scale, τ on a
//! log axis), and bias against temperature with a compensation curve. The
//! [`html`] module assembles them with tables into one self-contained page
//! (no network access needed), escaping everything that comes from a file.
//!
//! **What it is not:** no statistics (it draws what `allan` and `thermal`
//! computed) and no file reading.
//!
//! ```
//! use report::plots::{Curve, adev_plot};
//! let pts = allan::analyze(&[1.0, 2.0, 1.5, 1.7, 1.2, 1.9, 1.4, 1.6, 1.1, 1.8], &allan::Options::default())
//!     .unwrap()
//!     .points;
//! let svg = adev_plot("gyro x", "rad/s", &[Curve::plain("34 °C", &pts)]).unwrap();
//! assert!(svg.starts_with("<svg"));
//! ```

pub mod html;
pub mod plots;

/// Drawing failed (plotters' error, as text).
#[derive(Debug, thiserror::Error)]
#[error("plot: {0}")]
pub struct PlotError(pub String);
