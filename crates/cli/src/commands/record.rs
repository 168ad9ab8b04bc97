//! `imutherm record`: the logger. Reads the sensor's FIFO at a steady pace,
//! writes every sample, marks every lost stretch as a gap, flushes every
//! second and syncs to disk every five, and stops cleanly on Ctrl-C or
//! SIGTERM.

use std::fs::File;
use std::io::{BufWriter, IsTerminal};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant, SystemTime, UNIX_EPOCH};

use anyhow::{Context, Result, bail};

use imu::{LogFormat, LogWriter, Metadata};
use mpu9250::config::{AccelRange, Config, GyroRange};
use mpu9250::driver::{Bus, Error as DriverError, FifoRead, I2cBus, Mpu9250};
use mpu9250::regs;
use mpu9250::sim::{ADDRESS, SimChip, Source};
use mpu9250::stream_clock::StreamClock;

use crate::args::RecordArgs;
use crate::flags::{DeviceKind, UsageError};

/// The longest pause between FIFO reads. The FIFO holds 36 frames: 36 ms
/// at 1 kHz, so reads come at least twice in that time at every rate.
const POLL: Duration = Duration::from_millis(20);
/// Tries per read before waiting for the next poll.
const RETRIES: u32 = 5;
/// After this long without a single frame, the sensor is gone.
const GIVE_UP: Duration = Duration::from_secs(30);
/// Samples of the simulated signal computed at a time.
const SIM_CHUNK: usize = 256;

/// What the logger counted.
#[derive(Debug, Default)]
struct Counters {
    samples: u64,
    gap_samples: u64,
    gaps: u64,
    overflows: u64,
    resyncs: u64,
    bus_errors: u64,
    reconfigurations: u64,
}

impl Counters {
    /// Every kind of loss, for the status line and the closing message.
    fn losses(&self) -> String {
        format!(
            "{} lost in {} gaps ({} overflows, {} resyncs, {} reconfigurations), {} bus errors retried",
            self.gap_samples, self.gaps, self.overflows, self.resyncs, self.reconfigurations, self.bus_errors
        )
    }
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
    match &a.device.kind {
        DeviceKind::Sim { preset } => {
            let preset = preset.as_str();
            let source = sim_source(preset, rate, &config)?;
            let imu = Mpu9250::new(I2cBus::new(SimChip::new(source), ADDRESS))
                .map_err(|e| anyhow::anyhow!("{e}"))?;
            // The simulated chip runs on the wall clock, its own clock off
            // by --sim-clock-ppm as a real chip's oscillator is.
            let mut last = Instant::now();
            let mut last_stall = Instant::now();
            let stall_every = a.sim_stall_every;
            let mut brownout = a
                .sim_brownout_at
                .map(|s| Instant::now() + Duration::from_secs_f64(s.max(0.0)));
            let error_rate = a.sim_bus_errors;
            let speed = 1.0 + a.sim_clock_ppm * 1e-6;
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
                    imu.bus_mut()
                        .inner_mut()
                        .advance((now - last).as_secs_f64() * speed);
                    last = now;
                    if brownout.is_some_and(|at| now >= at) {
                        imu.bus_mut().inner_mut().power_cycle();
                        brownout = None;
                    }
                },
            )
        }
        #[cfg(target_os = "linux")]
        DeviceKind::I2c { path, address } => {
            // i2c:/dev/i2c-1[@0x68]; `i2c` alone is the Pi's header bus.
            let (path, address) = (path.as_str(), *address);
            let dev = linux_embedded_hal::I2cdev::new(path)
                .with_context(|| format!("opening {path} (is I2C enabled, and may this user use it?)"))?;
            let imu = Mpu9250::new(I2cBus::new(dev, address))
                .map_err(|e| anyhow::anyhow!("{path} @0x{address:02x}: {e}"))?;
            record(imu, config, rate, duration, &a.device.text, a, |_| {})
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
            let imu = Mpu9250::new(mpu9250::driver::SpiBus::new(dev))
                .map_err(|e| anyhow::anyhow!("{rest}: {e}"))?;
            record(imu, config, rate, duration, &a.device.text, a, |_| {})
        }
        #[cfg(not(target_os = "linux"))]
        _ => bail!(
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

/// Why samples were lost, for the gap's comment line.
#[derive(Debug, Clone, Copy)]
enum Loss {
    Overflow,
    PartRead,
    Stalled,
    Reset,
}

impl Loss {
    fn describe(self) -> &'static str {
        match self {
            Loss::Overflow => "FIFO overflow: read too late",
            Loss::PartRead => "a FIFO read broke off: FIFO reset to regain frame alignment",
            Loss::Stalled => "the sensor stopped delivering: reconfigured",
            Loss::Reset => "the sensor had lost its configuration (a brown-out?): configured again",
        }
    }
}

