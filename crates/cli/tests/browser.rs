//! The demo's report in a real browser: headless Chromium renders it with
//! the network disabled, every figure must hold a drawn plot, the summary
//! must be on the first screen of a 1280×800 window, the page must log no
//! error and fetch nothing, and the screenshots are kept under
//! `target/report-screenshots/` for people to look at.
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
        // No network: every request goes to a closed port (the page must
        // need none; the probe below checks it made none).
        "--proxy-server=127.0.0.1:9",
        "--proxy-bypass-list=<-loopback>",
    ];
    // Kept as CI artefacts: target/report-screenshots/.
    let shots = PathBuf::from(env!("CARGO_TARGET_TMPDIR"))
        .parent()
        .map_or_else(|| out.clone(), |t| t.join("report-screenshots"));
    std::fs::create_dir_all(&shots).expect("screenshot folder");
    let shot = shots.join("report.png");
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

    // The first screen: a 1280×800 window, as a reader opens the page.
    let first = shots.join("report-first-screen.png");
    let run_first = Process::new(&browser)
        .args(common)
        .arg(format!("--user-data-dir={}", profile.display()))
        .arg("--window-size=1280,800")
        .arg(format!("--screenshot={}", first.display()))
        .arg(&url)
        .output()
        .expect("chromium runs");
    assert!(run_first.status.success(), "chromium failed");
    // Where the summary is, and what the page fetched, measured in the same
    // window by a probe appended to a copy of the page (the report itself
    // carries no test code): it writes its findings into the DOM.
    let probe = out.join("report-probed.html");
    let page_html = std::fs::read_to_string(&page).unwrap();
    let probed = page_html.replace(
        "</body>",
        "<script>(function(){var s=document.getElementById('summary');\
         var r=s?s.getBoundingClientRect():null;\
         var net=performance.getEntriesByType('resource').filter(function(e){return !/^(file|data|blob):/.test(e.name);}).length;\
         document.body.setAttribute('data-probe',(r?Math.round(r.top)+','+Math.round(r.bottom):'none')+';'+window.innerWidth+'x'+window.innerHeight+';'+net);})();</script></body>",
    );
    std::fs::write(&probe, probed).unwrap();
    let measured = Process::new(&browser)
        .args(common)
        .arg(format!("--user-data-dir={}", profile.display()))
        .arg("--window-size=1280,800")
        .arg("--dump-dom")
        .arg(format!("file://{}", probe.display()))
        .output()
        .expect("chromium runs");
    let dom = String::from_utf8_lossy(&measured.stdout);
    let found = dom
        .split("data-probe=\"")
        .nth(1)
        .and_then(|s| s.split('"').next())
        .unwrap_or_else(|| {
            panic!(
                "the probe did not run: {}",
                String::from_utf8_lossy(&measured.stderr)
            )
        });
    let parts: Vec<&str> = found.split(';').collect();
    eprintln!("summary top,bottom; window; network requests: {found}");
    assert_eq!(parts.len(), 3, "probe: {found}");
    let top: f64 = parts[0]
        .split(',')
        .next()
        .and_then(|t| t.parse().ok())
        .unwrap_or_else(|| panic!("no summary on the page: {found}"));
    assert!(
        top < 800.0,
        "the summary starts {top} px down, below the first screen ({found})"
    );
    assert_eq!(parts[2], "0", "the page fetched from the network");
    let log =
        String::from_utf8_lossy(&run_first.stderr).to_string() + &String::from_utf8_lossy(&measured.stderr);
    for bad in ["Uncaught", "CONSOLE(", "SyntaxError", "ReferenceError"] {
        assert!(!log.contains(bad), "the page logged '{bad}': {log}");
    }
    for s in [&shot, &first] {
        eprintln!("screenshot: {}", s.display());
    }
}
