//! `imutherm report`: a page for any recordings, with file names shown as text.

mod support;
use support::{Refused, Simulation, cli, imutherm};

#[test]
fn report_escapes_file_names_and_draws_every_figure() {
    let dir = tempfile::tempdir().unwrap();
    // A file literally named `<script>alert(1)</script>.txt` (its `/` makes
    // the first part a folder).
    let folder = dir.path().join("<script>alert(1)<");
    std::fs::create_dir_all(&folder).unwrap();
    let evil = folder.join("script>.txt");
    let cooling = dir.path().join("cooling.txt");
    for (p, profile) in [(&evil, "constant:34"), (&cooling, "cooling:90:25:600")] {
        Simulation::new()
            .duration("30m")
            .rate("5")
            .profile(profile)
            .command(p)
            .assert()
            .success();
    }
    let out = dir.path().join("rep");
    cli!["report", &evil, &cooling, "--out", &out].assert().success();
    let html = std::fs::read_to_string(out.join("report.html")).unwrap();
    assert!(html.contains("&lt;script&gt;alert(1)&lt;/script&gt;.txt"));
    // The page carries scripts of its own since its charts became
    // interactive, but the file's name never appears unescaped: not in the
    // text, not in a chart's JSON (written with `\u003c` for `<`).
    assert!(!html.contains("<script>alert"));
    // Two sensor ADEV plots per run, six per-axis ADEV plots; for the run
    // whose temperature changes two raw-data plots, six heat maps of its
    // temperature bins and six of its dynamic ADEV (one 30 min window); the
    // navigation's error against time per run; the noise model of each of
    // the six axes of each run.
    let static_svg = html.matches("<figure class=\"plot\"><svg").count();
    let with_chart = html
        .matches("<figure class=\"plot\"><div class=\"static\"><svg")
        .count();
    assert_eq!(static_svg + with_chart, 26 + 12);
    // Every ADEV and raw-data plot is also an interactive chart; the heat
    // maps stay static.
    assert_eq!(with_chart, 12);
    assert!(html.contains("Velocity random walk N"));
    // Each run navigated without aiding, measured beside its prediction.
    assert!(html.contains("Navigation without GNSS"));
    let nav = &html[html.find("Navigation without GNSS").unwrap()..];
    for run in [
        "script&gt;.txt: horizontal position error",
        "cooling.txt: horizontal position error",
    ] {
        assert!(nav.contains(run), "{run} missing from the navigation section");
    }
    assert!(!nav.contains("not navigated"));
}

#[test]
fn a_recording_too_short_to_navigate_says_why() {
    let dir = tempfile::tempdir().unwrap();
    let short = Simulation::new()
        .duration("60")
        .rate("20")
        .write(dir.path(), "short.txt");
    let out = dir.path().join("rep");
    cli!["report", &short, "--out", &out].assert().success();
    let html = std::fs::read_to_string(out.join("report.html")).unwrap();
    assert!(html.contains("short.txt: not navigated"), "no reason given");
}

#[test]
fn the_summary_comes_first_beside_the_datasheet_named() {
    let dir = tempfile::tempdir().unwrap();
    let cold = Simulation::new()
        .duration("20m")
        .rate("5")
        .profile("constant:30")
        .write(dir.path(), "cold.txt");
    let hot = Simulation::new()
        .duration("20m")
        .rate("5")
        .profile("constant:70")
        .write(dir.path(), "hot.txt");
    let page = |datasheet: &[&str]| {
        let out = dir.path().join("rep");
        imutherm()
            .arg("report")
            .arg(&cold)
            .arg(&hot)
            .arg("--out")
            .arg(&out)
            .args(datasheet)
            .assert()
            .success();
        std::fs::read_to_string(out.join("report.html")).unwrap()
    };
    let html = page(&["--datasheet", "mpu-9250"]);
    let summary = html.find("<section id=\"summary\"").expect("a summary");
    assert!(
        summary < html.find("<h2>Command</h2>").unwrap(),
        "the summary is not first"
    );
    let s = &html[summary..html.find("</section>").unwrap()];
    // PS-MPU-9250A-01 rev 1.1 §3.1 gives the gyro's noise density, no B.
    assert!(s.contains("PS-MPU-9250A-01") && s.contains("revision 1.1"));
    assert!(s.contains("0.01 °/s/√Hz") && s.contains("not given"));
    // Six axes, three terms each; N in datasheet units.
    for term in ["N", "B", "K"] {
        assert_eq!(s.matches(&format!("<td>gyro_x</td><td>{term}</td>")).count(), 1);
    }
    assert!(s.contains("µg/√Hz") && s.contains("°/h"));
    // The noise growth from the coldest run to the hottest.
    assert!(s.contains("coldest run (30"), "{s}");
    // Without --datasheet, the page says there is none.
    let html = page(&[]);
    assert!(html.contains("No datasheet given"));
}

#[test]
fn an_unknown_datasheet_is_a_usage_error() {
    let dir = tempfile::tempdir().unwrap();
    let run = Simulation::new()
        .duration("60")
        .rate("20")
        .write(dir.path(), "run.txt");
    cli!["report", &run, "--out", "rep", "--datasheet", "no-such-part"]
        .current_dir(dir.path())
        .refused(2, "MPU-6050");
}

