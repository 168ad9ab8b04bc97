//! The demo's report in a real browser: headless Chromium renders it, every
//! figure must hold a drawn plot, the page must log no error, and the
//! screenshot is kept under `target/` for people to look at.
//!
//! Needs Debian's `chromium`. `.ci/run` installs it and sets
//! `IMUTHERM_REQUIRE_BROWSER=1`, so CI cannot skip this test; elsewhere it
//! says it is skipped when no browser is installed.

use std::path::PathBuf;
use std::process::Command as Process;

mod support;
use support::imutherm;

fn chromium() -> Option<PathBuf> {
    ["chromium", "chromium-browser", "google-chrome"]
        .iter()
        .find_map(|name| {
            std::env::var_os("PATH")?
                .to_str()?
                .split(':')
                .map(|d| PathBuf::from(d).join(name))
                .find(|p| p.is_file())
        })
}

#[test]
fn the_demo_report_renders_in_chromium() {
    let Some(browser) = chromium() else {
        assert!(
            std::env::var_os("IMUTHERM_REQUIRE_BROWSER").is_none(),
            "IMUTHERM_REQUIRE_BROWSER is set but no chromium is installed"
        );
        eprintln!("skipped: no chromium on PATH (apt-get install chromium to run this test)");
        return;
    };
    let out = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("browser-demo");
    let _ = std::fs::remove_dir_all(&out);
    imutherm()
        .args(["demo", "--quick", "--out"])
        .arg(&out)
        .assert()
        .success();
    let page = out.join("report.html");
    let url = format!("file://{}", page.display());
    let profile = out.join("chromium-profile");
    let common = [
        "--headless",
        "--no-sandbox",
        "--disable-gpu",
        "--disable-quic",
        "--no-first-run",
        "--disable-background-networking",
        "--disable-component-update",
        "--disable-sync",
        "--enable-logging=stderr",
        "--v=0",
    ];
    let shot = out.join("report.png");
    let run = Process::new(&browser)
        .args(common)
        .arg(format!("--user-data-dir={}", profile.display()))
        .arg("--window-size=1200,3000")
        .arg(format!("--screenshot={}", shot.display()))
        .arg(&url)
        .output()
        .expect("chromium runs");
    assert!(
        run.status.success(),
        "chromium failed: {}",
        String::from_utf8_lossy(&run.stderr)
    );
    let png = std::fs::read(&shot).expect("screenshot written");
    assert!(
        png.starts_with(b"\x89PNG") && png.len() > 50_000,
        "screenshot of {} bytes",
        png.len()
    );

    // The DOM as the browser built it.
    let dom = Process::new(&browser)
        .args(common)
        .arg(format!("--user-data-dir={}", profile.display()))
        .arg("--dump-dom")
        .arg(&url)
        .output()
        .expect("chromium runs");
    let html = String::from_utf8_lossy(&dom.stdout);
    let figures: Vec<&str> = html.split("<figure class=\"plot\">").skip(1).collect();
    assert_eq!(figures.len(), 28, "figures in the rendered page");
    for (i, f) in figures.iter().enumerate() {
        let body = f.split("</figure>").next().unwrap_or("");
        assert!(body.contains("<svg"), "figure {i} has no svg");
        let marks = body.matches("<circle").count()
            + body.matches("<rect").count()
            + body.matches("<polyline").count();
        assert!(marks > 10, "figure {i} is nearly empty ({marks} marks)");
    }
    // The six interactive surfaces were drawn by their script.
    let canvases = html.matches("<canvas").count();
    assert_eq!(canvases, 6, "3D surfaces");
    let rendered = html
        .split("data-rendered=\"")
        .skip(1)
        .filter(|s| {
            s.split('"')
                .next()
                .and_then(|n| n.parse::<usize>().ok())
                .is_some_and(|n| n > 0)
        })
        .count();
    assert_eq!(rendered, 6, "surfaces drawn");
    // No script error or console message from the page.
    let log = String::from_utf8_lossy(&run.stderr).to_string() + &String::from_utf8_lossy(&dom.stderr);
    for bad in ["Uncaught", "CONSOLE(", "SyntaxError", "ReferenceError"] {
        assert!(!log.contains(bad), "the page logged '{bad}': {log}");
    }
    // Kept for people: target/tmp/browser-demo/report.png.
    eprintln!("screenshot: {}", shot.display());
}
