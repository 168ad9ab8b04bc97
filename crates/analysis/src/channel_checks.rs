//! What a recording's inertial channels rule out, with the figures that
//! show it: a channel stuck at one value (a dead sensor reads exactly 0.0
//! in every message), a channel clipped at a full scale, a static
//! accelerometer whose norm is far from g, and motion.
//!
//! Every reader's output goes through [`check`]: `info` lists the
//! findings, every analysis repeats them, and the analyses that assume a
//! static sensor (`noise`, `ins`, `tcal`) refuse a moving record
//! ([`Checks::require_static`]).
//!
//! Motion is read off windows of [`window_len`] samples: a window whose
//! standard deviation is far above the channel's noise floor (the quiet
//! windows' level), or a step of the window means that neither the noise
//! nor a smooth drift explains. A temperature ramp moves the bias slowly
//! and evenly, so the step test compares each step of the means with its
//! neighbours' steps.

use std::fmt;

use imu::{Quantity, Recording};
use serde::Serialize;

pub use earth::STANDARD_GRAVITY;

/// A static accelerometer's norm further than this from g, m/s² (0.1 g):
/// a low-cost part's zero-g offsets (MPU-9250: ±80 mg) and scale errors
/// (±3 %) together stay well inside it; a unit or scale mistake does not.
pub const NORM_TOLERANCE: f64 = 0.1 * STANDARD_GRAVITY;

/// A window whose standard deviation exceeds the noise floor this many
/// times is moving (its variance is 25 times the floor's).
pub const VARIANCE_FACTOR: f64 = 5.0;

/// A step of the window means larger than this many noise-floor standard
/// deviations, beyond what its neighbours' steps show, is a level change.
/// The means of windows of 32 samples scatter by a fifth of the floor, so
/// noise alone never takes them this far.
pub const LEVEL_FACTOR: f64 = 8.0;

/// The smallest level change counted, by quantity: a turn of 0.3 °/s, a
/// tilt of about 0.3°. A thermal drift of a few mg/°C or °/s per 100 °C
/// moves a window's mean far less.
fn min_level_change(q: Quantity) -> f64 {
    match q {
        Quantity::AngularRate => 5e-3,
        _ => 0.05,
    }
}

/// A noise floor above this means the sensor never rested: no MEMS gyro at
/// rest scatters by 0.05 rad/s (2.9 °/s) nor accelerometer by 0.5 m/s²
/// sample to sample in a filtered log (MPU-9250 at 184 Hz bandwidth:
/// 0.14 °/s and 4 mg).
fn max_floor(q: Quantity) -> f64 {
    match q {
        Quantity::AngularRate => 0.05,
        _ => 0.5,
    }
}

/// Full scales of MEMS gyroscopes (°/s) and accelerometers (g) as their
/// datasheets list them (InvenSense MPU-9250, ICM-20602/20689/42688, Bosch
/// BMI055/088, ST LSM6DS…, ADIS16405's 300 °/s and 18 g).
const GYRO_FULL_SCALES_DPS: [f64; 7] = [125.0, 250.0, 300.0, 500.0, 1000.0, 2000.0, 4000.0];
const ACCEL_FULL_SCALES_G: [f64; 8] = [2.0, 3.0, 4.0, 6.0, 8.0, 16.0, 18.0, 24.0];

/// A sample within this fraction of a full scale sits on it (an int16
/// reaches 32767/32768 of it; a scale factor rounds by a few 1e-4).
const AT_FULL_SCALE: f64 = 0.995;

/// A channel is stuck where one value repeats over at least this share of
/// its samples (and at least [`MIN_STUCK_SAMPLES`]).
const STUCK_SHARE: f64 = 0.5;
const MIN_STUCK_SAMPLES: usize = 100;

