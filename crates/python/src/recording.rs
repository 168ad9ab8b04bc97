//! `imutherm.read`: any recording the command line reads (text logs, ROS
//! bags, ULog, DataFlash), through [`analysis::robot_logs`], as a dictionary
//! the Python `Recording` class wraps. The channels' samples move into NumPy
//! arrays without a copy.

use std::path::PathBuf;

use analysis::channel_checks::Checks;
use analysis::reading::{ReadingChoices, recording_options};
use analysis::robot_logs::Stream;
use analysis::source::{Source, read_source};
use imu::{ReadReport, Recording};
use numpy::IntoPyArray;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use crate::errors::analysis_err;
use crate::stamps::stamp_slots;

/// Reads `path` as `imutherm info` does (with several IMU streams and none
/// chosen, `info` summarises the first; here, as in every analysis, the
/// reader refuses and lists them).
#[pyfunction]
#[pyo3(signature = (path, rate=None, units=Vec::new(), topic=None, instance=None, temp_topic=None, allow_partial=false))]
#[allow(clippy::too_many_arguments)]
pub fn read(
    py: Python<'_>,
    path: PathBuf,
    rate: Option<f64>,
    units: Vec<String>,
    topic: Option<String>,
    instance: Option<u32>,
    temp_topic: Option<String>,
    allow_partial: bool,
) -> PyResult<Py<PyDict>> {
    let choices = ReadingChoices {
        rate_hz: rate,
        units,
        stream: imu::StreamChoice {
            topic,
            instance,
            temp_topic,
            first_if_several: false,
            allow_partial,
        },
        ..ReadingChoices::default()
    };
    let opts = recording_options(&choices).map_err(analysis_err)?;
    // The channel checks read every sample: with the GIL released, as the
    // read itself.
    let (source, checks) = py
        .detach(|| {
            read_source(&path, &opts).map(|source| {
                let checks = analysis::channel_checks::check(&source.recording);
                (source, checks)
            })
        })
        .map_err(analysis_err)?;
    let Source {
        format,
        rate_source,
        streams,
        recording: rec,
        report,
        ..
    } = source;
    let slots = rec
        .timestamps
        .as_ref()
        .map(|t| stamp_slots(t, rec.rate_hz, rec.len(), report.dropped_samples).map(|s| s.into_pyarray(py)));
    let d = recording_dict(py, rec)?;
    put_checks(py, &d, &checks)?;
    d.set_item("timestamp_slots", slots.flatten())?;
    d.set_item("file", path.display().to_string())?;
    d.set_item("format", format)?;
    d.set_item("rate_source", rate_source.name())?;
    put_report(py, &d, &report)?;
    d.set_item("streams", streams_list(py, &streams)?)?;
    Ok(d.unbind())
}

/// The channels, rate, time stamps and metadata of a recording; the samples
/// move into NumPy arrays.
pub(crate) fn recording_dict(py: Python<'_>, rec: Recording) -> PyResult<Bound<'_, PyDict>> {
    let d = PyDict::new(py);
    let channels = PyList::empty(py);
    for ch in rec.channels {
        let c = PyDict::new(py);
        c.set_item("name", &ch.name)?;
        c.set_item("source", &ch.source_name)?;
        c.set_item("quantity", ch.quantity.name())?;
        c.set_item("unit", &ch.unit)?;
        c.set_item("unit_source", ch.unit_source.name())?;
        c.set_item("data", ch.data.into_pyarray(py))?;
        channels.append(c)?;
    }
    d.set_item("channels", channels)?;
    d.set_item("rate_hz", rec.rate_hz)?;
    d.set_item("timestamps", rec.timestamps.map(|t| t.into_pyarray(py)))?;
    let meta = PyDict::new(py);
    meta.set_item("device", rec.meta.device)?;
    meta.set_item("start_time", rec.meta.start_time)?;
    meta.set_item("entries", rec.meta.entries)?;
    d.set_item("metadata", meta)?;
    Ok(d)
}

/// What the channels rule out, as `imutherm info --json` gives it under
/// `checks.findings`: a kind, the sentence and the figures.
fn put_checks(py: Python<'_>, d: &Bound<'_, PyDict>, checks: &Checks) -> PyResult<()> {
    let list = PyList::empty(py);
    for f in &checks.findings {
        // The finding's own fields, through serde (its `kind` tag first),
        // and its sentence.
        let q = pythonize::pythonize(py, f)?.cast_into::<PyDict>()?;
        q.set_item("message", f.to_string())?;
        list.append(q)?;
    }
    d.set_item("checks", list)
}

fn put_report(py: Python<'_>, d: &Bound<'_, PyDict>, report: &ReadReport) -> PyResult<()> {
    d.set_item("lines", report.lines)?;
    d.set_item("notes", report.notes.clone())?;
    d.set_item("dropped_samples", report.dropped_samples)?;
    d.set_item("problems_unlisted", report.unlisted)?;
    let problems = PyList::empty(py);
    for p in &report.problems {
        let q = PyDict::new(py);
        q.set_item("kind", p.kind.name())?;
        q.set_item("line", p.line)?;
        q.set_item("column", p.column)?;
        q.set_item("channel", p.channel.clone())?;
        q.set_item("count", p.count)?;
        q.set_item("message", &p.message)?;
        problems.append(q)?;
    }
    d.set_item("problems", problems)?;
    match &report.timing {
        Some(t) => {
            let c = PyDict::new(py);
            c.set_item("rate_hz", t.rate_hz)?;
            c.set_item("jitter_s", t.jitter_s)?;
            c.set_item("median_step_s", t.median_step_s)?;
            c.set_item("fitted_samples", t.fitted_samples)?;
            c.set_item("gaps", t.gaps.len())?;
            c.set_item("duplicate_stamps", t.duplicates.len())?;
            c.set_item("backward_stamps", t.backwards.len())?;
            d.set_item("clock", c)?;
        }
        None => d.set_item("clock", py.None())?,
    }
    Ok(())
}

fn streams_list<'py>(py: Python<'py>, streams: &[Stream]) -> PyResult<Bound<'py, PyList>> {
    let list = PyList::empty(py);
    for s in streams {
        let q = PyDict::new(py);
        q.set_item("name", &s.name)?;
        q.set_item("kind", s.kind)?;
        q.set_item("instance", s.instance)?;
        q.set_item("message_type", &s.message_type)?;
        q.set_item("messages", s.messages)?;
        q.set_item("rate_hz", s.rate_hz)?;
        q.set_item("temperature_source", &s.temperature_source)?;
        q.set_item("selected", s.selected)?;
        list.append(q)?;
    }
    Ok(list)
}
