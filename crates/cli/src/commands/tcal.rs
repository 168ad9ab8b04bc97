//! `imutherm tcal fit | apply | eval`: temperature compensation of the bias
//! (`tcal export` is in `tcal_export`).

use std::io::Write;
use std::path::Path;

use anyhow::{Context, Result, bail};
use serde_json::json;

use imu::output::{AtomicFile, OutputPolicy, check_output, write_file};
use imu::{LogFormat, RecordingOptions, write_recording};
use thermal::evaluation::{BinMean, SliceMinimum, bin_means, level, spread, surface_minima};
use thermal::firmware::{self, Calibration, Firmware, Target, sensor_axis};
use thermal::tcal::{FitOptions, Model, Order, Run, TcalChannel, fit as fit_model};

use analysis::file_identity::digest;
use analysis::selection::Selection;
use imu::output::same_file;

use crate::args::{TcalApplyArgs, TcalEvalArgs, TcalFitArgs};
use crate::flags::{recording_options, usage_error};
use crate::print::read_channels;

/// Reads channels and the temperature of one run.
fn run_data(file: &Path, channels: &[String], read: &RecordingOptions) -> Result<(Selection, Vec<f64>)> {
    let mut sel = read_channels(file, channels, read)?;
    let Some(temp) = sel.temperature.take() else {
        bail!("{}: no temperature channel to fit against", file.display());
    };
    // The temperature itself is not compensated.
    sel.channels.retain(|c| c.quantity != imu::Quantity::Temperature);
    Ok((sel, temp))
}

pub fn fit(a: &TcalFitArgs) -> Result<()> {
    let order = a.order;
    let firmware = a.for_firmware.map(Firmware::from);
    if let (Some(fw), Order::Fixed(n)) = (firmware, order)
        && n > Firmware::MAX_ORDER
    {
        usage_error(format!(
            "--order {n} --for {}: {} evaluates a cubic at most (--order 3 or auto)",
            fw.key(),
            fw.name()
        ));
    }
    let read = recording_options(&a.read)?;
    let policy = OutputPolicy {
        overwrite: a.overwrite,
        inputs: &a.files,
    };
    check_output(&a.output, &policy)?;
    let runs: Vec<(Selection, Vec<f64>)> = a
        .files
        .iter()
        .map(|f| run_data(f, &a.channels, &read))
        .collect::<Result<_>>()?;
    // One run given twice (by two names, or as a copy) would count twice.
    let digests: Vec<String> = a.files.iter().map(|f| file_digest(f)).collect::<Result<_>>()?;
    for (i, f) in a.files.iter().enumerate() {
        if let Some(j) = (0..i).find(|&j| digests[j] == digests[i] || same_file(&a.files[j], f)) {
            usage_error(format!(
                "{} and {} are the same recording: give each run once",
                a.files[j].display(),
                f.display()
            ));
        }
    }
    check_bins(runs.iter().map(|(_, t)| t.as_slice()), a.bin_width)?;
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
        t_ref_c: a.tref,
        bin_width_c: a.bin_width,
        rate_term: a.rate_term,
        max_auto_order: match firmware {
            Some(_) => Firmware::MAX_ORDER,
            None => thermal::tcal::MAX_AUTO_ORDER,
        },
    };
    let names: Vec<String> = a.files.iter().map(|f| f.display().to_string()).collect();
    let mut model = fit_model(&fit_runs, &opts).with_context(|| names.join(", "))?;
    model.fitted_on = names;
    model.fitted_on_digests = digests;
    model.device_id = recorded_device_id(&a.files);
    // A model fitted for a firmware is checked against its export before it
    // is written; its warnings (documented range, missing axes) come now,
    // not at the vehicle.
    let export_warnings = match firmware {
        Some(fw) => {
            firmware::export(&model, fw, Target::default())
                .with_context(|| format!("the fit cannot be written for {}", fw.name()))?
                .warnings
        }
        None => Vec::new(),
    };
    let export_warnings: Vec<String> = export_warnings
        .into_iter()
        .filter(|w| !w.contains("placeholder"))
        .collect();
    let text = serde_json::to_string_pretty(&model)?;
    write_file(&a.output, (text + "\n").as_bytes(), &policy)?;
    eprintln!(
        "wrote {}: {:.1}…{:.1} °C, T_ref {:.2} °C",
        a.output.display(),
        model.t_min_c,
        model.t_max_c,
        model.t_ref_c
    );
    for c in &model.channels {
        eprintln!(
            "  {:<8} order {}  residual RMS {:.3e} {}  max {:.3e}",
            c.name, c.order, c.residual_rms, c.unit, c.residual_max
        );
    }
    for w in &export_warnings {
        eprintln!("warning: {w}");
    }
    Ok(())
}

