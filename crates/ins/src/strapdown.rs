//! Coarse alignment by levelling and the strapdown update: quaternion
//! attitude with a coning correction, velocity and position in the
//! local-level frame (x north, y west, z up, see [`earth`]) with
//! normal gravity, and, for a given latitude, the Earth's rate, the
//! transport rate and the Coriolis acceleration.
//!
//! The algorithm is the classic two-speed-free form for one sample per
//! update (Savage, *Strapdown Analytics*, 2000, §7.1.1 and §7.2.2; Titterton
//! & Weston, *Strapdown Inertial Navigation Technology*, 2nd ed., §11.2):
//! the coning term Δθ_{k−1} × Δθ_k / 12 on the attitude, the rotation term
//! Δθ × Δv / 2 on the velocity.

use crate::InsError;
use crate::quaternion::{Quat, cross};

/// The six inertial channels of a recording, in SI (rad/s, m/s²), with NaN
/// at gaps.
#[derive(Debug, Clone, Copy)]
pub struct ImuData<'a> {
    /// Gyroscope x, y, z, rad/s.
    pub gyro: [&'a [f64]; 3],
    /// Accelerometer x, y, z (specific force), m/s².
    pub accel: [&'a [f64]; 3],
    /// Sample rate, Hz.
    pub rate_hz: f64,
}

impl ImuData<'_> {
    /// Samples in the shortest channel.
    pub fn len(&self) -> usize {
        self.gyro
            .iter()
            .chain(&self.accel)
            .map(|c| c.len())
            .min()
            .unwrap_or(0)
    }

    /// Whether there is no sample.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    #[inline]
    fn sample(&self, i: usize) -> ([f64; 3], [f64; 3]) {
        (
            [self.gyro[0][i], self.gyro[1][i], self.gyro[2][i]],
            [self.accel[0][i], self.accel[1][i], self.accel[2][i]],
        )
    }

    /// Whether samples `range` are all finite (a window across a gap is not
    /// navigated: a NaN would poison it, a zero would be a false input).
    pub fn finite(&self, range: std::ops::Range<usize>) -> bool {
        self.gyro
            .iter()
            .chain(&self.accel)
            .all(|c| c[range.clone()].iter().all(|v| v.is_finite()))
    }
}

/// How a window is aligned and navigated.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NavOptions {
    /// Length of the alignment window, s.
    pub align_s: f64,
    /// Geodetic latitude, degrees: normal gravity for it, and the Earth's
    /// rate, the transport rate and Coriolis. Without it, standard gravity
    /// and a non-rotating Earth.
    pub latitude_deg: Option<f64>,
    /// Take the gyro's mean over the alignment window (less the Earth's
    /// rate, when the latitude is known) as its bias, as a filter at rest
    /// does: without it the turn-on bias of a MEMS gyro (±30 °/s over
    /// temperature, PS-MPU-9250A-01 §3.1) swamps every other term.
    pub remove_gyro_bias: bool,
}

impl Default for NavOptions {
    fn default() -> Self {
        NavOptions {
            align_s: 10.0,
            latitude_deg: None,
            remove_gyro_bias: true,
        }
    }
}

impl NavOptions {
    /// Checks the options; an error names the wrong one.
    pub fn validate(&self) -> Result<(), InsError> {
        if !(self.align_s.is_finite() && self.align_s > 0.0) {
            return Err(InsError::Invalid(format!(
                "alignment window {} s: must be a positive number of seconds",
                self.align_s
            )));
        }
        if let Some(l) = self.latitude_deg
            && !(l.is_finite() && l.abs() <= 90.0)
        {
            return Err(InsError::Invalid(format!(
                "latitude {l}°: must be from −90 to 90 degrees"
            )));
        }
        Ok(())
    }

    /// The gravity the tilt acts through: normal gravity at the latitude,
    /// else standard gravity. (The vertical channel subtracts the window's
    /// measured magnitude instead, [`Alignment::gravity`].)
    pub fn gravity(&self) -> f64 {
        match self.latitude_deg {
            Some(l) => earth::normal_gravity(l.to_radians()),
            None => earth::STANDARD_GRAVITY,
        }
    }
}

