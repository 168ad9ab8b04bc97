//! The outputs users and scripts keep, byte for byte: the demo's table, the
//! JSON documents, the model, the Kalibr file and the firmware parameter
//! files, on fixed simulated runs, compared with the files in
//! `tests/golden/` (see its README for where they come from and how to
//! write them again).
//!
//! Only what legitimately varies is normalised before the comparison: the
//! version string (`imutherm_version`, "imutherm 0.1.0"). Paths do not vary:
//! every command runs in the runs' directory and names them relatively, as
//! a user would. No output compared here carries a wall-clock time. The
//! report is compared without its figures and its command line.

use std::path::Path;

mod support;
use support::{Simulation, imutherm, succeed};

const GOLDEN: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/golden");

/// Set to write the golden files from the current binary instead of
/// comparing with them.
const BLESS: &str = "IMUTHERM_BLESS";

/// The version, which changes with every release and nothing else.
fn normalise(text: &str) -> String {
    let v = env!("CARGO_PKG_VERSION");
    text.replace(
        &format!("\"imutherm_version\": \"{v}\""),
        "\"imutherm_version\": \"VERSION\"",
    )
    .replace(
        &format!("\"imutherm_version\":\"{v}\""),
        "\"imutherm_version\":\"VERSION\"",
    )
    .replace(&format!("imutherm {v}"), "imutherm VERSION")
}

/// Compares `actual` with the golden file `name`, or writes it when
/// `IMUTHERM_BLESS` is set.
fn check(name: &str, actual: &[u8]) {
    let actual = normalise(std::str::from_utf8(actual).expect("every compared output is UTF-8"));
    let path = Path::new(GOLDEN).join(name);
    if std::env::var_os(BLESS).is_some() {
        std::fs::write(&path, &actual).unwrap();
        return;
    }
    let expected = std::fs::read_to_string(&path)
        .unwrap_or_else(|e| panic!("{}: {e} (write it with {BLESS}=1)", path.display()));
    if actual != expected {
        let line = actual
            .lines()
            .zip(expected.lines())
            .position(|(a, e)| a != e)
            .unwrap_or_else(|| actual.lines().count().min(expected.lines().count()));
        panic!(
            "{name} differs from {} at line {}:\n  now:    {:?}\n  golden: {:?}",
            path.display(),
            line + 1,
            actual.lines().nth(line),
            expected.lines().nth(line)
        );
    }
}

/// The standard output of `imutherm ARGS` run in `dir`, which must succeed.
fn stdout_in(dir: &Path, args: &[&str]) -> Vec<u8> {
    succeed(imutherm().current_dir(dir).args(args)).stdout
}

/// Three short thesis-preset runs: one at a constant 34 °C for the noise
/// terms, a cooling run to fit a model on, a heating ramp it never saw.
fn runs() -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    let sim = |profile: &str, seed: &str, name: &str| {
        Simulation::new()
            .profile(profile)
            .duration("600")
            .rate("20")
            .seed(seed)
            .write(dir.path(), name);
    };
    sim("constant:34", "1", "const.txt");
    sim("cooling:80:20:300", "3", "cool.txt");
    sim("ramp:25:45:300", "5", "ramp.txt");
    dir
}

/// The runs and a model fitted on the cooling run for PX4's cubic.
fn runs_and_model() -> tempfile::TempDir {
    let dir = runs();
    stdout_in(
        dir.path(),
        &["tcal", "fit", "--for", "px4", "-o", "model.json", "cool.txt"],
    );
    dir
}

#[test]
fn demo_table() {
    let dir = tempfile::tempdir().unwrap();
    check(
        "demo_quick.txt",
        &stdout_in(dir.path(), &["demo", "--quick", "--out", "demo"]),
    );
    check(
        "demo_tcal_model.json",
        &std::fs::read(dir.path().join("demo/tcal_model.json")).unwrap(),
    );
}

