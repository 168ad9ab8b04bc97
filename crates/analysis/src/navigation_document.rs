//! The `imutherm.ins/1` JSON document of `imutherm ins --json`, as types:
//! each recording's navigation error beside its prediction and Monte
//! Carlo, raw and compensated. The schema has always given every object's
//! keys in alphabetical order, so the fields are declared in that order;
//! it only gains fields.

use std::collections::BTreeMap;

use ins::drift::Spread;
use ins::prediction::AxisNoise;
use serde::Serialize;

use crate::navigation::{AGREEMENT, CHANNELS, Navigated, Plan, Row};

/// The schema's name and version.
pub const SCHEMA: &str = "imutherm.ins/1";

/// The whole document.
#[derive(Debug, Serialize)]
pub struct NavigationDocument {
    /// One entry per recording.
    pub files: Vec<NavigationEntry>,
    /// The writing imutherm's version.
    pub imutherm_version: &'static str,
    /// [`SCHEMA`].
    pub schema: &'static str,
}

impl NavigationDocument {
    /// The document of these recordings, written by imutherm `version`.
    pub fn new(imutherm_version: &'static str, files: Vec<NavigationEntry>) -> Self {
        NavigationDocument {
            files,
            imutherm_version,
            schema: SCHEMA,
        }
    }
}

/// One recording navigated (raw), or its compensated samples navigated.
#[derive(Debug, Serialize)]
pub struct NavigationEntry {
    /// Alignment window, s.
    pub align_s: f64,
    /// The compensated samples navigated (on the raw entry, with a model).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub compensated: Option<Box<NavigationEntry>>,
    /// One row per report time.
    pub curve: Vec<CurveRow>,
    /// A window starts every this many seconds.
    pub every_s: f64,
    /// The recording (on the raw entry).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub file: Option<String>,
    /// The last report time, s.
    pub horizon_s: f64,
    /// The latitude navigated at, when given.
    pub latitude_deg: Option<f64>,
    /// The compensation model's file (on the compensated entry).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub model: Option<String>,
    /// How far outside the Monte Carlo's interval the closed form may be.
    pub monte_carlo_agreement: f64,
    /// The Monte Carlo's runs.
    pub monte_carlo_runs: usize,
    /// Its seed.
    pub monte_carlo_seed: u64,
    /// Where the noise terms were identified.
    pub noise_from: &'static str,
    /// The noise terms per channel, SI, by channel name.
    pub noise_si: BTreeMap<&'static str, NoiseTerms>,
    /// Where the horizontal prediction stops holding, s.
    pub prediction_stops_at_s: Option<f64>,
    /// Sample rate, Hz.
    pub rate_hz: f64,
    /// Whether the Schuler loop was navigated (a latitude given).
    pub schuler_loop: bool,
    /// Where the height's prediction stops holding, s.
    pub vertical_prediction_stops_at_s: Option<f64>,
    /// Windows navigated.
    pub windows: usize,
    /// Windows left out because they cross a gap.
    pub windows_with_gaps: usize,
}

/// One channel's noise terms, SI.
#[derive(Debug, Serialize)]
pub struct NoiseTerms {
    /// Bias instability.
    pub b: f64,
    /// Rate random walk.
    pub k: f64,
    /// White noise.
    pub n: f64,
}

/// A spread over the windows or runs.
#[derive(Debug, Serialize)]
pub struct SpreadEntry {
    /// Median.
    pub p50: f64,
    /// 95th percentile.
    pub p95: f64,
    /// Root mean square.
    pub rms: f64,
}

impl From<Spread> for SpreadEntry {
    fn from(s: Spread) -> Self {
        SpreadEntry {
            p50: s.p50,
            p95: s.p95,
            rms: s.rms,
        }
    }
}

