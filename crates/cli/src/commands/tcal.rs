//! `imutherm tcal fit | apply | eval`: temperature compensation of the bias
//! (`tcal export` is in `tcal_export`).

use std::io::Write;
use std::path::Path;

use anyhow::{Context, Result};

use analysis::AnalysisError;
use analysis::compensation::{self, AsLoaded, EvalDocument, FitRequest, RunData};
use imu::output::{AtomicFile, OutputPolicy, check_output, write_file};
use imu::{LogFormat, RecordingOptions, write_recording};
use thermal::firmware::Firmware;
use thermal::tcal::Model;

use crate::args::usage_error;
use crate::args::{TcalApplyArgs, TcalEvalArgs, TcalFitArgs};
use crate::flags::Instance;
use crate::print::{notes, static_checked};

/// Reads channels and the temperature of one run of a static sensor,
/// printing the reader's notes; the digest of its bytes comes from the same
/// read, so the run is opened once and may be a pipe.
fn run_data(
    file: &Path,
    channels: &[String],
    read: &RecordingOptions,
    allow_motion: bool,
) -> Result<RunData> {
    let (sel, digest) = analysis::selection::read_channels_digested(file, channels, read)?;
    notes(&sel.notes);
    Ok(RunData::new(
        file,
        static_checked(file, sel, allow_motion)?,
        digest,
    )?)
}

/// A compensation error; one in the flags given ends the program as a
/// usage error (status 2).
fn exit_status(e: AnalysisError) -> anyhow::Error {
    if e.is_usage() {
        usage_error(e);
    }
    anyhow::Error::new(e)
}

pub fn fit(a: &TcalFitArgs) -> Result<()> {
    let req = FitRequest {
        order: a.order,
        t_ref_c: a.tref,
        bin_width_c: a.bin_width,
        rate_term: a.rate_term,
        firmware: a.for_firmware.map(Firmware::from),
    };
    req.check().map_err(exit_status)?;
    let instances = fit_instances(a)?;
    let read = a.read.recording_options_any_instance()?;
    let policy = OutputPolicy {
        overwrite: a.overwrite,
        inputs: &a.files,
    };
    check_output(&a.output, &policy)?;
    let fit_one = |read: &RecordingOptions| -> Result<compensation::Fitted> {
        let runs: Vec<RunData> = a
            .files
            .iter()
            .map(|f| run_data(f, &a.channels, read, a.motion.allow_motion))
            .collect::<Result<_>>()?;
        compensation::fit(&a.files, &runs, &req).map_err(exit_status)
    };
    let (model, warnings) = match &instances {
        None => {
            let fitted = fit_one(&read)?;
            (fitted.model, fitted.export_warnings)
        }
        Some(numbers) => {
            let mut each = Vec::with_capacity(numbers.len());
            let mut warnings = Vec::new();
            for &n in numbers {
                let mut one = read.clone();
                one.stream.instance = Some(n);
                let mut fitted = fit_one(&one)?;
                fitted.model.instance = Some(n);
                warnings.extend(
                    fitted
                        .export_warnings
                        .into_iter()
                        .map(|w| format!("instance {n}: {w}")),
                );
                each.push(fitted.model);
            }
            let model = Model::of_instances(each).context("the log has no IMU instance")?;
            // Each instance fitted; the file they make together is checked
            // now, so that its faults show at the fit, not at the vehicle.
            if let Some(fw) = req.firmware {
                thermal::firmware::export(&model, fw, thermal::firmware::Target::default())
                    .with_context(|| format!("the instances together cannot be written for {}", fw.name()))?;
            }
            (model, warnings)
        }
    };
    let text = serde_json::to_string_pretty(&model)?;
    write_file(&a.output, (text + "\n").as_bytes(), &policy)?;
    eprintln!("wrote {}", a.output.display());
    for m in model.sensors() {
        eprintln!(
            "{}{:.1}…{:.1} °C, T_ref {:.2} °C{}",
            m.instance.map(|n| format!("instance {n}: ")).unwrap_or_default(),
            m.t_min_c,
            m.t_max_c,
            m.t_ref_c,
            match (m.device_id, m.accel_device_id) {
                (Some(g), Some(a)) => format!(", gyro id {g}, accelerometer id {a}"),
                (Some(g), None) => format!(", device id {g}"),
                _ => String::new(),
            }
        );
        for c in &m.channels {
            eprintln!(
                "  {:<8} order {}  residual RMS {:.3e} {}  max {:.3e}",
                c.name, c.order, c.residual_rms, c.unit, c.residual_max
            );
        }
    }
    for w in &warnings {
        eprintln!("warning: {w}");
    }
    Ok(())
}

