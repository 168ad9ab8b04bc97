//! What every command shows the same way on standard error: what the
//! readers and the analyses noted, and the checks of the channels read.

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

/// [`analysis::selection::read_channels`], showing what the reader noted
/// and the checks found.
pub fn read_channels(file: &Path, wanted: &[String], read: &RecordingOptions) -> Result<Selection> {
    let sel = analysis::selection::read_channels(file, wanted, read)?;
    notes(&sel.notes);
    Ok(sel)
}

/// [`read_channels`] for an analysis of a static sensor (`noise`, `ins`,
/// `tcal fit`, `tcal eval`): a record that moves is refused unless
/// `allow_motion` (`--allow-motion`), and then analysed with a warning.
pub fn read_static_channels(
    file: &Path,
    wanted: &[String],
    read: &RecordingOptions,
    allow_motion: bool,
) -> Result<Selection> {
    let sel = read_channels(file, wanted, read)?;
    // A dead channel is shown (among the notes) and left to the command:
    // `noise` refuses it, navigation shows what it costs.
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
    Ok(sel)
}
