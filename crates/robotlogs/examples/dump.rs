//! Prints the streams of a log and a summary of the chosen one:
//! `cargo run -p robotlogs --example dump -- LOG [TOPIC]`.

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let path = std::path::PathBuf::from(args.next().ok_or("usage: dump LOG [TOPIC]")?);
    let choice = robotlogs::Choice {
        topic: args.next(),
        first_if_several: true,
        ..Default::default()
    };
    let r = robotlogs::read(&path, &imu::RecordingOptions::default(), &choice)?;
    for s in &r.streams {
        println!("{s:?}");
    }
    let rec = &r.recording;
    println!("samples {} rate {:?}", rec.len(), rec.rate_hz);
    for c in &rec.channels {
        let fin: Vec<f64> = c.data.iter().copied().filter(|v| v.is_finite()).collect();
        let mean = fin.iter().sum::<f64>() / fin.len().max(1) as f64;
        println!(
            "  {} ({}) mean {mean:.6} finite {}",
            c.name,
            c.source_name,
            fin.len()
        );
    }
    for (k, v) in &rec.meta.entries {
        println!("  {k}: {v}");
    }
    for p in &r.report.problems {
        println!("  problem: {}", p.message);
    }
    for n in &r.report.notes {
        println!("  note: {n}");
    }
    Ok(())
}