/// The `# device_id:` the recordings carry, when they all carry the same.
fn recorded_device_id(files: &[std::path::PathBuf]) -> Option<u32> {
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

/// The digest of a run, naming it when it cannot be read.
fn file_digest(path: &Path) -> Result<String> {
    digest(path).with_context(|| format!("reading {}", path.display()))
}

pub fn apply(a: &TcalApplyArgs) -> Result<()> {
    // Checked before anything is read: the recording and the model are
    // never replaced, an existing file only with --overwrite.
    let inputs = [a.model.clone(), a.file.clone()];
    let policy = OutputPolicy {
        overwrite: a.overwrite,
        inputs: &inputs,
    };
    check_output(&a.output, &policy)?;
    let model = Model::read(&a.model)?;
    let read = recording_options(&a.read)?;
    let (mut rec, _, _) = analysis::robot_logs::read_recording_with_report(&a.file, &read)?;
    let rate = rec.rate_hz.unwrap_or(1.0);
    let temp = rec
        .temperature()
        .map(|t| t.data.clone())
        .with_context(|| format!("{}: no temperature channel", a.file.display()))?;
    let mut out_of_range = 0;
    for cm in &model.channels {
        let ch = rec
            .channels
            .iter_mut()
            .find(|c| c.name == cm.name)
            .with_context(|| {
                format!(
                    "{}: the model has channel '{}', the file does not",
                    a.file.display(),
                    cm.name
                )
            })?;
        out_of_range = out_of_range.max(model.apply(&cm.name, &mut ch.data, &temp, rate)?.out_of_range);
    }
    if out_of_range > 0 {
        eprintln!(
            "warning: {}: {out_of_range} samples outside the fitted {:.1}…{:.1} °C were compensated at the range's edge, not extrapolated",
            a.file.display(),
            model.t_min_c,
            model.t_max_c
        );
    }
    rec.meta
        .set("temperature_compensated_with", a.model.display().to_string());
    let mut file = AtomicFile::create(&a.output, &policy)?;
    write_recording(&mut file, &rec, LogFormat::Imutherm)
        .with_context(|| format!("writing {}", a.output.display()))?;
    file.commit()?;
    eprintln!("wrote {}", a.output.display());
    Ok(())
}

/// Most averaging bins a fit is asked for: 0.1 °C bins over 100 °C. Finer
/// bins hold a sample or two each, and the cross-validation over them would
/// run for hours; refused before the fit starts.
const MAX_FIT_BINS: f64 = 1000.0;

fn check_bins<'a>(temps: impl Iterator<Item = &'a [f64]>, width: f64) -> Result<()> {
    let (lo, hi) = temps
        .flatten()
        .filter(|t| t.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &t| {
            (a.min(t), b.max(t))
        });
    let bins = ((hi - lo) / width).floor() + 1.0;
    if bins > MAX_FIT_BINS {
        bail!(
            "--bin-width {width}: bins over {lo:.2} to {hi:.2} °C would be {bins:.0}; at most \
             {MAX_FIT_BINS} are fitted: give a wider bin"
        );
    }
    Ok(())
}

/// Width of the temperature slices whose ADEV minimum the evaluation
/// shows, °C.
const EVAL_SLICE_C: f64 = 5.0;

/// RMS and largest deviation of the bin means.
fn spread_of(bins: &[BinMean]) -> (f64, f64) {
    let s = spread(bins);
    (s.rms, s.max)
}

struct EvalRow {
    file: String,
    held_out: bool,
    channel: String,
    unit: String,
    before: Vec<BinMean>,
    after: Vec<BinMean>,
    /// After the firmware's own correction from the exported parameters.
    as_loaded: Option<Vec<BinMean>>,
    adev_before: Vec<SliceMinimum>,
    adev_after: Vec<SliceMinimum>,
    out_of_range: usize,
}

/// Whether `file` is one the model was fitted on: the same bytes (the
/// model keeps a digest of each fitted run), whatever its name. A model
/// from before digests were kept falls back to the file itself (device and
/// inode) or, failing that, its name.
fn was_fitted_on(model: &Model, file: &Path) -> Result<bool> {
    if !model.fitted_on_digests.is_empty() {
        let d = file_digest(file)?;
        return Ok(model.fitted_on_digests.contains(&d));
    }
    Ok(model
        .fitted_on
        .iter()
        .any(|f| Path::new(f) == file || same_file(Path::new(f), file)))
}

