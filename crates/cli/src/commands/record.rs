//! `imutherm record`: the logger. Reads the sensor's FIFO at a steady pace,
//! writes every sample, marks every lost stretch as a gap, flushes every
//! second and syncs to disk every five, and stops cleanly on Ctrl-C or
//! SIGTERM.

use std::fs::File;
use std::io::{BufWriter, IsTerminal};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use anyhow::{Context, Result, bail};

use imu::{LogFormat, LogWriter, Metadata};
use mpu9250::config::{AccelRange, Config, GyroRange};
use mpu9250::driver::{Bus, Error as DriverError, FifoRead, I2cBus, Mpu9250};
use mpu9250::sim::{ADDRESS, SimChip};

use crate::args::RecordArgs;
use crate::commands::simulate::parse_duration;

/// How often the FIFO is read: 36 frames fill it in 36 ms at 1 kHz, so
/// 20 ms keeps a margin at every rate.
const POLL: Duration = Duration::from_millis(20);
/// Tries per read before the stretch is counted as lost.
const RETRIES: u32 = 5;

/// What the logger counted.
#[derive(Debug, Default)]
struct Counters {
    samples: u64,
    gap_samples: u64,
    overflows: u64,
    bus_errors: u64,
}

pub fn run(a: &RecordArgs) -> Result<()> {
    let config = Config {
        gyro_range: GyroRange::from_dps(a.gyro_range)
            .with_context(|| format!("--gyro-range {}: expected 250, 500, 1000 or 2000", a.gyro_range))?,
        accel_range: AccelRange::from_g(a.accel_range)
            .with_context(|| format!("--accel-range {}: expected 2, 4, 8 or 16", a.accel_range))?,
        rate_hz: a.rate,
        dlpf_hz: a.dlpf,
    };
    let rate = config
        .actual_rate_hz()
        .with_context(|| format!("--rate {}: the MPU-9250 makes 1000/(1 + n) Hz, n = 0…255", a.rate))?;
    let duration = a.duration.as_deref().map(parse_duration).transpose()?;
    let (kind, rest) = a.device.split_once(':').unwrap_or((a.device.as_str(), ""));
    match kind {
        "sim" => {
            let preset = if rest.is_empty() { "mpu9250-thesis" } else { rest };
            let mut cfg = imusim::presets::preset(preset)?;
            cfg.rate_hz = rate;
            // Up to ten minutes of signal, repeated if the recording runs
            // longer (the chip's FIFO and timing are what is being run here;
            // long simulated runs are `imutherm simulate`'s job).
            cfg.duration_s = duration.map_or(600.0, |d| d + 5.0).min(600.0);
            let rec = imusim::Simulator::new(cfg)?.recording(Some(preset))?;
            let cols: Vec<Vec<f64>> = rec.channels.iter().map(|c| c.data.clone()).collect();
            let n = cols[0].len().max(1);
            let chip = SimChip::new(Box::new(move |k, _| {
                let i = (k as usize) % n;
                std::array::from_fn(|j| cols[j][i])
            }));
            let imu = Mpu9250::new(I2cBus::new(chip, ADDRESS)).map_err(|e| anyhow::anyhow!("{e}"))?;
            // The simulated chip runs on the wall clock.
            let mut last = Instant::now();
            let mut last_stall = Instant::now();
            let stall_every = a.sim_stall_every;
            let error_rate = a.sim_bus_errors;
            record(
                imu,
                config,
                rate,
                duration,
                &format!("sim:{preset}"),
                a,
                move |imu| {
                    // Faults start once the chip is set up, as a marginal bus in
                    // the middle of a recording would.
                    imu.bus_mut().inner_mut().set_error_rate(error_rate);
                    if let Some(every) = stall_every
                        && last_stall.elapsed().as_secs_f64() >= every
                    {
                        std::thread::sleep(Duration::from_millis(500));
                        last_stall = Instant::now();
                    }
                    let now = Instant::now();
                    imu.bus_mut().inner_mut().advance((now - last).as_secs_f64());
                    last = now;
                },
            )
        }
        #[cfg(target_os = "linux")]
        "i2c" => {
            // i2c:/dev/i2c-1[@0x68]
            let (path, address) = match rest.split_once('@') {
                Some((p, addr)) => {
                    let a = u8::from_str_radix(addr.trim_start_matches("0x"), 16).with_context(|| {
                        format!("--device {}: '{addr}' is not an address like 0x68", a.device)
                    })?;
                    (p, a)
                }
                None => (rest, 0x68),
            };
            let dev = linux_embedded_hal::I2cdev::new(path)
                .with_context(|| format!("opening {path} (is I2C enabled, and may this user use it?)"))?;
            let imu = Mpu9250::new(I2cBus::new(dev, address))
                .map_err(|e| anyhow::anyhow!("{path} @0x{address:02x}: {e}"))?;
            record(imu, config, rate, duration, &a.device, a, |_| {})
        }
        #[cfg(target_os = "linux")]
        "spi" => {
            use linux_embedded_hal::spidev::{SpiModeFlags, SpidevOptions};
            // spi:/dev/spidev0.0; every register at ≤ 1 MHz (PS-MPU-9250A-01 §7.5).
            let mut dev = linux_embedded_hal::SpidevDevice::open(rest)
                .with_context(|| format!("opening {rest} (is SPI enabled, and may this user use it?)"))?;
            let options = SpidevOptions::new()
                .bits_per_word(8)
                .max_speed_hz(1_000_000)
                .mode(SpiModeFlags::SPI_MODE_0)
                .build();
            dev.configure(&options)
                .with_context(|| format!("configuring {rest}"))?;
            let imu = Mpu9250::new(mpu9250::driver::SpiBus::new(dev))
                .map_err(|e| anyhow::anyhow!("{rest}: {e}"))?;
            record(imu, config, rate, duration, &a.device, a, |_| {})
        }
        other => {
            bail!("--device {other}: expected sim[:PRESET], i2c:/dev/i2c-N[@0x68] or spi:/dev/spidevB.C")
        }
    }
}

