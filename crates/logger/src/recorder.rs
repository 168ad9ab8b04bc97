//! The read loop: FIFO reads at a steady pace, gaps sized by the stream
//! clock, the trailer at the end.

use std::io;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

use embedded_hal::delay::DelayNs;

use imu::{LogFormat, LogWriter, Metadata};
use mpu9250::config::Config;
use mpu9250::driver::{Bus, Error as DriverError, FifoRead, Mpu9250};
use mpu9250::stream_clock::StreamClock;

use crate::clock::{Clock, Sleeper};
use crate::loss::{Counters, Loss};
use crate::storage::Storage;

/// The longest pause between FIFO reads. The FIFO holds 36 frames: 36 ms
/// at 1 kHz, so reads come at least twice in that time at every rate.
const POLL: Duration = Duration::from_millis(20);
/// Tries per read (and per configuration at the start) before giving up
/// until the next poll.
const RETRIES: u32 = 5;
/// After this long without a single frame, the sensor is gone.
const GIVE_UP_S: u64 = 30;

/// What to record, and how the file describes it.
#[derive(Debug, Clone)]
pub struct Settings {
    /// The sensor's configuration (written again after a stall or reset).
    pub config: Config,
    /// The rate the chip makes, Hz ([`Config::actual_rate_hz`]).
    pub rate_hz: f64,
    /// Rows to write before stopping (samples and gap rows alike); `None`:
    /// until stopped.
    pub target_rows: Option<u64>,
    /// Adds a column `host_time[s]`: each sample's Unix time as the host
    /// saw it.
    pub host_time: bool,
    /// The device as the user named it (`sim:counter`, `/dev/i2c-1`…).
    pub device: String,
    /// The Unix time at the clock's origin, s (NaN if unknown).
    pub unix_start: f64,
    /// Full scales as the user gave them, for the metadata.
    pub gyro_full_scale_dps: f64,
    /// Accelerometer full scale, g.
    pub accel_full_scale_g: f64,
    /// The program's version, for the metadata.
    pub version: String,
    /// How often the status callback is called.
    pub status_every: Duration,
}

/// What stopped a run.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StopReason {
    /// The rows asked for were written.
    Duration,
    /// Far past the duration in host time (the chip slow or silent).
    TimeLimit,
    /// The stop flag was raised (Ctrl-C, SIGTERM).
    Signal,
}

impl StopReason {
    /// As the trailer names it.
    pub fn name(self) -> &'static str {
        match self {
            StopReason::Duration => "duration",
            StopReason::TimeLimit => "time_limit",
            StopReason::Signal => "signal",
        }
    }
}

/// What the recorder tells its caller while it runs.
#[derive(Debug, Clone, Copy)]
pub struct Status {
    /// What was counted so far.
    pub counters: Counters,
    /// The chip's rate as measured, Hz, once known.
    pub measured_hz: Option<f64>,
    /// The last sample's temperature, °C (NaN before the first).
    pub temperature_c: f64,
    /// Bytes in the FIFO at the last read.
    pub fifo_bytes: usize,
}

/// A run that ended well.
#[derive(Debug, Clone, Copy)]
pub struct Summary {
    /// What was counted.
    pub counters: Counters,
    /// The chip's rate as measured, Hz, if a stretch was long enough.
    pub measured_hz: Option<f64>,
    /// What stopped it.
    pub stopped_by: StopReason,
}