/// The output file and what has gone into it.
struct Output {
    w: LogWriter<BufWriter<File>>,
    host_time: bool,
    /// Rows to write before stopping (samples and gap rows alike).
    target: Option<u64>,
    c: Counters,
    last: [f64; 7],
}

impl Output {
    fn rows(&self) -> u64 {
        self.c.samples + self.c.gap_samples
    }

    fn room(&self, n: u64) -> u64 {
        self.target.map_or(n, |t| n.min(t.saturating_sub(self.rows())))
    }

    fn full(&self) -> bool {
        self.target.is_some_and(|t| self.rows() >= t)
    }

    /// A gap: a comment with its size and cause, then one row of NaN per
    /// lost sample, so that the samples after it keep their place in time.
    fn gap(&mut self, n: u64, cause: Loss, rate: f64) -> Result<()> {
        let n = self.room(n);
        if n == 0 {
            return Ok(());
        }
        self.w.write_comment(
            "gap",
            &format!(
                "{n} samples lost ({}); sized from host time at {rate:.3} Hz, ±1",
                cause.describe()
            ),
        )?;
        for _ in 0..n {
            self.w.write_row_with(&[f64::NAN; 7], &[f64::NAN])?;
        }
        self.c.gap_samples += n;
        self.c.gaps += 1;
        Ok(())
    }

    /// At the end of a run: the samples a pending loss took up to `t_s`.
    fn final_gap(&mut self, clock: &StreamClock, t_s: f64, cause: Loss) -> Result<()> {
        self.gap(clock.lost_until(t_s), cause, clock.rate_hz())
    }

