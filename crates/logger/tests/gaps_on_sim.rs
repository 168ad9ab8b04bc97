//! The recorder's gap sizing against the simulated chip, in simulated time:
//! the library's own loop reads a FIFO under bus errors, with a host whose
//! sleeps overshoot, and every sample's place in the file is checked
//! against its true index, which the counting pattern carries in every
//! field.

use std::time::Duration;

use mpu9250::config::Config;
use mpu9250::sim::FaultSchedule;

mod support;
use support::{Run, rows, trailer, worst_place_error};

/// The largest error of a sample's place allowed. Sizing each gap from the
/// host time between its two reads (an earlier logger) left samples up to
/// 54 places off; from a clock interval carried from read to read, with the
/// rate measured only over uninterrupted stretches, up to 14 (100 Hz, the
/// chip 0.2 % slow: every gap of the first 13 s judged one short). Keeping
/// every (phase, period) the reads allow, across the gaps, leaves a gap
/// misjudged by one only when its read falls at the edge of the phase the
/// reads allow, and the next gap puts it right: every sample is within 1
/// of its place, in the sweep below and over 40 seeds of each setup
/// (`GAPS_SEEDS=40`).
const BOUND: i64 = 1;

/// The sweep: rates, clock errors (the chip's oscillator is ±1 % over
/// temperature, PS-MPU-9250A-01 §4.15) and seeds of the host's jitter.
const SETUPS: [(f64, f64); 6] = [
    (200.0, 0.0),
    (200.0, 8000.0),
    (500.0, -5000.0),
    (100.0, 300.0),
    (100.0, -2000.0),
    (1000.0, 3000.0),
];

/// Seeds of the jitter per setup: `GAPS_SEEDS` sweeps more.
#[test]
fn a_hundred_gaps_under_bus_errors_leave_every_sample_in_its_place() {
    let seeds: u64 = std::env::var("GAPS_SEEDS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(2);
    let mut worst = 0;
    for (rate, ppm) in SETUPS {
        for seed in 1..=seeds {
            let config = Config {
                rate_hz: rate,
                ..Config::default()
            };
            let run = Run {
                config,
                seconds: Some(120.0),
                faults: FaultSchedule {
                    bus_errors: 0.05,
                    clock_ppm: ppm,
                    ..FaultSchedule::default()
                },
                // A sleep overshoots by up to 1.5 ms on a loaded host.
                overshoot: Duration::from_micros(1500),
                seed,
                ..Run::default()
            }
            .record();
            let gaps = trailer(&run.text, "gaps");
            let w = worst_place_error(&rows(&run.text), &config);
            eprintln!(
                "{rate} Hz, clock {ppm:+} ppm, seed {seed}: {gaps} gaps, worst place error {w} samples"
            );
            assert!(gaps >= 100.0, "{rate} Hz: only {gaps} gaps");
            assert!(
                w <= BOUND,
                "{rate} Hz, {ppm} ppm, seed {seed}: a sample {w} places off"
            );
            worst = worst.max(w);
        }
    }
    eprintln!("worst place error over the sweep: {worst} samples");
}
