//! imutherm's readers on arbitrary bytes (text, CSV, thesis logs, gzip):
//! they may refuse a file, never panic.
#![no_main]

use std::path::PathBuf;

use imu::table::{ReadPolicy, TableReader};
use imu::{RecordingOptions, read_recording_with_report};
use libfuzzer_sys::fuzz_target;

/// The readers take a path: one scratch file per fuzzing process.
fn scratch() -> PathBuf {
    std::env::temp_dir().join(format!("imutherm-fuzz-readers-{}.txt", std::process::id()))
}

fuzz_target!(|bytes: &[u8]| {
    let path = scratch();
    if std::fs::write(&path, bytes).is_err() {
        return;
    }
    for skip_bad_lines in [false, true] {
        if let Ok(r) = TableReader::open(&path) {
            let _ = r.read_with(None, &ReadPolicy { skip_bad_lines });
        }
        // As read by default, and with the overrides of the command line:
        // a unit, a named time column and its unit.
        let overrides = RecordingOptions {
            rate_hz: Some(200.0),
            units: vec!["gyro_x=deg/s".parse().unwrap(), "2=mg".parse().unwrap()],
            time_column: Some("t".into()),
            time_unit: Some("ms".into()),
            skip_bad_lines,
            ..RecordingOptions::default()
        };
        for opts in [
            RecordingOptions {
                skip_bad_lines,
                ..RecordingOptions::default()
            },
            overrides,
        ] {
            if let Ok((rec, _)) = read_recording_with_report(&path, &opts) {
                let n = rec.len();
                assert!(rec.channels.iter().all(|c| c.data.len() == n));
            }
        }
    }
});
