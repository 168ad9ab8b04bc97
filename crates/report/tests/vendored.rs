//! The vendored charting library is the one its README names: each file's
//! SHA-256 is recorded there (`sha256 FILE HEX`), so a changed file cannot
//! go into a report unnoticed.

use sha2::{Digest, Sha256};

#[test]
fn vendored_files_match_their_recorded_hashes() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("vendor/uplot");
    let readme = std::fs::read_to_string(dir.join("README.md")).expect("vendor README");
    let recorded: Vec<(&str, &str)> = readme
        .lines()
        .filter_map(|l| {
            let mut w = l.split_whitespace();
            (w.next() == Some("sha256")).then(|| (w.next().unwrap_or(""), w.next().unwrap_or("")))
        })
        .collect();
    assert_eq!(recorded.len(), 2, "hashes recorded in {readme}");
    for (file, hex) in recorded {
        let bytes = std::fs::read(dir.join(file)).unwrap_or_else(|e| panic!("{file}: {e}"));
        let digest: String = Sha256::digest(&bytes)
            .iter()
            .map(|b| format!("{b:02x}"))
            .collect();
        assert_eq!(digest, hex, "{file} differs from the vendored release");
    }
    // And the page embeds exactly these files.
    assert_eq!(
        report::charts::UPLOT_JS.as_bytes(),
        std::fs::read(dir.join("uPlot.iife.min.js")).unwrap().as_slice()
    );
    assert!(report::charts::UPLOT_JS.contains("uPlot"));
}