/// Samples in a motion window at `rate_hz`: one second, and never fewer
/// than 32 samples (the means must be sharper than the floor they are
/// compared with).
pub fn window_len(rate_hz: f64) -> usize {
    let per_second = if rate_hz.is_finite() && rate_hz > 0.0 {
        rate_hz.round() as usize
    } else {
        1
    };
    per_second.max(32)
}

/// Fewer windows than this and motion is not judged.
const MIN_WINDOWS: usize = 4;

/// One thing a recording's channels rule out.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Finding {
    /// One value repeated over most of a channel (all of it: a dead sensor).
    Stuck {
        /// The channel.
        channel: String,
        /// The value it holds, in the channel's unit.
        value: f64,
        /// Samples holding it.
        samples: usize,
        /// The channel's finite samples.
        of: usize,
        /// The first of them, 0-based sample index.
        first_sample: usize,
    },
    /// Samples at a full scale: the sensor clipped.
    Saturated {
        /// The channel.
        channel: String,
        /// The full scale reached, in the channel's unit (rad/s, m/s²).
        full_scale: f64,
        /// The full scale as datasheets give it (`2000 °/s`, `16 g`).
        full_scale_label: String,
        /// Samples at it.
        samples: usize,
    },
    /// The accelerometer's norm at rest is far from g.
    AccelNorm {
        /// Norm of the mean specific force over the static windows, m/s².
        norm: f64,
        /// g, m/s².
        gravity: f64,
    },
    /// The sensor moved.
    Motion(Motion),
}

/// Where a record moves and what shows it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Motion {
    /// Moving stretches, (start, end) in seconds from the first sample.
    pub stretches: Vec<(f64, f64)>,
    /// Seconds moving.
    pub moving_s: f64,
    /// Seconds checked.
    pub total_s: f64,
    /// The channel with the strongest sign of it.
    pub channel: String,
    /// The largest window standard deviation of that channel, its unit.
    pub max_window_std: f64,
    /// The largest unexplained step of its window means, or (a gyro) the
    /// largest departure of a window's mean from the windows around it,
    /// its unit.
    pub max_level_change: f64,
    /// Its noise floor: the standard deviation of its quiet windows.
    pub noise_floor: f64,
}

impl Motion {
    /// Whether the record moves all along (no stretch left to analyse).
    pub fn throughout(&self) -> bool {
        self.moving_s >= self.total_s * 0.999
    }
}

impl fmt::Display for Finding {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Finding::Stuck {
                channel,
                value,
                samples,
                of,
                first_sample,
            } => {
                let at = if *value == 0.0 {
                    "zero".to_string()
                } else {
                    format!("{value}")
                };
                if samples == of {
                    write!(
                        f,
                        "{channel} is stuck at {at} in all {of} samples: the sensor is dead or not read"
                    )
                } else {
                    write!(
                        f,
                        "{channel} holds {at} in {samples} of {of} samples from sample {first_sample}: stuck there"
                    )
                }
            }
            Finding::Saturated {
                channel,
                full_scale_label,
                samples,
                ..
            } => write!(
                f,
                "{channel} is saturated: {samples} samples at its ±{full_scale_label} full scale"
            ),
            Finding::AccelNorm { norm, gravity } => write!(
                f,
                "the accelerometer's norm at rest is {norm:.3} m/s², not g ({gravity:.3} m/s²): its unit or scale is wrong"
            ),
            Finding::Motion(m) => {
                let shown: Vec<String> = m
                    .stretches
                    .iter()
                    .take(3)
                    .map(|(a, b)| format!("{a:.1}–{b:.1} s"))
                    .collect();
                let more = m.stretches.len().saturating_sub(3);
                write!(
                    f,
                    "the sensor moves: {:.1} of {:.1} s in {} stretch{} ({}{}); {}: window std up to {:.3e}, \
                     level steps up to {:.3e}, against a noise floor of {:.3e}",
                    m.moving_s,
                    m.total_s,
                    m.stretches.len(),
                    if m.stretches.len() == 1 { "" } else { "es" },
                    shown.join(", "),
                    if more > 0 {
                        format!(", … {more} more")
                    } else {
                        String::new()
                    },
                    m.channel,
                    m.max_window_std,
                    m.max_level_change,
                    m.noise_floor
                )
            }
        }
    }
}

