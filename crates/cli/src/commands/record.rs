//! `imutherm record`: the flags and the printing around the recorder
//! ([`logger`]): the sensor is opened, the loop runs until the duration,
//! Ctrl-C or SIGTERM, and what it counted is said.

use std::fs::File;
use std::io::{BufWriter, IsTerminal};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, SystemTime, UNIX_EPOCH};

use anyhow::{Context, Result};

use logger::{Clock, Counters, HostClock, NoTick, Settings, Status, ThreadSleeper, Tick};
use mpu9250::config::{AccelRange, Config, GyroRange};
use mpu9250::driver::{Bus, I2cBus, Mpu9250, StdDelay};
use mpu9250::regs;
use mpu9250::sim::{ADDRESS, FaultSchedule, SimChip, Source};

use crate::args::RecordArgs;
use crate::flags::{DeviceKind, UsageError};

/// The pause of `--sim-stall-every`.
const SIM_STALL_S: f64 = 0.5;

/// Every kind of loss, for the status line and the closing message.
fn losses(c: &Counters) -> String {
    format!(
        "{} lost in {} gaps ({} overflows, {} resyncs, {} reconfigurations), {} bus errors retried",
        c.gap_samples, c.gaps, c.overflows, c.resyncs, c.reconfigurations, c.bus_errors
    )
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
    if (rate - a.rate).abs() > 1e-9 * rate {
        say(format_args!(
            "note: --rate {}: the MPU-9250 makes 1000/(1 + n) Hz; recording at {} Hz (SMPLRT_DIV {})\n",
            a.rate,
            hz(rate),
            config.divider().unwrap_or(0)
        ));
    }
    let duration = a.duration;
    if let Some(d) = duration
        && (d * rate).round() < 1.0
    {
        return Err(UsageError(format!(
            "--duration {d} s: less than one sample at {} Hz",
            hz(rate)
        ))
        .into());
    }
    let is_sim = matches!(a.device.kind, DeviceKind::Sim { .. });
    if !is_sim
        && (a.sim_bus_errors > 0.0
            || a.sim_stall_every.is_some()
            || a.sim_clock_ppm != 0.0
            || a.sim_brownout_at.is_some())
    {
        return Err(UsageError(
            "--sim-bus-errors, --sim-stall-every, --sim-clock-ppm and --sim-brownout-at are for \
             --device sim only"
                .to_string(),
        )
        .into());
    }
    // Refused before the sensor is touched; created once it is configured,
    // so that a sensor that fails leaves no empty file behind.
    imu::output::check_output(
        &a.output,
        &imu::output::OutputPolicy {
            overwrite: a.overwrite,
            inputs: &[],
        },
    )?;
    // Host time: the monotonic clock from here, so that a clock adjustment
    // during the run cannot bend the timestamps.
    let clock = HostClock::start();
    match &a.device.kind {
        DeviceKind::Sim { preset } => {
            let preset = preset.as_str();
            let source = sim_source(preset, rate, &config)?;
            // The simulated chip runs on the host's clock, its own clock off
            // by --sim-clock-ppm as a real chip's oscillator is.
            let chip = SimChip::new(source)
                .with_host_clock(Box::new(move || clock.now_s()))
                .with_faults(FaultSchedule {
                    bus_errors: a.sim_bus_errors,
                    stall_every_s: a.sim_stall_every,
                    stall_s: SIM_STALL_S,
                    clock_ppm: a.sim_clock_ppm,
                    brownout_at_s: a.sim_brownout_at.map(|s| s.max(0.0)),
                });
            let imu =
                Mpu9250::new(I2cBus::new(chip, ADDRESS), StdDelay).map_err(|e| anyhow::anyhow!("{e}"))?;
            record(
                imu,
                clock,
                config,
                rate,
                duration,
                &format!("sim:{preset}"),
                a,
                logger::sim::FollowHost,
            )
        }
        #[cfg(target_os = "linux")]
        DeviceKind::I2c { path, address } => {
            // i2c:/dev/i2c-1[@0x68]; `i2c` alone is the Pi's header bus.
            let (path, address) = (path.as_str(), *address);
            let dev = linux_embedded_hal::I2cdev::new(path)
                .with_context(|| format!("opening {path} (is I2C enabled, and may this user use it?)"))?;
            let imu = Mpu9250::new(I2cBus::new(dev, address), StdDelay)
                .map_err(|e| anyhow::anyhow!("{path} @0x{address:02x}: {e}"))?;
            record(imu, clock, config, rate, duration, &a.device.text, a, NoTick)
        }
        #[cfg(target_os = "linux")]
        DeviceKind::Spi { path } => {
            use linux_embedded_hal::spidev::{SpiModeFlags, SpidevOptions};
            // spi:/dev/spidev0.0 (`spi` alone: CE0 of the Pi's header);
            // every register at ≤ 1 MHz (PS-MPU-9250A-01 §7.5).
            let rest = path.as_str();
            // The error's message already holds its cause: print it once.
            let mut dev = linux_embedded_hal::SpidevDevice::open(rest).map_err(|e| {
                anyhow::anyhow!("opening {rest} (is SPI enabled, and may this user use it?): {e}")
            })?;
            let options = SpidevOptions::new()
                .bits_per_word(8)
                .max_speed_hz(1_000_000)
                .mode(SpiModeFlags::SPI_MODE_0)
                .build();
            dev.configure(&options)
                .with_context(|| format!("configuring {rest}"))?;
            let imu = Mpu9250::new(mpu9250::driver::SpiBus::new(dev), StdDelay)
                .map_err(|e| anyhow::anyhow!("{rest}: {e}"))?;
            record(imu, clock, config, rate, duration, &a.device.text, a, NoTick)
        }
        #[cfg(not(target_os = "linux"))]
        _ => anyhow::bail!(
            "--device {}: I2C and SPI are read through Linux's i2c-dev and spidev",
            a.device
        ),
    }
}

