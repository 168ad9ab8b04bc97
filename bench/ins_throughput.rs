//! Samples navigated per second on one core: the strapdown loop of `ins` on
//! a simulated white-noise recording, with and without the rotating Earth.
//!
//! cargo run --release -p ins --example ins_throughput

use std::time::Instant;

use ins::strapdown::{ImuData, NavOptions, navigate_window};

fn main() {
    let rate = 100.0;
    let mut cfg = imusim::presets::preset("white").expect("the white preset exists");
    cfg.duration_s = 1000.0;
    let chunk = imusim::Simulator::new(cfg)
        .expect("the preset is valid")
        .generator()
        .next_chunk(100_000);
    let c = &chunk.columns;
    let imu = ImuData {
        accel: [&c[0], &c[1], &c[2]],
        gyro: [&c[3], &c[4], &c[5]],
        rate_hz: rate,
    };
    let times = [990.0];
    for (label, latitude_deg) in [("no Earth rotation", None), ("latitude 48°", Some(48.0))] {
        let opts = NavOptions {
            align_s: 10.0,
            latitude_deg,
            remove_gyro_bias: true,
        };
        let mut best = f64::INFINITY;
        let mut sink = 0.0;
        for _ in 0..20 {
            let t0 = Instant::now();
            let e = navigate_window(&imu, 0, &opts, &times).expect("the window fits");
            best = best.min(t0.elapsed().as_secs_f64());
            sink += e[0].horizontal_position_m;
        }
        let samples = 99_000.0;
        println!(
            "{label}: {:.3e} samples/s on one core (best of 20 runs of {samples} samples; checksum {sink:.3e})",
            samples / best
        );
    }
}
