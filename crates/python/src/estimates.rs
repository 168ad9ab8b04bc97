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
