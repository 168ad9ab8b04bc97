//! `imutherm.simulate`: the recording `imutherm simulate` writes, in memory,
//! from the same configuration (a preset, then the overrides) and the same
//! generator ([`imusim::Simulator`]), a unit of a population included.

use imusim::population::{self, Defect, Scatter};
use imusim::thermal::Profile;
use imusim::{Simulator, presets};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::errors::to_py;
use crate::recording::recording_dict;

#[pyfunction]
#[pyo3(signature = (preset="mpu9250-thesis", duration=None, rate=None, profile=None, seed=None, unit=None, scatter=None, defect=None))]
// One argument per flag of `imutherm simulate`, as Python passes them.
#[allow(clippy::too_many_arguments)]
pub fn simulate<'py>(
    py: Python<'py>,
    preset: &str,
    duration: Option<f64>,
    rate: Option<f64>,
    profile: Option<&str>,
    seed: Option<u64>,
    unit: Option<&str>,
    scatter: Option<&str>,
    defect: Option<&str>,
) -> PyResult<Bound<'py, PyDict>> {
    // The overrides in the order `imutherm simulate` applies them, so that
    // a refused value gets the same message.
    let mut cfg = presets::preset(preset).map_err(|e| to_py(&e))?;
    if let Some(p) = profile {
        cfg.profile = Profile::parse(p).map_err(|e| to_py(&e))?;
    }
    if let Some(d) = duration {
        cfg.duration_s = d;
    }
    if let Some(r) = rate {
        cfg.rate_hz = r;
    }
    if let Some(s) = seed {
        cfg.seed = s;
    }
    cfg.validate().map_err(|e| to_py(&e))?;
    let scatter = scatter
        .map_or(Ok(Scatter::default()), Scatter::parse)
        .map_err(|e| to_py(&e))?;
    let defect = defect.map(Defect::parse).transpose().map_err(|e| to_py(&e))?;
    if unit.is_none() && (defect.is_some() || scatter != Scatter::default()) {
        return Err(to_py(&imusim::SimError::Population(
            "scatter and defect describe a unit: give its id (unit=...)".into(),
        )));
    }
    if let Some(id) = unit {
        cfg = population::draw(&cfg, id, scatter, defect.as_ref()).map_err(|e| to_py(&e))?;
    }
    let mut rec = py
        .detach(|| Simulator::new(cfg).and_then(|sim| sim.recording(Some(preset))))
        .map_err(|e| to_py(&e))?;
    if let Some(id) = unit {
        for (k, v) in population::describe(id, scatter, defect.as_ref()) {
            rec.meta.set(k, v);
        }
    }
    let d = recording_dict(py, rec)?;
    d.set_item("file", py.None())?;
    d.set_item("format", "simulated")?;
    d.set_item("rate_source", "file metadata")?;
    Ok(d)
}
