//! The generator: a recording sample by sample, in chunks, the six axes in
//! parallel, each term of each axis from its own random stream.
//!
//! Per axis, a sample is
//!
//! ```text
//! y = (1 + scale_factor)·input + bias(T) + R·t + s(T)·(n_Q + n_N + B·flicker) + walk_K
//! ```
//!
//! then rounded to the full scale's LSB and clipped (the output stage);
//! `input` is gravity for the static orientation (accelerometers) or zero
//! (gyroscopes; the Earth's rotation when a latitude is configured, see
//! [`crate::earth`]), `T` the die temperature, `bias` the configured polynomial,
//! `s(T)` the noise factor, and the random walk's steps are scaled by
//! `s(T)` as they are taken.
//!
//! ## The truth in the log's metadata
//!
//! | key | value |
//! | --- | --- |
//! | `seed`, `quantized`, `gyro_full_scale_dps`, `accel_full_scale_g` | the run |
//! | `true.profile`, `true.sensor_lag_s`, `true.t_ref_c`, `true.orientation_deg` | temperature and attitude |
//! | `true.latitude_deg`, `true.heading_deg` | only when the Earth rotates (a configured latitude) |
//! | `true.{accel,gyro}.unit` | `m/s^2` or `rad/s`: the unit of every value below (times s^-½, s, … as the term needs) |
//! | `true.{accel,gyro}.noise_scale` | `°C:factor` pairs, interpolated |
//! | `true.{accel,gyro}.flicker_tau_s` | the τ range where bias instability is flat |
//! | `true.{g}_{a}.q` `.n` `.b` `.k` `.r` | IEEE 952 Q, N, B, K, R at noise factor 1, SI |
//! | `true.{g}_{a}.adev_floor` | 0.664·B, the flat Allan deviation of B |
//! | `true.{g}_{a}.bias_poly` | bias coefficients in (T − t_ref), ascending powers, SI |
//! | `true.{g}_{a}.scale_factor`, `true.{g}_{a}.input` | scale-factor error and true input (gravity) |
//!
//! `{g}_{a}` is `accel_x` … `gyro_z`, as the channels are named.

use std::io::Write;

use rand::SeedableRng;
use rand_distr::{Distribution, StandardNormal};
use rand_xoshiro::Xoshiro256PlusPlus;
use rayon::prelude::*;

use imu::log_file::format_row;
use imu::{Axis, Channel, LogFormat, LogWriter, Metadata, Quantity, Recording};

use crate::SimError;
use crate::config::{GroupConfig, SimConfig};
use crate::earth;
use crate::flicker::FlickerBank;
use crate::sensor;
use crate::terms::NoiseTerms;
use crate::thermal::Thermal;

/// Samples generated at a time: large enough to keep both cores busy,
/// small enough to stay in cache and to report progress often.
pub const CHUNK: usize = 1 << 15;

/// IEEE 952's flat Allan deviation of bias instability, per unit B:
/// √(2 ln2/π) ≈ 0.664.
pub const FLICKER_FLOOR: f64 = 0.664_282_629_657_927_7;

/// One chunk of output: the seven columns of the log, from sample `start`.
#[derive(Debug, Clone)]
pub struct Chunk {
    /// Index of the first sample.
    pub start: u64,
    /// accel x, y, z (m/s²), gyro x, y, z (rad/s), temperature (°C), as
    /// the sensor reports them.
    pub columns: [Vec<f64>; 7],
    /// The die temperature before the temperature sensor's quantization.
    pub true_temperature: Vec<f64>,
    /// The chamber's temperature, which the die's lags.
    pub chamber_temperature: Vec<f64>,
}

/// The random streams of one axis, one per term, so that adding or
/// removing a term leaves the others' realisations as they were.
struct Streams {
    white: Xoshiro256PlusPlus,
    quantization: Xoshiro256PlusPlus,
    flicker: Xoshiro256PlusPlus,
    walk: Xoshiro256PlusPlus,
}

