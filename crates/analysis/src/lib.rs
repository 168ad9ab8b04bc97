//! # analysis — imutherm's analyses as values
//!
//! "The thesis", in this crate and across imutherm, is Yongxu Duan's master
//! thesis *Temperature Dependency of a Low-cost IMU* (GEOENGINE, University
//! of Stuttgart), whose experiment imutherm reproduces: an MPU-9250 logged
//! for an hour at each of 34, 43, 62 and 82 °C and while cooling from 100 °C,
//! its noise terms read per run from the Allan deviation, and its bias over
//! temperature.
//!
//! What the `imutherm` binary, the report and the Python package share, so
//! that none of them repeats the pipeline:
//! - [`selection`]: which channels of a file are analysed, read in SI with
//!   their gaps, and what the reader noted on the way;
//! - [`reading`]: the reader's options from what a user gives;
//! - [`channel_spec`]: what a channel list names (a group or a channel);
//! - [`source`]: one read of a recording, with its format, streams and
//!   where its rate came from, which every caller shares;
//! - [`info_document`], [`adev_document`], [`noise_document`],
//!   [`thermal_document`], [`navigation_document`]: the versioned JSON
//!   documents of `info`, `adev`, `noise`, `thermal` and `ins` as types;
//! - [`channel_checks`]: what a recording's channels rule out (a dead or
//!   clipped channel, an accelerometer far from g, motion), with figures;
//! - [`units`]: the unit systems of noise terms (SI, datasheet, thesis);
//! - [`noise`]: each run's ADEV and noise terms;
//! - [`dynamic_adev`]: the OADEV of sliding time windows labelled by their
//!   mean temperature (the thesis's dynamic ADEV), `thermal`'s own, which
//!   `imutherm thermal --by time` slices with too;
//! - [`datasheet`]: a datasheet's figures (built in for a few parts, or a
//!   TOML file), each with its source;
//! - [`summary`]: what an IMU is, first: N, B, K beside the datasheet,
//!   its temperature sensitivity, the compensation's gain, the drift at 60 s;
//! - [`thesis`]: the thesis's noise tables as one model, drawn as text or
//!   HTML by their callers;
//! - [`term_law`]: each noise term's law over temperature across runs or
//!   bins, its interval and whether it is real, and every pair of
//!   temperatures compared (a regression on the models' results, the one
//!   statistic of this crate's own);
//! - [`kalibr`]: Kalibr's `imu.yaml`;
//! - [`navigation`]: what the noise costs in metres without GNSS;
//! - [`compensation`]: the temperature compensation's fit, checks,
//!   firmware view and evaluation document, as `tcal` and Python share them;
//! - [`tcal_instances`]: every IMU instance of a log in one model: its fit,
//!   the instance a compensation takes, the evaluation per instance;
//! - [`experiment`]: the thesis's whole experiment (noise terms, ADEV over
//!   temperature, compensation fitted and evaluated on a held-out run,
//!   navigation) as one value.
//!
//! **What it is not:** no plots and no HTML (`report`), no printing and no
//! flags (the `imutherm` binary), no statistics of its own (`allan`,
//! `thermal`, `ins` compute; this crate chooses what to compute on what).
//! Errors are [`AnalysisError`]s naming the file and channel at fault.
//!
//! ```
//! use allan::noise_terms::Term;
//! use analysis::selection::read_channels;
//! use analysis::units::si_unit;
//! use imu::RecordingOptions;
//!
//! let dir = tempfile::tempdir()?;
//! let path = dir.path().join("run.csv");
//! // A gyro and its temperature, in rad/s and °C by their names.
//! let rows: String = (0..200).map(|i| format!("{},{}\n", (i % 7) as f64 * 1e-3, 30.0 + i as f64 * 0.01)).collect();
//! std::fs::write(&path, format!("gyro_x,temperature\n{rows}"))?;
//! let read = RecordingOptions { rate_hz: Some(100.0), ..RecordingOptions::default() };
//! let sel = read_channels(&path, &[], &read)?;
//! let gyro = &sel.channels[0];
//! assert_eq!((gyro.name.as_str(), sel.rate_hz), ("gyro_x", 100.0));
//! assert_eq!(si_unit(Term::WhiteNoise, gyro.quantity, &gyro.unit), "rad/√s");
//! assert!((sel.temperature_mean_c.unwrap() - 30.995).abs() < 1e-9);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

mod error;

pub mod adev_document;
pub mod channel_checks;
pub mod channel_spec;
pub mod compensation;
pub mod datasheet;
pub use thermal::dynamic_adev;
pub mod experiment;
pub mod file_identity;
pub mod filters;
pub mod info_document;
pub mod kalibr;
pub mod monte_carlo;
pub mod navigation;
pub mod navigation_document;
pub mod noise;
pub mod noise_document;
pub mod reading;
pub mod robot_logs;
pub mod selection;
pub mod source;
pub mod source_facts;
pub mod summary;
pub mod tcal_instances;
pub mod term_law;
pub mod thermal_document;
pub mod thesis;
pub mod units;

pub use error::AnalysisError;