/// The bias slope across constant-temperature runs: the thesis preset's
/// gyro x bias is −2.1 + 0.02·(T−34) + 1e-4·(T−34)² °/s
/// (`imusim::presets`), so the least-squares line through runs placed
/// symmetrically about 50 °C has slope 0.02 + 2·1e-4·(50−34) = 0.0232 °/s/°C.
#[test]
fn the_report_fits_the_bias_slope_across_its_runs() {
    let dir = tempfile::tempdir().unwrap();
    let runs = constant_runs(dir.path(), &[30, 40, 50, 60, 70], "10m");
    let out = dir.path().join("rep");
    imutherm()
        .arg("report")
        .args(&runs)
        .arg("--out")
        .arg(&out)
        .assert()
        .success();
    let html = std::fs::read_to_string(out.join("report.html")).unwrap();
    let row = html
        .split("<tr")
        .find(|r| r.contains("<td>gyro_x</td>") && r.contains("°/s/°C"))
        .expect("a bias-slope row for gyro_x");
    assert!(row.contains("from the run means"), "{row}");
    let cell = row.split("<td>").nth(2).unwrap();
    let mut nums = cell.split(|c: char| !(c.is_ascii_digit() || c == '.' || c == '-' || c == 'e'));
    let mut next = || {
        nums.find_map(|s| s.parse::<f64>().ok())
            .expect("a number in the bias-slope cell")
    };
    let (slope, half) = (next(), next());
    assert!(half > 0.0 && half < 0.01, "{cell}");
    assert!(
        (slope - 0.0232).abs() <= half,
        "slope {slope} ± {half}, expected 0.0232"
    );
}

/// `--units`: the noise figures of the page (the summary and its answer,
/// the thesis tables, the ADEV charts' axes and legends) carry the chosen
/// system's units and no other system's (the labels of
/// `report::page_units`, as whole tokens: `°/s` is not in `°/s/√Hz`).
#[test]
fn the_page_quotes_its_noise_figures_in_one_unit_system() {
    use report::page_units::{Units, labels};
    let dir = tempfile::tempdir().unwrap();
    let runs = constant_runs(dir.path(), &[30], "5m");
    let all = [Units::Si, Units::Datasheet, Units::Thesis];
    for (flag, units) in ["si", "datasheet", "thesis"].into_iter().zip(all) {
        let out = dir.path().join(flag);
        imutherm()
            .arg("report")
            .args(&runs)
            .args(["--units", flag, "--out"])
            .arg(&out)
            .assert()
            .success();
        let html = std::fs::read_to_string(out.join("report.html")).unwrap();
        let figures = noise_figures(&html);
        let own = labels(units);
        let foreign: Vec<&str> = all
            .iter()
            .flat_map(|&u| labels(u))
            .filter(|l| !own.contains(l))
            .collect();
        for l in &foreign {
            assert!(!has_token(&figures, l), "--units {flag}: '{l}' on the page");
        }
        // Each figure keeps its unit: the chosen system's N and B are there.
        let (n, b) = match units {
            Units::Si => ("rad/√s", "rad/s"),
            Units::Datasheet => ("°/s/√Hz", "°/h"),
            Units::Thesis => ("°/√s", "°/s"),
        };
        for l in [n, b] {
            assert!(has_token(&figures, l), "--units {flag}: no '{l}'");
        }
    }
}

/// The page's noise figures: the summary section, the thesis tables, the
/// ADEV figures (their SVG and chart data) and each axis's noise-model
/// figure.
fn noise_figures(html: &str) -> String {
    let mut out = String::new();
    let summary = html.split("<section id=\"summary\"").nth(1).expect("a summary");
    out.push_str(&summary[..summary.find("</section>").expect("the summary's end")]);
    for table in html.split("<table>").skip(1) {
        let table = &table[..table.find("</table>").unwrap()];
        if ["random walk N [", "Bias instability"]
            .iter()
            .any(|c| table.contains(c))
        {
            out.push_str(table);
        }
    }
    for fig in html.split("<figure class=\"plot\">").skip(1) {
        let fig = &fig[..fig.find("</figure>").unwrap()];
        if fig.contains("overlapping ADEV")
            || fig.contains("the three axes")
            || fig.contains("the selected model")
        {
            out.push_str(fig);
        }
    }
    assert!(out.len() > 1000, "too little of the page found");
    out
}

/// `label` as a whole unit in `text`: not part of a longer unit.
fn has_token(text: &str, label: &str) -> bool {
    let unit_char = |c: char| c.is_alphanumeric() || "/√²³°µ".contains(c);
    text.match_indices(label).any(|(i, _)| {
        let before = text[..i].chars().next_back();
        let after = text[i + label.len()..].chars().next();
        !before.is_some_and(|c| c.is_alphabetic() || c == '/') && !after.is_some_and(unit_char)
    })
}

/// Runs at 5 Hz held at each of `temps` (°C), `duration` long, as `runT.txt`.
fn constant_runs(dir: &std::path::Path, temps: &[u32], duration: &str) -> Vec<std::path::PathBuf> {
    temps
        .iter()
        .map(|t| {
            Simulation::new()
                .duration(duration)
                .rate("5")
                .profile(&format!("constant:{t}"))
                .write(dir, &format!("run{t}.txt"))
        })
        .collect()
}
