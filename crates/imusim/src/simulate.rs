//! The generator: a recording sample by sample, in chunks, the six axes in
//! parallel, each from its own random stream.

use std::io::Write;

use rand::SeedableRng;
use rand_distr::{Distribution, StandardNormal};
use rand_xoshiro::Xoshiro256PlusPlus;
use rayon::prelude::*;

use imu::log::format_row;
use imu::{Axis, Channel, LogFormat, LogWriter, Metadata, Quantity, Recording};

use crate::SimError;
use crate::config::{GroupConfig, SimConfig};
use crate::flicker::FlickerBank;
use crate::sensor;
use crate::terms::NoiseTerms;
use crate::thermal::Thermal;

/// Samples generated at a time: large enough to keep both cores busy,
/// small enough to stay in cache and to report progress often.
pub const CHUNK: usize = 1 << 15;

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
}

struct AxisState {
    rng: Xoshiro256PlusPlus,
    terms: NoiseTerms,
    flicker: Option<FlickerBank>,
    walk: f64,
    previous_q: f64,
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
}

impl Simulator {
    /// Checks the configuration.
    pub fn new(cfg: SimConfig) -> Result<Simulator, SimError> {
        cfg.validate()?;
        // A file profile is read now, so a bad one fails before any output.
        Thermal::new(&cfg.profile, 1.0 / cfg.rate_hz, cfg.sensor_lag_s)?;
        Ok(Simulator { cfg })
    }

    /// The configuration.
    pub fn config(&self) -> &SimConfig {
        &self.cfg
    }

    fn group(&self, g: usize) -> &GroupConfig {
        if g == 0 { &self.cfg.accel } else { &self.cfg.gyro }
    }

    /// Every true parameter, as `true.*` metadata entries, so an analysis of
    /// the output can be compared with what was put in.
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
                let poly: Vec<String> = gc.bias[i].iter().map(|v| v.to_string()).collect();
                m.set(key("bias_poly"), poly.join(" "));
                m.set(key("scale_factor"), gc.scale_factor[i].to_string());
            }
        }
        m
    }

    fn axis_states(&self, base: &Xoshiro256PlusPlus) -> Vec<AxisState> {
        let c = &self.cfg;
        let tau0 = 1.0 / c.rate_hz;
        let gravity = sensor::gravity(c.sensor.roll_deg.to_radians(), c.sensor.pitch_deg.to_radians());
        let mut stream = base.clone();
        (0..6)
            .map(|k| {
                // Each axis draws from its own stream, 2^128 steps apart.
                stream.jump();
                let mut rng = stream.clone();
                let (group, axis) = (k / 3, k % 3);
                let g = self.group(group);
                let terms = g.terms[axis];
                let flicker = (terms.b > 0.0)
                    .then(|| FlickerBank::new(tau0, g.flicker_tau_s[0], g.flicker_tau_s[1], &mut rng));
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
                    truth: if group == 0 { gravity[axis] } else { 0.0 },
                    scale_factor: g.scale_factor[axis],
                    group,
                    axis,
                    lsb,
                }
            })
            .collect()
    }

    /// Runs the simulation, handing each chunk to `sink` in order.
    pub fn run(&self, mut sink: impl FnMut(&Chunk) -> Result<(), SimError>) -> Result<(), SimError> {
        let c = &self.cfg;
        let tau0 = 1.0 / c.rate_hz;
        let total = c.samples();
        let base = Xoshiro256PlusPlus::seed_from_u64(c.seed);
        let mut thermal_rng = base.clone();
        let mut thermal = Thermal::new(&c.profile, tau0, c.sensor_lag_s)?;
        let mut axes = self.axis_states(&base);
        let mut start = 0u64;
        while start < total {
            let len = (total - start).min(CHUNK as u64) as usize;
            let temps: Vec<f64> = (0..len).map(|_| thermal.next(&mut thermal_rng)).collect();
            let mut cols: Vec<Vec<f64>> = axes
                .par_iter_mut()
                .map(|ax| self.fill(ax, start, &temps))
                .collect();
            cols.push(temps.iter().map(|&t| sensor::temperature_reading(t)).collect());
            let columns: [Vec<f64>; 7] = match cols.try_into() {
                Ok(a) => a,
                Err(_) => unreachable!("six axes and the temperature"),
            };
            sink(&Chunk {
                start,
                columns,
                true_temperature: temps,
            })?;
            start += len as u64;
        }
        Ok(())
    }

    fn fill(&self, ax: &mut AxisState, start: u64, temps: &[f64]) -> Vec<f64> {
        let c = &self.cfg;
        let tau0 = 1.0 / c.rate_hz;
        let g = self.group(ax.group);
        let t = ax.terms;
        let white = t.n / tau0.sqrt();
        let step = t.k * tau0.sqrt();
        temps
            .iter()
            .enumerate()
            .map(|(i, &temp)| {
                let s = g.noise_factor(temp);
                let mut noise = 0.0;
                let mut walk = 0.0;
                if t.n > 0.0 {
                    let w: f64 = StandardNormal.sample(&mut ax.rng);
                    noise += white * w;
                }
                if t.q > 0.0 {
                    let e: f64 = StandardNormal.sample(&mut ax.rng);
                    noise += t.q * (e - ax.previous_q) / tau0;
                    ax.previous_q = e;
                }
                if let Some(f) = &mut ax.flicker {
                    noise += t.b * f.next(&mut ax.rng);
                }
                if t.k > 0.0 {
                    // A sample is the average of the continuous walk over
                    // its interval (as the sensor's filter averages): the
                    // walk at the start, half the interval's step, and the
                    // bridge's own spread of variance K²τ0/12. Point samples
                    // of the walk would lift the ADEV at τ0 by half.
                    let (w, xi): (f64, f64) = (
                        StandardNormal.sample(&mut ax.rng),
                        StandardNormal.sample(&mut ax.rng),
                    );
                    // The walk carries the temperature scaling of each step.
                    let delta = s * step * w;
                    walk = ax.walk + 0.5 * delta + s * step * xi / 12f64.sqrt();
                    ax.walk += delta;
                }
                let time = (start + i as u64) as f64 * tau0;
                let bias = g.bias_at(ax.axis, temp, c.t_ref_c) + t.r * time;
                let value = (1.0 + ax.scale_factor) * (ax.truth + bias + s * noise + walk);
                match ax.lsb {
                    Some(lsb) => sensor::quantize(value, lsb),
                    None => value,
                }
            })
            .collect()
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
        let n = self.cfg.samples() as usize;
        let mut cols: Vec<Vec<f64>> = (0..7).map(|_| Vec::with_capacity(n)).collect();
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