struct AxisState {
    rng: Streams,
    terms: NoiseTerms,
    flicker: Option<FlickerBank>,
    walk: f64,
    previous_q: f64,
    /// The true specific force or rate, before the scale-factor error.
    truth: f64,
    scale_factor: f64,
    group: usize, // 0 accel, 1 gyro
    axis: usize,
    lsb: Option<f64>,
}

/// A configured simulation.
#[derive(Debug, Clone)]
pub struct Simulator {
    cfg: SimConfig,
    /// The prepared profile (a file profile already read).
    thermal: Thermal,
}

impl Simulator {
    /// Checks the configuration, and reads a file profile, so that a bad
    /// one fails before any output.
    pub fn new(cfg: SimConfig) -> Result<Simulator, SimError> {
        cfg.validate()?;
        let thermal = Thermal::new(&cfg.profile, 1.0 / cfg.rate_hz, cfg.sensor_lag_s)?;
        Ok(Simulator { cfg, thermal })
    }

    /// The configuration.
    pub fn config(&self) -> &SimConfig {
        &self.cfg
    }

    fn group(&self, g: usize) -> &GroupConfig {
        group(&self.cfg, g)
    }

    /// Every true parameter, as `true.*` metadata entries (listed in the
    /// module documentation), so an analysis of the output can be compared
    /// with what was put in.
    pub fn metadata(&self, preset: Option<&str>) -> Metadata {
        let c = &self.cfg;
        let mut m = Metadata {
            device: Some(format!("imusim:{}", preset.unwrap_or("config"))),
            ..Metadata::default()
        };
        m.set(
            "generator",
            format!("imutherm {} imusim", env!("CARGO_PKG_VERSION")),
        );
        m.set("seed", c.seed.to_string());
        m.set("gyro_full_scale_dps", c.sensor.gyro_range_dps.to_string());
        m.set("accel_full_scale_g", c.sensor.accel_range_g.to_string());
        m.set("quantized", c.sensor.quantize.to_string());
        m.set("true.profile", c.profile.describe());
        m.set("true.sensor_lag_s", c.sensor_lag_s.to_string());
        m.set("true.t_ref_c", c.t_ref_c.to_string());
        m.set(
            "true.orientation_deg",
            format!("roll {} pitch {}", c.sensor.roll_deg, c.sensor.pitch_deg),
        );
        // Written only for a rotating Earth, so that the default output is
        // as it always was.
        if let Some(lat) = c.sensor.latitude_deg {
            m.set("true.latitude_deg", lat.to_string());
            m.set("true.heading_deg", c.sensor.heading_deg.to_string());
        }
        let gravity = self.gravity();
        let earth = self.earth_rate();
        for (g, name, unit) in [(0, "accel", "m/s^2"), (1, "gyro", "rad/s")] {
            let gc = self.group(g);
            m.set(format!("true.{name}.unit"), unit);
            m.set(
                format!("true.{name}.flicker_tau_s"),
                format!("{} {}", gc.flicker_tau_s[0], gc.flicker_tau_s[1]),
            );
            let scale: Vec<String> = gc
                .noise_scale
                .iter()
                .map(|p| format!("{}:{}", p[0], p[1]))
                .collect();
            m.set(format!("true.{name}.noise_scale"), scale.join(" "));
            for (i, a) in ["x", "y", "z"].iter().enumerate() {
                let t = &gc.terms[i];
                let key = |k: &str| format!("true.{name}_{a}.{k}");
                m.set(key("q"), t.q.to_string());
                m.set(key("n"), t.n.to_string());
                m.set(key("b"), t.b.to_string());
                m.set(key("k"), t.k.to_string());
                m.set(key("r"), t.r.to_string());
                m.set(key("adev_floor"), (FLICKER_FLOOR * t.b).to_string());
                let poly: Vec<String> = gc.bias[i].iter().map(|v| v.to_string()).collect();
                m.set(key("bias_poly"), poly.join(" "));
                m.set(key("scale_factor"), gc.scale_factor[i].to_string());
                let input = if g == 0 { gravity[i] } else { earth[i] };
                m.set(key("input"), input.to_string());
            }
        }
        m
    }

