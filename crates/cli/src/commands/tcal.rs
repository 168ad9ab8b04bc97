//! `imutherm tcal fit | apply | eval`: temperature compensation of the bias.

use std::fmt::Write as _;
use std::io::Write;
use std::path::Path;

use anyhow::{Context, Result, bail};
use serde_json::json;

use imu::{LogFormat, RecordingOptions, read_recording, write_recording};
use thermal::surface::{Slicing, surface};
use thermal::tcal::{ChannelModel, FitOptions, Model, Run, fit as fit_model};

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
    let order = a.order;
    let read = recording_options(&a.read)?;
    let runs: Vec<(Selection, Vec<f64>)> = a
        .files
        .iter()
        .map(|f| run_data(f, &a.channels, &read))
        .collect::<Result<_>>()?;
    check_bins(runs.iter().map(|(_, t)| t.as_slice()), a.bin_width)?;
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
    let names: Vec<String> = a.files.iter().map(|f| f.display().to_string()).collect();
    let mut model = fit_model(&fit_runs, &opts).with_context(|| names.join(", "))?;
    model.fitted_on = names;
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

/// One 1 °C bin: mean temperature, mean value, standard error of the mean.
#[derive(Clone, Copy)]
pub(crate) struct BinMean {
    pub(crate) t: f64,
    pub(crate) mean: f64,
    pub(crate) se: f64,
}

/// Bin means of `x` over 1 °C bins holding at least `min_samples` samples.
/// The standard error is that of white samples (0 for a single sample);
/// correlated noise makes it a lower bound.
pub(crate) fn bin_means(x: &[f64], t: &[f64], min_samples: usize) -> Vec<BinMean> {
    let mut bins: std::collections::BTreeMap<i64, (f64, f64, f64, usize)> = Default::default();
    for (&v, &tt) in x.iter().zip(t) {
        if v.is_finite() && tt.is_finite() {
            let e = bins.entry(tt.floor() as i64).or_default();
            e.0 += tt;
            e.1 += v;
            e.2 += v * v;
            e.3 += 1;
        }
    }
    bins.values()
        .filter(|b| b.3 >= min_samples.max(1))
        .map(|&(t, s, s2, n)| {
            let nf = n as f64;
            let mean = s / nf;
            let var = ((s2 - s * mean) / (nf - 1.0)).max(0.0);
            BinMean {
                t: t / nf,
                mean,
                se: (var / nf).sqrt(),
            }
        })
        .collect()
}

/// RMS and largest deviation of the bin means from their mean: the bias
/// left over temperature.
pub(crate) fn spread(bins: &[BinMean]) -> (f64, f64) {
    let mean = bins.iter().map(|b| b.mean).sum::<f64>() / bins.len().max(1) as f64;
    let rms = (bins.iter().map(|b| (b.mean - mean).powi(2)).sum::<f64>() / bins.len().max(1) as f64).sqrt();
    let max = bins.iter().fold(0.0f64, |m, b| m.max((b.mean - mean).abs()));
    (rms, max)
}

/// σ_min of each 5 °C slice of the ADEV surface: (mean T, σ_min, τ).
fn surface_minima(x: &[f64], t: &[f64], rate: f64) -> Vec<(f64, f64, f64)> {
    surface(x, t, rate, Slicing::Temperature { bin_width_c: 5.0 }, 0.683)
        .map(|rows| {
            rows.iter()
                .filter_map(|r| {
                    r.terms
                        .slope
                        .sigma_min
                        .map(|m| (r.t_mean_c, m.value, m.tau.unwrap_or(f64::NAN)))
                })
                .collect()
        })
        .unwrap_or_default()
}

struct EvalRow {
    file: String,
    held_out: bool,
    channel: String,
    unit: String,
    before: Vec<BinMean>,
    after: Vec<BinMean>,
    adev_before: Vec<(f64, f64, f64)>,
    adev_after: Vec<(f64, f64, f64)>,
    out_of_range: usize,
}

