//! A stability curve with intervals ([`allan::analyze`]) and the noise terms
//! read from it ([`allan::noise_terms::analyze_terms`]), as dictionaries of
//! NumPy arrays.

use allan::noise_terms::{Chosen, NoiseTerms, Term, TermEstimate, analyze_terms};
use allan::{DataType, Options, Point, Stat, TauSpec};
use numpy::{IntoPyArray, PyReadonlyArray1};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::{samples, to_py_err};

/// A tau grid as Python gives it: a name or seconds.
#[derive(FromPyObject)]
pub enum Taus {
    /// "octave", "decade", "all" or "many".
    Name(String),
    /// Explicit taus in seconds.
    Seconds(Vec<f64>),
}

impl Taus {
    fn spec(self) -> PyResult<TauSpec> {
        match self {
            Taus::Name(name) => match name.trim().to_ascii_lowercase().as_str() {
                // A comma list in a string is the command line's spelling, not
                // Python's: a sequence of numbers is.
                "octave" | "decade" | "all" | "many" => name.parse().map_err(crate::to_py_err),
                _ => Err(crate::to_py_err(allan::AllanError::InvalidTaus(name))),
            },
            Taus::Seconds(taus) => {
                if taus.is_empty() || taus.iter().any(|t| !(t.is_finite() && *t > 0.0)) {
                    let list: Vec<String> = taus.iter().map(|t| t.to_string()).collect();
                    return Err(crate::to_py_err(allan::AllanError::InvalidTaus(list.join(","))));
                }
                Ok(TauSpec::List(taus))
            }
        }
    }
}

fn parse<T: std::str::FromStr<Err = allan::AllanError>>(s: &str) -> PyResult<T> {
    s.parse().map_err(to_py_err)
}

/// One column of points as a NumPy array.
fn column<'py, T: numpy::Element>(
    py: Python<'py>,
    points: &[Point],
    f: impl Fn(&Point) -> T,
) -> Bound<'py, PyAny> {
    points
        .iter()
        .map(f)
        .collect::<Vec<T>>()
        .into_pyarray(py)
        .into_any()
}

fn put_points<'py>(py: Python<'py>, dict: &Bound<'py, PyDict>, points: &[Point]) -> PyResult<()> {
    dict.set_item("taus", column(py, points, |p| p.tau))?;
    dict.set_item("m", column(py, points, |p| p.m as u64))?;
    dict.set_item("devs", column(py, points, |p| p.dev))?;
    dict.set_item("lo", column(py, points, |p| p.dev_lo))?;
    dict.set_item("hi", column(py, points, |p| p.dev_hi))?;
    dict.set_item("edf", column(py, points, |p| p.edf))?;
    dict.set_item("n", column(py, points, |p| p.n as u64))?;
    dict.set_item("alpha", column(py, points, |p| p.alpha))?;
    let ids: Vec<&str> = points.iter().map(|p| p.noise_id.name()).collect();
    dict.set_item("noise_id", ids)?;
    Ok(())
}

/// The options `analyze` and `time_library` read from their arguments.
fn options(stat: &str, data_type: &str, rate: f64, taus: Taus, confidence: f64) -> PyResult<Options> {
    Ok(Options {
        stat: parse::<Stat>(stat)?,
        data_type: parse::<DataType>(data_type)?,
        rate_hz: rate,
        taus: taus.spec()?,
        confidence,
    })
}

/// `stat` of the samples `y` over the tau grid `taus`, with intervals at
/// `confidence`: what `imutherm adev` computes.
#[pyfunction]
#[pyo3(signature = (stat, y, rate, taus, data_type, confidence))]
pub fn analyze<'py>(
    py: Python<'py>,
    stat: &str,
    y: PyReadonlyArray1<'py, f64>,
    rate: f64,
    taus: Taus,
    data_type: &str,
    confidence: f64,
) -> PyResult<Bound<'py, PyDict>> {
    let opts = options(stat, data_type, rate, taus, confidence)?;
    let data = samples(&y)?;
    let curve = py.detach(|| allan::analyze(data, &opts)).map_err(to_py_err)?;
    let dict = PyDict::new(py);
    put_points(py, &dict, &curve.points)?;
    dict.set_item("stat", curve.stat.name())?;
    dict.set_item("data_type", curve.data_type.name())?;
    dict.set_item("rate", curve.rate_hz)?;
    dict.set_item("confidence", curve.confidence)?;
    dict.set_item("samples", curve.samples)?;
    dict.set_item("nan_samples", curve.nan_samples)?;
    Ok(dict)
}