/// What the checks found in one recording.
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct Checks {
    /// Each finding, in channel order, motion last.
    pub findings: Vec<Finding>,
}

/// A record an analysis of a static sensor cannot take.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CheckError {
    /// The sensor moved.
    #[error("{0}; an analysis of a static sensor cannot take it")]
    Moving(Motion),
    /// A channel to analyse is stuck.
    #[error("{0}; no noise can be read from it")]
    Stuck(Finding),
}

impl fmt::Display for Motion {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        Finding::Motion(self.clone()).fmt(f)
    }
}

impl Checks {
    /// The motion found, if any.
    pub fn motion(&self) -> Option<&Motion> {
        self.findings.iter().find_map(|f| match f {
            Finding::Motion(m) => Some(m),
            _ => None,
        })
    }

    /// The channels found stuck over all their samples.
    pub fn dead(&self) -> impl Iterator<Item = &Finding> {
        self.findings
            .iter()
            .filter(|f| matches!(f, Finding::Stuck { samples, of, .. } if samples == of))
    }

    /// Refuses a moving record unless `allow_motion`, and any of `channels`
    /// stuck over all its samples.
    pub fn require_static(&self, channels: &[&str], allow_motion: bool) -> Result<(), CheckError> {
        if let Some(f) = self.dead().find(|f| match f {
            Finding::Stuck { channel, .. } => channels.contains(&channel.as_str()),
            _ => false,
        }) {
            return Err(CheckError::Stuck(f.clone()));
        }
        match self.motion() {
            Some(m) if !allow_motion => Err(CheckError::Moving(m.clone())),
            _ => Ok(()),
        }
    }
}

/// Mean and standard deviation of the finite values, with their count.
fn mean_std(v: &[f64]) -> (f64, f64, usize) {
    let (mut n, mut mean, mut m2) = (0usize, 0.0, 0.0);
    for &x in v.iter().filter(|x| x.is_finite()) {
        n += 1;
        let d = x - mean;
        mean += d / n as f64;
        m2 += d * (x - mean);
    }
    let std = if n > 1 { (m2 / (n - 1) as f64).sqrt() } else { 0.0 };
    (mean, std, n)
}

/// The longest run of one repeated value over the finite samples (gaps do
/// not break it): (value, samples, first sample, finite samples).
fn longest_repeat(v: &[f64]) -> Option<(f64, usize, usize, usize)> {
    let mut best: Option<(f64, usize, usize)> = None;
    let mut cur: Option<(f64, usize, usize)> = None;
    let mut finite = 0;
    for (i, &x) in v.iter().enumerate() {
        if !x.is_finite() {
            continue;
        }
        finite += 1;
        cur = match cur {
            Some((y, n, s)) if y.to_bits() == x.to_bits() || (y == 0.0 && x == 0.0) => Some((y, n + 1, s)),
            _ => Some((x, 1, i)),
        };
        if let Some(c) = cur
            && best.is_none_or(|b| c.1 > b.1)
        {
            best = Some(c);
        }
    }
    best.map(|(y, n, s)| (y, n, s, finite))
}

/// A temperature of exactly 0 °C in every sample: a field the logger left
/// at zero (a sensor not read), not a chamber held at the freezing point,
/// whose readings would scatter by the sensor's resolution.
fn temperature_not_read(t: &imu::Channel) -> Option<Finding> {
    stuck(&t.name, &t.data)
        .filter(|f| matches!(f, Finding::Stuck { value, samples, of, .. } if *value == 0.0 && samples == of))
}

