//! The recorder in simulated time against the simulated chip, and a reading
//! of what it wrote that uses nothing of imutherm's readers: the format is
//! spelled out in the README ("imutherm log").

#![allow(dead_code)]

use std::sync::atomic::AtomicBool;
use std::time::Duration;

use logger::{Clock, Settings, SimTime, Sleeper, Summary, Tick};
use mpu9250::config::Config;
use mpu9250::driver::{I2cBus, Mpu9250};
use mpu9250::sim::{ADDRESS, FaultSchedule, SimChip, Source};

/// The sample taken at chip time t reads round(t·rate) mod 2^15 LSB on
/// every field: its index on the chip's sample grid, so that a row's place
/// in the file can be checked against the time it was sampled at.
pub fn counting(cfg: Config) -> Source {
    let rate = cfg.actual_rate_hz().unwrap();
    let (a, g) = (cfg.accel_range.lsb_si(), cfg.gyro_range.lsb_rad());
    Box::new(move |_, t| {
        let v = ((t * rate).round() as u64 % 32_768) as f64;
        // Temperature: 333.87 LSB/°C from 21 °C (RM-MPU-9250A-00 §4.23).
        [v * a, v * a, v * a, v * g, v * g, v * g, 21.0 + v / 333.87]
    })
}

/// One simulated run's outcome.
pub struct Recorded {
    pub text: String,
    pub summary: Result<Summary, String>,
    /// Host time at the end, s.
    pub host_s: f64,
}

/// A tick that follows the host and raises the stop flag at `stop_at` s.
struct Follow<'a> {
    stop_at: Option<f64>,
    stop: &'a AtomicBool,
}

impl Tick<I2cBus<SimChip>, SimTime> for Follow<'_> {
    fn before_read(
        &mut self,
        imu: &mut Mpu9250<I2cBus<SimChip>, SimTime>,
        clock: &dyn Clock,
        sleeper: &mut dyn Sleeper,
    ) {
        if self.stop_at.is_some_and(|t| clock.now_s() >= t) {
            self.stop.store(true, std::sync::atomic::Ordering::SeqCst);
        }
        logger::sim::FollowHost.before_read(imu, clock, sleeper);
    }
}

/// What to run.
pub struct Run {
    pub config: Config,
    pub seconds: Option<f64>,
    pub faults: FaultSchedule,
    pub host_time: bool,
    /// Sleeps overshoot by up to this much (a loaded host).
    pub overshoot: Duration,
    pub seed: u64,
    pub stop_at: Option<f64>,
    pub source: Option<Source>,
}

impl Default for Run {
    fn default() -> Self {
        Run {
            config: Config::default(),
            seconds: None,
            faults: FaultSchedule::default(),
            host_time: false,
            overshoot: Duration::ZERO,
            seed: 1,
            stop_at: None,
            source: None,
        }
    }
}

impl Run {
    /// Records in simulated time into memory.
    pub fn record(self) -> Recorded {
        let rate = self.config.actual_rate_hz().unwrap();
        let source = self.source.unwrap_or_else(|| counting(self.config));
        let time = SimTime::new().with_overshoot(self.overshoot, self.seed);
        let host = time.clone();
        let chip = SimChip::new(source)
            .with_faults(self.faults)
            .with_host_clock(Box::new(move || host.now_s()));
        let mut imu = Mpu9250::new(I2cBus::new(chip, ADDRESS), time.clone()).unwrap();
        let mut sleeper = time.clone();
        logger::configure(&mut imu, self.config, &mut sleeper).unwrap();
        let settings = Settings {
            config: self.config,
            rate_hz: rate,
            target_rows: self.seconds.map(|d| (d * rate).round() as u64),
            host_time: self.host_time,
            device: "sim:counter".to_string(),
            unix_start: 1.7e9,
            gyro_full_scale_dps: 250.0,
            accel_full_scale_g: 2.0,
            version: "0.1.0".to_string(),
            status_every: Duration::from_secs(60),
        };
        let stop = AtomicBool::new(false);
        let mut tick = Follow {
            stop_at: self.stop_at,
            stop: &stop,
        };
        let mut out = Vec::new();
        let summary = logger::record(
            &mut imu,
            &mut out,
            &settings,
            &time,
            &mut sleeper,
            &mut tick,
            &stop,
            &mut |_| {},
        )
        .map_err(|e| e.to_string());
        Recorded {
            text: String::from_utf8(out).unwrap(),
            summary,
            host_s: time.now_s(),
        }
    }
}

/// The data rows: comma-separated numbers after the header line.
pub fn rows(text: &str) -> Vec<Vec<f64>> {
    text.lines()
        .filter(|l| !l.starts_with('#') && !l.starts_with("mpu_"))
        .map(|l| l.split(", ").map(|v| v.parse::<f64>().unwrap()).collect())
        .collect()
}

/// A number from the `# trailer:` line.
pub fn trailer(text: &str, key: &str) -> f64 {
    let line = text.lines().find(|l| l.starts_with("# trailer:")).unwrap();
    line.split_whitespace()
        .find_map(|f| f.strip_prefix(&format!("{key}=")))
        .and_then(|v| v.parse().ok())
        .unwrap_or_else(|| panic!("no number {key} in {line}"))
}

/// The counting pattern's index of a row (`None` for a gap row); panics on
/// a row whose fields disagree (a frame decoded from misaligned bytes).
pub fn counter_index(row: &[f64], cfg: &Config) -> Option<i64> {
    if row[..7].iter().all(|v| v.is_nan()) {
        return None;
    }
    let (a, g) = (cfg.accel_range.lsb_si(), cfg.gyro_range.lsb_rad());
    let k: Vec<f64> = (0..3)
        .map(|i| row[i] / a)
        .chain((3..6).map(|i| row[i] / g))
        .chain(std::iter::once((row[6] - 21.0) * 333.87))
        .collect();
    let k0 = k[0].round();
    assert!(k.iter().all(|v| (v - k0).abs() < 1e-3), "misaligned frame: {k:?}");
    Some(k0 as i64)
}

/// The largest |place in the file − true index| over the samples, after the
/// first sample's offset: how far a gap's size was misjudged, accumulated.
pub fn worst_place_error(rows: &[Vec<f64>], cfg: &Config) -> i64 {
    let mut offset = None;
    let mut worst = 0;
    for (place, row) in rows.iter().enumerate() {
        let Some(k) = counter_index(row, cfg) else {
            continue;
        };
        let place = place as i64;
        // The true index, unwrapped from its 2^15 modulus near its place.
        let truth = k + 32_768 * ((place - k) as f64 / 32_768.0).round() as i64;
        let off = *offset.get_or_insert(place - truth);
        worst = worst.max((place - truth - off).abs());
    }
    worst
}