fn record<B: Bus>(
    mut imu: Mpu9250<B>,
    config: Config,
    rate: f64,
    duration: Option<f64>,
    device: &str,
    a: &RecordArgs,
    mut tick: impl FnMut(&mut Mpu9250<B>),
) -> Result<()> {
    let stop = Arc::new(AtomicBool::new(false));
    {
        let stop = stop.clone();
        ctrlc::set_handler(move || stop.store(true, Ordering::SeqCst))
            .context("installing the Ctrl-C handler")?;
    }
    imu.configure(config)
        .map_err(|e| anyhow::anyhow!("configuring the sensor: {e}"))?;
    let mut meta = Metadata {
        device: Some(format!("{} ({device})", imu.chip().name())),
        start_time: Some(
            std::time::SystemTime::now()
                .duration_since(std::time::UNIX_EPOCH)
                .map_or_else(|_| "unknown".into(), |d| format!("unix {:.3} s", d.as_secs_f64())),
        ),
        ..Metadata::default()
    };
    meta.set("gyro_full_scale_dps", a.gyro_range.to_string());
    meta.set("accel_full_scale_g", a.accel_range.to_string());
    meta.set("dlpf_cfg", config.dlpf_cfg().to_string());
    meta.set("imutherm_version", env!("CARGO_PKG_VERSION"));
    let file = File::create(&a.output).with_context(|| format!("creating {}", a.output.display()))?;
    let mut w = LogWriter::new(BufWriter::new(file), LogFormat::Imutherm, &meta, Some(rate))?;
    let target = duration.map(|d| (d * rate).round() as u64);
    let mut c = Counters::default();
    let started = Instant::now();
    let (mut last_flush, mut last_sync) = (Instant::now(), Instant::now());
    let status = std::io::stderr().is_terminal();
    let mut frames = Vec::new();
    let mut stopped_by = "duration";
    loop {
        std::thread::sleep(POLL);
        tick(&mut imu);
        let signalled = stop.load(Ordering::SeqCst);
        frames.clear();
        let mut read = None;
        for attempt in 0..RETRIES {
            match imu.read_fifo(&mut frames) {
                Ok(r) => {
                    read = Some(r);
                    break;
                }
                Err(DriverError::Bus(_)) => {
                    c.bus_errors += 1;
                    std::thread::sleep(Duration::from_micros(200 << attempt));
                }
                Err(e) => bail!("reading the sensor: {e}"),
            }
        }
        let expected = (started.elapsed().as_secs_f64() * rate) as u64;
        match read {
            Some(FifoRead::Frames(_)) => {}
            // The FIFO was reset or could not be read: the samples between
            // the last one written and now are lost and written as a gap.
            Some(FifoRead::Overflow) | None => {
                if read.is_some() {
                    c.overflows += 1;
                }
                let lost = expected.saturating_sub(c.samples + c.gap_samples);
                let lost = target.map_or(lost, |t| lost.min(t.saturating_sub(c.samples + c.gap_samples)));
                for _ in 0..lost {
                    w.write_row(&[f64::NAN; 7])?;
                }
                c.gap_samples += lost;
            }
        }
        for f in &frames {
            if target.is_some_and(|t| c.samples + c.gap_samples >= t) {
                break;
            }
            w.write_row(&config.to_si(f))?;
            c.samples += 1;
        }
        if last_flush.elapsed() >= Duration::from_secs(1) {
            w.flush()?;
            last_flush = Instant::now();
            if status {
                eprint!(
                    "\r{} samples, {:.1} Hz, {} lost, {} overflows, {} bus errors   ",
                    c.samples,
                    c.samples as f64 / started.elapsed().as_secs_f64(),
                    c.gap_samples,
                    c.overflows,
                    c.bus_errors
                );
            }
        }
        if last_sync.elapsed() >= Duration::from_secs(5) {
            w.get_mut().get_ref().sync_data()?;
            last_sync = Instant::now();
        }
        if target.is_some_and(|t| c.samples + c.gap_samples >= t) {
            break;
        }
        if signalled {
            stopped_by = "signal";
            break;
        }
    }
    w.write_trailer(
        "trailer",
        &format!(
            "samples={} gap_samples={} overflows={} bus_errors={} stopped_by={stopped_by} elapsed_s={:.3}",
            c.samples,
            c.gap_samples,
            c.overflows,
            c.bus_errors,
            started.elapsed().as_secs_f64()
        ),
    )?;
    w.flush()?;
    w.get_mut().get_ref().sync_all()?;
    if status {
        eprintln!();
    }
    eprintln!(
        "wrote {}: {} samples at {rate} Hz, {} lost to {} overflows, {} bus errors retried",
        a.output.display(),
        c.samples,
        c.gap_samples,
        c.overflows,
        c.bus_errors
    );
    Ok(())
}
