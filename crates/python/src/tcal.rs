//! The temperature compensation of `imutherm tcal`: fit, apply, evaluate
//! and export, on [`thermal::tcal`], [`thermal::evaluation`] and
//! [`thermal::firmware`]. A model travels as the JSON text of its model file,
//! so what Python saves is the file `tcal fit` writes.

use std::path::{Path, PathBuf};

use analysis::file_identity::digest;
use analysis::reading::{ReadingChoices, recording_options};
use analysis::selection::{Selection, read_channels};
use imu::RecordingOptions;
use numpy::{IntoPyArray, PyArray1, PyReadonlyArray1};
use pyo3::prelude::*;
use serde_json::json;
use thermal::evaluation::{BinMean, SliceMinimum, bin_means, level, spread, surface_minima};
use thermal::firmware::{self, Calibration, Firmware, Target, sensor_axis};
use thermal::tcal::{FitOptions, Model, Order, Run, TcalChannel, fit};

use crate::errors::{analysis_err, in_context, refused, to_py};

/// Most averaging bins a fit is asked for, as `tcal fit` allows: finer bins
/// hold a sample or two each and the cross-validation would run for hours.
const MAX_FIT_BINS: f64 = 1000.0;
/// Width of the temperature slices whose ADEV minimum `tcal eval` shows, °C.
const EVAL_SLICE_C: f64 = 5.0;

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

fn options(r: Reading) -> PyResult<RecordingOptions> {
    recording_options(&ReadingChoices {
        rate_hz: r.rate,
        units: r.units,
        stream: imu::StreamChoice {
            topic: r.topic,
            instance: r.instance,
            temp_topic: r.temp_topic,
            first_if_several: false,
        },
        ..ReadingChoices::default()
    })
    .map_err(analysis_err)
}

fn model_of(text: &str) -> PyResult<Model> {
    Model::from_json(text).map_err(|e| to_py(&e))
}

/// The channels and the temperature of one run.
fn run_data(file: &Path, channels: &[String], read: &RecordingOptions) -> PyResult<(Selection, Vec<f64>)> {
    let mut sel = read_channels(file, channels, read).map_err(analysis_err)?;
    let Some(temp) = sel.temperature.take() else {
        return Err(refused(format!(
            "{}: no temperature channel to fit against",
            file.display()
        )));
    };
    sel.channels.retain(|c| c.quantity != imu::Quantity::Temperature);
    Ok((sel, temp))
}

fn file_digest(path: &Path) -> PyResult<String> {
    digest(path).map_err(|e| in_context(&format!("reading {}", path.display()), &e))
}

/// The `# device_id:` every run carries, when they carry the same (PX4's
/// TC_x0_ID), read as `tcal fit` reads it.
fn recorded_device_id(files: &[PathBuf]) -> Option<u32> {
    let ids: Vec<Option<u32>> = files
        .iter()
        .map(|f| {
            let reader = imu::table::TableReader::open(f).ok()?;
            let meta = imu::log_file::parse_metadata(reader.comments());
            let v = meta.get("device_id")?.trim().to_string();
            match v.strip_prefix("0x") {
                Some(hex) => u32::from_str_radix(hex, 16).ok(),
                None => v.parse().ok(),
            }
        })
        .collect();
    match ids.first() {
        Some(Some(id)) if ids.iter().all(|i| *i == Some(*id)) => Some(*id),
        _ => None,
    }
}