/// The signal the simulated chip samples: a simulator preset streamed
/// without end, or `counter`, a test pattern in which sample k reads k LSB
/// on all seven fields (mod 2^15), so that a misaligned frame, a lost
/// sample or a misplaced gap shows in the file.
fn sim_source(preset: &str, rate: f64, config: &Config) -> Result<Source> {
    if preset == "counter" {
        let (a, g) = (config.accel_range.lsb_si(), config.gyro_range.lsb_rad());
        return Ok(Box::new(move |k, _| {
            let v = (k % 32_768) as f64;
            [
                v * a,
                v * a,
                v * a,
                v * g,
                v * g,
                v * g,
                v / regs::TEMP_LSB_PER_C + regs::TEMP_OFFSET_C,
            ]
        }));
    }
    sim_preset(preset, rate)
}

/// A simulator preset streamed without end.
#[cfg(feature = "simulator")]
fn sim_preset(preset: &str, rate: f64) -> Result<Source> {
    /// Samples of the simulated signal computed at a time.
    const SIM_CHUNK: usize = 256;
    let mut cfg = imusim::presets::preset(preset)
        .with_context(|| format!("--device sim:{preset}: presets are mpu9250-thesis, white and counter"))?;
    cfg.rate_hz = rate;
    // The chip quantizes to its configured full scales, not the preset's.
    cfg.sensor.quantize = false;
    let mut generator = imusim::Simulator::new(cfg)?.generator();
    let mut chunk = generator.next_chunk(SIM_CHUNK);
    let mut i = 0;
    Ok(Box::new(move |_, _| {
        if i == SIM_CHUNK {
            chunk = generator.next_chunk(SIM_CHUNK);
            i = 0;
        }
        i += 1;
        std::array::from_fn(|j| chunk.columns[j][i - 1])
    }))
}

/// Built without the simulator: only the counting pattern.
#[cfg(not(feature = "simulator"))]
fn sim_preset(preset: &str, _rate: f64) -> Result<Source> {
    Err(UsageError(format!(
        "--device sim:{preset}: this imutherm is built without the simulator (feature `simulator`); \
         sim:counter needs none"
    ))
    .into())
}

