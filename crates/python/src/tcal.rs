//! The temperature compensation of `imutherm tcal`: fit, apply, evaluate
//! and export, on [`analysis::compensation`] as the command line calls it.
//! A model travels as the JSON text of its model file, so what Python saves
//! is the file `tcal fit` writes.

use std::path::PathBuf;

use analysis::compensation::{self, FitRequest, RunData};
use analysis::reading::{ReadingChoices, recording_options};
use analysis::tcal_instances::{self as instances, Instances};
use imu::RecordingOptions;
use numpy::{IntoPyArray, PyArray1, PyReadonlyArray1};
use pyo3::prelude::*;
use thermal::firmware::{self, Firmware, Target};
use thermal::tcal::{Model, Order};

use crate::errors::{analysis_err, in_context, refused, to_py};

fn firmware_of(key: &str) -> PyResult<Firmware> {
    match key.trim().to_ascii_lowercase().as_str() {
        "px4" => Ok(Firmware::Px4),
        "ardupilot" => Ok(Firmware::ArduPilot),
        other => Err(refused(format!("firmware '{other}': expected px4 or ardupilot"))),
    }
}

/// The reading flags of `tcal fit` and `tcal eval`, as Python passes them.
#[derive(FromPyObject)]
#[pyo3(from_item_all)]
pub struct Reading {
    rate: Option<f64>,
    units: Vec<String>,
    topic: Option<String>,
    instance: Option<u32>,
    temp_topic: Option<String>,
}

/// The instances asked for: every one with `all`, else the one read.
fn asked(r: &Reading, all: bool) -> Option<Instances> {
    if all {
        Some(Instances::All)
    } else {
        r.instance.map(Instances::One)
    }
}

fn options(r: Reading) -> PyResult<RecordingOptions> {
    recording_options(&ReadingChoices {
        rate_hz: r.rate,
        units: r.units,
        stream: imu::StreamChoice {
            topic: r.topic,
            instance: r.instance,
            temp_topic: r.temp_topic,
            first_if_several: false,
            allow_partial: false,
        },
        ..ReadingChoices::default()
    })
    .map_err(analysis_err)
}

fn model_of(text: &str) -> PyResult<Model> {
    Model::from_json(text).map_err(|e| to_py(&e))
}

/// Fits a model on the runs in `files`, as `imutherm tcal fit`; returns the
/// model file's text and the export's warnings for `firmware`. With
/// `all_instances`, and by default for a firmware on a log of several IMUs,
/// the model holds every instance of the log.
#[pyfunction]
#[pyo3(signature = (files, channels, order, tref, bin_width, rate_term, firmware, reading, all_instances=false))]
// One argument per flag of `tcal fit`, as Python passes them.
#[allow(clippy::too_many_arguments)]
pub fn tcal_fit(
    py: Python<'_>,
    files: Vec<PathBuf>,
    channels: Vec<String>,
    order: Option<usize>,
    tref: Option<f64>,
    bin_width: f64,
    rate_term: bool,
    firmware: Option<&str>,
    reading: Reading,
    all_instances: bool,
) -> PyResult<(String, Vec<String>)> {
    let req = FitRequest {
        order: order.map_or(Order::Auto, Order::Fixed),
        t_ref_c: tref,
        bin_width_c: bin_width,
        rate_term,
        firmware: firmware.map(firmware_of).transpose()?,
    };
    req.check().map_err(analysis_err)?;
    if files.is_empty() {
        return Err(refused("no run to fit on"));
    }
    let asked = asked(&reading, all_instances);
    let topic_named = reading.topic.is_some();
    let read = options(reading)?;
    py.detach(|| {
        let fitted = instances::fit(&files, &req, &read, asked, topic_named, |f, read, pick| {
            RunData::read_each(f, &channels, read, pick)
        })
        .map_err(analysis_err)?;
        let text = serde_json::to_string_pretty(&fitted.model).map_err(|e| refused(e.to_string()))?;
        Ok((text + "\n", fitted.export_warnings))
    })
}

/// Checks a model file's text (as `tcal apply` loads it).
#[pyfunction]
pub fn tcal_check(text: &str) -> PyResult<()> {
    model_of(text).map(|_| ())
}

