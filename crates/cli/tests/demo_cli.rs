//! `imutherm demo --quick`: the whole experiment, and a report a browser can show.

use predicates::prelude::*;

mod support;
use support::{cli, read_json};

#[test]
fn quick_demo_writes_a_complete_report() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("demo");
    cli!["demo", "--quick", "--format", "png", "--out", &out]
        .assert()
        .success()
        .stdout(predicate::str::contains("report: ").and(predicate::str::contains("gyro_z")));
    let html = std::fs::read_to_string(out.join("report.html")).unwrap();
    assert!(html.starts_with("<!DOCTYPE html>") && html.trim_end().ends_with("</html>"));
    // Eight sensor ADEV plots (two per run), six per-axis ADEV plots over
    // temperature, two raw-data plots, six heat maps of temperature bins and
    // six of the dynamic ADEV, six bias plots, the navigation's error
    // against time, and the noise model of each of the six axes in each of
    // the four constant-temperature runs. The ADEV and raw-data plots are
    // also interactive charts, their SVG kept for print.
    let charts = html
        .matches("<figure class=\"plot\"><div class=\"static\"><svg")
        .count();
    let figures = html.matches("<figure class=\"plot\"><svg").count() + charts;
    assert_eq!(figures, 35 + 24, "figures");
    assert_eq!(
        html.matches("noise model: measured ADEV").count(),
        24,
        "noise-model figures"
    );
    assert_eq!(charts, 16, "interactive charts");
    // The dynamic ADEV's 3D views, raw and compensated per channel, over
    // the thesis's windows: a 1 h quick cooling run holds 21.
    assert_eq!(html.matches("<canvas").count(), 12, "3D views");
    assert!(
        html.contains("sliding windows of 1800 s stepped every 90 s (21 windows)"),
        "dynamic ADEV note"
    );
    // The thesis's table, in the page's default units (the datasheets':
    // `--units datasheet`, docs/demo.md).
    assert!(html.contains("Angle random walk N [°/s/√Hz]"));
    assert!(html.contains("34 °C") && html.contains("82 °C"));
    assert!(html.contains("residual bias over temperature on the held-out heating run"));
    // Navigation without GNSS on the cooling run: compensated drifts less.
    assert!(html.contains("Navigation without GNSS: the cooling run, raw and compensated"));
    assert!(html.contains("60 s without GNSS, by alignment window"));
    let metres = |after: &str| -> f64 {
        let i = html.find(after).unwrap_or_else(|| panic!("{after}")) + after.len();
        html[i..].split(" m").next().unwrap().parse().unwrap()
    };
    let (raw, comp) = (metres("60 s without GNSS: raw "), metres(" m, compensated "));
    assert!(comp < raw, "compensated {comp} m, raw {raw} m");
    // Self-contained: nothing is fetched (the SVG namespace URI is a name,
    // not a download).
    for fetch in ["src=\"http", "href=\"http", "<link", "<script src", "url(http"] {
        assert!(!html.contains(fetch), "{fetch}");
    }
    // --format png: every plot also as a PNG file.
    let pngs = std::fs::read_dir(out.join("figures")).unwrap().count();
    assert_eq!(pngs, 35 + 24, "PNG figures");
    let model = read_json(&out.join("tcal_model.json"));
    assert_eq!(model["schema"], "imutherm.tcal/1");
}