    /// The specific force on the static sensor: standard gravity, or the
    /// normal gravity of the latitude when the Earth rotates.
    fn gravity(&self) -> [f64; 3] {
        let s = &self.cfg.sensor;
        let f = sensor::gravity(s.roll_deg.to_radians(), s.pitch_deg.to_radians());
        match s.latitude_deg {
            Some(lat) => f.map(|v| v / sensor::G * earth::normal_gravity(lat.to_radians())),
            None => f,
        }
    }

    /// What the static gyros read: the Earth's rotation when a latitude is
    /// configured, else nothing.
    fn earth_rate(&self) -> [f64; 3] {
        let s = &self.cfg.sensor;
        match s.latitude_deg {
            Some(lat) => earth::earth_rate_body(
                lat.to_radians(),
                s.roll_deg.to_radians(),
                s.pitch_deg.to_radians(),
                s.heading_deg.to_radians(),
            ),
            None => [0.0; 3],
        }
    }

    /// A generator at the first sample: chunks on demand, without end (the
    /// configured duration is for [`Simulator::run`] and the writers). The
    /// simulated chip pulls its samples from one.
    pub fn generator(&self) -> Generator {
        let c = &self.cfg;
        let tau0 = 1.0 / c.rate_hz;
        let base = Xoshiro256PlusPlus::seed_from_u64(c.seed);
        let gravity = self.gravity();
        let earth = self.earth_rate();
        // The temperature draws from the seed's own stream. Axis k's white
        // noise draws from that stream jumped k+1 times (2^128 steps each);
        // its other terms from the stream long-jumped k+1 times (2^192
        // steps each) and then jumped 0, 1, 2 times. No two ever overlap.
        let mut white_base = base.clone();
        let mut terms_base = base.clone();
        let axes = (0..6)
            .map(|k| {
                white_base.jump();
                terms_base.long_jump();
                let mut s = terms_base.clone();
                let mut next = || {
                    let r = s.clone();
                    s.jump();
                    r
                };
                let mut rng = Streams {
                    white: white_base.clone(),
                    quantization: next(),
                    flicker: next(),
                    walk: next(),
                };
                let (group, axis) = (k / 3, k % 3);
                let g = self.group(group);
                let terms = g.terms[axis];
                let flicker = (terms.b > 0.0).then(|| {
                    FlickerBank::new(tau0, g.flicker_tau_s[0], g.flicker_tau_s[1], &mut rng.flicker)
                });
                let lsb = c.sensor.quantize.then(|| {
                    if group == 0 {
                        sensor::accel_lsb_si(c.sensor.accel_range_g)
                    } else {
                        sensor::gyro_lsb_rad(c.sensor.gyro_range_dps)
                    }
                });
                AxisState {
                    rng,
                    terms,
                    flicker,
                    walk: 0.0,
                    previous_q: 0.0,
                    truth: if group == 0 { gravity[axis] } else { earth[axis] },
                    scale_factor: g.scale_factor[axis],
                    group,
                    axis,
                    lsb,
                }
            })
            .collect();
        Generator {
            cfg: c.clone(),
            thermal: self.thermal.clone(),
            thermal_rng: base,
            axes,
            next: 0,
        }
    }

    /// Runs the simulation for the configured duration, handing each chunk
    /// to `sink` in order.
    pub fn run(&self, mut sink: impl FnMut(&Chunk) -> Result<(), SimError>) -> Result<(), SimError> {
        let total = self.cfg.samples();
        let mut generator = self.generator();
        while generator.position() < total {
            let len = (total - generator.position()).min(CHUNK as u64) as usize;
            sink(&generator.next_chunk(len))?;
        }
        Ok(())
    }

