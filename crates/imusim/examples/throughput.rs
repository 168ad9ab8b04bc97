//! Generation throughput of the simulator, without any output:
//! `cargo run --release -p imusim --example throughput [SAMPLES]`.

use std::time::Instant;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let samples: f64 = std::env::args().nth(1).map_or(Ok(1e7), |s| s.parse())?;
    let mut cfg = imusim::presets::preset("mpu9250-thesis")?;
    cfg.duration_s = samples / cfg.rate_hz;
    let sim = imusim::Simulator::new(cfg)?;
    let start = Instant::now();
    let mut checksum = 0.0;
    let mut n = 0u64;
    sim.run(|chunk| {
        n += chunk.columns[0].len() as u64;
        checksum += chunk.columns.iter().map(|c| c[0]).sum::<f64>();
        Ok(())
    })?;
    let secs = start.elapsed().as_secs_f64();
    println!(
        "generated {n} samples x 6 axes + temperature in {secs:.2} s: {:.2} M samples/s (checksum {checksum:.6})",
        n as f64 / secs / 1e6
    );
    Ok(())
}