/// One time since alignment.
#[derive(Debug, Serialize)]
pub struct CurveRow {
    /// Heading error, °.
    pub heading_deg: SpreadEntry,
    /// Horizontal position error, m.
    pub horizontal_position_m: SpreadEntry,
    /// Horizontal velocity error, m/s.
    pub horizontal_velocity_m_s: SpreadEntry,
    /// The Monte Carlo's horizontal position error, m.
    pub monte_carlo_horizontal_position_m: SpreadEntry,
    /// The 95 % interval of its rms, m.
    pub monte_carlo_horizontal_position_rms_95_m: [f64; 2],
    /// The Monte Carlo's height error, m.
    pub monte_carlo_vertical_position_m: SpreadEntry,
    /// The 95 % interval of its rms, m.
    pub monte_carlo_vertical_position_rms_95_m: [f64; 2],
    /// The old name of the DRMS, kept: it is not a 1σ of the distance.
    pub predicted_horizontal_position_1sigma_m: f64,
    /// The closed form's horizontal DRMS, m.
    pub predicted_horizontal_position_drms_m: f64,
    /// Each term's share, m, by term.
    pub predicted_terms_m: BTreeMap<&'static str, f64>,
    /// The closed form's height 1σ, m.
    pub predicted_vertical_position_1sigma_m: f64,
    /// Whether the closed form agrees with the Monte Carlo here.
    pub prediction_within_monte_carlo: bool,
    /// Time since alignment, s.
    pub t_s: f64,
    /// Tilt error, °.
    pub tilt_deg: SpreadEntry,
    /// Height error, m.
    pub vertical_position_m: SpreadEntry,
    /// Whether the height's closed form agrees with the Monte Carlo here.
    pub vertical_prediction_within_monte_carlo: bool,
}

impl CurveRow {
    fn of(r: &Row) -> Self {
        let deg = 180.0 / std::f64::consts::PI;
        let m = &r.measured;
        CurveRow {
            heading_deg: m.heading_rad.scaled(deg).into(),
            horizontal_position_m: m.horizontal_position_m.into(),
            horizontal_velocity_m_s: m.horizontal_velocity_m_s.into(),
            monte_carlo_horizontal_position_m: r.monte_carlo.into(),
            monte_carlo_horizontal_position_rms_95_m: r.monte_carlo_rms_95,
            monte_carlo_vertical_position_m: r.monte_carlo_vertical.into(),
            monte_carlo_vertical_position_rms_95_m: r.monte_carlo_vertical_rms_95,
            predicted_horizontal_position_1sigma_m: r.predicted.total_m,
            predicted_horizontal_position_drms_m: r.predicted.total_m,
            predicted_terms_m: r.predicted.terms.iter().map(|(t, v)| (t.key(), *v)).collect(),
            predicted_vertical_position_1sigma_m: r.predicted.vertical_m,
            prediction_within_monte_carlo: r.prediction_holds(),
            t_s: m.t_s,
            tilt_deg: m.tilt_rad.scaled(deg).into(),
            vertical_position_m: m.vertical_position_m.into(),
            vertical_prediction_within_monte_carlo: r.vertical_prediction_holds(),
        }
    }
}

impl NavigationEntry {
    /// The entry of `n`, navigated at `rate_hz` by `plan` up to
    /// `horizon_s`; `file`, `model` and `compensated` are the caller's to
    /// set.
    pub fn of(n: &Navigated, rate_hz: f64, plan: &Plan, horizon_s: f64) -> Self {
        let axis = |x: &AxisNoise| NoiseTerms {
            b: x.b,
            k: x.k,
            n: x.n,
        };
        let noise_si = CHANNELS
            .iter()
            .enumerate()
            .map(|(k, name)| {
                let x = if k < 3 {
                    &n.noise.accel[k]
                } else {
                    &n.noise.gyro[k - 3]
                };
                (*name, axis(x))
            })
            .collect();
        let latitude_deg = plan.options.latitude_deg;
        NavigationEntry {
            align_s: plan.options.align_s,
            compensated: None,
            curve: n.rows.iter().map(CurveRow::of).collect(),
            every_s: plan.every_s,
            file: None,
            horizon_s,
            latitude_deg,
            model: None,
            monte_carlo_agreement: AGREEMENT,
            monte_carlo_runs: n.monte_carlo_runs,
            monte_carlo_seed: n.monte_carlo_seed,
            noise_from: n.noise_from.key(),
            noise_si,
            prediction_stops_at_s: n.prediction_stops_at(),
            rate_hz,
            schuler_loop: latitude_deg.is_some(),
            vertical_prediction_stops_at_s: n.vertical_prediction_stops_at(),
            windows: n.windows,
            windows_with_gaps: n.windows_with_gaps,
        }
    }
}