/// Why a recording failed. The file, once created, has its trailer and is
/// on the disk whatever the error.
#[derive(Debug, thiserror::Error)]
pub enum RecordError<E: core::fmt::Debug> {
    /// The sensor could not be configured at the start.
    #[error("configuring the sensor: {0}")]
    Configure(DriverError<E>),
    /// A read failed for another reason than the bus.
    #[error("reading the sensor: {0}")]
    Read(DriverError<E>),
    /// The sensor could not be configured again after a stall.
    #[error("configuring the sensor again: {0}")]
    Reconfigure(DriverError<E>),
    /// The sensor delivered nothing for too long.
    #[error(
        "no sample from the sensor for {seconds} s ({bus_errors} bus errors, {reconfigurations} \
         reconfigurations): is it still connected and powered?"
    )]
    Silent {
        /// Seconds of silence.
        seconds: u64,
        /// Bus errors retried meanwhile.
        bus_errors: u64,
        /// Configurations tried.
        reconfigurations: u64,
    },
    /// The header could not be written.
    #[error("writing the header: {0}")]
    Header(io::Error),
    /// Writing the file failed during the run.
    #[error(transparent)]
    Write(io::Error),
    /// The run ended, but the trailer, the flush or the sync failed.
    #[error("closing the file: {0}")]
    Close(io::Error),
}

/// What a simulated device does before each read (brings the chip up to
/// the host's time, injects its faults); a real device needs nothing.
pub trait Tick<B, D> {
    /// Called just before every FIFO read, retries included.
    fn before_read(&mut self, imu: &mut Mpu9250<B, D>, clock: &dyn Clock, sleeper: &mut dyn Sleeper);
}

/// A real device: nothing to do.
#[derive(Debug, Clone, Copy, Default)]
pub struct NoTick;

impl<B, D> Tick<B, D> for NoTick {
    fn before_read(&mut self, _: &mut Mpu9250<B, D>, _: &dyn Clock, _: &mut dyn Sleeper) {}
}

/// Configures the sensor, retrying a glitch on the bus at the start like
/// one during the run (with a growing pause).
pub fn configure<B: Bus, D: DelayNs>(
    imu: &mut Mpu9250<B, D>,
    config: Config,
    sleeper: &mut dyn Sleeper,
) -> Result<(), RecordError<B::Error>> {
    let mut attempt = 0;
    while let Err(e) = imu.configure(config) {
        attempt += 1;
        match e {
            DriverError::Bus(_) if attempt < RETRIES => sleeper.sleep(Duration::from_millis(10 << attempt)),
            e => return Err(RecordError::Configure(e)),
        }
    }
    Ok(())
}

/// The log's metadata.
fn metadata(imu_name: &str, s: &Settings) -> Metadata {
    let mut meta = Metadata {
        device: Some(format!("{imu_name} ({})", s.device)),
        start_time: Some(format!("unix {:.3} s", s.unix_start)),
        ..Metadata::default()
    };
    meta.set("gyro_full_scale_dps", s.gyro_full_scale_dps.to_string());
    meta.set("accel_full_scale_g", s.accel_full_scale_g.to_string());
    meta.set("dlpf_cfg", s.config.dlpf_cfg().to_string());
    meta.set("sample_rate_divider", s.config.divider().unwrap_or(0).to_string());
    meta.set(
        "gaps",
        "rows of nan, each stretch after a '# gap:' line naming its size and cause",
    );
    if s.host_time {
        meta.set(
            "host_time",
            "unix time of each sample as the host saw it: the read's time less the sample's age in the FIFO",
        );
    }
    meta.set("imutherm_version", s.version.clone());
    meta
}