pub fn eval(a: &TcalEvalArgs) -> Result<()> {
    let model = load(&a.model)?;
    let read = recording_options(&a.read)?;
    let names: Vec<String> = model.channels.iter().map(|c| c.name.clone()).collect();
    let mut rows = Vec::new();
    for file in &a.files {
        let (sel, temp) = run_data(file, &names, &read)?;
        let shown = file.display().to_string();
        let held_out = !model.fitted_on.iter().any(|f| Path::new(f) == file.as_path());
        for ch in sel.channels {
            let mut comp = ch.data.clone();
            let report = model.apply(&ch.name, &mut comp, &temp, sel.rate_hz)?;
            rows.push(EvalRow {
                file: shown.clone(),
                held_out,
                before: bin_means(&ch.data, &temp, 2),
                after: bin_means(&comp, &temp, 2),
                adev_before: surface_minima(&ch.data, &temp, sel.rate_hz),
                adev_after: surface_minima(&comp, &temp, sel.rate_hz),
                channel: ch.name,
                unit: ch.unit,
                out_of_range: report.out_of_range,
            });
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
        let minima = |m: &[(f64, f64, f64)]| {
            m.iter()
                .map(|m| json!({"t_c": m.0, "sigma_min": m.1, "tau": m.2}))
                .collect::<Vec<_>>()
        };
        let doc = json!({
            "schema": "imutherm.tcal-eval/1",
            "model": a.model.display().to_string(),
            "rows": rows.iter().map(|r| {
                let (rb, mb) = spread(&r.before);
                let (ra, ma) = spread(&r.after);
                json!({
                    "file": r.file, "held_out": r.held_out, "channel": r.channel, "unit": r.unit,
                    "bias_rms_before": rb, "bias_max_before": mb,
                    "bias_rms_after": ra, "bias_max_after": ma,
                    "samples_out_of_range": r.out_of_range,
                    "bins_before": bins(&r.before), "bins_after": bins(&r.after),
                    "adev_minimum_over_temperature_before": minima(&r.adev_before),
                    "adev_minimum_over_temperature_after": minima(&r.adev_after),
                })
            }).collect::<Vec<_>>(),
        });
        serde_json::to_writer_pretty(&mut out, &doc)?;
        writeln!(out)?;
    } else if !rows.is_empty() {
        writeln!(
            out,
            "residual bias over 1 °C temperature bins (spread of the bin means), before → after; \
             ADEV minimum per 5 °C bin, before → after"
        )?;
        for r in &rows {
            let (rb, mb) = spread(&r.before);
            let (ra, ma) = spread(&r.after);
            let reduction = if rb > 0.0 { 100.0 * (1.0 - ra / rb) } else { 0.0 };
            writeln!(
                out,
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
            )?;
            let pairs: Vec<String> = r
                .adev_before
                .iter()
                .zip(&r.adev_after)
                .map(|(b, a)| format!("{:.0} °C {:.2e}→{:.2e}", b.0, b.1, a.1))
                .collect();
            if !pairs.is_empty() {
                writeln!(out, "{:<24} {:<8}   σ_min: {}", "", "", pairs.join(", "))?;
            }
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
/// A channel's compensation as the four coefficients of a cubic in
/// (T − T_ref), for firmware that takes no more; a higher order is refused.
fn cubic(model: &Model, c: &ChannelModel, firmware: &str, limit: &str) -> Result<[f64; 4]> {
    if c.order > 3 {
        bail!("--export {firmware}: {} has order {}; {limit}", c.name, c.order);
    }
    let p = c.power_coefficients(model);
    Ok(std::array::from_fn(|k| p.get(k).copied().unwrap_or(0.0)))
}

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
                    let p = cubic(model, c, "px4", "PX4 takes a cubic at most (fit with --order 3)")?;
                    for (k, pk) in p.iter().enumerate() {
                        let _ = writeln!(s, "{prefix}_X{k}_{} {pk:.9e}", axis(&c.name));
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
                    let p = cubic(model, c, "ardupilot", "ArduPilot takes a cubic at most")?;
                    let xyz = ["X", "Y", "Z"][axis(&c.name)];
                    for (k, pk) in p.iter().enumerate().skip(1) {
                        let _ = writeln!(s, "INS_TCAL1_{key}{k}_{xyz} {pk:.9e}");
                    }
                }
            }
        }
        other => bail!("--export {other}: expected px4 or ardupilot"),
    }
    Ok(s)
}