    fn sample(&mut self, row: [f64; 7], host_s: f64) -> Result<()> {
        if self.host_time {
            self.w.write_row_with(&row, &[host_s])?;
        } else {
            self.w.write_row(&row)?;
        }
        self.c.samples += 1;
        self.last = row;
        Ok(())
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
    // A glitch on the bus at the start is retried like one during the run.
    let mut attempt = 0;
    while let Err(e) = imu.configure(config) {
        attempt += 1;
        match e {
            DriverError::Bus(_) if attempt < RETRIES => {
                std::thread::sleep(Duration::from_millis(10 << attempt))
            }
            e => bail!("configuring the sensor: {e}"),
        }
    }
    let file = create_output(&a.output, a.overwrite)?;
    // Host time: the wall clock at the start, then the monotonic clock, so
    // that a clock adjustment during the run cannot bend the timestamps.
    let started = Instant::now();
    let unix_start = SystemTime::now()
        .duration_since(UNIX_EPOCH)
        .map_or(f64::NAN, |d| d.as_secs_f64());
    let mut meta = Metadata {
        device: Some(format!("{} ({device})", imu.chip().name())),
        start_time: Some(format!("unix {unix_start:.3} s")),
        ..Metadata::default()
    };
    meta.set("gyro_full_scale_dps", a.gyro_range.to_string());
    meta.set("accel_full_scale_g", a.accel_range.to_string());
    meta.set("dlpf_cfg", config.dlpf_cfg().to_string());
    meta.set("sample_rate_divider", config.divider().unwrap_or(0).to_string());
    meta.set(
        "gaps",
        "rows of nan, each stretch after a '# gap:' line naming its size and cause",
    );
    if a.host_time {
        meta.set(
            "host_time",
            "unix time of each sample as the host saw it: the read's time less the sample's age in the FIFO",
        );
    }
    meta.set("imutherm_version", env!("CARGO_PKG_VERSION"));
    let extra: &[&str] = if a.host_time { &["host_time[s]"] } else { &[] };
    let w = LogWriter::with_columns(
        BufWriter::new(file),
        LogFormat::Imutherm,
        &meta,
        Some(rate),
        extra,
    )
    .with_context(|| format!("writing {}", a.output.display()))?;
    let mut out = Output {
        w,
        host_time: a.host_time,
        target: duration.map(|d| (d * rate).round() as u64),
        c: Counters::default(),
        last: [f64::NAN; 7],
    };
    let mut clock = StreamClock::new(rate, started.elapsed().as_secs_f64());
    let result = record_loop(
        &mut imu, config, rate, &mut out, &stop, &mut tick, started, unix_start, &mut clock,
    );
    // Whatever ended the run, the file gets its trailer and reaches the disk.
    let stopped_by = *result.as_ref().unwrap_or(&"error");
    let elapsed = started.elapsed().as_secs_f64();
    let measured = clock
        .measured_hz()
        .map_or_else(|| "unknown".to_string(), |r| format!("{r:.4}"));
    let c = &out.c;
    let trailer = format!(
        "samples={} gap_samples={} gaps={} overflows={} resyncs={} bus_errors={} reconfigurations={} \
         stopped_by={stopped_by} elapsed_s={elapsed:.3} rate_measured_hz={measured}",
        c.samples, c.gap_samples, c.gaps, c.overflows, c.resyncs, c.bus_errors, c.reconfigurations,
    );
    let closed = out
        .w
        .write_trailer("trailer", &trailer)
        .and_then(|()| out.w.flush())
        .and_then(|()| out.w.get_mut().get_ref().sync_all());
    if std::io::stderr().is_terminal() {
        say(format_args!("\n"));
    }
    // The run's own error comes first; closing the file may have failed
    // for the same reason (a full disk).
    result.with_context(|| format!("recording to {}", a.output.display()))?;
    closed.with_context(|| format!("closing {}", a.output.display()))?;
    let c = &out.c;
    say(format_args!(
        "wrote {}: {} samples at {} Hz, {}; chip rate {}\n",
        a.output.display(),
        c.samples,
        hz(rate),
        c.losses(),
        clock.measured_hz().map_or_else(
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

#[allow(clippy::too_many_arguments)]
fn record_loop<B: Bus>(
    imu: &mut Mpu9250<B>,
    config: Config,
    rate: f64,
    out: &mut Output,
    stop: &AtomicBool,
    tick: &mut impl FnMut(&mut Mpu9250<B>),
    started: Instant,
    unix_start: f64,
    clock: &mut StreamClock,
) -> Result<&'static str> {
    let now = || started.elapsed().as_secs_f64();
    let poll = POLL.min(Duration::from_secs_f64(18.0 / rate));
    // No frame for this long means the chip stopped (a brown-out resets
    // its registers): configure it again.
    let stall_limit = (40.0 / rate).max(1.0);
    // With --duration, a chip far slower than its nominal rate (or silent)
    // must not keep the run going for ever: host time bounds it too.
    let deadline = out.target.map(|t| t as f64 / rate * 1.05 + 2.0);
    let mut cause = None;
    // The last read that delivered frames, and the last sign of life
    // (frames, or a reconfiguration) that spaces reconfigurations.
    let mut last_delivery = now();
    let mut last_frame = now();
    let (mut last_flush, mut last_sync, mut last_status) = (Instant::now(), Instant::now(), Instant::now());
    let terminal = std::io::stderr().is_terminal();
    let mut frames = Vec::new();
    loop {
        std::thread::sleep(poll);
        // Read after the flag: a stop asked for now still gets the samples
        // the FIFO holds.
        let signalled = stop.load(Ordering::SeqCst);
        frames.clear();
        let mut read = None;
        for attempt in 0..RETRIES {
            // The read's time is taken just before it: the newest frame in
            // the FIFO was sampled within one period before (a simulated
            // chip is brought up to this moment first, retries included).
            tick(imu);
            let t = now();
            match imu.read_fifo(&mut frames) {
                Ok(r) => {
                    read = Some((t, r));
                    break;
                }
                Err(DriverError::Bus(_)) => {
                    out.c.bus_errors += 1;
                    std::thread::sleep(Duration::from_micros(200 << attempt));
                }
                Err(e) => bail!("reading the sensor: {e}"),
            }
        }
        match read {
            Some((t, FifoRead::Frames(n))) => {
                let lost = clock.frames(t, n);
                if lost > 0 {
                    out.gap(lost, cause.take().unwrap_or(Loss::Overflow), clock.rate_hz())?;
                }
                if n > 0 {
                    cause = None;
                    last_frame = t;
                    last_delivery = t;
                }
                for (i, f) in frames.iter().enumerate() {
                    if out.full() {
                        break;
                    }
                    out.sample(config.to_si(f), unix_start + clock.sample_time(t, i, n))?;
                }
                if n == 0 && t - last_frame > stall_limit {
                    match imu.configure(config) {
                        Ok(()) => {
                            out.c.reconfigurations += 1;
                            clock.lost();
                            cause.get_or_insert(Loss::Stalled);
                            last_frame = now();
                        }
                        // Tried again at the next poll.
                        Err(DriverError::Bus(_)) => out.c.bus_errors += 1,
                        Err(e) => bail!("configuring the sensor again: {e}"),
                    }
                }
            }
            Some((_, FifoRead::Overflow)) => {
                out.c.overflows += 1;
                clock.lost();
                cause.get_or_insert(Loss::Overflow);
            }
            Some((_, FifoRead::Resync)) => {
                out.c.resyncs += 1;
                clock.lost();
                cause.get_or_insert(Loss::PartRead);
            }
            Some((t, FifoRead::Reconfigured)) => {
                out.c.reconfigurations += 1;
                clock.lost();
                cause.get_or_insert(Loss::Reset);
                last_frame = t;
            }
            // Every try failed: the next poll tries again.
            None => {}
        }
        if now() - last_delivery > GIVE_UP.as_secs_f64() {
            // The silence up to now is a gap, then the run ends.
            clock.lost();
            out.final_gap(clock, now(), cause.unwrap_or(Loss::Stalled))?;
            out.w.flush()?;
            bail!(
                "no sample from the sensor for {} s ({} bus errors, {} reconfigurations): is it still \
                 connected and powered?",
                GIVE_UP.as_secs(),
                out.c.bus_errors,
                out.c.reconfigurations
            );
        }
        if last_flush.elapsed() >= Duration::from_secs(1) {
            out.w.flush()?;
            last_flush = Instant::now();
        }
        if last_sync.elapsed() >= Duration::from_secs(5) {
            out.w.get_mut().get_ref().sync_data()?;
            last_sync = Instant::now();
        }
        // On a terminal the status line is redrawn every second; in a log
        // (nohup, systemd) one line a minute.
        let every = if terminal { 1 } else { 60 };
        if last_status.elapsed() >= Duration::from_secs(every) {
            let line = status(out, clock, imu.fifo_level());
            if terminal {
                say(format_args!("\r{line}   "));
            } else {
                say(format_args!("{line}\n"));
            }
            last_status = Instant::now();
        }
        if out.full() {
            return Ok("duration");
        }
        if deadline.is_some_and(|d| now() > d) {
            // Far past the duration in host time: what is missing is lost.
            if now() - last_delivery > 2.0 / rate {
                clock.lost();
            }
            out.final_gap(clock, now(), cause.unwrap_or(Loss::Stalled))?;
            return Ok("time_limit");
        }
        if signalled {
            // A loss still waiting for frames to size it ends the file.
            out.final_gap(clock, now(), cause.unwrap_or(Loss::Overflow))?;
            return Ok("signal");
        }
    }
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
fn status(out: &Output, clock: &StreamClock, fifo_bytes: usize) -> String {
    let c = &out.c;
    format!(
        "{} samples, {}, {:.2} °C, FIFO {fifo_bytes}/{} B, {}",
        c.samples,
        clock
            .measured_hz()
            .map_or_else(|| "rate not yet measured".to_string(), |r| format!("{r:.3} Hz")),
        out.last[6],
        regs::FIFO_BYTES,
        c.losses(),
    )
}