/// The result of levelling over an alignment window.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Alignment {
    /// Roll, rad (the convention of [`earth::body_to_level`]).
    pub roll: f64,
    /// Pitch, rad.
    pub pitch: f64,
    /// The attitude, sensor to local level, heading 0.
    pub attitude: Quat,
    /// The gyro bias taken out, rad/s (zero unless
    /// [`NavOptions::remove_gyro_bias`]).
    pub gyro_bias: [f64; 3],
    /// The mean specific force's magnitude over the window, m/s²: the
    /// gravity the vertical channel subtracts. A filter at rest fixes the
    /// vertical accelerometer's bias so (or a barometer does); with a
    /// gravity model instead, a 60 mg offset of an MPU-9250 (PS-MPU-9250A-01
    /// §3.2) would move the height by a kilometre a minute and, through
    /// Coriolis, the horizontal position too.
    pub gravity: f64,
}

/// Levels on the mean specific force of samples `range`: roll and pitch
/// from its direction; heading 0 (the sensor's x is taken as north),
/// because a MEMS gyro cannot gyrocompass: the horizontal Earth rate
/// (≤ 7.3e-5 rad/s) is hundreds of times below its bias instability and
/// noise over any alignment a user waits for.
pub fn align(imu: &ImuData, range: std::ops::Range<usize>, opts: &NavOptions) -> Alignment {
    let n = range.len().max(1) as f64;
    let mean = |c: &[f64]| c[range.clone()].iter().sum::<f64>() / n;
    let f = imu.accel.map(mean);
    let roll = f[1].atan2(f[2]);
    let pitch = (-f[0]).atan2(f[1].hypot(f[2]));
    let c = earth::body_to_level(roll, pitch, 0.0);
    let attitude = Quat::from_matrix(c);
    let gyro_bias = if opts.remove_gyro_bias {
        let w = imu.gyro.map(mean);
        let e = match opts.latitude_deg {
            Some(l) => {
                let e = earth::earth_rate_level(l.to_radians());
                std::array::from_fn(|j| (0..3).map(|i| c[i][j] * e[i]).sum())
            }
            None => [0.0; 3],
        };
        std::array::from_fn(|k| w[k] - e[k])
    } else {
        [0.0; 3]
    };
    Alignment {
        roll,
        pitch,
        attitude,
        gyro_bias,
        gravity: f[0].hypot(f[1]).hypot(f[2]),
    }
}

/// What the Earth does to a navigation frame at a fixed latitude.
#[derive(Debug, Clone, Copy)]
struct RotatingEarth {
    rate: [f64; 3],
    meridian_radius: f64,
    prime_radius: f64,
    tan_lat: f64,
}

/// The state of one strapdown solution, started at rest at the origin.
#[derive(Debug, Clone)]
pub struct Navigator {
    /// Attitude, sensor to local level.
    pub attitude: Quat,
    /// Velocity in the local-level frame, m/s.
    pub velocity: [f64; 3],
    /// Position from the start, m (x north, y west, z up).
    pub position: [f64; 3],
    gyro_bias: [f64; 3],
    gravity: f64,
    dt: f64,
    previous_increment: [f64; 3],
    earth: Option<RotatingEarth>,
}

impl Navigator {
    /// A solution at rest at the origin with the alignment's attitude. The
    /// latitude is held fixed: a static drift of metres moves it by 1e-7°.
    pub fn new(alignment: &Alignment, opts: &NavOptions, rate_hz: f64) -> Navigator {
        let earth = opts.latitude_deg.map(|l| {
            let lat = l.to_radians();
            let (meridian_radius, prime_radius) = earth::radii(lat);
            RotatingEarth {
                rate: earth::earth_rate_level(lat),
                meridian_radius,
                prime_radius,
                tan_lat: lat.tan(),
            }
        });
        Navigator {
            attitude: alignment.attitude,
            velocity: [0.0; 3],
            position: [0.0; 3],
            gyro_bias: alignment.gyro_bias,
            gravity: alignment.gravity,
            dt: 1.0 / rate_hz,
            previous_increment: [0.0; 3],
            earth,
        }
    }

