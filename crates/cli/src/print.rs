//! What every command shows the same way on standard error: what the
//! readers and the analyses noted.

use std::path::Path;

use anyhow::Result;

use analysis::selection::Selection;
use imu::RecordingOptions;

/// Shows each line an analysis noted (`warning: …`, `note: …`).
pub fn notes(lines: &[String]) {
    for line in lines {
        eprintln!("{line}");
    }
}

/// [`analysis::selection::read_channels`], showing what the reader noted.
pub fn read_channels(file: &Path, wanted: &[String], read: &RecordingOptions) -> Result<Selection> {
    let sel = analysis::selection::read_channels(file, wanted, read)?;
    notes(&sel.notes);
    Ok(sel)
}
