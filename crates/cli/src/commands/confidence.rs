//! The `--confidence` flag, shared by the commands that print intervals.

use anyhow::{Result, bail};

/// A confidence level from the command line: a fraction (0.683) or, since
/// "68.3" is as natural to type, a percentage. Anything else is a mistake.
pub fn confidence_level(given: f64) -> Result<f64> {
    let level = if (1.0..100.0).contains(&given) {
        given / 100.0
    } else {
        given
    };
    if !(level > 0.0 && level < 1.0) {
        bail!("--confidence {given}: give a level between 0 and 1 (0.683) or a percentage (68.3)");
    }
    Ok(level)
}