    /// One sample: the gyro's mean rate and the accelerometer's mean specific
    /// force over the sample interval.
    #[inline]
    pub fn step(&mut self, gyro: [f64; 3], accel: [f64; 3]) {
        let dt = self.dt;
        let dth: [f64; 3] = std::array::from_fn(|k| (gyro[k] - self.gyro_bias[k]) * dt);
        let coning = cross(self.previous_increment, dth);
        self.previous_increment = dth;
        let phi: [f64; 3] = std::array::from_fn(|k| dth[k] + coning[k] / 12.0);
        let dv: [f64; 3] = accel.map(|a| a * dt);
        let rot = cross(dth, dv);
        let dv_body: [f64; 3] = std::array::from_fn(|k| dv[k] + 0.5 * rot[k]);
        let mut dv_level = self.attitude.rotate(dv_body);
        let mut q = self.attitude.compose(Quat::from_rotation_vector(phi));
        let v = self.velocity;
        let mut acc = [0.0, 0.0, -self.gravity];
        if let Some(e) = &self.earth {
            // Transport rate of the local-level frame over the ellipsoid
            // (Titterton & Weston eq. 3.66, in x north, y west, z up).
            let rho = [
                -v[1] / e.prime_radius,
                v[0] / e.meridian_radius,
                -v[1] * e.tan_lat / e.prime_radius,
            ];
            let w_in: [f64; 3] = std::array::from_fn(|k| e.rate[k] + rho[k]);
            let zeta = w_in.map(|w| w * dt);
            q = Quat::from_rotation_vector(zeta.map(|z| -z)).compose(q);
            // The level frame turns during the interval too: the velocity
            // increment, resolved at its start, is brought to its middle
            // (Savage §7.2.2.2, the −½·ζ × Δv term). On a sensor at rest
            // it cancels the rotation term above, which would otherwise
            // read the Earth's rate as a 3e-6 m/s² acceleration.
            let turn = cross(zeta, dv_level);
            for k in 0..3 {
                dv_level[k] -= 0.5 * turn[k];
            }
            let c = cross(std::array::from_fn(|k| 2.0 * e.rate[k] + rho[k]), v);
            for k in 0..3 {
                acc[k] -= c[k];
            }
        }
        self.attitude = q.normalized();
        for k in 0..3 {
            let nv = v[k] + dv_level[k] + acc[k] * dt;
            self.position[k] += 0.5 * (v[k] + nv) * dt;
            self.velocity[k] = nv;
        }
    }
}

/// The error of a static solution against the truth (at rest, where it
/// started, in the attitude it was aligned in).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StaticError {
    /// Time since alignment, s.
    pub t_s: f64,
    /// Horizontal distance from the start, m.
    pub horizontal_position_m: f64,
    /// Horizontal speed, m/s.
    pub horizontal_velocity_m_s: f64,
    /// Height above the start, unsigned, m. The vertical channel has no
    /// gravity gradient, so none of the instability of a real one (2g/R).
    pub vertical_position_m: f64,
    /// Rotation about the horizontal axes since alignment, rad.
    pub tilt_rad: f64,
    /// Rotation about the vertical since alignment, rad.
    pub heading_rad: f64,
}

impl Navigator {
    /// The error against the static truth, `initial` being the aligned
    /// attitude (the truth's attitude does not change: the attitude error
    /// grown since alignment is the change of the solution's).
    pub fn static_error(&self, initial: Quat, t_s: f64) -> StaticError {
        let r = self.attitude.compose(initial.conj()).rotation_vector();
        StaticError {
            t_s,
            horizontal_position_m: self.position[0].hypot(self.position[1]),
            horizontal_velocity_m_s: self.velocity[0].hypot(self.velocity[1]),
            vertical_position_m: self.position[2].abs(),
            tilt_rad: r[0].hypot(r[1]),
            heading_rad: r[2].abs(),
        }
    }
}

/// Aligns on the first `opts.align_s` seconds from sample `start`, then
/// navigates and reports the error at each time of `times_s` (seconds since
/// alignment, ascending). None when the window runs past the data or
/// crosses a gap.
pub fn navigate_window(
    imu: &ImuData,
    start: usize,
    opts: &NavOptions,
    times_s: &[f64],
) -> Option<Vec<StaticError>> {
    let na = align_samples(opts.align_s, imu.rate_hz);
    let steps: Vec<usize> = times_s
        .iter()
        .map(|&t| (t * imu.rate_hz).round() as usize)
        .collect();
    let last = steps.iter().copied().max().unwrap_or(0);
    let end = start + na + last;
    if end > imu.len() || !imu.finite(start..end) {
        return None;
    }
    let alignment = align(imu, start..start + na, opts);
    let mut nav = Navigator::new(&alignment, opts, imu.rate_hz);
    let mut out = Vec::with_capacity(times_s.len());
    let mut done = 0;
    for (&k, &t) in steps.iter().zip(times_s) {
        while done < k {
            let (w, f) = imu.sample(start + na + done);
            nav.step(w, f);
            done += 1;
        }
        out.push(nav.static_error(alignment.attitude, t));
    }
    Some(out)
}

/// Samples in an alignment window of `align_s` seconds (at least one).
pub fn align_samples(align_s: f64, rate_hz: f64) -> usize {
    ((align_s * rate_hz).round() as usize).max(1)
}
