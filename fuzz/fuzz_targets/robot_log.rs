//! What every robot-log fuzz target does with its bytes: decoded as the
//! format the target names (no detection, so that any bytes reach that
//! reader), then assembled into a recording. A reader may refuse a file,
//! never panic, and a recording's channels all have one length.

use std::path::PathBuf;

use imu::RecordingOptions;
use robotlogs::{Choice, Format};

pub fn run(format: Format, ext: &str, bytes: &[u8]) {
    let path: PathBuf = std::env::temp_dir().join(format!("imutherm-fuzz-{}.{ext}", std::process::id()));
    if std::fs::write(&path, bytes).is_err() {
        return;
    }
    let Ok(decoded) = robotlogs::decode(&path, format) else {
        return;
    };
    let choice = Choice {
        first_if_several: true,
        ..Choice::default()
    };
    if let Ok((rec, _, _)) = robotlogs::assemble::assemble(&path, format.name(), decoded, &choice) {
        let n = rec.len();
        assert!(rec.channels.iter().all(|c| c.data.len() == n));
    }
    let _ = robotlogs::read(&path, &RecordingOptions::default(), &choice);
}
