//! `imutherm tcal fit | apply | eval`: temperature compensation of the bias
//! (`tcal export` is in `tcal_export`).

use std::io::Write;
use std::path::Path;

use anyhow::{Context, Result};

use analysis::AnalysisError;
use analysis::compensation::{self, AsLoaded, FitRequest, RunData};
use analysis::tcal_instances::{self, Instances};
use imu::output::{AtomicFile, OutputPolicy, check_output, write_file};
use imu::{InstancePick, LogFormat, RecordingOptions, write_recording};
use thermal::firmware::Firmware;
use thermal::tcal::Model;

use crate::args::usage_error;
use crate::args::{TcalApplyArgs, TcalEvalArgs, TcalFitArgs};
use crate::flags::Instance;
use crate::print::{notes, static_checked};

/// Reads channels and the temperature of one run of a static sensor for
/// each IMU instance `pick` asks, printing the reader's notes; the file is
/// opened and decoded once for all of them, and the digest of its bytes
/// comes from the same read, so the run may be a pipe.
fn run_data(
    file: &Path,
    channels: &[String],
    read: &RecordingOptions,
    pick: &InstancePick,
    allow_motion: bool,
) -> Result<tcal_instances::EachRun> {
    let (each, digest) = analysis::selection::read_channels_digested_each(file, channels, read, pick)?;
    each.into_iter()
        .map(|(n, sel)| {
            notes(&sel.notes);
            let sel = static_checked(file, sel, allow_motion)?;
            Ok((n, RunData::new(file, sel, digest.clone())?))
        })
        .collect()
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
    let read = a.read.recording_options_any_instance()?;
    let policy = OutputPolicy {
        overwrite: a.overwrite,
        inputs: &a.files,
    };
    check_output(&a.output, &policy)?;
    let fitted = tcal_instances::fit(
        &a.files,
        &req,
        &read,
        a.read.instance.map(instances_of),
        a.read.topic.is_some(),
        |f, read, pick| run_data(f, &a.channels, read, pick, a.motion.allow_motion),
    )
    .map_err(usage_exit)?;
    let (model, warnings) = (fitted.model, fitted.export_warnings);
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
        if let Some(step) = m.temperature_step_c {
            eprintln!(
                "  the temperature reads in steps of {step:.4} °C: smoothed between its changes before use"
            );
        }
        for c in &m.channels {
            eprintln!(
                "  {:<8} order {}  residual RMS {:.3e} {}  max {:.3e}",
                c.name, c.order, c.residual_rms, c.unit, c.residual_max
            );
            for line in found(c) {
                eprintln!("           {line}");
            }
        }
    }
    for w in &warnings {
        eprintln!("warning: {w}");
    }
    Ok(())
}

/// What the fit found beyond the polynomial, with its intervals.
fn found(c: &thermal::tcal::ChannelModel) -> Vec<String> {
    let mut out = Vec::new();
    if let Some(lag) = c.lag_s {
        out.push(match c.lag_interval_s {
            Some([lo, hi]) => format!("element lags the sensor by {lag:.0} s [{lo:.0}, {hi:.0}]"),
            None => format!("element lags the sensor by {lag:.0} s"),
        });
    }
    if let Some(h) = &c.hysteresis_term {
        out.push(format!(
            "heating reads {:.2e} {} above cooling [{:.2e}, {:.2e}] (saturating at {:.2} °C/min)",
            h.heating_minus_cooling,
            c.unit,
            h.interval_95[0],
            h.interval_95[1],
            h.rate_scale_c_per_s * 60.0
        ));
    }
    if let Some(p) = &c.projection {
        let mut what = Vec::new();
        if let Some(l) = p.lag_s {
            what.push(format!("a {l:.0} s lag"));
        }
        if let Some(h) = p.heating_minus_cooling {
            what.push(format!("{h:.2e} {} of hysteresis", c.unit));
        }
        out.push(format!(
            "the firmware applies T only ({} dropped, the equilibrium curve kept): a {:.0} °C/min climb leaves {:.2e} {} that the full model removes{}",
            what.join(" and "),
            p.climb_c_per_min,
            p.climb_left.abs(),
            c.unit,
            match (p.full_residual_rms, p.projected_residual_rms) {
                (Some(f), Some(q)) => format!("; on the fitted runs {q:.2e} {} left against the full model's {f:.2e}", c.unit),
                _ => String::new(),
            }
        ));
    }
    out
}

/// The library's name of `--instance N|all`.
fn instances_of(i: Instance) -> Instances {
    match i {
        Instance::One(n) => Instances::One(n),
        Instance::All => Instances::All,
    }
}

/// [`exit_status`] for an error that may wrap a compensation error.
fn usage_exit(e: anyhow::Error) -> anyhow::Error {
    match e.downcast::<AnalysisError>() {
        Ok(e) => exit_status(e),
        Err(e) => e,
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
    let asked = match a.read.instance {
        Some(Instance::One(n)) => Some(n),
        _ => None,
    };
    let model = tcal_instances::to_apply(&model, &a.model.display().to_string(), asked)
        .map_err(|e| exit_status(e.into()))?;
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
    let loaded: Option<AsLoaded> = a
        .export
        .map(|f| compensation::as_loaded(&model, f.into(), a.params.as_deref()))
        .transpose()?;
    let doc = tcal_instances::evaluate(
        &model,
        &a.model.display().to_string(),
        &a.files,
        loaded.as_ref(),
        a.read.instance.map(instances_of),
        &read,
        |file, names, read, pick| run_data(file, names, read, pick, a.motion.allow_motion),
    )
    .map_err(usage_exit)?;
    if let Some(l) = &loaded {
        for w in &l.warnings {
            eprintln!("warning: {w}");
        }
    }
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
