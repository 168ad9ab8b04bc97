//! `imutherm tcal fit | apply | eval`: temperature compensation of the bias.

use std::fmt::Write as _;
use std::io::Write;
use std::path::Path;

use anyhow::{Context, Result, bail};
use serde_json::json;

use imu::{LogFormat, RecordingOptions, read_recording, write_recording};
use thermal::tcal::{FitOptions, Model, Order, Run, fit as fit_model};

use crate::args::{TcalApplyArgs, TcalEvalArgs, TcalFitArgs};
use crate::commands::info::recording_options;
use crate::commands::selection::{Selection, read_channels};

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
    let order = match a.order.to_ascii_lowercase().as_str() {
        "auto" => Order::Auto,
        n => Order::Fixed(
            n.parse::<usize>()
                .ok()
                .filter(|&o| o <= 9)
                .with_context(|| format!("--order {n}: expected auto or an order from 0 to 9"))?,
        ),
    };
    let read = recording_options(&a.read)?;
    let runs: Vec<(Selection, Vec<f64>)> = a
        .files
        .iter()
        .map(|f| run_data(f, &a.channels, &read))
        .collect::<Result<_>>()?;
    let columns: Vec<Vec<(String, String, &[f64])>> = runs
        .iter()
        .map(|(sel, _)| {
            sel.channels
                .iter()
                .map(|c| (c.name.clone(), c.unit.clone(), c.data.as_slice()))
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
    };
    let model = fit_model(&fit_runs, &opts).with_context(|| {
        let names: Vec<String> = a.files.iter().map(|f| f.display().to_string()).collect();
        names.join(", ")
    })?;
    let text = serde_json::to_string_pretty(&model)?;
    std::fs::write(&a.output, text + "\n").with_context(|| format!("writing {}", a.output.display()))?;
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
    Ok(())
}

fn load(path: &Path) -> Result<Model> {
    let text = std::fs::read_to_string(path).with_context(|| format!("reading {}", path.display()))?;
    let model: Model = serde_json::from_str(&text)
        .with_context(|| format!("{}: not an imutherm compensation model", path.display()))?;
    if model.schema != thermal::tcal::SCHEMA {
        bail!(
            "{}: schema '{}', expected '{}'",
            path.display(),
            model.schema,
            thermal::tcal::SCHEMA
        );
    }
    Ok(model)
}

pub fn apply(a: &TcalApplyArgs) -> Result<()> {
    let model = load(&a.model)?;
    let read = recording_options(&a.read)?;
    let mut rec = read_recording(&a.file, &read)?;
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
    let file =
        std::fs::File::create(&a.output).with_context(|| format!("creating {}", a.output.display()))?;
    write_recording(std::io::BufWriter::new(file), &rec, LogFormat::Imutherm)
        .with_context(|| format!("writing {}", a.output.display()))?;
    eprintln!("wrote {}", a.output.display());
    Ok(())
}

/// Bin means of `x` over 1 °C bins: (mean T, mean x).
fn bin_means(x: &[f64], t: &[f64]) -> Vec<(f64, f64)> {
    let mut bins: std::collections::BTreeMap<i64, (f64, f64, usize)> = Default::default();
    for (&v, &tt) in x.iter().zip(t) {
        if v.is_finite() && tt.is_finite() {
            let e = bins.entry(tt.floor() as i64).or_default();
            e.0 += tt;
            e.1 += v;
            e.2 += 1;
        }
    }
    bins.values()
        .map(|&(t, v, n)| (t / n as f64, v / n as f64))
        .collect()
}

/// RMS and largest deviation of the bin means from their mean: the bias
/// left over temperature.
fn spread(bins: &[(f64, f64)]) -> (f64, f64) {
    let mean = bins.iter().map(|b| b.1).sum::<f64>() / bins.len().max(1) as f64;
    let rms = (bins.iter().map(|b| (b.1 - mean).powi(2)).sum::<f64>() / bins.len().max(1) as f64).sqrt();
    let max = bins.iter().fold(0.0f64, |m, b| m.max((b.1 - mean).abs()));
    (rms, max)
}