/// Fits a model on the runs in `files`, as `imutherm tcal fit`; returns the
/// model file's text and the export's warnings for `firmware`.
#[pyfunction]
#[pyo3(signature = (files, channels, order, tref, bin_width, rate_term, firmware, reading))]
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
) -> PyResult<(String, Vec<String>)> {
    let firmware = firmware.map(firmware_of).transpose()?;
    let order = order.map_or(Order::Auto, Order::Fixed);
    if let (Some(fw), Order::Fixed(n)) = (firmware, order)
        && n > Firmware::MAX_ORDER
    {
        return Err(refused(format!(
            "--order {n} --for {}: {} evaluates a cubic at most (--order 3 or auto)",
            fw.key(),
            fw.name()
        )));
    }
    if files.is_empty() {
        return Err(refused("no run to fit on"));
    }
    let read = options(reading)?;
    py.detach(|| {
        let runs: Vec<(Selection, Vec<f64>)> = files
            .iter()
            .map(|f| run_data(f, &channels, &read))
            .collect::<PyResult<_>>()?;
        let digests: Vec<String> = files.iter().map(|f| file_digest(f)).collect::<PyResult<_>>()?;
        for (i, f) in files.iter().enumerate() {
            if let Some(j) =
                (0..i).find(|&j| digests[j] == digests[i] || imu::output::same_file(&files[j], f))
            {
                return Err(refused(format!(
                    "{} and {} are the same recording: give each run once",
                    files[j].display(),
                    f.display()
                )));
            }
        }
        let (lo, hi) = runs
            .iter()
            .flat_map(|(_, t)| t.iter())
            .filter(|t| t.is_finite())
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &t| {
                (a.min(t), b.max(t))
            });
        let bins = ((hi - lo) / bin_width).floor() + 1.0;
        if bins > MAX_FIT_BINS {
            return Err(refused(format!(
                "--bin-width {bin_width}: bins over {lo:.2} to {hi:.2} °C would be {bins:.0}; at most \
                 {MAX_FIT_BINS} are fitted: give a wider bin"
            )));
        }
        let columns: Vec<Vec<TcalChannel>> = runs
            .iter()
            .map(|(sel, _)| {
                sel.channels
                    .iter()
                    .map(|c| TcalChannel::new(c.name.clone(), c.unit.clone(), &c.data))
                    .collect()
            })
            .collect();
        let fit_runs: Vec<Run> = runs
            .iter()
            .zip(&columns)
            .map(|((sel, temp), cols)| Run {
                channels: cols,
                temp,
                rate_hz: sel.rate_hz,
            })
            .collect();
        let opts = FitOptions {
            order,
            t_ref_c: tref,
            bin_width_c: bin_width,
            rate_term,
            max_auto_order: match firmware {
                Some(_) => Firmware::MAX_ORDER,
                None => thermal::tcal::MAX_AUTO_ORDER,
            },
        };
        let names: Vec<String> = files.iter().map(|f| f.display().to_string()).collect();
        let mut model = fit(&fit_runs, &opts).map_err(|e| in_context(&names.join(", "), &e))?;
        model.fitted_on = names;
        model.fitted_on_digests = digests;
        model.device_id = recorded_device_id(&files);
        let warnings = match firmware {
            Some(fw) => {
                firmware::export(&model, fw, Target::default())
                    .map_err(|e| in_context(&format!("the fit cannot be written for {}", fw.name()), &e))?
                    .warnings
            }
            None => Vec::new(),
        };
        let warnings = warnings
            .into_iter()
            .filter(|w| !w.contains("placeholder"))
            .collect();
        let text = serde_json::to_string_pretty(&model).map_err(|e| refused(e.to_string()))?;
        Ok((text + "\n", warnings))
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

/// The exported parameter file and the firmware's view of it.
struct AsLoaded {
    firmware: Firmware,
    text: String,
    warnings: Vec<String>,
    calibration: Calibration,
    cal_temp_c: f64,
}

fn as_loaded(model: &Model, firmware: Firmware, params: Option<&Path>) -> PyResult<AsLoaded> {
    let (text, warnings) = match params {
        Some(path) => (
            std::fs::read_to_string(path)
                .map_err(|e| in_context(&format!("reading {}", path.display()), &e))?,
            Vec::new(),
        ),
        None => {
            let exported = firmware::export(model, firmware, Target::default()).map_err(|e| {
                in_context(
                    &format!("--export {}: the model cannot be written for it", firmware.key()),
                    &e,
                )
            })?;
            (exported.text, exported.warnings)
        }
    };
    // Read back as the ground station loads it, so that what is evaluated is
    // the file, float32 rounding included.
    let calibration = firmware::load(firmware, &text, None).map_err(|e| {
        let what = match params {
            Some(p) => format!(
                "{}: not a {} parameter file imutherm can apply",
                p.display(),
                firmware.name()
            ),
            None => format!("--export {}: the written file does not load", firmware.key()),
        };
        in_context(&what, &e)
    })?;
    Ok(AsLoaded {
        firmware,
        text,
        warnings,
        calibration,
        cal_temp_c: model.t_ref_c,
    })
}

fn bins_json(b: &[BinMean]) -> Vec<serde_json::Value> {
    b.iter()
        .map(|b| json!({"t_c": b.t, "mean": b.mean, "lo": b.mean - 1.96 * b.se, "hi": b.mean + 1.96 * b.se}))
        .collect()
}

fn minima_json(m: &[SliceMinimum]) -> Vec<serde_json::Value> {
    m.iter()
        .map(|m| json!({"t_c": m.t_c, "sigma_min": m.sigma_min, "tau": m.tau}))
        .collect()
}

/// Whether `file` holds a run the model was fitted on (the same bytes).
fn was_fitted_on(model: &Model, file: &Path) -> PyResult<bool> {
    if !model.fitted_on_digests.is_empty() {
        return Ok(model.fitted_on_digests.contains(&file_digest(file)?));
    }
    Ok(model
        .fitted_on
        .iter()
        .any(|f| Path::new(f) == file || imu::output::same_file(Path::new(f), file)))
}

/// `imutherm tcal eval --json`'s document (`imutherm.tcal-eval/1`), as text.
#[pyfunction]
#[pyo3(signature = (model, model_name, files, export, params, reading))]
pub fn tcal_eval(
    py: Python<'_>,
    model: &str,
    model_name: &str,
    files: Vec<PathBuf>,
    export: Option<&str>,
    params: Option<PathBuf>,
    reading: Reading,
) -> PyResult<(String, Vec<String>)> {
    let model = model_of(model)?;
    let read = options(reading)?;
    let firmware = export.map(firmware_of).transpose()?;
    py.detach(|| {
        let loaded = firmware
            .map(|f| as_loaded(&model, f, params.as_deref()))
            .transpose()?;
        let names: Vec<String> = model.channels.iter().map(|c| c.name.clone()).collect();
        let mut rows = Vec::new();
        for file in &files {
            let (sel, temp) = run_data(file, &names, &read)?;
            let held_out = !was_fitted_on(&model, file)?;
            for ch in sel.channels {
                let mut comp = ch.data.clone();
                let report = model
                    .apply(&ch.name, &mut comp, &temp, sel.rate_hz)
                    .map_err(|e| to_py(&e))?;
                let before = bin_means(&ch.data, &temp, 2);
                let after = bin_means(&comp, &temp, 2);
                let (rb, mb) = (spread(&before).rms, spread(&before).max);
                let (ra, ma) = (spread(&after).rms, spread(&after).max);
                let mut row = json!({
                    "file": file.display().to_string(), "held_out": held_out,
                    "channel": ch.name, "unit": ch.unit,
                    "bias_rms_before": rb, "bias_max_before": mb,
                    "bias_rms_after": ra, "bias_max_after": ma,
                    "samples_out_of_range": report.out_of_range,
                    "bins_before": bins_json(&before), "bins_after": bins_json(&after),
                    "adev_minimum_over_temperature_before":
                        minima_json(&surface_minima(&ch.data, &temp, sel.rate_hz, EVAL_SLICE_C)),
                    "adev_minimum_over_temperature_after":
                        minima_json(&surface_minima(&comp, &temp, sel.rate_hz, EVAL_SLICE_C)),
                });
                if let (Some(l), Some((sensor, axis))) = (&loaded, sensor_axis(&ch.name)) {
                    let corrected: Vec<f64> = ch
                        .data
                        .iter()
                        .zip(&temp)
                        .map(|(&x, &t)| l.calibration.correct(sensor, axis, x, t, l.cal_temp_c))
                        .collect();
                    let bins = bin_means(&corrected, &temp, 2);
                    let s = spread(&bins);
                    row["bias_rms_as_loaded"] = json!(s.rms);
                    row["level_before"] = json!(level(&before));
                    row["level_as_loaded"] = json!(level(&bins));
                    row["bias_max_as_loaded"] = json!(s.max);
                    row["bins_as_loaded"] = json!(bins_json(&bins));
                }
                rows.push(row);
            }
        }
        let mut doc = json!({
            "schema": "imutherm.tcal-eval/1",
            "model": model_name,
            "rows": rows,
        });
        let mut warnings = Vec::new();
        if let Some(l) = loaded {
            doc["firmware"] = json!({
                "name": l.firmware.key(),
                "parameters": l.text,
                "warnings": l.warnings,
                "cal_temp_c": matches!(l.firmware, Firmware::ArduPilot).then_some(l.cal_temp_c),
            });
            warnings = l.warnings;
        }
        let text = serde_json::to_string_pretty(&doc).map_err(|e| refused(e.to_string()))?;
        Ok((text + "\n", warnings))
    })
}

/// `imutherm tcal export`'s parameter file and warnings.
#[pyfunction]
#[pyo3(signature = (model, model_name, firmware, instance, device_id))]
pub fn tcal_export(
    model: &str,
    model_name: &str,
    firmware: &str,
    instance: Option<u8>,
    device_id: Option<u32>,
) -> PyResult<(String, Vec<String>)> {
    let firmware = firmware_of(firmware)?;
    if let Some(n) = instance {
        let range = firmware.instances();
        if !range.contains(&n) {
            return Err(refused(format!(
                "--instance {n}: {} has calibration instances {} to {}",
                firmware.name(),
                range.start(),
                range.end()
            )));
        }
    }
    let model = model_of(model)?;
    let exported = firmware::export(&model, firmware, Target { instance, device_id }).map_err(|e| {
        in_context(
            &format!("{model_name}: cannot be written for {}", firmware.name()),
            &e,
        )
    })?;
    Ok((exported.text, exported.warnings))
}