fn stuck(name: &str, v: &[f64]) -> Option<Finding> {
    let (value, samples, first, of) = longest_repeat(v)?;
    let whole = samples == of && of >= 2;
    (whole || (samples >= MIN_STUCK_SAMPLES && samples as f64 >= STUCK_SHARE * of as f64)).then(|| {
        Finding::Stuck {
            channel: name.to_string(),
            value,
            samples,
            of,
            first_sample: first,
        }
    })
}

fn saturated(name: &str, q: Quantity, v: &[f64]) -> Option<Finding> {
    let peak = v
        .iter()
        .filter(|x| x.is_finite())
        .fold(0.0f64, |m, x| m.max(x.abs()));
    let (scales, unit, si): (&[f64], &str, f64) = match q {
        Quantity::AngularRate => (&GYRO_FULL_SCALES_DPS, "°/s", std::f64::consts::PI / 180.0),
        Quantity::Acceleration => (&ACCEL_FULL_SCALES_G, "g", STANDARD_GRAVITY),
        _ => return None,
    };
    // The full scale the peak sits on: within a percent below it (int16
    // and scale factors), or a little above (an offset or a calibration
    // applied after the clip).
    let (scale, fs) = scales
        .iter()
        .map(|s| (*s, s * si))
        .find(|(_, fs)| peak >= AT_FULL_SCALE * fs && peak <= 1.02 * fs)?;
    let at = v
        .iter()
        .filter(|x| x.is_finite() && x.abs() >= AT_FULL_SCALE * fs)
        .count();
    // One sample touching a full scale is a peak; a clip holds it.
    (at >= 2).then(|| Finding::Saturated {
        channel: name.to_string(),
        full_scale: fs,
        full_scale_label: format!("{scale} {unit}"),
        samples: at,
    })
}

/// Per-window (mean, std) over windows of `w` samples with at least half
/// their samples finite; NaN for the others.
fn windows(v: &[f64], w: usize) -> Vec<(f64, f64)> {
    v.chunks(w)
        .map(|c| {
            let (m, s, n) = mean_std(c);
            if n * 2 >= w { (m, s) } else { (f64::NAN, f64::NAN) }
        })
        .collect()
}

/// The `p`-quantile of the finite values.
fn quantile(v: &[f64], p: f64) -> Option<f64> {
    let mut s: Vec<f64> = v.iter().copied().filter(|x| x.is_finite()).collect();
    if s.is_empty() {
        return None;
    }
    let k = ((s.len() - 1) as f64 * p).round() as usize;
    Some(*s.select_nth_unstable_by(k, f64::total_cmp).1)
}

/// One channel's motion verdict per window, with its figures.
struct ChannelMotion {
    moving: Vec<bool>,
    floor: f64,
    max_std: f64,
    max_step: f64,
    /// How far beyond its limits the worst window goes (to pick the
    /// channel that shows the motion best).
    excess: f64,
}

