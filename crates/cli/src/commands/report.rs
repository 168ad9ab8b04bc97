//! `imutherm report`: one HTML page for a set of recordings.

use anyhow::{Context, Result};

use analysis::dynamic_adev::{DynamicAdevError, dynamic_adev};
use analysis::navigation::{Plan, navigate, take_six_channels};
use analysis::noise::analyse_selection;
use analysis::selection::Selection;
use analysis::summary::Summary;
use ins::drift::report_times;
use report::experiment::{
    PAGE_MARK, PngDir, adev_figures, command_section, dynamic_heatmap, dynamic_note, dynamic_slices, figure,
    model_figures, noise_tables, recordings_navigation_section, refuse_foreign_files, time_figures,
};
use report::html::Page;
use report::plots::adev_heatmap_bins;
use thermal::surface::bin_curves_only;

use crate::args::{FigureFormat, ReportArgs};
use crate::print::notes;

/// Temperature span from which a run gets its ADEV-over-temperature maps, °C.
const SURFACE_SPAN_C: f64 = 5.0;

pub fn run(a: &ReportArgs) -> Result<()> {
    let read = a.read.recording_options()?;
    let sheet = a.datasheet.as_deref().map(crate::flags::datasheet).transpose()?;
    // Before any work: the page is never one of the inputs, nor a file
    // imutherm did not write.
    imu::output::check_output(
        &a.out.join("report.html"),
        &imu::output::OutputPolicy {
            overwrite: true,
            inputs: &a.files,
        },
    )?;
    refuse_foreign_files(&a.out, &[("report.html", PAGE_MARK)])?;
    std::fs::create_dir_all(&a.out).with_context(|| format!("creating {}", a.out.display()))?;
    let png = PngDir::new(a.format == FigureFormat::Png, &a.out)?;
    let mut rows = Vec::new();
    let mut problems = Vec::new();
    let mut changing = Vec::new();
    let dynamic = a.dynamic.dynamic_options();
    // Each input read once, its selection held for every section below:
    // a pipe gives its bytes once.
    let mut read_runs = Vec::with_capacity(a.files.len());
    for f in &a.files {
        let sel = analysis::selection::read_channels(f, &[], &read)?;
        let facts = &sel.recording;
        // One pass, without a copy of the channel; the sum in order from
        // -0.0, as `Iterator::sum`.
        let temp = sel.temperature.as_ref().map(|t| {
            let (lo, hi, sum, n) = t.iter().filter(|x| x.is_finite()).fold(
                (f64::INFINITY, f64::NEG_INFINITY, -0.0, 0usize),
                |(a, b, s, n), &x| (a.min(x), b.max(x), s + x, n + 1),
            );
            (lo, sum / n.max(1) as f64, hi)
        });
        if let Some((lo, _, hi)) = temp
            && hi - lo >= SURFACE_SPAN_C
        {
            // Asked for in so many words, a window the run cannot hold is
            // the user's to change; the default one is left out with a note.
            if a.dynamic.dyn_window.is_some()
                && let Some(d) = facts.duration_s
                && dynamic.window_s > d
            {
                crate::args::usage_error(format!(
                    "--dyn-window {} s is longer than {} ({d:.1} s)",
                    dynamic.window_s,
                    f.display()
                ));
            }
            changing.push(read_runs.len());
        }
        rows.push(vec![
            f.display().to_string(),
            facts.device.clone().unwrap_or_else(|| "—".into()),
            facts.samples.to_string(),
            facts.rate_hz.map_or("unknown".into(), |r| {
                format!("{} Hz", imu::log_file::round_rate(r))
            }),
            facts.duration_s.map_or("—".into(), |d| format!("{d:.1} s")),
            temp.map_or("—".into(), |(lo, m, hi)| format!("{lo:.1} / {m:.1} / {hi:.1}")),
            (facts.problems.len() + facts.unlisted).to_string(),
        ]);
        for p in &facts.problems {
            problems.push(vec![
                f.display().to_string(),
                p.line.map_or("—".into(), |l| l.to_string()),
                p.message.clone(),
            ]);
        }
        read_runs.push(sel);
    }
    // The noise analysis takes the channels' samples: it is given a copy,
    // and the selection stays for the figures and the navigation.
    let analysed = a
        .files
        .iter()
        .zip(&read_runs)
        .map(|(f, sel)| analyse_selection(f, sel.clone()))
        .collect::<Result<Vec<_>, _>>()?;
    for run in &analysed {
        notes(&run.notes);
    }
    let mut page = Page::new("imutherm report");
    page.summary(&Summary::of_runs(&analysed, sheet.as_ref()), a.page_units.units());
    command_section(&mut page, &std::env::args().collect::<Vec<_>>().join(" "));
    page.heading("Inputs");
    page.table(
        "recordings",
        &[
            "file",
            "device",
            "samples",
            "rate",
            "duration",
            "temperature min / mean / max [°C]",
            "problems",
        ]
        .map(String::from),
        &rows,
    );
    if !problems.is_empty() {
        page.table(
            "problems found while reading",
            &["file", "line", "problem"].map(String::from),
            &problems,
        );
    }

    noise_tables(&mut page, &analysed, a.page_units.units());
    adev_figures(&mut page, &analysed, &png, a.page_units.units())?;
    model_figures(&mut page, &analysed, &png, a.page_units.units())?;

    for &i in &changing {
        let (f, sel) = (&a.files[i], &read_runs[i]);
        page.heading(&format!("ADEV over temperature: {}", f.display()));
        // The reader's notes again beside this section's figures.
        notes(&sel.notes);
        time_figures(&mut page, sel, &f.display().to_string(), &png)?;
        let Some(temp) = &sel.temperature else { continue };
        let mut noted = false;
        for c in &sel.channels {
            match dynamic_adev(&c.data, temp, sel.rate_hz, &dynamic) {
                Ok(d) => {
                    if !noted {
                        page.paragraph(&dynamic_note(&d));
                        noted = true;
                    }
                    // One window is a curve, not a surface: its heat map
                    // is one band, and no 3D view is drawn.
                    if d.windows.len() > 1 {
                        page.surface3d(&c.name, &c.unit, &dynamic_slices(&d));
                    }
                    dynamic_heatmap(
                        &mut page,
                        &png,
                        &c.name,
                        &c.unit,
                        &d,
                        &format!("adev_dynamic_{}_{}", f.display(), c.name),
                    )?;
                }
                Err(e @ DynamicAdevError::WindowLongerThanRun { .. }) if !noted => {
                    page.paragraph(&format!("No dynamic ADEV: {e} (--dyn-window)."));
                    noted = true;
                }
                Err(DynamicAdevError::WindowLongerThanRun { .. }) => {}
                Err(e) => return Err(e).with_context(|| format!("{}: {}", f.display(), c.name)),
            }
            let rows = bin_curves_only(&c.data, temp, sel.rate_hz, 5.0, allan::DEFAULT_CONFIDENCE)?;
            figure(
                &mut page,
                &png,
                &format!("adev_over_temperature_{}_{}", f.display(), c.name),
                &format!("{}: σ(τ, T) over 5 °C bins", c.name),
                |t| adev_heatmap_bins(t, &c.name, &c.unit, &rows),
            )?;
        }
    }

    navigation_section(&mut page, &a.files, read_runs, &png)?;

    let path = a.out.join("report.html");
    // DIR is the report's own: its report.html is replaced (atomically),
    // unless it is one of the inputs.
    imu::output::write_file(
        &path,
        page.finish()?.as_bytes(),
        &imu::output::OutputPolicy {
            overwrite: true,
            inputs: &a.files,
        },
    )?;
    println!("report: {}", path.display());
    Ok(())
}

/// What each recording's noise costs in metres: navigated without aiding
/// from a start point every 10 s, measured beside the closed-form
/// prediction from its own noise terms (`imutherm ins` with its defaults).
/// A recording that cannot be navigated (no six inertial axes, shorter than
/// an alignment and a horizon) says why instead.
fn navigation_section(
    page: &mut Page,
    files: &[std::path::PathBuf],
    read_runs: Vec<Selection>,
    png: &PngDir,
) -> Result<()> {
    let plan = Plan::standard(report_times(120.0));
    let mut navigated = Vec::new();
    for (f, mut sel) in files.iter().zip(read_runs) {
        notes(&sel.notes);
        let six = take_six_channels(f, &mut sel);
        let rate = sel.rate_hz;
        // What is left, the temperature, is not navigated: freed first.
        drop(sel);
        let n = six.and_then(|six| navigate(f, &six, rate, &plan));
        navigated.push((f.clone(), n));
    }
    recordings_navigation_section(page, &plan, &navigated, png)?;
    Ok(())
}