#[test]
fn noise_documents_and_kalibr() {
    let dir = runs();
    let d = dir.path();
    check("noise.json", &stdout_in(d, &["noise", "--json", "const.txt"]));
    check("noise.txt", &stdout_in(d, &["noise", "const.txt"]));
    check(
        "noise_datasheet.txt",
        &stdout_in(d, &["noise", "--units", "datasheet", "const.txt"]),
    );
    stdout_in(d, &["noise", "--kalibr", "imu.yaml", "const.txt"]);
    check("kalibr_imu.yaml", &std::fs::read(d.join("imu.yaml")).unwrap());
}

#[test]
fn adev_info_and_thermal_documents() {
    let dir = runs();
    let d = dir.path();
    check("adev.json", &stdout_in(d, &["adev", "--json", "const.txt"]));
    check(
        "info.json",
        &stdout_in(d, &["info", "--json", "const.txt", "cool.txt"]),
    );
    check(
        "thermal.json",
        &stdout_in(
            d,
            &[
                "thermal",
                "--json",
                "--bin-width",
                "10",
                "-c",
                "gyro_z,accel_x",
                "cool.txt",
            ],
        ),
    );
}

#[test]
fn tcal_model_evaluation_and_exports() {
    let dir = runs_and_model();
    let d = dir.path();
    check("tcal_model.json", &std::fs::read(d.join("model.json")).unwrap());
    check(
        "tcal_eval.json",
        &stdout_in(d, &["tcal", "eval", "--json", "model.json", "ramp.txt"]),
    );
    check(
        "tcal_eval_ardupilot.txt",
        &stdout_in(
            d,
            &["tcal", "eval", "--export", "ardupilot", "model.json", "ramp.txt"],
        ),
    );
    check(
        "tcal_export_px4.params",
        &stdout_in(d, &["tcal", "export", "model.json", "--firmware", "px4"]),
    );
    check(
        "tcal_export_ardupilot.parm",
        &stdout_in(
            d,
            &[
                "tcal",
                "export",
                "model.json",
                "--firmware",
                "ardupilot",
                "--instance",
                "2",
            ],
        ),
    );
}

#[test]
fn ins_document() {
    let dir = runs_and_model();
    check(
        "ins.json",
        &stdout_in(
            dir.path(),
            &[
                "ins",
                "--json",
                "--model",
                "model.json",
                "--horizon",
                "60",
                "cool.txt",
            ],
        ),
    );
}

/// Every `<open…</close>` span of `text` replaced by `with`.
fn blank_spans(text: &str, open: &str, close: &str, with: &str) -> String {
    let mut out = String::new();
    let mut rest = text;
    while let Some(i) = rest.find(open) {
        out.push_str(&rest[..i]);
        out.push_str(with);
        let after = &rest[i..];
        rest = after.find(close).map_or("", |j| &after[j + close.len()..]);
    }
    out.push_str(rest);
    out
}

#[test]
fn noise_tables_of_two_runs() {
    let dir = runs();
    let d = dir.path();
    check(
        "noise_two_runs.txt",
        &stdout_in(d, &["noise", "const.txt", "ramp.txt"]),
    );
    check(
        "noise_two_runs_datasheet_verbose.txt",
        &stdout_in(
            d,
            &["noise", "--units", "datasheet", "-v", "const.txt", "ramp.txt"],
        ),
    );
}

/// The report's page without its figures (drawn by plotters, compared by
/// the report's own tests) and without its command line (which names the
/// test's binary and folder): the tables and text, byte for byte.
#[test]
fn report_page_without_figures() {
    let dir = runs();
    let d = dir.path();
    stdout_in(d, &["report", "const.txt", "cool.txt", "--out", "rep"]);
    let html = std::fs::read_to_string(d.join("rep/report.html")).unwrap();
    let html = blank_spans(&html, "<svg", "</svg>", "<svg/>");
    let html = blank_spans(&html, "<pre>", "</pre>", "<pre/>");
    check("report_without_figures.html", html.as_bytes());
}