fn channel_motion(q: Quantity, v: &[f64], w: usize, rate_hz: f64) -> Option<ChannelMotion> {
    let win = windows(v, w);
    // The quiet windows' level, over the windows that vary at all: a few
    // windows of one repeated value must not make every other one look
    // loud, and a channel stuck throughout (reported as such) has none.
    let varying: Vec<f64> = win.iter().map(|x| x.1).filter(|s| *s > 0.0).collect();
    if varying.len() * 2 < win.len() {
        return None;
    }
    let floor = quantile(&varying, 0.1)?;
    let mut moving = vec![false; win.len()];
    let mut excess: f64 = 0.0;
    let mut max_std: f64 = 0.0;
    if floor > max_floor(q) {
        moving.iter_mut().for_each(|m| *m = true);
        excess = floor / max_floor(q);
    }
    for (k, &(_, s)) in win.iter().enumerate() {
        if s.is_finite() {
            max_std = max_std.max(s);
            if s > VARIANCE_FACTOR * floor {
                moving[k] = true;
                excess = excess.max(s / (VARIANCE_FACTOR * floor));
            }
        }
    }
    // A gyro turning holds a rate away from its bias for as long as it
    // turns: each window's mean against the median of the windows around
    // it (a minute each side, over which a thermal drift stays small).
    // An accelerometer tilted stays at its new level at rest, so only its
    // steps count.
    let mut max_offset: f64 = 0.0;
    if q == Quantity::AngularRate {
        let means: Vec<f64> = win.iter().map(|x| x.0).collect();
        let reach = (60.0 * rate_hz / w as f64).ceil() as usize;
        let limit = (LEVEL_FACTOR * floor).max(min_level_change(q));
        for k in 0..means.len() {
            if !means[k].is_finite() {
                continue;
            }
            let lo = k.saturating_sub(reach);
            let hi = (k + reach + 1).min(means.len());
            let Some(base) = quantile(&means[lo..hi], 0.5) else {
                continue;
            };
            let off = (means[k] - base).abs();
            max_offset = max_offset.max(off);
            if off > limit {
                moving[k] = true;
                excess = excess.max(off / limit);
            }
        }
    }
    // Steps of the means, less what the neighbouring steps share (a drift).
    let steps: Vec<f64> = win.windows(2).map(|p| p[1].0 - p[0].0).collect();
    let limit = (LEVEL_FACTOR * floor).max(min_level_change(q));
    let mut max_step: f64 = 0.0;
    for k in 0..steps.len() {
        let around: Vec<f64> = [k.checked_sub(1), Some(k + 1)]
            .into_iter()
            .flatten()
            .filter_map(|j| steps.get(j).copied())
            .filter(|s| s.is_finite())
            .collect();
        if !steps[k].is_finite() {
            continue;
        }
        let drift = if around.is_empty() {
            0.0
        } else {
            around.iter().sum::<f64>() / around.len() as f64
        };
        // A drift is a trend the neighbours share in sign; a step's own
        // neighbours do not explain it.
        let drift = if drift.signum() == steps[k].signum() {
            drift.abs().min(steps[k].abs())
        } else {
            0.0
        };
        let jump = steps[k].abs() - drift;
        max_step = max_step.max(jump);
        if jump > limit {
            moving[k] = true;
            moving[k + 1] = true;
            excess = excess.max(jump / limit);
        }
    }
    Some(ChannelMotion {
        moving,
        floor,
        max_std,
        max_step: max_step.max(max_offset),
        excess,
    })
}

fn motion(rec: &Recording, rate_hz: f64) -> Option<Motion> {
    let w = window_len(rate_hz);
    let n = rec.len();
    let n_windows = n.div_ceil(w);
    if n_windows < MIN_WINDOWS {
        return None;
    }
    let mut moving = vec![false; n_windows];
    let mut worst: Option<(f64, &str, ChannelMotion)> = None;
    for c in rec.inertial() {
        let Some(cm) = channel_motion(c.quantity, &c.data, w, rate_hz) else {
            continue;
        };
        for (m, c) in moving.iter_mut().zip(&cm.moving) {
            *m |= *c;
        }
        if cm.excess > 0.0 && worst.as_ref().is_none_or(|(e, _, _)| cm.excess > *e) {
            worst = Some((cm.excess, c.name.as_str(), cm));
        }
    }
    let (_, channel, cm) = worst?;
    let dt = 1.0 / rate_hz;
    let mut stretches: Vec<(f64, f64)> = Vec::new();
    for (k, &m) in moving.iter().enumerate() {
        if !m {
            continue;
        }
        let (a, b) = ((k * w) as f64 * dt, (((k + 1) * w).min(n)) as f64 * dt);
        match stretches.last_mut() {
            Some(last) if last.1 >= a => last.1 = b,
            _ => stretches.push((a, b)),
        }
    }
    Some(Motion {
        moving_s: stretches.iter().map(|(a, b)| b - a).sum(),
        total_s: n as f64 * dt,
        stretches,
        channel: channel.to_string(),
        max_window_std: cm.max_std,
        max_level_change: cm.max_step,
        noise_floor: cm.floor,
    })
}