#[allow(clippy::too_many_arguments)]
fn record<B: Bus>(
    mut imu: Mpu9250<B, StdDelay>,
    clock: HostClock,
    config: Config,
    rate: f64,
    duration: Option<f64>,
    device: &str,
    a: &RecordArgs,
    mut tick: impl Tick<B, StdDelay>,
) -> Result<()> {
    let stop = Arc::new(AtomicBool::new(false));
    {
        let stop = stop.clone();
        ctrlc::set_handler(move || stop.store(true, Ordering::SeqCst))
            .context("installing the Ctrl-C handler")?;
    }
    let mut sleeper = ThreadSleeper;
    logger::configure(&mut imu, config, &mut sleeper).map_err(|e| anyhow::anyhow!("{e}"))?;
    let file = create_output(&a.output, a.overwrite)?;
    // The wall clock once, at the start: the Unix time of the clock's origin.
    let unix_start = SystemTime::now()
        .duration_since(UNIX_EPOCH)
        .map_or(f64::NAN, |d| d.as_secs_f64() - clock.now_s());
    let terminal = std::io::stderr().is_terminal();
    let settings = Settings {
        config,
        rate_hz: rate,
        target_rows: duration.map(|d| (d * rate).round() as u64),
        host_time: a.host_time,
        device: device.to_string(),
        unix_start,
        gyro_full_scale_dps: a.gyro_range,
        accel_full_scale_g: a.accel_range,
        version: env!("CARGO_PKG_VERSION").to_string(),
        // On a terminal the status line is redrawn every second; in a log
        // (nohup, systemd) one line a minute.
        status_every: Duration::from_secs(if terminal { 1 } else { 60 }),
    };
    let result = logger::record(
        &mut imu,
        BufWriter::new(file),
        &settings,
        &clock,
        &mut sleeper,
        &mut tick,
        &stop,
        &mut |s| {
            let line = status(s);
            if terminal {
                say(format_args!("\r{line}   "));
            } else {
                say(format_args!("{line}\n"));
            }
        },
    );
    if terminal {
        say(format_args!("\n"));
    }
    let summary = result.map_err(|e| match e {
        logger::RecordError::Close(e) => {
            anyhow::Error::new(e).context(format!("closing {}", a.output.display()))
        }
        logger::RecordError::Header(e) => {
            anyhow::Error::new(e).context(format!("writing {}", a.output.display()))
        }
        e => anyhow::anyhow!("{e}").context(format!("recording to {}", a.output.display())),
    })?;
    let c = &summary.counters;
    say(format_args!(
        "wrote {}: {} samples at {} Hz, {}; chip rate {}\n",
        a.output.display(),
        c.samples,
        hz(rate),
        losses(c),
        summary.measured_hz.map_or_else(
            || "not measured (under 5 s without a loss)".to_string(),
            |r| format!("measured {r:.4} Hz")
        ),
    ));
    Ok(())
}

/// Writes to stderr, ignoring failure: a closed stderr (a pipe whose reader
/// left, a restarted journal) must not stop a recording.
fn say(args: std::fmt::Arguments<'_>) {
    use std::io::Write;
    let _ = std::io::stderr().write_fmt(args);
}

/// The output file, created once the sensor is configured (its existence
/// was checked before the sensor was touched). A recording is hours of
/// work: an existing file is only replaced with `--overwrite`. It is
/// written in place, so that a kill or a power cut leaves every row synced
/// so far at its name, and locked while the run lasts: a second recorder
/// onto the same file is refused instead of interleaving its rows.
fn create_output(path: &std::path::Path, overwrite: bool) -> Result<File> {
    Ok(imu::output::create_in_place(path, overwrite)?)
}

/// A rate for people: 200, 333.333.
fn hz(rate: f64) -> String {
    if rate.fract() == 0.0 {
        format!("{rate}")
    } else {
        format!("{rate:.3}")
    }
}

/// The live status: samples, the rate achieved, temperature, FIFO level,
/// and every kind of loss.
fn status(s: &Status) -> String {
    format!(
        "{} samples, {}, {:.2} °C, FIFO {}/{} B, {}",
        s.counters.samples,
        s.measured_hz
            .map_or_else(|| "rate not yet measured".to_string(), |r| format!("{r:.3} Hz")),
        s.temperature_c,
        s.fifo_bytes,
        regs::FIFO_BYTES,
        losses(&s.counters),
    )
}
