//! What every command shows the same way on standard error: what the
//! readers and the analyses noted, and the checks of the channels read.

use std::path::Path;
use std::sync::OnceLock;

use anyhow::Result;

use analysis::selection::Selection;
use imu::RecordingOptions;

/// Set once by the command that analyses a static sensor (`noise`, `ins`,
/// `tcal fit`, `tcal eval`): whether it takes a moving record
/// (`--allow-motion`). Unset, a command only shows the checks.
static STATIC_SENSOR: OnceLock<bool> = OnceLock::new();

/// Makes every [`read_channels`] of this run refuse a moving record (unless
/// `allow_motion`).
pub fn analyse_a_static_sensor(allow_motion: bool) {
    // Set once, before the command runs; a second call would change
    // nothing.
    let _ = STATIC_SENSOR.set(allow_motion);
}

/// Shows each line an analysis noted (`warning: …`, `note: …`).
pub fn notes(lines: &[String]) {
    for line in lines {
        eprintln!("{line}");
    }
}

/// [`analysis::selection::read_channels`], showing what the reader noted
/// and the checks found; for an analysis of a static sensor, refusing a
/// record that moves.
pub fn read_channels(file: &Path, wanted: &[String], read: &RecordingOptions) -> Result<Selection> {
    let sel = analysis::selection::read_channels(file, wanted, read)?;
    notes(&sel.notes);
    if let Some(&allow_motion) = STATIC_SENSOR.get() {
        // A dead channel is shown (among the notes) and left to the
        // command: `noise` refuses it, navigation shows what it costs.
        if let Err(e) = sel.checks.require_static(&[], allow_motion) {
            anyhow::bail!(
                "{}: {e}; pass --allow-motion to analyse it anyway",
                file.display()
            );
        }
        if allow_motion && let Some(m) = sel.checks.motion() {
            eprintln!(
                "warning: {}: analysed as if static though it moves {:.1} of {:.1} s (--allow-motion)",
                file.display(),
                m.moving_s,
                m.total_s
            );
        }
    }
    Ok(sel)
}
