//! `imutherm demo`: the thesis's whole experiment on simulated data.

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{Context, Result};
use indicatif::{ProgressBar, ProgressStyle};

use allan::noise_terms::Term;
use analysis::experiment::{Experiment, Inputs};
use analysis::noise::ChannelNoise;
use analysis::summary::Summary;
use analysis::units::deg;
use imu::RecordingOptions;
use imu::output::{AtomicFile, OutputPolicy, write_file};
use imusim::thermal::Profile;
use imusim::{Simulator, presets};
use report::experiment::{
    LOG_MARK, PAGE_MARK, PngDir, adev_figures, command_section, compensation_section, model_figures,
    navigation_section, noise_tables, refuse_foreign_files, surface_section, time_figures,
};
use report::html::Page;
use thermal::evaluation::spread;
use thermal::tcal::FitOptions;

use crate::args::{DemoArgs, FigureFormat};
use crate::print::notes;

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
    let dynamic = a.dynamic.dynamic_options();
    if dynamic.window_s > cooling_s {
        crate::args::usage_error(format!(
            "--dyn-window {} s is longer than the demo's cooling run ({cooling_s} s){}",
            dynamic.window_s,
            if a.quick { " with --quick" } else { "" }
        ));
    }
    let runs_named: Vec<String> = TEMPERATURES.iter().map(|t| format!("run_{t:.0}C.txt")).collect();
    let mut own: Vec<(&str, &str)> = runs_named.iter().map(|n| (n.as_str(), LOG_MARK)).collect();
    own.extend([
        ("cooling_100_to_20C.txt", LOG_MARK),
        ("heating_25_to_95C.txt", LOG_MARK),
        ("tcal_model.json", "\"schema\": \"imutherm.tcal/1\""),
        ("report.html", PAGE_MARK),
    ]);
    let sheet = if a.datasheet.eq_ignore_ascii_case("none") {
        None
    } else {
        Some(crate::flags::datasheet(&a.datasheet)?)
    };
    refuse_foreign_files(&a.out, &own)?;
    std::fs::create_dir_all(&a.out).with_context(|| format!("creating {}", a.out.display()))?;
    let png = PngDir::new(a.format == FigureFormat::Png, &a.out)?;
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
        let profile = Profile::constant(*t, 0.05);
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

    // 2–4. Noise terms, ADEV over temperature, compensation, navigation.
    let exp = Experiment::run(
        &Inputs {
            constant: runs.clone(),
            cooling: cooling.clone(),
            heating: heating.clone(),
        },
        &RecordingOptions::default(),
        // Capped at the flight stacks' cubic and projected on what they
        // apply, so the demo's model exports.
        &FitOptions {
            max_auto_order: thermal::firmware::Firmware::MAX_ORDER,
            firmware_projection: true,
            ..FitOptions::default()
        },
        &dynamic,
        |step| eprintln!("{step}…"),
    )?;
    notes(&exp.notes);
    write_file(
        &file("tcal_model.json"),
        (serde_json::to_string_pretty(&exp.model)? + "\n").as_bytes(),
        &OWN_FILE,
    )?;

    // 5. The report.
    let mut page = Page::new("imutherm — temperature dependency of a simulated MPU-9250");
    page.summary(
        &Summary::of_experiment(&exp, sheet.as_ref()),
        a.page_units.units(),
    );
    page.paragraph(&format!(
        "Simulated with the mpu9250-thesis preset: four {} s runs at {} Hz held at 34, 43, 62 and 82 °C, \
         a {} s cooling run from 100 °C towards 20 °C and a heating run from 25 to 95 °C that the \
         compensation never saw.",
        constant_s, rate, cooling_s
    ));
    command_section(&mut page, &std::env::args().collect::<Vec<_>>().join(" "));
    page.heading("Inputs");
    let inputs: Vec<Vec<String>> = runs
        .iter()
        .chain([&cooling, &heating])
        .map(|p| vec![p.display().to_string()])
        .collect();
    page.table("recordings", &["file".to_string()], &inputs);

    noise_tables(&mut page, &exp.runs, a.page_units.units());
    adev_figures(&mut page, &exp.runs, &png, a.page_units.units())?;
    model_figures(&mut page, &exp.runs, &png, a.page_units.units())?;

    page.heading("Cooling run: raw data");
    time_figures(&mut page, &exp.cooling, "cooling run", &png)?;
    surface_section(&mut page, &exp, &png)?;
    compensation_section(&mut page, &exp, &png)?;
    navigation_section(&mut page, &exp, &png)?;
    let html = page.finish()?;
    let report_path = file("report.html");
    write_file(&report_path, html.as_bytes(), &OWN_FILE)?;

    // 6. Summary.
    println!("report: {}", report_path.display());
    println!(
        "{:<8} {:>12} {:>12} {:<7} {:>12} {:>12} bias unit",
        "axis", "N 34 °C", "N 82 °C", "N unit", "bias raw", "bias comp"
    );
    let (compensation, analysed) = (&exp.compensation, &exp.runs);
    for (i, r) in analysed[0].channels.iter().enumerate() {
        let q = r.channel.quantity;
        // The one answer: the selected model's N, or its bound.
        let n = |a: &ChannelNoise| {
            a.terms
                .choose(Term::WhiteNoise)
                .value()
                .map_or(f64::NAN, |v| v * deg(q))
        };
        let hot = analysed[3].channels.get(i).map_or(f64::NAN, n);
        let c = &compensation[i.min(compensation.len() - 1)];
        // Every figure with its unit: N in the thesis's °/√s (m/s/√s),
        // the bias in the channel's own unit.
        let n_unit = if q == imu::Quantity::AngularRate {
            "°/√s"
        } else {
            "m/s/√s"
        };
        println!(
            "{:<8} {:>12.5} {:>12.5} {:<7} {:>12.3e} {:>12.3e} {}",
            r.channel.name,
            n(r),
            hot,
            n_unit,
            spread(&c.before).rms,
            spread(&c.after).rms,
            c.unit
        );
    }
    println!(
        "(N from the selected noise model, or its upper bound; bias: RMS over temperature \
         of the held-out run's 1 °C bin means, raw and compensated)"
    );
    eprintln!("done in {:.1} s", started.elapsed().as_secs_f64());
    Ok(())
}
