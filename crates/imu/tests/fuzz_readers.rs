//! The readers on arbitrary input: they may refuse it, never panic or hang.

use std::io::Write;

use imu::table::{ReadPolicy, TableReader};
use imu::{RecordingOptions, read_recording_with_report};
use proptest::prelude::*;

fn write(bytes: &[u8]) -> tempfile::NamedTempFile {
    let mut f = tempfile::NamedTempFile::new().unwrap();
    f.write_all(bytes).unwrap();
    f
}

/// Text made of the pieces real logs are made of, in any order.
fn loglike() -> impl Strategy<Value = Vec<u8>> {
    let piece = prop_oneof![
        Just(b"0.25".to_vec()),
        Just(b"-1e-3".to_vec()),
        Just(b"nan".to_vec()),
        Just(b"inf".to_vec()),
        Just(b", ".to_vec()),
        Just(b",".to_vec()),
        Just(b"\t".to_vec()),
        Just(b" ".to_vec()),
        Just(b"\n".to_vec()),
        Just(b"\r\n".to_vec()),
        Just(b"# k: v\n".to_vec()),
        Just(b"gyro_x[deg/s]".to_vec()),
        Just(b"time_ns".to_vec()),
        Just(b"t[s]".to_vec()),
        Just(b"1e300".to_vec()),
        Just(b"123456789012".to_vec()),
        Just(b"x".to_vec()),
        Just(vec![0xff]),
        Just(vec![0x1f, 0x8b]),
    ];
    prop::collection::vec(piece, 0..200).prop_map(|v| v.concat())
}

fn exercise(bytes: &[u8]) {
    let f = write(bytes);
    for skip_bad_lines in [false, true] {
        if let Ok(r) = TableReader::open(f.path()) {
            let _ = r.read_with(None, &ReadPolicy { skip_bad_lines });
        }
        let opts = RecordingOptions {
            skip_bad_lines,
            ..RecordingOptions::default()
        };
        if let Ok((rec, report)) = read_recording_with_report(f.path(), &opts) {
            // What is kept is consistent: all channels the same length.
            let n = rec.len();
            assert!(rec.channels.iter().all(|c| c.data.len() == n));
            assert!(report.problems.len() <= imu::read_report::MAX_LISTED);
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    #[test]
    fn random_bytes_never_panic(bytes in prop::collection::vec(any::<u8>(), 0..2048)) {
        exercise(&bytes);
    }

    #[test]
    fn loglike_text_never_panics(bytes in loglike()) {
        exercise(&bytes);
    }
}