/// The exported parameter file and the firmware's view of it.
struct AsLoaded {
    firmware: Firmware,
    text: String,
    warnings: Vec<String>,
    calibration: Calibration,
    /// ArduPilot's INS_ACCn_CALTEMP / INS_GYRn_CALTEMP for the evaluation.
    cal_temp_c: f64,
}

fn as_loaded(model: &Model, firmware: Firmware, params: Option<&Path>) -> Result<AsLoaded> {
    if let Some(path) = params {
        let text = std::fs::read_to_string(path).with_context(|| format!("reading {}", path.display()))?;
        let calibration = firmware::load(firmware, &text, None).with_context(|| {
            format!(
                "{}: not a {} parameter file imutherm can apply",
                path.display(),
                firmware.name()
            )
        })?;
        return Ok(AsLoaded {
            firmware,
            text,
            warnings: Vec::new(),
            calibration,
            cal_temp_c: model.t_ref_c,
        });
    }
    let exported = firmware::export(model, firmware, Target::default())
        .with_context(|| format!("--export {}: the model cannot be written for it", firmware.key()))?;
    // Read back as the ground station loads it, so what is evaluated is the
    // file, float32 rounding included, not the model.
    let calibration = firmware::load(firmware, &exported.text, None)
        .with_context(|| format!("--export {}: the written file does not load", firmware.key()))?;
    Ok(AsLoaded {
        firmware,
        text: exported.text,
        warnings: exported.warnings,
        calibration,
        cal_temp_c: model.t_ref_c,
    })
}

