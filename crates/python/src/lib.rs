//! The `imutherm._imutherm` extension module: the `allan` crate's statistics
//! for NumPy arrays. The Python package around it (`python/imutherm`) checks
//! the arguments, builds the result objects and holds the AllanTools drop-in.
//!
//! Samples arrive as a read-only view of the caller's contiguous `float64`
//! array (no copy on the way in), and every computation runs with the GIL
//! released so that the statistics' own threads and other Python threads run
//! at the same time.

use pyo3::create_exception;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

mod curve;
mod errors;
mod estimates;
mod model;
mod naming;
mod recording;
mod simulation;
mod stamps;
mod tcal;

create_exception!(
    _imutherm,
    ImuthermError,
    PyValueError,
    "Raised when imutherm cannot compute what was asked; its message names settings by their keyword arguments."
);

/// Turns an `allan` error into the Python exception carrying its message.
pub(crate) fn to_py_err(err: allan::AllanError) -> PyErr {
    ImuthermError::new_err(err.to_string())
}

/// The read-only slice of a 1-D array, which the Python layer has made
/// contiguous (a no-op for a contiguous `float64` array).
pub(crate) fn samples<'a>(y: &'a numpy::PyReadonlyArray1<'_, f64>) -> PyResult<&'a [f64]> {
    y.as_slice()
        .map_err(|_| PyValueError::new_err("samples must be a contiguous 1-D float64 array"))
}

#[pymodule]
fn _imutherm(m: &Bound<'_, PyModule>) -> PyResult<()> {
    naming::install();
    m.add("ImuthermError", m.py().get_type::<ImuthermError>())?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add_function(wrap_pyfunction!(curve::analyze, m)?)?;
    m.add_function(wrap_pyfunction!(curve::long_run_note, m)?)?;
    m.add_function(wrap_pyfunction!(curve::noise_terms, m)?)?;
    m.add_function(wrap_pyfunction!(curve::time_library, m)?)?;
    m.add_function(wrap_pyfunction!(estimates::estimates, m)?)?;
    m.add_function(wrap_pyfunction!(estimates::chi2_quantile, m)?)?;
    m.add_function(wrap_pyfunction!(estimates::greenhall_edf, m)?)?;
    m.add_function(wrap_pyfunction!(estimates::edf_for, m)?)?;
    m.add_function(wrap_pyfunction!(recording::read, m)?)?;
    m.add_function(wrap_pyfunction!(simulation::simulate, m)?)?;
    for f in [
        wrap_pyfunction!(tcal::tcal_fit, m)?,
        wrap_pyfunction!(tcal::tcal_check, m)?,
        wrap_pyfunction!(tcal::tcal_apply, m)?,
        wrap_pyfunction!(tcal::tcal_eval, m)?,
        wrap_pyfunction!(tcal::tcal_export, m)?,
        wrap_pyfunction!(tcal::tcal_instances, m)?,
        wrap_pyfunction!(tcal::tcal_sensor, m)?,
    ] {
        m.add_function(f)?;
    }
    Ok(())
}