pub fn eval(a: &TcalEvalArgs) -> Result<()> {
    let model = load(&a.model)?;
    let read = recording_options(&a.read)?;
    let names: Vec<String> = model.channels.iter().map(|c| c.name.clone()).collect();
    let mut rows = Vec::new();
    for file in &a.files {
        let (sel, temp) = run_data(file, &names, &read)?;
        for ch in sel.channels {
            let before = bin_means(&ch.data, &temp);
            let mut comp = ch.data.clone();
            let report = model.apply(&ch.name, &mut comp, &temp, sel.rate_hz)?;
            let after = bin_means(&comp, &temp);
            let (rb, mb) = spread(&before);
            let (ra, ma) = spread(&after);
            rows.push((
                file.display().to_string(),
                ch.name,
                ch.unit,
                rb,
                mb,
                ra,
                ma,
                report.out_of_range,
            ));
        }
    }
    let stdout = std::io::stdout();
    let mut out = std::io::BufWriter::new(stdout.lock());
    if a.json {
        let doc = json!({
            "schema": "imutherm.tcal-eval/1",
            "model": a.model.display().to_string(),
            "rows": rows.iter().map(|r| json!({
                "file": r.0, "channel": r.1, "unit": r.2,
                "bias_rms_before": r.3, "bias_max_before": r.4,
                "bias_rms_after": r.5, "bias_max_after": r.6,
                "samples_out_of_range": r.7,
            })).collect::<Vec<_>>(),
        });
        serde_json::to_writer_pretty(&mut out, &doc)?;
        writeln!(out)?;
    } else if !rows.is_empty() {
        writeln!(
            out,
            "residual bias over 1 °C temperature bins (spread of the bin means), before → after"
        )?;
        for r in &rows {
            let reduction = if r.3 > 0.0 { 100.0 * (1.0 - r.5 / r.3) } else { 0.0 };
            writeln!(
                out,
                "{:<24} {:<8} RMS {:.3e} → {:.3e} {} ({reduction:.1} % less), max {:.3e} → {:.3e}{}",
                r.0,
                r.1,
                r.3,
                r.5,
                r.2,
                r.4,
                r.6,
                if r.7 > 0 {
                    format!(", {} samples out of range", r.7)
                } else {
                    String::new()
                }
            )?;
        }
    }
    if let Some(kind) = &a.export {
        write!(out, "{}", export(&model, kind)?)?;
    }
    out.flush()?;
    Ok(())
}

/// The coefficients in the shape flight stacks load them. These follow the
/// stacks' conventions (a cubic in T − T_ref); parameter names follow them
/// closely but are to be checked against the firmware version in use.
fn export(model: &Model, kind: &str) -> Result<String> {
    let mut s = String::new();
    let axis = |name: &str| match name.chars().last() {
        Some('x') => 0,
        Some('y') => 1,
        _ => 2,
    };
    match kind.to_ascii_lowercase().as_str() {
        "px4" => {
            let _ = writeln!(
                s,
                "# PX4-style thermal calibration: offset = X0 + X1·dT + X2·dT² + X3·dT³, dT = T − TREF (°C)"
            );
            for (prefix, stem) in [("TC_A0", "accel"), ("TC_G0", "gyro")] {
                let _ = writeln!(s, "{prefix}_TREF {:.4}", model.t_ref_c);
                let _ = writeln!(s, "{prefix}_TMIN {:.4}", model.t_min_c);
                let _ = writeln!(s, "{prefix}_TMAX {:.4}", model.t_max_c);
                for c in model.channels.iter().filter(|c| c.name.starts_with(stem)) {
                    if c.order > 3 {
                        bail!(
                            "--export px4: {} has order {}; PX4 takes a cubic at most (fit with --order 3)",
                            c.name,
                            c.order
                        );
                    }
                    let p = c.power_coefficients(model);
                    for k in 0..4 {
                        let _ = writeln!(
                            s,
                            "{prefix}_X{k}_{} {:.9e}",
                            axis(&c.name),
                            p.get(k).copied().unwrap_or(0.0)
                        );
                    }
                }
            }
        }
        "ardupilot" => {
            let _ = writeln!(
                s,
                "# ArduPilot-style: v −= p(T − TREF) − p(T_cal − TREF), p without a constant term, cubic"
            );
            let _ = writeln!(s, "INS_TCAL1_ENABLE 1");
            let _ = writeln!(s, "INS_TCAL1_TMIN {:.4}", model.t_min_c);
            let _ = writeln!(s, "INS_TCAL1_TMAX {:.4}", model.t_max_c);
            let _ = writeln!(
                s,
                "# TREF = {:.4} °C (ArduPilot's is 35 °C: fit with --tref 35 to load directly)",
                model.t_ref_c
            );
            for (stem, key) in [("accel", "ACC"), ("gyro", "GYR")] {
                for c in model.channels.iter().filter(|c| c.name.starts_with(stem)) {
                    if c.order > 3 {
                        bail!(
                            "--export ardupilot: {} has order {}; ArduPilot takes a cubic at most",
                            c.name,
                            c.order
                        );
                    }
                    let p = c.power_coefficients(model);
                    let xyz = ["X", "Y", "Z"][axis(&c.name)];
                    for k in 1..4 {
                        let _ = writeln!(
                            s,
                            "INS_TCAL1_{key}{k}_{xyz} {:.9e}",
                            p.get(k).copied().unwrap_or(0.0)
                        );
                    }
                }
            }
        }
        other => bail!("--export {other}: expected px4 or ardupilot"),
    }
    Ok(s)
}