/// Records from a configured sensor ([`configure`]) into `storage` until
/// the rows asked for are written, `stop` is raised, or the sensor is
/// gone; the file always ends with its trailer and is synced.
#[allow(clippy::too_many_arguments)]
pub fn record<B: Bus, D: DelayNs, S: Storage>(
    imu: &mut Mpu9250<B, D>,
    storage: S,
    settings: &Settings,
    clock: &dyn Clock,
    sleeper: &mut dyn Sleeper,
    tick: &mut dyn Tick<B, D>,
    stop: &AtomicBool,
    status: &mut dyn FnMut(&Status),
) -> Result<Summary, RecordError<B::Error>> {
    let started = clock.now_s();
    let meta = metadata(imu.chip().name(), settings);
    let extra: &[&str] = if settings.host_time {
        &["host_time[s]"]
    } else {
        &[]
    };
    let w = LogWriter::with_columns(storage, LogFormat::Imutherm, &meta, Some(settings.rate_hz), extra)
        .map_err(RecordError::Header)?;
    let mut out = Output {
        w,
        host_time: settings.host_time,
        target: settings.target_rows,
        c: Counters::default(),
        last: [f64::NAN; 7],
    };
    let mut stream = StreamClock::new(settings.rate_hz, clock.now_s());
    let mut run = Run {
        imu,
        settings,
        out: &mut out,
        clock,
        sleeper,
        tick,
        stream: &mut stream,
    };
    let result = run.read_loop(stop, status);
    // Whatever ended the run, the file gets its trailer and reaches the disk.
    let stopped_by = result.as_ref().map_or("error", |r| r.name());
    let elapsed = clock.now_s() - started;
    let measured_hz = stream.measured_hz();
    let measured = measured_hz.map_or_else(|| "unknown".to_string(), |r| format!("{r:.4}"));
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
        .and_then(|()| out.w.get_mut().sync_all());
    // The run's own error comes first; closing the file may have failed
    // for the same reason (a full disk).
    let stopped_by = result?;
    closed.map_err(RecordError::Close)?;
    Ok(Summary {
        counters: out.c,
        measured_hz,
        stopped_by,
    })
}

/// The output file and what has gone into it.
struct Output<S: Storage> {
    w: LogWriter<S>,
    host_time: bool,
    target: Option<u64>,
    c: Counters,
    last: [f64; 7],
}

