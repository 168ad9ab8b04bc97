//! `imutherm demo`: the thesis's whole experiment on simulated data.

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{Context, Result};
use indicatif::{ProgressBar, ProgressStyle};
use rayon::prelude::*;

use allan::noise_terms::Term;
use imu::RecordingOptions;
use imu::output::{AtomicFile, OutputPolicy, write_file};
use imusim::thermal::Profile;
use imusim::{Simulator, presets};
use report::html::Page;
use report::plots::{adev_heatmap, bias_plot};
use thermal::surface::{Slicing, surface};
use thermal::tcal::{FitOptions, Run, fit};

use crate::args::DemoArgs;
use crate::commands::experiment::{
    Analysed, LOG_MARK, PAGE_MARK, PngDir, adev_figures, analyse_run, command_section, deg, noise_tables,
    refuse_foreign_files, time_figures,
};
use crate::commands::ins::{Navigated, compensated_channels, navigate, six_channels};
use crate::commands::selection::{Selection, read_channels};
use crate::commands::tcal::{BinMean, bin_means, spread};

/// The demo writes only its own files, into its own directory: replacing
/// them is what running it again means.
const OWN_FILE: OutputPolicy<'static> = OutputPolicy {
    overwrite: true,
    inputs: &[],
};

/// The thesis's constant-temperature runs, °C.
const TEMPERATURES: [f64; 4] = [34.0, 43.0, 62.0, 82.0];

fn simulate(
    path: &Path,
    profile: Profile,
    seed: u64,
    rate: f64,
    duration: f64,
    bar: &ProgressBar,
) -> Result<()> {
    let mut cfg = presets::preset("mpu9250-thesis")?;
    cfg.rate_hz = rate;
    cfg.duration_s = duration;
    cfg.seed = seed;
    cfg.profile = profile;
    let sim = Simulator::new(cfg)?;
    // The demo's directory is its own: its files are replaced, each
    // atomically, and nothing else in it is touched.
    let mut file = AtomicFile::create(path, &OWN_FILE)?;
    let base = bar.position();
    sim.write_log(&mut file, &sim.metadata(Some("mpu9250-thesis")), |done, _| {
        bar.set_position(base + done)
    })
    .with_context(|| format!("writing {}", path.display()))?;
    file.commit()?;
    Ok(())
}

