//! An hour of recording with every fault the recorder handles, in
//! simulated time: FIFO overflows (the host stalls), reads broken off and
//! address NACKs (bus errors), a chip clock 1 % fast, and a brown-out.

use std::time::Duration;

use mpu9250::config::Config;
use mpu9250::sim::FaultSchedule;

mod support;
use support::{Run, counter_index, rows, trailer, worst_place_error};

#[test]
fn an_hour_with_every_fault_keeps_every_sample_in_its_place_and_accounts_for_every_row() {
    let started = std::time::Instant::now();
    let config = Config::default();
    let run = Run {
        config,
        seconds: Some(3600.0),
        faults: FaultSchedule {
            bus_errors: 0.01,
            stall_every_s: Some(300.0),
            stall_s: 0.5,
            clock_ppm: 10_000.0,
            brownout_at_s: Some(1800.0),
        },
        host_time: true,
        overshoot: Duration::from_micros(1500),
        ..Run::default()
    }
    .record();
    let host_seconds = started.elapsed().as_secs_f64();
    let text = &run.text;
    let summary = run.summary.unwrap();
    let r = rows(text);
    let field = |k| trailer(text, k) as u64;
    let c = summary.counters;
    // 200 Hz × 3600 s: every row a sample or a lost sample's NaN.
    assert_eq!(r.len(), 720_000);
    assert_eq!(c.samples + c.gap_samples, 720_000);
    assert_eq!(field("samples"), c.samples);
    assert_eq!(field("gap_samples"), c.gap_samples);
    let nan_rows = r.iter().filter(|row| row.iter().all(|v| v.is_nan())).count() as u64;
    assert_eq!(nan_rows, c.gap_samples);
    // No half-read frame: a row is all numbers or all gap.
    assert!(
        r.iter()
            .all(|row| row.iter().all(|v| v.is_nan()) || row.iter().all(|v| v.is_finite()))
    );
    // Each gap is announced with its size.
    let announced: u64 = text
        .lines()
        .filter_map(|l| l.strip_prefix("# gap: "))
        .map(|l| l.split(' ').next().unwrap().parse::<u64>().unwrap())
        .sum();
    assert_eq!(announced, c.gap_samples);
    assert_eq!(
        text.lines().filter(|l| l.starts_with("# gap: ")).count() as u64,
        c.gaps
    );
    // Every fault was met: 12 stalls of 0.5 s each overflow a 36-frame FIFO,
    // 1 % of transfers fail, the brown-out is noticed and configured away.
    assert!(c.overflows >= 11, "{c:?}");
    assert!(c.bus_errors > 1000 && c.resyncs > 100, "{c:?}");
    assert_eq!(c.reconfigurations, 1, "{c:?}");
    assert!(text.contains("the sensor stopped delivering: reconfigured"));
    assert!(text.contains("FIFO overflow: read too late"));
    assert!(text.contains("a FIFO read broke off"));
    assert_eq!(summary.stopped_by.name(), "duration");
    // Every sample within one of its place in time, the brown-out's restart
    // of the chip's sample clock included.
    let worst = worst_place_error(&r, &config);
    assert!(worst <= 1, "a sample {worst} places off");
    // The chip's clock is 1 % fast and the recorder measures it.
    let measured = summary.measured_hz.unwrap();
    assert!((measured / 202.0 - 1.0).abs() < 2e-4, "{measured} Hz");
    // Host times increase over the file, at the measured rate.
    let host: Vec<f64> = r.iter().map(|row| row[7]).filter(|t| t.is_finite()).collect();
    assert!(
        host.windows(2).all(|w| w[1] > w[0] - 0.003),
        "host time runs backwards"
    );
    let span = host.last().unwrap() - host[0];
    assert!((span * 202.0 / 720_000.0 - 1.0).abs() < 0.002, "{span} s");
    // The stream stays recognisable: it starts at its first sample.
    assert!(counter_index(&r[0], &config).is_some());
    eprintln!(
        "an hour at 200 Hz in {host_seconds:.2} s of host time: {c:?}, worst place error {worst}, \
         {measured:.4} Hz"
    );
}