/// The static accelerometer's norm: the mean of each axis over the windows
/// not `moving`, when the recording has all three axes.
fn accel_norm(rec: &Recording, static_windows: Option<(&[bool], usize)>) -> Option<f64> {
    let axes = rec.of_quantity(Quantity::Acceleration);
    let axes: Vec<_> = imu::Axis::ALL
        .iter()
        .filter_map(|a| axes.iter().find(|c| c.axis == Some(*a)))
        .collect();
    if axes.len() != 3 {
        return None;
    }
    let mut sq = 0.0;
    for c in axes {
        let (m, _, n) = match static_windows {
            Some((moving, w)) => {
                let kept: Vec<f64> = c
                    .data
                    .chunks(w)
                    .zip(moving)
                    .filter(|(_, m)| !**m)
                    .flat_map(|(d, _)| d.iter().copied())
                    .collect();
                mean_std(&kept)
            }
            None => mean_std(&c.data),
        };
        if n == 0 {
            return None;
        }
        sq += m * m;
    }
    Some(sq.sqrt())
}

/// Checks a recording's inertial channels (SI units: rad/s, m/s²).
pub fn check(rec: &Recording) -> Checks {
    let rate = rec.rate_hz.filter(|r| r.is_finite() && *r > 0.0).unwrap_or(1.0);
    let mut findings = Vec::new();
    for c in rec.inertial() {
        if let Some(f) = stuck(&c.name, &c.data) {
            findings.push(f);
        }
        if let Some(f) = saturated(&c.name, c.quantity, &c.data) {
            findings.push(f);
        }
    }
    findings.extend(rec.temperature().and_then(temperature_not_read));
    let motion = motion(rec, rate);
    let w = window_len(rate);
    let moving: Option<Vec<bool>> = motion.as_ref().map(|m| {
        (0..rec.len().div_ceil(w))
            .map(|k| {
                let t = (k * w) as f64 / rate;
                m.stretches.iter().any(|(a, b)| t >= a - 1e-9 && t < *b - 1e-9)
            })
            .collect()
    });
    let all_moving = moving.as_ref().is_some_and(|m| m.iter().all(|x| *x));
    if !all_moving
        && let Some(norm) = accel_norm(rec, moving.as_deref().map(|m| (m, w)))
        && (norm - STANDARD_GRAVITY).abs() > NORM_TOLERANCE
    {
        findings.push(Finding::AccelNorm {
            norm,
            gravity: STANDARD_GRAVITY,
        });
    }
    if let Some(m) = motion {
        findings.push(Finding::Motion(m));
    }
    Checks { findings }
}

#[cfg(test)]
mod tests {
    use super::*;
    use imu::{Axis, Channel};

    /// A static IMU at `rate` Hz: white noise of `gyro_sd` rad/s and
    /// `accel_sd` m/s² per sample, g on z (a fixed pseudo-random sequence).
    fn static_rec(n: usize, rate: f64, gyro_sd: f64, accel_sd: f64) -> Recording {
        let mut uniform = allan::work::uniform(0x2545_f491_4f6c_dd1d);
        // Sum of 12 uniforms less 6: unit variance, near-normal.
        let mut noise = move || uniform.by_ref().take(12).sum::<f64>() - 6.0;
        let mut channels = Vec::new();
        for (q, sd, bias) in [
            (Quantity::Acceleration, accel_sd, [0.1, -0.2, STANDARD_GRAVITY]),
            (Quantity::AngularRate, gyro_sd, [1e-3, -2e-3, 5e-4]),
        ] {
            for (i, a) in Axis::ALL.into_iter().enumerate() {
                let data = (0..n).map(|_| bias[i] + sd * noise()).collect();
                channels.push(Channel::inertial(q, a, data));
            }
        }
        Recording {
            channels,
            rate_hz: Some(rate),
            ..Default::default()
        }
    }