pub fn eval(a: &TcalEvalArgs) -> Result<()> {
    let model = Model::read(&a.model)?;
    let read = recording_options(&a.read)?;
    let loaded = a
        .export
        .map(|f| as_loaded(&model, f.into(), a.params.as_deref()))
        .transpose()?;
    let names: Vec<String> = model.channels.iter().map(|c| c.name.clone()).collect();
    let mut rows = Vec::new();
    for file in &a.files {
        let (sel, temp) = run_data(file, &names, &read)?;
        let shown = file.display().to_string();
        let held_out = !was_fitted_on(&model, file)?;
        for ch in sel.channels {
            let mut comp = ch.data.clone();
            let report = model.apply(&ch.name, &mut comp, &temp, sel.rate_hz)?;
            let as_loaded = match (&loaded, sensor_axis(&ch.name)) {
                (Some(l), Some((sensor, axis))) => {
                    let corrected: Vec<f64> = ch
                        .data
                        .iter()
                        .zip(&temp)
                        .map(|(&x, &t)| l.calibration.correct(sensor, axis, x, t, l.cal_temp_c))
                        .collect();
                    Some(bin_means(&corrected, &temp, 2))
                }
                _ => None,
            };
            rows.push(EvalRow {
                file: shown.clone(),
                held_out,
                before: bin_means(&ch.data, &temp, 2),
                after: bin_means(&comp, &temp, 2),
                as_loaded,
                adev_before: surface_minima(&ch.data, &temp, sel.rate_hz, EVAL_SLICE_C),
                adev_after: surface_minima(&comp, &temp, sel.rate_hz, EVAL_SLICE_C),
                channel: ch.name,
                unit: ch.unit,
                out_of_range: report.out_of_range,
            });
        }
    }
    if let Some(l) = &loaded {
        for w in &l.warnings {
            eprintln!("warning: {w}");
        }
    }
    let stdout = std::io::stdout();
    let mut out = std::io::BufWriter::new(stdout.lock());
    if a.json {
        let bins = |b: &[BinMean]| {
            b.iter()
                .map(|b| json!({"t_c": b.t, "mean": b.mean, "lo": b.mean - 1.96 * b.se, "hi": b.mean + 1.96 * b.se}))
                .collect::<Vec<_>>()
        };
        let minima = |m: &[SliceMinimum]| {
            m.iter()
                .map(|m| json!({"t_c": m.t_c, "sigma_min": m.sigma_min, "tau": m.tau}))
                .collect::<Vec<_>>()
        };
        let mut doc = json!({
            "schema": "imutherm.tcal-eval/1",
            "model": a.model.display().to_string(),
            "rows": rows.iter().map(|r| {
                let (rb, mb) = spread_of(&r.before);
                let (ra, ma) = spread_of(&r.after);
                let mut row = json!({
                    "file": r.file, "held_out": r.held_out, "channel": r.channel, "unit": r.unit,
                    "bias_rms_before": rb, "bias_max_before": mb,
                    "bias_rms_after": ra, "bias_max_after": ma,
                    "samples_out_of_range": r.out_of_range,
                    "bins_before": bins(&r.before), "bins_after": bins(&r.after),
                    "adev_minimum_over_temperature_before": minima(&r.adev_before),
                    "adev_minimum_over_temperature_after": minima(&r.adev_after),
                });
                if let Some(l) = &r.as_loaded {
                    let (rl, ml) = spread_of(l);
                    row["bias_rms_as_loaded"] = json!(rl);
                    row["level_before"] = json!(level(&r.before));
                    row["level_as_loaded"] = json!(level(l));
                    row["bias_max_as_loaded"] = json!(ml);
                    row["bins_as_loaded"] = json!(bins(l));
                }
                row
            }).collect::<Vec<_>>(),
        });
        if let Some(l) = &loaded {
            doc["firmware"] = json!({
                "name": l.firmware.key(),
                "parameters": l.text,
                "warnings": l.warnings,
                "cal_temp_c": matches!(l.firmware, Firmware::ArduPilot).then_some(l.cal_temp_c),
            });
        }
        serde_json::to_writer_pretty(&mut out, &doc)?;
        writeln!(out)?;
        out.flush()?;
        return Ok(());
    }
    let mut table: Vec<String> = Vec::new();
    if !rows.is_empty() {
        table.push(
            "residual bias over 1 °C temperature bins (spread of the bin means), before → after; \
             ADEV minimum per 5 °C bin, before → after"
                .to_string(),
        );
        if let Some(l) = &loaded {
            table.push(format!(
                "\"as loaded\": {} applied as {} applies it{}",
                match &a.params {
                    Some(p) => p.display().to_string(),
                    None => format!("the exported {} parameter file", l.firmware.name()),
                },
                l.firmware.name(),
                match l.firmware {
                    Firmware::ArduPilot => format!(", with INS_ACC/GYR CALTEMP = {:.2} °C", l.cal_temp_c),
                    Firmware::Px4 if model.device_id.is_none() => {
                        " (as if TC_x0_ID held the sensor's device id)".to_string()
                    }
                    Firmware::Px4 => String::new(),
                }
            ));
        }
    }
    for r in &rows {
        let (rb, mb) = spread_of(&r.before);
        let (ra, ma) = spread_of(&r.after);
        let reduction = if rb > 0.0 { 100.0 * (1.0 - ra / rb) } else { 0.0 };
        table.push(format!(
            "{:<24} {:<8} {} RMS {:.3e} → {:.3e} {} ({reduction:.1} % less), max {:.3e} → {:.3e}{}",
            r.file,
            r.channel,
            if r.held_out { "held out" } else { "fitted  " },
            rb,
            ra,
            r.unit,
            mb,
            ma,
            if r.out_of_range > 0 {
                format!(", {} samples out of range", r.out_of_range)
            } else {
                String::new()
            }
        ));
        if let Some(l) = &r.as_loaded {
            let (rl, ml) = spread_of(l);
            let reduction = if rb > 0.0 { 100.0 * (1.0 - rl / rb) } else { 0.0 };
            table.push(format!(
                "{:<24} {:<8} as loaded RMS {:.3e} {} ({reduction:.1} % less), max {:.3e}, level {:.4} → {:.4}",
                "",
                "",
                rl,
                r.unit,
                ml,
                level(&r.before),
                level(l)
            ));
        }
        let pairs: Vec<String> = r
            .adev_before
            .iter()
            .zip(&r.adev_after)
            .map(|(b, a)| format!("{:.0} °C {:.2e}→{:.2e}", b.t_c, b.sigma_min, a.sigma_min))
            .collect();
        if !pairs.is_empty() {
            table.push(format!("{:<24} {:<8}   σ_min: {}", "", "", pairs.join(", ")));
        }
    }
    match &loaded {
        // The parameter lines follow on standard output: the table goes in
        // as comments, so the whole output still loads.
        Some(l) if a.params.is_none() => {
            for line in &table {
                writeln!(out, "# {line}")?;
            }
            write!(out, "{}", l.text)?;
        }
        _ => {
            for line in &table {
                writeln!(out, "{line}")?;
            }
        }
    }
    out.flush()?;
    Ok(())
}