/// The instances `tcal fit` fits at once: every one of the first log's
/// with `--instance all`, and by default for `--for` when it has several;
/// `None` for one sensor.
fn fit_instances(a: &TcalFitArgs) -> Result<Option<Vec<u32>>> {
    let all = match a.read.instance {
        Some(Instance::One(_)) => return Ok(None),
        Some(Instance::All) => true,
        None if a.for_firmware.is_some() && a.read.topic.is_none() => false,
        None => return Ok(None),
    };
    let Some(first) = a.files.first() else {
        return Ok(None);
    };
    let found = analysis::robot_logs::imu_instances(first).map_err(exit_status)?;
    match found.len() {
        0 if all => usage_error(format!(
            "--instance all: {} has no IMU instances (it is not a PX4 ULog or ArduPilot DataFlash log with several IMUs)",
            first.display()
        )),
        0 | 1 if !all => Ok(None),
        _ => Ok(Some(found)),
    }
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
    let read = a.read.recording_options()?;
    // A model of several IMUs compensates the one instance asked for, with
    // that instance's own model.
    let model = if model.instances.is_empty() {
        model
    } else {
        let numbers: Vec<u32> = model.instances.iter().filter_map(|m| m.instance).collect();
        match a.read.instance {
            Some(Instance::One(n)) => match model.instances.iter().find(|m| m.instance == Some(n)) {
                Some(m) => m.clone(),
                None => usage_error(format!(
                    "--instance {n}: {} holds instances {numbers:?}",
                    a.model.display()
                )),
            },
            _ => usage_error(format!(
                "{} holds instances {numbers:?}: give --instance N to compensate one",
                a.model.display()
            )),
        }
    };
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

pub fn eval(a: &TcalEvalArgs) -> Result<()> {
    let model = Model::read(&a.model)?;
    let read = a.read.recording_options_any_instance()?;
    let many = !model.instances.is_empty();
    if !many && a.read.instance == Some(Instance::All) {
        usage_error(format!(
            "--instance all: {} is the model of one sensor; give its instance number",
            a.model.display()
        ));
    }
    let loaded: Option<AsLoaded> = a
        .export
        .map(|f| compensation::as_loaded(&model, f.into(), a.params.as_deref()))
        .transpose()?;
    // A model of several instances is judged per instance: each read from
    // the log as its own IMU, against its own set of the file.
    let sensors: Vec<&Model> = model
        .sensors()
        .into_iter()
        .filter(|m| match (many, a.read.instance) {
            (true, Some(Instance::One(n))) => m.instance == Some(n),
            _ => true,
        })
        .collect();
    if sensors.is_empty() {
        usage_error(format!(
            "--instance: {} holds instances {:?}",
            a.model.display(),
            model
                .instances
                .iter()
                .filter_map(|m| m.instance)
                .collect::<Vec<_>>()
        ));
    }
    let mut rows = Vec::new();
    let mut verdicts = Vec::new();
    for file in &a.files {
        for m in &sensors {
            let mut read = read.clone();
            let for_instance = match (many, &loaded) {
                (true, Some(l)) => Some(l.for_instance(m)?),
                _ => None,
            };
            if many {
                read.stream.instance = m.instance;
            }
            let names: Vec<String> = m.channels.iter().map(|c| c.name.clone()).collect();
            let run = run_data(file, &names, &read, a.motion.allow_motion)?;
            let loaded = for_instance.as_ref().or(loaded.as_ref());
            if let Some(l) = loaded {
                let mut v = compensation::judge(l, file, &run)?;
                v.instance = m.instance.filter(|_| many);
                verdicts.push(v);
            }
            let for_run = match loaded {
                Some(l) => l.for_run(file, &run)?,
                None => None,
            };
            rows.extend(compensation::eval_rows(
                m,
                file,
                run,
                for_run.as_ref().or(loaded),
            )?);
        }
    }
    if let Some(l) = &loaded {
        for w in &l.warnings {
            eprintln!("warning: {w}");
        }
    }
    let doc = EvalDocument::new(&a.model.display().to_string(), rows, loaded.as_ref(), verdicts);
    let nothing: Vec<&str> = doc
        .firmware
        .iter()
        .flat_map(|f| &f.verdicts)
        .filter(|v| !v.applies)
        .map(|v| v.file.as_str())
        .collect();
    let stdout = std::io::stdout();
    let mut out = std::io::BufWriter::new(stdout.lock());
    if a.json {
        serde_json::to_writer_pretty(&mut out, &doc)?;
        writeln!(out)?;
        out.flush()?;
        return applied_somewhere(&nothing);
    }
    let mut table: Vec<String> = Vec::new();
    if !doc.rows.is_empty() {
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
    for r in &doc.rows {
        let file = match r.instance {
            Some(n) => format!("{} [IMU {n}]", r.file),
            None => r.file.clone(),
        };
        let (rb, mb) = (r.bias_rms_before, r.bias_max_before);
        let (ra, ma) = (r.bias_rms_after, r.bias_max_after);
        let reduction = if rb > 0.0 { 100.0 * (1.0 - ra / rb) } else { 0.0 };
        table.push(format!(
            "{:<24} {:<8} {} RMS {:.3e} → {:.3e} {} ({reduction:.1} % less), max {:.3e} → {:.3e}{}",
            file,
            r.channel,
            if r.held_out { "held out" } else { "fitted  " },
            rb,
            ra,
            r.unit,
            mb,
            ma,
            if r.samples_out_of_range > 0 {
                format!(", {} samples out of range", r.samples_out_of_range)
            } else {
                String::new()
            }
        ));
        if let (Some(rl), Some(ml)) = (r.bias_rms_as_loaded, r.bias_max_as_loaded) {
            let reduction = if rb > 0.0 { 100.0 * (1.0 - rl / rb) } else { 0.0 };
            table.push(format!(
                "{:<24} {:<8} as loaded RMS {:.3e} {} ({reduction:.1} % less), max {:.3e}, level {:.4} → {:.4}",
                "",
                "",
                rl,
                r.unit,
                ml,
                r.level_before.unwrap_or(f64::NAN),
                r.level_as_loaded.unwrap_or(f64::NAN)
            ));
        }
        let pairs: Vec<String> = r
            .adev_minimum_over_temperature_before
            .iter()
            .zip(&r.adev_minimum_over_temperature_after)
            .map(|(b, a)| format!("{:.0} °C {:.2e}→{:.2e}", b.t_c, b.sigma_min, a.sigma_min))
            .collect();
        if !pairs.is_empty() {
            table.push(format!("{:<24} {:<8}   σ_min: {}", "", "", pairs.join(", ")));
        }
    }
    for v in doc.firmware.iter().flat_map(|f| &f.verdicts) {
        for said in &v.says {
            match v.instance {
                Some(n) => table.push(format!("{} [IMU {n}]: {said}", v.file)),
                None => table.push(format!("{}: {said}", v.file)),
            }
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
    applied_somewhere(&nothing)
}

/// A runtime error (status 1) where the firmware would correct nothing on a
/// run: the table above says why.
fn applied_somewhere(nothing: &[&str]) -> Result<()> {
    match nothing {
        [] => Ok(()),
        files => anyhow::bail!(
            "the firmware would apply no temperature correction on {}",
            files.join(", ")
        ),
    }
}