/// What the command line says before a long computation of `stat` on `n`
/// samples (`None` for a short one), for `analyze` to warn with first.
#[pyfunction]
#[pyo3(signature = (stat, n, rate, taus, data_type, confidence))]
pub fn long_run_note(
    stat: &str,
    n: usize,
    rate: f64,
    taus: Taus,
    data_type: &str,
    confidence: f64,
) -> PyResult<Option<String>> {
    let opts = options(stat, data_type, rate, taus, confidence)?;
    let operations = allan::work::workload(n, &opts).operations;
    // The cores rayon's pool runs on, as the command line counts them.
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let seconds = allan::work::estimated_seconds(opts.stat, operations, cores);
    Ok(allan::work::long_run_note(opts.stat, operations, seconds, cores))
}

/// The best of `runs` timings, in seconds, of the `allan` library's own
/// `analyze` on the samples, called from Rust with no Python in between:
/// the yardstick `bench/python_vs_allantools.py` measures the Python call
/// against.
#[pyfunction]
#[pyo3(signature = (stat, y, rate, taus, data_type, confidence, runs))]
#[allow(clippy::too_many_arguments)] // analyze's arguments and the run count
pub fn time_library<'py>(
    py: Python<'py>,
    stat: &str,
    y: PyReadonlyArray1<'py, f64>,
    rate: f64,
    taus: Taus,
    data_type: &str,
    confidence: f64,
    runs: usize,
) -> PyResult<f64> {
    let opts = options(stat, data_type, rate, taus, confidence)?;
    let data = samples(&y)?;
    py.detach(|| {
        let mut best = f64::INFINITY;
        for _ in 0..runs.max(1) {
            let start = std::time::Instant::now();
            let curve = allan::analyze(data, &opts)?;
            best = best.min(start.elapsed().as_secs_f64());
            // Keeps the result alive to the end of the timing.
            std::hint::black_box(curve);
        }
        Ok(best)
    })
    .map_err(to_py_err)
}

/// A term's estimate as (value, lo, hi) or the reason it is not identifiable
/// with its upper bound.
fn estimate<'py>(py: Python<'py>, est: &TermEstimate) -> PyResult<Bound<'py, PyDict>> {
    let dict = PyDict::new(py);
    match est {
        TermEstimate::Value(v) => {
            dict.set_item("value", v.value)?;
            dict.set_item("lo", v.lo)?;
            dict.set_item("hi", v.hi)?;
        }
        TermEstimate::NotIdentifiable(reason) => {
            dict.set_item("value", py.None())?;
            dict.set_item("reason", reason)?;
        }
    }
    Ok(dict)
}

fn terms_dict<'py>(py: Python<'py>, terms: &NoiseTerms) -> PyResult<Bound<'py, PyDict>> {
    let out = PyDict::new(py);
    for term in Term::ALL {
        let entry = PyDict::new(py);
        entry.set_item("symbol", term.symbol())?;
        // One estimator now: the keys of the former two methods both
        // carry the selected model's answer.
        let model = estimate(py, terms.model.get(term))?;
        entry.set_item("slope", model.clone())?;
        entry.set_item("fit", model)?;
        entry.set_item("bound", terms.model.bound(term))?;
        // In the selected model as a value, or dropped (its bound stands).
        entry.set_item("kept", terms.model.get(term).value().is_some())?;
        let choice = terms.choose(term);
        let how = match choice.chosen {
            Chosen::Model(_) => "fit",
            Chosen::Bound(_) => "upper_bound",
            Chosen::Nothing => "none",
        };
        entry.set_item("value", choice.value())?;
        entry.set_item("how", how)?;
        entry.set_item("note", choice.note)?;
        out.set_item(term.name(), entry)?;
    }
    Ok(out)
}

/// The IEEE 952 noise terms of rate samples `y`, from the selected noise
/// model, with the octave OADEV curve they were read from, and the model's
/// details as JSON text ([`crate::model::details_json`]; the filters'
/// parameters where `quantity` names the sensor).
#[pyfunction]
#[pyo3(signature = (y, rate, confidence, quantity=None))]
pub fn noise_terms<'py>(
    py: Python<'py>,
    y: PyReadonlyArray1<'py, f64>,
    rate: f64,
    confidence: f64,
    quantity: Option<&str>,
) -> PyResult<Bound<'py, PyDict>> {
    if !(confidence > 0.0 && confidence < 1.0) {
        return Err(to_py_err(allan::AllanError::InvalidConfidence(confidence)));
    }
    let quantity = crate::model::parse_quantity(quantity)?;
    let data = samples(&y)?;
    let (points, terms) = py
        .detach(|| analyze_terms(data, rate, confidence))
        .map_err(to_py_err)?;
    let curve = PyDict::new(py);
    put_points(py, &curve, &points)?;
    let dict = PyDict::new(py);
    dict.set_item("curve", curve)?;
    dict.set_item("terms", terms_dict(py, &terms)?)?;
    dict.set_item("details", crate::model::details_json(&terms, quantity)?)?;
    Ok(dict)
}
