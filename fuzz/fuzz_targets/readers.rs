//! imutherm's readers on arbitrary bytes (text, CSV, thesis logs, gzip):
//! they may refuse a file, never panic.
#![no_main]

use std::path::PathBuf;
use std::sync::Once;

use imu::table::{ReadPolicy, TableReader};
use imu::{RecordingOptions, read_recording_with_report};
use libfuzzer_sys::fuzz_target;

/// The readers take a path: one scratch file per fuzzing process.
fn scratch() -> PathBuf {
    std::env::temp_dir().join(format!("imutherm-fuzz-readers-{}.txt", std::process::id()))
}

/// The reader's columns may take a quarter of the process's address-space
/// limit (`imu::table::column_limit`); with none set they may take half the
/// machine's memory, far above the 2 GiB of resident memory the runs are
/// given, so a wide gzip table the reader rightly accepts would be called a
/// leak. A 3 GiB limit holds the columns to 768 MiB, with room for a copy.
fn limit_address_space() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        let mut limit = libc::rlimit {
            rlim_cur: 0,
            rlim_max: 0,
        };
        // SAFETY: getrlimit and setrlimit read and write the struct given,
        // which lives here.
        unsafe {
            if libc::getrlimit(libc::RLIMIT_AS, &mut limit) == 0 {
                limit.rlim_cur = limit.rlim_max.min(3 << 30);
                libc::setrlimit(libc::RLIMIT_AS, &limit);
            }
        }
    });
}

fuzz_target!(|bytes: &[u8]| {
    limit_address_space();
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
