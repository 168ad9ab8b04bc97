//! What every command shows the same way on standard error: what the
//! readers and the analyses noted, and the checks of the channels read.

use std::path::Path;

use anyhow::Result;

use analysis::selection::{SelectedChannel, Selection};
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

/// Values beyond √MAX/2: their differences square past the largest
/// double, so every deviation, fit and integral over them would be
/// infinite or NaN.
fn overflow_limit() -> f64 {
    f64::MAX.sqrt() / 2.0
}

/// The first finite value of `data` beyond [`overflow_limit`].
fn first_overflowing(data: &[f64]) -> Option<f64> {
    let limit = overflow_limit();
    data.iter().copied().find(|v| v.is_finite() && v.abs() > limit)
}

/// Refuses channels holding a value beyond [`overflow_limit`], naming the
/// column and saying the cause rather than anything about taus or fits.
pub fn refuse_overflowing(channels: &[SelectedChannel]) -> Result<()> {
    for ch in channels {
        if let Some(v) = first_overflowing(&ch.data) {
            anyhow::bail!(
                "{}: column {} ({}): a value of {v:e} overflows double precision in the statistics (values must stay within ±{:.1e})",
                ch.file.display(),
                ch.column,
                ch.name,
                overflow_limit()
            );
        }
    }
    Ok(())
}

/// [`refuse_overflowing`] for a selection, its temperature included.
pub fn refuse_overflow(sel: &Selection) -> Result<()> {
    refuse_overflowing(&sel.channels)?;
    let limit = overflow_limit();
    if let (Some(t), Some(ch)) = (&sel.temperature, sel.channels.first())
        && let Some(v) = first_overflowing(t)
    {
        anyhow::bail!(
            "{}: the temperature channel: a value of {v:e} °C overflows double precision in the statistics (values must stay within ±{limit:.1e})",
            ch.file.display()
        );
    }
    Ok(())
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
    static_checked(file, read_channels(file, wanted, read)?, allow_motion)
}

/// The checks of [`read_static_channels`] on channels read from `file`.
pub fn static_checked(file: &Path, sel: Selection, allow_motion: bool) -> Result<Selection> {
    refuse_overflow(&sel)?;
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