    /// Writes imutherm's log, with every true parameter in its metadata.
    /// `progress` is told (samples done, total) after each chunk. Returns
    /// the number of rows written.
    pub fn write_log<W: Write + Send>(
        &self,
        out: W,
        meta: &Metadata,
        mut progress: impl FnMut(u64, u64),
    ) -> Result<u64, SimError> {
        const ROWS_PER_PART: usize = 4096;
        type Parts = Vec<(Vec<u8>, u64)>;
        let total = self.cfg.samples();
        let mut w = LogWriter::new(out, LogFormat::Imutherm, meta, Some(self.cfg.rate_hz))?;
        // A writer thread does the system calls while the next chunk is
        // generated and formatted; text buffers travel back to be reused
        // (fresh megabyte buffers would each cost a round of page faults).
        let (full_tx, full_rx) = std::sync::mpsc::sync_channel::<Parts>(2);
        let (empty_tx, empty_rx) = std::sync::mpsc::channel::<Parts>();
        std::thread::scope(|scope| {
            let writer = scope.spawn(move || -> std::io::Result<u64> {
                for parts in full_rx {
                    for (text, rows) in &parts {
                        w.write_formatted(text, *rows)?;
                    }
                    // The generator may have finished; then nobody reuses it.
                    let _ = empty_tx.send(parts);
                }
                w.flush()?;
                Ok(w.rows())
            });
            let generated = self.run(|chunk| {
                let n = chunk.columns[0].len();
                let count = n.div_ceil(ROWS_PER_PART);
                let mut parts = empty_rx.try_recv().unwrap_or_default();
                parts.resize_with(count, || (Vec::with_capacity(ROWS_PER_PART * 160), 0));
                parts.par_iter_mut().enumerate().for_each(|(p, (text, rows))| {
                    text.clear();
                    let range = p * ROWS_PER_PART..((p + 1) * ROWS_PER_PART).min(n);
                    *rows = range.len() as u64;
                    for i in range {
                        let row: [f64; 7] = std::array::from_fn(|k| chunk.columns[k][i]);
                        format_row(&row, text);
                    }
                });
                // A closed channel means the writer failed: its error is
                // the one reported below.
                if full_tx.send(parts).is_err() {
                    return Err(SimError::Io(std::io::Error::other("the log writer stopped")));
                }
                progress(chunk.start + n as u64, total);
                Ok(())
            });
            drop(full_tx);
            let written = writer
                .join()
                .map_err(|_| SimError::Io(std::io::Error::other("the log writer panicked")))?;
            // The writer's own error explains a generator stopped by it.
            let rows = written?;
            generated?;
            Ok(rows)
        })
    }

    /// The whole recording in memory (for tests and short runs).
    pub fn recording(&self, preset: Option<&str>) -> Result<Recording, SimError> {
        let n = usize::try_from(self.cfg.samples()).unwrap_or(usize::MAX);
        let mut cols: Vec<Vec<f64>> = Vec::with_capacity(7);
        for _ in 0..7 {
            let mut c = Vec::new();
            c.try_reserve_exact(n).map_err(|_| {
                SimError::Io(std::io::Error::other(format!(
                    "{n} samples do not fit in memory: write them as a log instead"
                )))
            })?;
            cols.push(c);
        }
        self.run(|chunk| {
            for (dst, src) in cols.iter_mut().zip(&chunk.columns) {
                dst.extend_from_slice(src);
            }
            Ok(())
        })?;
        let temp = cols.pop().unwrap_or_default();
        let mut channels = Vec::with_capacity(7);
        for (k, data) in cols.into_iter().enumerate() {
            let q = if k < 3 {
                Quantity::Acceleration
            } else {
                Quantity::AngularRate
            };
            channels.push(Channel::inertial(q, Axis::ALL[k % 3], data));
        }
        channels.push(Channel::temperature(temp));
        Ok(Recording {
            channels,
            rate_hz: Some(self.cfg.rate_hz),
            timestamps: None,
            meta: self.metadata(preset),
        })
    }
}

fn group(cfg: &SimConfig, g: usize) -> &GroupConfig {
    if g == 0 { &cfg.accel } else { &cfg.gyro }
}

/// The simulation's state: every random stream, the flicker banks, the
/// random walks and the temperature, at some sample. Memory does not grow
/// with the samples drawn.
pub struct Generator {
    cfg: SimConfig,
    thermal: Thermal,
    thermal_rng: Xoshiro256PlusPlus,
    axes: Vec<AxisState>,
    next: u64,
}

