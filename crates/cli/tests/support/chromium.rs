//! Headless Chromium for the browser tests: where it is, the flags that keep
//! it off the network, and where screenshots are kept.

use std::path::{Path, PathBuf};

/// The browser on PATH, if any.
pub fn chromium() -> Option<PathBuf> {
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

/// The browser, or `None` after saying the test is skipped; with
/// `IMUTHERM_REQUIRE_BROWSER` set (as `.ci/run` sets it) a missing browser
/// fails the test instead.
pub fn chromium_or_skip() -> Option<PathBuf> {
    let found = chromium();
    if found.is_none() {
        assert!(
            std::env::var_os("IMUTHERM_REQUIRE_BROWSER").is_none(),
            "IMUTHERM_REQUIRE_BROWSER is set but no chromium is installed"
        );
        eprintln!("skipped: no chromium on PATH (apt-get install chromium to run this test)");
    }
    found
}

/// Headless, without a GPU, and with every request sent to a closed port:
/// a page that needs the network shows it.
pub const FLAGS: [&str; 13] = [
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
    "--proxy-server=127.0.0.1:9",
    "--proxy-bypass-list=<-loopback>",
    "--hide-scrollbars",
];

/// `target/report-screenshots/`, kept as CI artefacts; created.
pub fn screenshots(fallback: &Path) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR"))
        .parent()
        .map_or_else(|| fallback.to_path_buf(), |t| t.join("report-screenshots"));
    std::fs::create_dir_all(&dir).expect("screenshot folder");
    dir
}

/// The console lines of a page that mean something went wrong.
pub fn console_errors(log: &str) -> Vec<&str> {
    log.lines()
        .filter(|l| {
            [
                "Uncaught",
                "CONSOLE(",
                ":CONSOLE",
                "SyntaxError",
                "ReferenceError",
                "TypeError",
            ]
            .iter()
            .any(|bad| l.contains(bad))
        })
        // A test probe's own pixel reads draw Chromium's advice to set
        // willReadFrequently: the probe's, not the page's.
        .filter(|l| !l.contains("willReadFrequently"))
        .collect()
}