/// Compensates one channel: a new array and the samples out of range.
#[pyfunction]
pub fn tcal_apply<'py>(
    py: Python<'py>,
    model: &str,
    name: &str,
    data: PyReadonlyArray1<'_, f64>,
    temp: PyReadonlyArray1<'_, f64>,
    rate: f64,
) -> PyResult<(Bound<'py, PyArray1<f64>>, usize)> {
    let model = model_of(model)?;
    let mut out = crate::samples(&data)?.to_vec();
    let temp = crate::samples(&temp)?;
    let report = py
        .detach(|| model.apply(name, &mut out, temp, rate))
        .map_err(|e| to_py(&e))?;
    Ok((out.into_pyarray(py), report.out_of_range))
}

/// The text of the model that compensates a recording of IMU `instance`,
/// as `tcal apply --instance N` picks it: the model itself for one sensor,
/// else that instance's own model.
#[pyfunction]
#[pyo3(signature = (model, model_name, instance))]
pub fn tcal_sensor(model: &str, model_name: &str, instance: Option<u32>) -> PyResult<String> {
    let whole = model_of(model)?;
    if whole.instances.is_empty() {
        return Ok(model.to_string());
    }
    let one = instances::to_apply(&whole, model_name, instance).map_err(|e| to_py(&e))?;
    let text = serde_json::to_string_pretty(&one).map_err(|e| refused(e.to_string()))?;
    Ok(text + "\n")
}

/// Each instance of a model of several, as (its number, its model's text);
/// empty for a model of one sensor.
#[pyfunction]
pub fn tcal_instances(text: &str) -> PyResult<Vec<(u32, String)>> {
    let model = model_of(text)?;
    model
        .instances
        .iter()
        .map(|m| {
            let text = serde_json::to_string_pretty(m).map_err(|e| refused(e.to_string()))?;
            Ok((m.instance.unwrap_or(0), text + "\n"))
        })
        .collect()
}

/// `imutherm tcal eval --json`'s document (`imutherm.tcal-eval/1`), as
/// text, and the export's warnings. A model of several instances is judged
/// per instance (the one in `reading`, or all), as the command line does.
#[pyfunction]
#[pyo3(signature = (model, model_name, files, export, params, reading, all_instances=false))]
// One argument per flag of `tcal eval`, as Python passes them.
#[allow(clippy::too_many_arguments)]
pub fn tcal_eval(
    py: Python<'_>,
    model: &str,
    model_name: &str,
    files: Vec<PathBuf>,
    export: Option<&str>,
    params: Option<PathBuf>,
    reading: Reading,
    all_instances: bool,
) -> PyResult<(String, Vec<String>)> {
    let model = model_of(model)?;
    let asked = asked(&reading, all_instances);
    let read = options(reading)?;
    let firmware = export.map(firmware_of).transpose()?;
    py.detach(|| {
        let loaded = firmware
            .map(|f| compensation::as_loaded(&model, f, params.as_deref()))
            .transpose()
            .map_err(analysis_err)?;
        let doc = instances::evaluate(
            &model,
            model_name,
            &files,
            loaded.as_ref(),
            asked,
            &read,
            RunData::read_each,
        )
        .map_err(analysis_err)?;
        let text = serde_json::to_string_pretty(&doc).map_err(|e| refused(e.to_string()))?;
        Ok((text + "\n", loaded.map(|l| l.warnings).unwrap_or_default()))
    })
}

/// `imutherm tcal export`'s parameter file and warnings.
#[pyfunction]
#[pyo3(signature = (model, model_name, firmware, instance, device_id))]
pub fn tcal_export(
    py: Python<'_>,
    model: &str,
    model_name: &str,
    firmware: &str,
    instance: Option<u8>,
    device_id: Option<u32>,
) -> PyResult<(String, Vec<String>)> {
    let firmware = firmware_of(firmware)?;
    compensation::check_instance(firmware, instance).map_err(analysis_err)?;
    let model = model_of(model)?;
    // Released like every other call, so that a fleet's threads export
    // while others fit.
    let exported = py
        .detach(|| firmware::export(&model, firmware, Target { instance, device_id }))
        .map_err(|e| {
            in_context(
                &format!("{model_name}: cannot be written for {}", firmware.name()),
                &e,
            )
        })?;
    Ok((exported.text, exported.warnings))
}
