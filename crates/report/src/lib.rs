//! # report — plots and the HTML report of an imutherm experiment
//!
//! SVG plots drawn with plotters and an embedded DejaVu Sans (no system
//! fonts needed): Allan deviations on log-log axes with their confidence
//! bands, the ADEV over temperature as a heat map (log colour scale, τ on a
//! log axis), and bias against temperature with a compensation curve, each
//! also as a PNG file. The [`html`] module renders them with tables through
//! a minijinja template into one self-contained page (no network access
//! needed), escaping everything that comes from a file; [`experiment`]
//! draws the sections of an `analysis` value (thesis tables, ADEV figures,
//! surfaces, compensation, navigation).
//!
//! **What it is not:** no statistics and no reading of recordings (it draws
//! what `analysis`, `allan` and `thermal` computed); the files it writes
//! are figures.
//!
//! ```
//! use report::plots::{Curve, Target, adev_plot};
//! let pts = allan::analyze(&[1.0, 2.0, 1.5, 1.7, 1.2, 1.9, 1.4, 1.6, 1.1, 1.8], &allan::Options::default())
//!     .unwrap()
//!     .points;
//! let svg = adev_plot(Target::Svg, "gyro x", "rad/s", &[Curve::plain("34 °C", &pts)])
//!     .unwrap()
//!     .into_svg()
//!     .unwrap();
//! assert!(svg.starts_with("<svg"));
//! ```

pub mod charts;
pub mod experiment;
pub mod html;
pub mod model_plot;
pub mod navigation_plot;
pub mod page_units;
pub mod plots;

use std::path::PathBuf;

/// A page that cannot be made.
#[derive(Debug, thiserror::Error)]
pub enum ReportError {
    /// A plot could not be drawn.
    #[error(transparent)]
    Plot(#[from] PlotError),
    /// A folder or file of the report could not be written.
    #[error("{}: {cause}", path.display())]
    Io {
        /// The folder or file.
        path: PathBuf,
        /// Why.
        cause: std::io::Error,
    },
    /// A file under one of the report's names that imutherm did not write.
    #[error("{} exists and was not written by imutherm: move it, or choose another --out", .0.display())]
    Foreign(PathBuf),
    /// The page template did not render.
    #[error("page template: {0}")]
    Template(String),
    /// A value the page needs is missing.
    #[error("{0}")]
    Missing(String),
}

/// Drawing failed (plotters' error, as text).
#[derive(Debug, thiserror::Error)]
#[error("plot: {0}")]
pub struct PlotError(pub String);
