//! Writes a thesis-format IMU log of about the given size, for reader
//! benchmarks: `cargo run --release -p imu --example make_thesis_log -- OUT MB`.
//!
//! Values look like an MPU-9250 at rest (gravity on z, small gyro biases,
//! noise at full double precision) so the text has realistic lengths.

use std::fs::File;
use std::io::BufWriter;

use imu::{LogFormat, LogWriter, Metadata};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let (Some(out), Some(mb)) = (args.next(), args.next()) else {
        return Err("usage: make_thesis_log OUT SIZE_MB".into());
    };
    let target: u64 = mb.parse::<u64>()? * 1_000_000;
    let file = BufWriter::with_capacity(1 << 20, File::create(&out)?);
    let meta = Metadata {
        device: Some("benchmark data".into()),
        ..Metadata::default()
    };
    let mut w = LogWriter::new(file, LogFormat::Imutherm, &meta, Some(200.0))?;
    // SplitMix64: a fixed, dependency-free generator.
    let mut state = 0x1234_5678_9abc_def0_u64;
    let mut uniform = move || {
        state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    };
    let mut written = 0u64;
    let mut row = [0.0; 7];
    while written < target {
        row[0] = 0.88 + 0.05 * uniform();
        row[1] = 0.21 + 0.05 * uniform();
        row[2] = 9.36 + 0.05 * uniform();
        row[3] = -0.036 + 0.002 * uniform();
        row[4] = 0.023 + 0.002 * uniform();
        row[5] = 0.019 + 0.002 * uniform();
        row[6] = 34.0 + 0.01 * uniform();
        w.write_row(&row)?;
        written += 7 * 20 + 12; // about one row of text
    }
    w.flush()?;
    eprintln!("{} rows written to {out}", w.rows());
    Ok(())
}
