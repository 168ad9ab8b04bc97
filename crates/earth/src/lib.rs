//! # earth — the rotating Earth a static sensor sits on
//!
//! The rotating Earth a static sensor sits on: WGS-84's rotation rate,
//! radii and normal gravity (NIMA TR8350.2, 3rd ed., 2000: Table 3.1 for the
//! defining constants, Table 3.3 and eq. 4-1 for Somigliana's formula).
//!
//! Frames: the local-level frame is x north, y west, z up, so that a level
//! sensor facing north (its z up, reading +1 g, as the MPU-9250 does face
//! up) has the identity attitude. Heading is clockwise from north, as a
//! compass reads it.
//!
//! Both the simulator (what a sensor at rest reads) and the navigation
//! (what the strapdown subtracts) take their gravity, Earth rate and frame
//! from here, so the two cannot disagree.
//!
//! Without its default `std` feature only the constants are compiled, for
//! a `no_std` driver that needs g (the functions need `std`'s
//! trigonometry).
//!
//! **What it is not:** no geoid, no height above the ellipsoid, no gravity
//! anomaly model: a bench on the ellipsoid at a known latitude.
//!
//! ```
//! // Normal gravity: 9.7803 m/s² at the equator, 9.8322 at the poles.
//! assert!((earth::normal_gravity(0.0) - 9.780_325_335_9).abs() < 1e-9);
//! let pole = earth::normal_gravity(std::f64::consts::FRAC_PI_2);
//! assert!((pole - 9.832_184_937_8).abs() < 1e-6);
//! // A level sensor facing north has the identity attitude.
//! let c = earth::body_to_level(0.0, 0.0, 0.0);
//! assert_eq!(c, [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]);
//! ```

#![cfg_attr(not(feature = "std"), no_std)]
#![deny(missing_docs)]

/// Standard gravity, m/s²: the conventional value of the 3rd CGPM (1901),
/// the "g" of every datasheet's mg and LSB/g, of ArduPilot's `GRAVITY_MSS`
/// and of PX4's `CONSTANTS_ONE_G`. Not the local gravity, which
/// [`normal_gravity`] gives.
pub const STANDARD_GRAVITY: f64 = 9.806_65;

/// Earth's rotation rate, rad/s (WGS-84, Table 3.1).
pub const EARTH_RATE: f64 = 7.292_115e-5;
/// Semi-major axis, m (WGS-84, Table 3.1).
pub const SEMI_MAJOR_AXIS: f64 = 6_378_137.0;
/// First eccentricity squared (WGS-84, Table 3.3).
pub const ECCENTRICITY_SQUARED: f64 = 6.694_379_990_14e-3;
/// Normal gravity at the equator, m/s² (WGS-84, Table 3.3).
pub const GAMMA_EQUATOR: f64 = 9.780_325_335_9;
/// Somigliana's constant k = b·γ_p/(a·γ_e) − 1 (WGS-84, Table 3.3).
pub const SOMIGLIANA_K: f64 = 1.931_852_652_41e-3;

/// Normal gravity on the ellipsoid at geodetic latitude `lat` (radians),
/// m/s²: Somigliana's closed formula (TR8350.2 eq. 4-1). It includes the
/// centrifugal part, so it is what a static accelerometer reads.
#[cfg(feature = "std")]
pub fn normal_gravity(lat: f64) -> f64 {
    let s2 = lat.sin().powi(2);
    GAMMA_EQUATOR * (1.0 + SOMIGLIANA_K * s2) / (1.0 - ECCENTRICITY_SQUARED * s2).sqrt()
}

/// Meridian and prime-vertical radii of curvature at `lat`, m.
#[cfg(feature = "std")]
pub fn radii(lat: f64) -> (f64, f64) {
    let w2 = 1.0 - ECCENTRICITY_SQUARED * lat.sin().powi(2);
    let prime = SEMI_MAJOR_AXIS / w2.sqrt();
    (prime * (1.0 - ECCENTRICITY_SQUARED) / w2, prime)
}

/// Earth's rotation in the local-level frame (x north, y west, z up), rad/s.
#[cfg(feature = "std")]
pub fn earth_rate_level(lat: f64) -> [f64; 3] {
    [EARTH_RATE * lat.cos(), 0.0, EARTH_RATE * lat.sin()]
}

/// The rotation from the sensor's axes to the local-level frame for a roll,
/// pitch and heading (radians), row-major: the roll and pitch of a static
/// accelerometer's reading (x = −g·sin pitch), then the heading about the vertical
/// (clockwise from north, hence the minus sign about z up).
#[cfg(feature = "std")]
pub fn body_to_level(roll: f64, pitch: f64, heading: f64) -> [[f64; 3]; 3] {
    let (sr, cr) = roll.sin_cos();
    let (sp, cp) = pitch.sin_cos();
    let (sy, cy) = (-heading).sin_cos();
    // Rz(−heading)·Ry(pitch)·Rx(roll).
    [
        [cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
        [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
        [-sp, cp * sr, cp * cr],
    ]
}

/// What a static gyroscope reads of the Earth's rotation, rad/s per axis.
#[cfg(feature = "std")]
pub fn earth_rate_body(lat: f64, roll: f64, pitch: f64, heading: f64) -> [f64; 3] {
    let c = body_to_level(roll, pitch, heading);
    let w = earth_rate_level(lat);
    // The transpose takes the level frame to the sensor's axes.
    std::array::from_fn(|j| (0..3).map(|i| c[i][j] * w[i]).sum())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn normal_gravity_matches_wgs84() {
        // TR8350.2 Table 3.3: γ_e = 9.7803253359, γ_p = 9.8321849378 m/s².
        assert!((normal_gravity(0.0) - 9.780_325_335_9).abs() < 1e-9);
        assert!((normal_gravity(std::f64::consts::FRAC_PI_2) - 9.832_184_937_8).abs() < 1e-8);
    }

    #[test]
    fn level_attitude_is_the_identity() {
        let c = body_to_level(0.0, 0.0, 0.0);
        for (i, row) in c.iter().enumerate() {
            for (j, v) in row.iter().enumerate() {
                assert_eq!(*v, if i == j { 1.0 } else { 0.0 });
            }
        }
    }

    #[test]
    fn heading_east_puts_the_horizontal_earth_rate_on_y() {
        // Facing east, the sensor's y axis (its left) points north.
        let w = earth_rate_body(0.0, 0.0, 0.0, std::f64::consts::FRAC_PI_2);
        assert!(w[0].abs() < 1e-15 && (w[1] - EARTH_RATE).abs() < 1e-15 && w[2].abs() < 1e-15);
    }
}
