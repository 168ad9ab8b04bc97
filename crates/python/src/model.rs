//! The selected noise model's details as the `imutherm.noise/1` document
//! gives them (`analysis::noise_document`, `analysis::filters`,
//! `analysis::kalibr`): one JSON text, which the Python layer parses, so
//! that a notebook reads the same fields, names and numbers as
//! `imutherm noise --json`.

use allan::noise_terms::NoiseTerms;
use analysis::filters::{FilterParam, FilterParams, StateSpaceTerm, filter_params, gauss_markov_state_space};
use analysis::kalibr::kalibr_params;
use analysis::noise_document::{ModelEntry, model_entry};
use imu::Quantity;
use pyo3::PyResult;
use pyo3::exceptions::PyValueError;
use serde::Serialize;

/// What `noise_terms` adds to the terms: the model, the verdict, the state
/// space, and the filters' parameters where the sensor is known.
#[derive(Serialize)]
struct Details {
    model: ModelEntry,
    /// "fits", "does_not_fit" (a model, p below 0.01) or
    /// "no_candidate_fits" (no candidate keeps the rules); where it is not
    /// "fits", `model.defeat` says where the best candidate parts from the
    /// curve.
    verdict: &'static str,
    state_space: Vec<StateSpaceTerm>,
    filters: Option<Vec<FilterParams>>,
    kalibr: Option<Vec<FilterParam>>,
}

/// The sensor of `quantity` as the Python API names it (as
/// `Channel.quantity` does): "angular_rate", "acceleration" or none.
pub fn parse_quantity(quantity: Option<&str>) -> PyResult<Option<Quantity>> {
    match quantity {
        None => Ok(None),
        Some("angular_rate") => Ok(Some(Quantity::AngularRate)),
        Some("acceleration") => Ok(Some(Quantity::Acceleration)),
        Some(other) => Err(PyValueError::new_err(format!(
            "quantity must be \"angular_rate\" (rad/s) or \"acceleration\" (m/s²), not {other:?}"
        ))),
    }
}

/// The details of `terms`' model as JSON text; the data are in SI units of
/// `quantity` where given.
pub fn details_json(terms: &NoiseTerms, quantity: Option<Quantity>) -> PyResult<String> {
    let m = &terms.model;
    let unit = match quantity {
        Some(Quantity::AngularRate) => "rad/s",
        Some(Quantity::Acceleration) => "m/s^2",
        // The Gauss–Markov σ is in the samples' own unit.
        _ => "unit of y",
    };
    let verdict = match (m.quality.is_some(), m.fits) {
        (_, true) => "fits",
        (true, false) => "does_not_fit",
        (false, false) => "no_candidate_fits",
    };
    let details = Details {
        model: model_entry(m, unit),
        verdict,
        state_space: gauss_markov_state_space(m),
        filters: quantity.and_then(|q| filter_params(q, terms)),
        kalibr: quantity.and_then(|q| kalibr_params(q, terms)),
    };
    serde_json::to_string(&details).map_err(|e| PyValueError::new_err(e.to_string()))
}
