//! What the recorder writes from the simulator's white-noise preset has
//! the preset's noise: the chip's quantization and the recorder's rows
//! change nothing but the LSB's rounding.

use mpu9250::config::Config;

mod support;
use support::{Run, rows};

#[test]
fn ten_seconds_at_200_hz_are_2000_samples_with_the_configured_noise() {
    let mut cfg = imusim::presets::preset("white").unwrap();
    cfg.rate_hz = 200.0;
    // The chip quantizes to its configured full scales, not the preset's.
    cfg.sensor.quantize = false;
    let mut generator = imusim::Simulator::new(cfg).unwrap().generator();
    let chunk = generator.next_chunk(4000);
    let run = Run {
        config: Config::default(),
        seconds: Some(10.0),
        source: Some(Box::new(move |k, _| {
            std::array::from_fn(|j| chunk.columns[j][k as usize % 4000])
        })),
        ..Run::default()
    }
    .record();
    let r = rows(&run.text);
    assert_eq!(r.len(), 2000);
    // Gyro x: white noise of N = 1.5e-4 rad/√s (the preset), so the ADEV
    // at τ0 = 5 ms is N/√τ0 = 2.12e-3 rad/s, plus the ±250 °/s LSB's
    // rounding, whose variance LSB²/12 adds to the Allan variance at τ0.
    let gx: Vec<f64> = r.iter().map(|row| row[3]).collect();
    // One test over all octave τ at a 95 % family level (Bonferroni: each
    // point at 1 − 0.05/points).
    let curve = |confidence| {
        allan::analyze(
            &gx,
            &allan::Options {
                rate_hz: 200.0,
                confidence,
                ..allan::Options::default()
            },
        )
        .unwrap()
    };
    let curve = curve(1.0 - 0.05 / curve(0.95).points.len() as f64);
    let lsb = std::f64::consts::PI / 180.0 / 131.0;
    let want = ((1.5e-4f64).powi(2) * 200.0 + lsb * lsb / 12.0).sqrt();
    // At every octave τ the white-noise line N/√τ lies in the interval.
    for p in &curve.points {
        let want = if p.tau == 0.005 {
            want
        } else {
            1.5e-4 / p.tau.sqrt()
        };
        assert!(
            p.dev_lo < want && want < p.dev_hi,
            "τ {} s: {} [{}, {}] vs {want}",
            p.tau,
            p.dev,
            p.dev_lo,
            p.dev_hi
        );
    }
    assert!(run.text.contains("# trailer: samples=") && run.text.contains("stopped_by=duration"));
}