impl std::fmt::Debug for Generator {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Generator")
            .field("next", &self.next)
            .finish_non_exhaustive()
    }
}

impl Generator {
    /// Index of the next sample.
    pub fn position(&self) -> u64 {
        self.next
    }

    /// The next `len` samples.
    pub fn next_chunk(&mut self, len: usize) -> Chunk {
        let start = self.next;
        let mut temps = Vec::with_capacity(len);
        let mut chamber = Vec::with_capacity(len);
        for _ in 0..len {
            temps.push(self.thermal.next(&mut self.thermal_rng));
            chamber.push(self.thermal.chamber());
        }
        let cfg = &self.cfg;
        // Small chunks (a chip's FIFO read) are not worth the threads.
        let mut cols: Vec<Vec<f64>> = if len >= 4096 {
            self.axes
                .par_iter_mut()
                .map(|ax| fill(cfg, ax, start, &temps))
                .collect()
        } else {
            self.axes
                .iter_mut()
                .map(|ax| fill(cfg, ax, start, &temps))
                .collect()
        };
        cols.push(if cfg.sensor.quantize {
            temps.iter().map(|&t| sensor::temperature_reading(t)).collect()
        } else {
            temps.clone()
        });
        let columns: [Vec<f64>; 7] = match cols.try_into() {
            Ok(a) => a,
            Err(_) => unreachable!("six axes and the temperature"),
        };
        self.next += len as u64;
        Chunk {
            start,
            columns,
            true_temperature: temps,
            chamber_temperature: chamber,
        }
    }
}

/// The samples of one axis over a chunk: input × (1 + scale factor) + the
/// bias polynomial at the die temperature + the rate ramp + the noise terms
/// scaled by the noise factor at that temperature, then the output stage.
fn fill(cfg: &SimConfig, ax: &mut AxisState, start: u64, temps: &[f64]) -> Vec<f64> {
    let tau0 = 1.0 / cfg.rate_hz;
    let g = group(cfg, ax.group);
    let t = ax.terms;
    let white = t.n / tau0.sqrt();
    let step = t.k * tau0.sqrt();
    let bridge = step / 12f64.sqrt();
    let input = (1.0 + ax.scale_factor) * ax.truth;
    let constant_scale = g.noise_scale.is_empty();
    temps
        .iter()
        .enumerate()
        .map(|(i, &temp)| {
            let s = if constant_scale { 1.0 } else { g.noise_factor(temp) };
            let mut noise = 0.0;
            if t.n > 0.0 {
                let w: f64 = StandardNormal.sample(&mut ax.rng.white);
                noise += white * w;
            }
            if t.q > 0.0 {
                // White phase (angle) noise of σ = Q, differenced into rate:
                // Allan variance 3Q²/τ² at every τ.
                let e: f64 = StandardNormal.sample(&mut ax.rng.quantization);
                noise += t.q * (e - ax.previous_q) / tau0;
                ax.previous_q = e;
            }
            if let Some(f) = &mut ax.flicker {
                noise += t.b * f.next(&mut ax.rng.flicker);
            }
            let mut walk = 0.0;
            if t.k > 0.0 {
                // A sample is the average of the continuous walk over its
                // interval (as the sensor's filter averages): the walk at
                // the start, half the interval's step, and the bridge's own
                // spread of variance K²τ0/12. Point samples of the walk
                // would lift the ADEV at τ0 by half.
                let (w, xi): (f64, f64) = (
                    StandardNormal.sample(&mut ax.rng.walk),
                    StandardNormal.sample(&mut ax.rng.walk),
                );
                // The walk carries the temperature scaling of each step.
                let delta = s * step * w;
                walk = ax.walk + 0.5 * delta + s * bridge * xi;
                ax.walk += delta;
            }
            let time = (start + i as u64) as f64 * tau0;
            let bias = g.bias_at(ax.axis, temp, cfg.t_ref_c) + t.r * time;
            let value = input + bias + s * noise + walk;
            match ax.lsb {
                Some(lsb) => sensor::quantize(value, lsb),
                None => value,
            }
        })
        .collect()
}
