//! Bare estimates at given averaging factors ([`allan::stats::compute_many`]),
//! without the stop ratio, EDF or intervals: what the AllanTools drop-in
//! returns, on AllanTools' own tau grid.

use allan::{AllanError, DataType, PhaseSeries, Stat};
use numpy::{IntoPyArray, PyArray1, PyReadonlyArray1};
use pyo3::prelude::*;

use crate::{samples, to_py_err};

/// `stat` of `y` at each averaging factor of `ms`: the deviations and the
/// numbers of terms, NaN and 0 where the series cannot support a factor.
#[pyfunction]
#[pyo3(signature = (stat, y, rate, data_type, ms))]
#[allow(clippy::type_complexity)]
pub fn estimates<'py>(
    py: Python<'py>,
    stat: &str,
    y: PyReadonlyArray1<'py, f64>,
    rate: f64,
    data_type: &str,
    ms: Vec<usize>,
) -> PyResult<(Bound<'py, PyArray1<f64>>, Bound<'py, PyArray1<u64>>)> {
    let stat: Stat = stat.parse().map_err(to_py_err)?;
    let data_type: DataType = data_type.parse().map_err(to_py_err)?;
    let data = samples(&y)?;
    let found = py
        .detach(|| {
            let series = PhaseSeries::new(data, data_type, rate)?;
            if series.has_gaps() && !stat.supports_gaps() {
                return Err(AllanError::GapsNotSupported {
                    stat: stat.name(),
                    count: series.nan_samples(),
                    first: data.iter().position(|v| v.is_nan()).unwrap_or_default(),
                });
            }
            let valid: Vec<usize> = ms.iter().copied().filter(|&m| m >= 1).collect();
            let estimates = allan::stats::compute_many(stat, &series, &valid);
            let mut by_m = valid.into_iter().zip(estimates);
            // Factors below 1 have no estimate; the rest come back in order.
            Ok(ms
                .iter()
                .map(|&m| {
                    if m >= 1 {
                        by_m.next().and_then(|(_, e)| e)
                    } else {
                        None
                    }
                })
                .collect::<Vec<_>>())
        })
        .map_err(to_py_err)?;
    let devs: Vec<f64> = found.iter().map(|e| e.map_or(f64::NAN, |e| e.dev)).collect();
    let ns: Vec<u64> = found.iter().map(|e| e.map_or(0, |e| e.n as u64)).collect();
    Ok((devs.into_pyarray(py), ns.into_pyarray(py)))
}

/// The `p` quantile of the chi-squared distribution with `k` degrees of
/// freedom (k need not be whole), as the engine's intervals use it.
#[pyfunction]
pub fn chi2_quantile(p: f64, k: f64) -> PyResult<f64> {
    if !(p > 0.0 && p < 1.0 && k.is_finite() && k > 0.0) {
        return Err(pyo3::exceptions::PyValueError::new_err(format!(
            "chi2 quantile: p = {p} must lie in (0, 1) and k = {k} be positive"
        )));
    }
    Ok(allan::confidence::chi2_quantile(p, k))
}

/// Greenhall and Riley's EDF of a difference-based variance
/// ([`allan::edf::greenhall_edf`]); None where the variance does not
/// converge for the noise or the record holds no term.
#[pyfunction]
pub fn greenhall_edf(
    alpha: i32,
    d: u32,
    m: usize,
    n: usize,
    overlapping: bool,
    modified: bool,
) -> Option<f64> {
    allan::edf::greenhall_edf(alpha, d, m, n, overlapping, modified)
}

/// The EDF the engine's intervals use for `stat` ([`allan::edf::edf_for`]).
#[pyfunction]
pub fn edf_for(stat: &str, alpha: i32, m: usize, n: usize) -> PyResult<Option<f64>> {
    let stat: Stat = stat.parse().map_err(to_py_err)?;
    Ok(allan::edf::edf_for(stat, alpha, m, n))
}