impl<S: Storage> Output<S> {
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
    fn gap(&mut self, n: u64, cause: Loss, rate: f64) -> io::Result<()> {
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
    fn final_gap(&mut self, clock: &StreamClock, t_s: f64, cause: Loss) -> io::Result<()> {
        self.gap(clock.lost_until(t_s), cause, clock.rate_hz())
    }

    fn sample(&mut self, row: [f64; 7], host_s: f64) -> io::Result<()> {
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

/// One run's state.
struct Run<'a, B, D, S: Storage> {
    imu: &'a mut Mpu9250<B, D>,
    settings: &'a Settings,
    out: &'a mut Output<S>,
    clock: &'a dyn Clock,
    sleeper: &'a mut dyn Sleeper,
    tick: &'a mut dyn Tick<B, D>,
    stream: &'a mut StreamClock,
}

impl<B: Bus, D: DelayNs, S: Storage> Run<'_, B, D, S> {
    fn read_loop(
        &mut self,
        stop: &AtomicBool,
        status: &mut dyn FnMut(&Status),
    ) -> Result<StopReason, RecordError<B::Error>> {
        let rate = self.settings.rate_hz;
        let config = self.settings.config;
        let unix_start = self.settings.unix_start;
        let w = RecordError::Write;
        let poll = POLL.min(Duration::from_secs_f64(18.0 / rate));
        // No frame for this long means the chip stopped (a brown-out resets
        // its registers): configure it again.
        let stall_limit = (40.0 / rate).max(1.0);
        // With a duration, a chip far slower than its nominal rate (or
        // silent) must not keep the run going for ever: host time bounds it
        // too.
        let deadline = self.out.target.map(|t| t as f64 / rate * 1.05 + 2.0);
        let mut cause = None;
        // The last read that delivered frames, and the last sign of life
        // (frames, or a reconfiguration) that spaces reconfigurations.
        let now = self.clock.now_s();
        let (mut last_delivery, mut last_frame) = (now, now);
        let (mut last_flush, mut last_sync, mut last_status) = (now, now, now);
        let mut frames = Vec::new();
        loop {
            self.sleeper.sleep(poll);
            // Read after the flag: a stop asked for now still gets the
            // samples the FIFO holds.
            let signalled = stop.load(Ordering::SeqCst);
            frames.clear();
            let mut read = None;
            for attempt in 0..RETRIES {
                // The read's time is taken just before it: the newest frame
                // in the FIFO was sampled within one period before (a
                // simulated chip is brought up to this moment first,
                // retries included).
                self.tick.before_read(self.imu, self.clock, self.sleeper);
                let t = self.clock.now_s();
                match self.imu.read_frames(&mut frames) {
                    Ok(r) => {
                        read = Some((t, r));
                        break;
                    }
                    Err(DriverError::Bus(_)) => {
                        self.out.c.bus_errors += 1;
                        self.sleeper.sleep(Duration::from_micros(200 << attempt));
                    }
                    Err(e) => return Err(RecordError::Read(e)),
                }
            }
            match read {
                Some((t, FifoRead::Frames(n))) => {
                    let lost = self.stream.frames(t, n);
                    if lost > 0 {
                        let rate = self.stream.rate_hz();
                        self.out
                            .gap(lost, cause.take().unwrap_or(Loss::Overflow), rate)
                            .map_err(w)?;
                    }
                    if n > 0 {
                        cause = None;
                        last_frame = t;
                        last_delivery = t;
                    }
                    for (i, f) in frames.iter().enumerate() {
                        if self.out.full() {
                            break;
                        }
                        let host = unix_start + self.stream.sample_time(t, i, n);
                        self.out.sample(config.sample(f).to_log_row(), host).map_err(w)?;
                    }
                    if n == 0 && t - last_frame > stall_limit {
                        match self.imu.configure(config) {
                            Ok(()) => {
                                self.out.c.reconfigurations += 1;
                                self.stream.lost();
                                cause.get_or_insert(Loss::Stalled);
                                last_frame = self.clock.now_s();
                            }
                            // Tried again at the next poll.
                            Err(DriverError::Bus(_)) => self.out.c.bus_errors += 1,
                            Err(e) => return Err(RecordError::Reconfigure(e)),
                        }
                    }
                }
                Some((_, FifoRead::Overflow)) => {
                    self.out.c.overflows += 1;
                    self.stream.lost();
                    cause.get_or_insert(Loss::Overflow);
                }
                Some((_, FifoRead::Resync)) => {
                    self.out.c.resyncs += 1;
                    self.stream.lost();
                    cause.get_or_insert(Loss::PartRead);
                }
                Some((t, FifoRead::Reconfigured)) => {
                    self.out.c.reconfigurations += 1;
                    self.stream.lost();
                    cause.get_or_insert(Loss::Reset);
                    last_frame = t;
                }
                // Every try failed: the next poll tries again.
                None => {}
            }
            let now = self.clock.now_s();
            if now - last_delivery > GIVE_UP_S as f64 {
                // The silence up to now is a gap, then the run ends.
                self.stream.lost();
                self.out
                    .final_gap(self.stream, now, cause.unwrap_or(Loss::Stalled))
                    .map_err(w)?;
                self.out.w.flush().map_err(w)?;
                return Err(RecordError::Silent {
                    seconds: GIVE_UP_S,
                    bus_errors: self.out.c.bus_errors,
                    reconfigurations: self.out.c.reconfigurations,
                });
            }
            if now - last_flush >= 1.0 {
                self.out.w.flush().map_err(w)?;
                last_flush = now;
            }
            if now - last_sync >= 5.0 {
                self.out.w.get_mut().sync_data().map_err(w)?;
                last_sync = now;
            }
            if now - last_status >= self.settings.status_every.as_secs_f64() {
                status(&Status {
                    counters: self.out.c,
                    measured_hz: self.stream.measured_hz(),
                    temperature_c: self.out.last[6],
                    fifo_bytes: self.imu.fifo_level(),
                });
                last_status = now;
            }
            if self.out.full() {
                return Ok(StopReason::Duration);
            }
            if deadline.is_some_and(|d| now > d) {
                // Far past the duration in host time: what is missing is
                // lost.
                if now - last_delivery > 2.0 / rate {
                    self.stream.lost();
                }
                self.out
                    .final_gap(self.stream, now, cause.unwrap_or(Loss::Stalled))
                    .map_err(w)?;
                return Ok(StopReason::TimeLimit);
            }
            if signalled {
                // A loss still waiting for frames to size it ends the file.
                self.out
                    .final_gap(self.stream, now, cause.unwrap_or(Loss::Overflow))
                    .map_err(w)?;
                return Ok(StopReason::Signal);
            }
        }
    }
}