    fn channel<'a>(rec: &'a mut Recording, name: &str) -> &'a mut Vec<f64> {
        &mut rec.channels.iter_mut().find(|c| c.name == name).unwrap().data
    }

    #[test]
    fn a_static_record_passes_even_with_a_thermal_drift() {
        let mut rec = static_rec(20_000, 100.0, 2e-3, 2e-2);
        assert_eq!(check(&rec).findings, []);
        // A bias drifting 0.02 rad/s and 0.3 m/s² over 200 s, along a
        // cooling curve: fast first, slow after.
        for (name, span) in [("gyro_x", 0.02), ("accel_z", 0.3)] {
            for (k, v) in channel(&mut rec, name).iter_mut().enumerate() {
                *v += span * (-(k as f64) / 3000.0).exp();
            }
        }
        assert_eq!(check(&rec).findings, []);
    }

    #[test]
    fn a_temperature_stuck_at_zero_is_not_read() {
        let mut rec = static_rec(2000, 50.0, 2e-3, 2e-2);
        rec.channels.push(Channel::temperature(vec![0.0; 2000]));
        let found: Vec<String> = check(&rec).findings.iter().map(|f| f.to_string()).collect();
        assert_eq!(
            found,
            ["temp is stuck at zero in all 2000 samples: the sensor is dead or not read"]
        );
        // Held at one other reading, or at zero for a while: a temperature.
        rec.channels.pop();
        rec.channels.push(Channel::temperature(vec![25.0; 2000]));
        assert_eq!(check(&rec).findings, []);
        rec.channels.pop();
        let mut t = vec![0.0; 2000];
        t[1999] = 0.003;
        rec.channels.push(Channel::temperature(t));
        assert_eq!(check(&rec).findings, []);
    }

    #[test]
    fn a_dead_gyro_is_stuck_at_zero() {
        let mut rec = static_rec(8578, 50.0, 2e-3, 2e-2);
        for g in ["gyro_x", "gyro_y", "gyro_z"] {
            channel(&mut rec, g).iter_mut().for_each(|v| *v = 0.0);
        }
        let c = check(&rec);
        let stuck: Vec<String> = c.dead().map(|f| f.to_string()).collect();
        assert_eq!(stuck.len(), 3, "{:?}", c.findings);
        assert!(
            stuck[0].starts_with("gyro_x is stuck at zero in all 8578 samples"),
            "{}",
            stuck[0]
        );
        assert!(c.motion().is_none(), "{:?}", c.findings);
        assert!(matches!(
            c.require_static(&["gyro_y"], true),
            Err(CheckError::Stuck(Finding::Stuck { ref channel, .. })) if channel == "gyro_y"
        ));
        assert!(c.require_static(&["accel_x"], false).is_ok());
    }

    #[test]
    fn an_accelerometer_of_norm_3_38_is_not_g() {
        let mut rec = static_rec(5000, 100.0, 2e-3, 2e-2);
        // The real case: a static log whose accelerometer reads 3.38 m/s².
        let scale = 3.38
            / rec.channels[..3]
                .iter()
                .map(|c| mean_std(&c.data).0.powi(2))
                .sum::<f64>()
                .sqrt();
        for c in &mut rec.channels[..3] {
            c.data.iter_mut().for_each(|v| *v *= scale);
        }
        let c = check(&rec);
        match c.findings.as_slice() {
            [Finding::AccelNorm { norm, .. }] => assert!((norm - 3.38).abs() < 0.01, "{norm}"),
            f => panic!("{f:?}"),
        }
        assert!(c.findings[0].to_string().contains("3.380 m/s²"));
    }

    #[test]
    fn a_clipped_gyro_is_saturated_at_its_full_scale() {
        let mut rec = static_rec(5000, 100.0, 2e-3, 2e-2);
        let fs = 2000.0f64.to_radians() * 32767.0 / 32768.0;
        let g = channel(&mut rec, "gyro_z");
        for v in &mut g[1000..1100] {
            *v = fs;
        }
        let c = check(&rec);
        assert!(
            c.findings.iter().any(
                |f| matches!(f, Finding::Saturated { channel, samples: 100, full_scale_label, .. }
                if channel == "gyro_z" && full_scale_label == "2000 °/s")
            ),
            "{:?}",
            c.findings
        );
        // and a clip is motion too.
        assert!(c.motion().is_some());
    }

    #[test]
    fn a_driving_robot_moves_throughout_and_is_refused() {
        // A robot driving: the gyro scatters by 0.1 rad/s (the real bag).
        let rec = static_rec(6000, 100.0, 0.1, 0.8);
        let c = check(&rec);
        let m = c.motion().expect("motion");
        assert!(m.throughout(), "{m:?}");
        assert!(matches!(c.require_static(&[], false), Err(CheckError::Moving(_))));
        assert!(c.require_static(&[], true).is_ok());
        // Moving all along, no norm is claimed.
        assert!(!c.findings.iter().any(|f| matches!(f, Finding::AccelNorm { .. })));
    }

    #[test]
    fn a_turn_and_a_tilt_are_found_where_they_are() {
        let mut rec = static_rec(30_000, 100.0, 2e-3, 2e-2);
        // A turn at 0.3 rad/s from 100 s to 110 s; a tilt of 5° at 200 s.
        for v in &mut channel(&mut rec, "gyro_z")[10_000..11_000] {
            *v += 0.3;
        }
        let tilt = 5f64.to_radians();
        for v in &mut channel(&mut rec, "accel_x")[20_000..] {
            *v += STANDARD_GRAVITY * tilt.sin();
        }
        let c = check(&rec);
        let m = c.motion().expect("motion");
        assert_eq!(m.stretches.len(), 2, "{m:?}");
        assert!(m.stretches[0].0 >= 98.0 && m.stretches[0].1 <= 112.0, "{m:?}");
        assert!(m.stretches[1].0 >= 198.0 && m.stretches[1].1 <= 202.0, "{m:?}");
        assert!(!m.throughout());
        assert!(c.to_owned().findings.len() == 1, "{:?}", c.findings);
    }

    #[test]
    fn a_record_moving_half_the_time_keeps_the_floor_of_its_static_half() {
        let mut rec = static_rec(12_000, 100.0, 2e-3, 2e-2);
        let moving = static_rec(6000, 100.0, 0.1, 0.8);
        for (c, m) in rec.channels.iter_mut().zip(&moving.channels) {
            for (v, w) in c.data[3000..9000].iter_mut().zip(&m.data) {
                *v = *w;
            }
        }
        let c = check(&rec);
        let m = c.motion().expect("motion");
        assert_eq!(m.stretches.len(), 1, "{m:?}");
        assert!(m.stretches[0].0 >= 29.0 && m.stretches[0].1 <= 91.0, "{m:?}");
        // The floor is the static half's (2e-3 rad/s or 2e-2 m/s² per sample).
        let static_sd = if m.channel.starts_with("gyro") { 2e-3 } else { 2e-2 };
        assert!(m.noise_floor < 1.2 * static_sd, "{m:?}");
    }

    #[test]
    fn quantized_noise_is_not_stuck_nor_moving() {
        // A gyro of 1 LSB noise, most samples on one code: repeats, but
        // never over half of the record in one run.
        let mut rec = static_rec(10_000, 100.0, 2e-3, 2e-2);
        let lsb = 1.3e-4;
        for v in channel(&mut rec, "gyro_x") {
            *v = (*v / lsb / 10.0).round() * lsb;
        }
        assert_eq!(check(&rec).findings, []);
    }
}