pub fn run(a: &DemoArgs) -> Result<()> {
    let started = Instant::now();
    // The thesis's rate in both: its scripts analyse at Fs = 20 Hz.
    let rate = presets::THESIS_RATE_HZ;
    let (constant_s, cooling_s) = if a.quick {
        (900.0, 3600.0)
    } else {
        (3600.0, 3.0 * 3600.0)
    };
    let runs_named: Vec<String> = TEMPERATURES.iter().map(|t| format!("run_{t:.0}C.txt")).collect();
    let mut own: Vec<(&str, &str)> = runs_named.iter().map(|n| (n.as_str(), LOG_MARK)).collect();
    own.extend([
        ("cooling_100_to_20C.txt", LOG_MARK),
        ("heating_25_to_95C.txt", LOG_MARK),
        ("tcal_model.json", "\"schema\": \"imutherm.tcal/1\""),
        ("report.html", PAGE_MARK),
    ]);
    refuse_foreign_files(&a.out, &own)?;
    std::fs::create_dir_all(&a.out).with_context(|| format!("creating {}", a.out.display()))?;
    let png = PngDir::new(&a.format, &a.out)?;
    let file = |name: &str| a.out.join(name);

    // 1. The recordings.
    let total = ((4.0 * constant_s + 2.0 * cooling_s) * rate) as u64;
    let bar = ProgressBar::new(total).with_style(
        ProgressStyle::with_template("{msg:<28} [{bar:40}] {percent:>3} %")
            .unwrap_or_else(|_| ProgressStyle::default_bar())
            .progress_chars("=> "),
    );
    bar.set_message("simulating the runs");
    let mut runs: Vec<PathBuf> = Vec::new();
    for (i, t) in TEMPERATURES.iter().enumerate() {
        let p = file(&runs_named[i]);
        let profile = Profile::Constant {
            temp_c: *t,
            fluctuation_c: 0.05,
            fluctuation_tau_s: 60.0,
        };
        simulate(&p, profile, 10 + i as u64, rate, constant_s, &bar)?;
        runs.push(p);
    }
    let cooling = file("cooling_100_to_20C.txt");
    let cooling_profile = Profile::Cooling {
        start_c: 100.0,
        ambient_c: 20.0,
        tau_s: cooling_s / 4.0,
    };
    simulate(&cooling, cooling_profile, 20, rate, cooling_s, &bar)?;
    let heating = file("heating_25_to_95C.txt");
    let heating_profile = Profile::Ramp {
        from_c: 25.0,
        to_c: 95.0,
        duration_s: cooling_s * 0.9,
    };
    simulate(&heating, heating_profile, 21, rate, cooling_s, &bar)?;
    bar.finish_and_clear();

    // 2. Noise terms of the constant runs.
    eprintln!("noise terms of the four constant-temperature runs…");
    let analysed: Vec<(Vec<Analysed>, Option<f64>)> = runs
        .iter()
        .map(|p| analyse_run(p, &RecordingOptions::default()))
        .collect::<Result<_>>()?;

    // 3. ADEV over temperature of the cooling run.
    eprintln!("ADEV over temperature of the cooling run…");
    let cool = read_channels(&cooling, &[], &RecordingOptions::default())?;
    let cool_temp = cool
        .temperature
        .clone()
        .context("the cooling run has no temperature")?;
    let surfaces: Vec<_> = cool
        .channels
        .par_iter()
        .map(|c| {
            surface(
                &c.data,
                &cool_temp,
                cool.rate_hz,
                Slicing::Temperature { bin_width_c: 5.0 },
                0.683,
            )
        })
        .collect::<Result<_, _>>()?;

    // 4. Compensation fitted on the cooling run, evaluated on the heating run.
    eprintln!("compensation: fit on cooling, evaluation on heating…");
    let cols: Vec<(String, String, &[f64])> = cool
        .channels
        .iter()
        .map(|c| (c.name.clone(), c.unit.clone(), c.data.as_slice()))
        .collect();
    let mut model = fit(
        &[Run {
            channels: &cols,
            temp: &cool_temp,
            rate_hz: cool.rate_hz,
        }],
        // Capped at the flight stacks' cubic, so the demo's model exports.
        &FitOptions {
            max_auto_order: thermal::firmware::Firmware::MAX_ORDER,
            ..FitOptions::default()
        },
    )?;
    model.fitted_on = vec![cooling.display().to_string()];
    write_file(
        &file("tcal_model.json"),
        (serde_json::to_string_pretty(&model)? + "\n").as_bytes(),
        &OWN_FILE,
    )?;
    let heat = read_channels(&heating, &[], &RecordingOptions::default())?;
    let heat_temp = heat
        .temperature
        .clone()
        .context("the heating run has no temperature")?;
    let mut compensation = Vec::new();
    let mut adev_change = Vec::new();
    for c in &heat.channels {
        let mut comp = c.data.clone();
        model.apply(&c.name, &mut comp, &heat_temp, heat.rate_hz)?;
        // Every 1 °C bin, a single sample's too.
        let (before, after) = (bin_means(&c.data, &heat_temp, 1), bin_means(&comp, &heat_temp, 1));
        // The ADEV over temperature before and after: its minimum per
        // 10 °C bin, where a drifting bias shows as a rise at long τ.
        let minima = |x: &[f64]| -> Result<Vec<(f64, f64)>> {
            Ok(surface(
                x,
                &heat_temp,
                heat.rate_hz,
                Slicing::Temperature { bin_width_c: 10.0 },
                0.683,
            )?
            .iter()
            .filter_map(|r| r.terms.slope.sigma_min.map(|m| (r.t_mean_c, m.value)))
            .collect())
        };
        adev_change.push((c.name.clone(), c.unit.clone(), minima(&c.data)?, minima(&comp)?));
        compensation.push((c.name.clone(), c.unit.clone(), c.quantity, before, after));
    }

    // 5. The report.
    let mut page = Page::new("imutherm — temperature dependency of a simulated MPU-9250");
    page.paragraph(&format!(
        "Simulated with the mpu9250-thesis preset: four {} s runs at {} Hz held at 34, 43, 62 and 82 °C, \
         a {} s cooling run from 100 °C towards 20 °C and a heating run from 25 to 95 °C that the \
         compensation never saw.",
        constant_s, rate, cooling_s
    ));
    command_section(&mut page);
    page.heading("Inputs");
    let inputs: Vec<Vec<String>> = runs
        .iter()
        .chain([&cooling, &heating])
        .map(|p| vec![p.display().to_string()])
        .collect();
    page.table("recordings", &["file".to_string()], &inputs);

    noise_tables(&mut page, &analysed);
    adev_figures(&mut page, &analysed, &png)?;

    page.heading("Cooling run: raw data");
    time_figures(&mut page, &cool, "cooling run", &png)?;

    page.heading("Cooling run: ADEV over temperature (3D ADEV)");
    for (c, rows) in cool.channels.iter().zip(&surfaces) {
        let grid: Vec<(f64, Vec<(f64, f64)>)> = rows
            .iter()
            .map(|r| (r.t_mean_c, r.points.iter().map(|p| (p.tau, p.dev)).collect()))
            .collect();
        page.surface3d(&c.name, &c.unit, &grid);
    }
    for (c, rows) in cool.channels.iter().zip(&surfaces) {
        page.figure(
            &adev_heatmap(&c.name, &c.unit, rows)?,
            &format!("{}: σ(τ, T) over 5 °C bins of the cooling run", c.name),
        );
        if let Some(p) = png.path(&format!("adev_over_temperature_{}", c.name)) {
            report::plots::adev_heatmap_png(&p, &c.name, &c.unit, rows)?;
        }
    }

    page.heading("Temperature compensation (fitted on cooling, evaluated on heating)");
    let mut comp_rows = Vec::new();
    for (name, unit, _, before, after) in &compensation {
        let points = |bins: &[BinMean]| -> Vec<(f64, f64)> { bins.iter().map(|b| (b.t, b.mean)).collect() };
        let (raw, compensated) = (points(before), points(after));
        let cm = model.channel(name).context("model channel")?;
        // The same unit: its raw bias is p(T) itself.
        let curve = |t: f64| cm.bias(&model, t.clamp(model.t_min_c, model.t_max_c));
        page.figure(
            &bias_plot(
                &format!("{name}: bias against temperature"),
                unit,
                &raw,
                &compensated,
                &curve,
            )?,
            &format!("{name}: 1 °C bin means of the heating run, raw and compensated, and the fitted p(T)"),
        );
        if let Some(p) = png.path(&format!("compensation_{name}")) {
            report::plots::bias_plot_png(
                &p,
                &format!("{name}: bias against temperature"),
                unit,
                &raw,
                &compensated,
                &curve,
            )?;
        }
        let (rb, ra) = (spread(before).0, spread(after).0);
        comp_rows.push(vec![
            name.clone(),
            format!("{}", cm.order),
            format!("{rb:.3e} {unit}"),
            format!("{ra:.3e} {unit}"),
            format!("{:.1} %", 100.0 * (1.0 - ra / rb)),
        ]);
    }
    page.table(
        "residual bias over temperature on the held-out heating run (RMS of 1 °C bin means)",
        &["channel", "order", "raw", "compensated", "reduction"].map(String::from),
        &comp_rows,
    );
    let mut adev_rows = Vec::new();
    for (name, unit, before, after) in &adev_change {
        for ((t, b), (_, a)) in before.iter().zip(after) {
            adev_rows.push(vec![
                name.clone(),
                format!("{t:.1}"),
                format!("{b:.3e} {unit}"),
                format!("{a:.3e} {unit}"),
            ]);
        }
    }
    page.table(
        "ADEV over temperature on the heating run, before and after compensation: σ_min per 10 °C bin",
        &["channel", "T [°C]", "raw", "compensated"].map(String::from),
        &adev_rows,
    );
    navigation_section(&mut page, &cooling, &cool, &model)?;
    let html = page.finish();
    let report_path = file("report.html");
    write_file(&report_path, html.as_bytes(), &OWN_FILE)?;

    // 6. Summary.
    println!("report: {}", report_path.display());
    println!(
        "{:<8} {:>12} {:>12} {:>12} {:>12}",
        "axis", "N 34 °C", "N 82 °C", "bias raw", "bias comp"
    );
    for (i, r) in analysed[0].0.iter().enumerate() {
        let q = r.channel.quantity;
        // The estimate that holds: the fit's, never a slope read where the
        // curve does not hold it.
        let n = |a: &Analysed| {
            a.terms
                .choose(Term::WhiteNoise)
                .value()
                .map_or(f64::NAN, |v| v * deg(q))
        };
        let hot = analysed[3].0.get(i).map_or(f64::NAN, n);
        let (_, _, _, b, af) = &compensation[i.min(compensation.len() - 1)];
        println!(
            "{:<8} {:>12.5} {:>12.5} {:>12.3e} {:>12.3e}",
            r.channel.name,
            n(r),
            hot,
            spread(b).0,
            spread(af).0
        );
    }
    println!(
        "(N from the model fit, or the slope method where the fit cannot separate it, in °/√s for gyros, \
         m/s/√s for accelerometers; bias: RMS over temperature on the held-out run)"
    );
    eprintln!("done in {:.1} s", started.elapsed().as_secs_f64());
    Ok(())
}

/// What the noise and the temperature cost in metres: the cooling run
/// navigated without aiding from many start points, raw and compensated,
/// measured beside the prediction from its noise terms; and the 60 s drift
/// for longer alignment windows.
fn navigation_section(
    page: &mut Page,
    cooling: &Path,
    cool: &Selection,
    model: &thermal::tcal::Model,
) -> Result<()> {
    use ins::drift::{drift_over_windows, report_times};
    use ins::strapdown::{ImuData, NavOptions};

    eprintln!("navigation of the cooling run, raw and compensated…");
    let every = 10.0;
    let opts = NavOptions::default();
    let times = report_times(120.0);
    let six = six_channels(cooling, cool)?;
    let comp_six = compensated_channels(cooling, cool, model, &six)?;
    let raw = navigate(cooling, &six, cool.rate_hz, &opts, every, &times)?;
    let comp = navigate(cooling, &comp_six, cool.rate_hz, &opts, every, &times)?;
    page.heading("Navigation without GNSS: the cooling run, raw and compensated");
    page.paragraph(&format!(
        "Strapdown navigation of the cooling run from a start point every {every} s ({} windows), each \
         levelled on its first {} s (heading 0: a MEMS gyro cannot gyrocompass; the gyro's mean over \
         the window taken as its bias) and navigated without aiding. The sensor is static, so every \
         metre is error. Predicted: the horizontal position 1σ from the noise terms identified on the \
         run itself (closed form per term, summed in quadrature; bias instability bounded as a bias); \
         the temperature drift is in no prediction, so on the raw run the measured error above the \
         predicted is the temperature's.",
        raw.windows, opts.align_s
    ));
    let rows: Vec<Vec<String>> = raw
        .rows
        .iter()
        .zip(&comp.rows)
        .map(|(r, c)| {
            vec![
                format!("{}", r.measured.t_s),
                format!("{:.3}", r.measured.horizontal_position_m.rms),
                format!("{:.3}", r.measured.horizontal_position_m.p95),
                format!("{:.3}", r.predicted.total_m),
                format!("{:.3}", c.measured.horizontal_position_m.rms),
                format!("{:.3}", c.measured.horizontal_position_m.p95),
                format!("{:.3}", c.predicted.total_m),
            ]
        })
        .collect();
    page.table(
        "horizontal position error against time since alignment, m (RMS and 95th percentile over the windows)",
        &[
            "t [s]",
            "raw RMS",
            "raw p95",
            "raw predicted 1σ",
            "compensated RMS",
            "compensated p95",
            "compensated predicted 1σ",
        ]
        .map(String::from),
        &rows,
    );
    // The 60 s figure for longer alignment windows: a longer window averages
    // the noise out of the gyro bias it takes, but on a cooling run that
    // bias is older when the navigation starts. The same times as above, so
    // that the 10 s row has the same windows.
    let rate_hz = cool.rate_hz;
    fn data(c: &[Vec<f64>], rate_hz: f64) -> ImuData<'_> {
        ImuData {
            accel: [&c[0], &c[1], &c[2]],
            gyro: [&c[3], &c[4], &c[5]],
            rate_hz,
        }
    }
    let at60 = |c: &[Vec<f64>], o: &NavOptions| -> Result<f64> {
        let d = drift_over_windows(&data(c, rate_hz), o, every, &times)?;
        d.curve
            .iter()
            .find(|p| p.t_s == 60.0)
            .map(|p| p.horizontal_position_m.rms)
            .context("60 s is one of the report's times")
    };
    let mut rows = Vec::new();
    for align_s in [10.0, 30.0, 60.0] {
        let o = NavOptions { align_s, ..opts };
        let (r, c) = (at60(&six, &o)?, at60(&comp_six, &o)?);
        rows.push(vec![
            format!("{align_s}"),
            format!("{r:.2}"),
            format!("{c:.2}"),
            format!("{:.2}", c / r),
        ]);
    }
    page.table(
        "60 s without GNSS, by alignment window: horizontal position RMS, m",
        &["alignment [s]", "raw", "compensated", "compensated / raw"].map(String::from),
        &rows,
    );
    page.paragraph(&summary(&raw, &comp));
    Ok(())
}

/// One sentence on what the compensation buys at 60 s, and why not more.
fn summary(raw: &Navigated, comp: &Navigated) -> String {
    let at60 = |n: &Navigated| {
        n.rows
            .iter()
            .find(|r| r.measured.t_s == 60.0)
            .map(|r| (r.measured.horizontal_position_m.rms, r.predicted.total_m))
    };
    match (at60(raw), at60(comp)) {
        (Some((r, _)), Some((c, floor))) => {
            let head = format!(
                "60 s without GNSS: raw {r:.1} m, compensated {c:.1} m ({:.0} % of raw).",
                100.0 * c / r
            );
            // Within the Monte Carlo's and the windows' spread of the floor,
            // or above it: say which, from the figures.
            if c <= 1.2 * floor {
                format!(
                    "{head} The compensated run is at the floor its own noise terms predict ({floor:.1} m): \
                     what is left is white noise and bias instability, which no temperature model removes."
                )
            } else {
                format!(
                    "{head} The compensated run stays above the floor its noise terms predict ({floor:.1} m): \
                     the model leaves part of the temperature drift."
                )
            }
        }
        _ => String::new(),
    }
}
