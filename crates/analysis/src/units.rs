//! The units noise terms are given in: SI, the datasheets', and the
//! thesis's (degrees for gyros).

use std::f64::consts::PI;

use allan::noise_terms::Term;
use imu::Quantity;
use imu::units::STANDARD_GRAVITY;

/// The unit systems terms are printed in.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Units {
    /// rad/√s, rad/s, rad/s/√s; m/s/√s, m/s², m/s²/√s.
    Si,
    /// What datasheets quote: °/√h, °/h; m/s/√h, µg.
    Datasheet,
    /// The thesis tables: °/√s and °/s for gyros, SI for accelerometers.
    Thesis,
}

/// The SI unit of `term` for a channel of `quantity` in `data_unit`.
pub fn si_unit(term: Term, quantity: Quantity, data_unit: &str) -> String {
    unit_of(term, quantity, data_unit, Units::Si).1
}

/// The factor from the SI value of `term` to `units`, and the unit's label.
pub fn unit_of(term: Term, quantity: Quantity, data_unit: &str, units: Units) -> (f64, String) {
    let deg = 180.0 / PI;
    let ug = 1.0 / (STANDARD_GRAVITY * 1e-6);
    let (f, label): (f64, &str) = match (quantity, units, term) {
        (Quantity::AngularRate, Units::Si, t) => match t {
            Term::Quantization => (1.0, "rad"),
            Term::WhiteNoise => (1.0, "rad/√s"),
            Term::BiasInstability => (1.0, "rad/s"),
            Term::RateRandomWalk => (1.0, "rad/s/√s"),
            Term::RateRamp => (1.0, "rad/s²"),
        },
        (Quantity::AngularRate, Units::Datasheet, t) => match t {
            Term::Quantization => (deg, "°"),
            Term::WhiteNoise => (deg * 60.0, "°/√h"),
            Term::BiasInstability => (deg * 3600.0, "°/h"),
            Term::RateRandomWalk => (deg * 216_000.0, "°/h/√h"),
            Term::RateRamp => (deg * 3600.0 * 3600.0, "°/h²"),
        },
        (Quantity::AngularRate, Units::Thesis, t) => match t {
            Term::Quantization => (deg, "°"),
            Term::WhiteNoise => (deg, "°/√s"),
            Term::BiasInstability => (deg, "°/s"),
            Term::RateRandomWalk => (deg, "°/s/√s"),
            Term::RateRamp => (deg, "°/s²"),
        },
        (Quantity::Acceleration, Units::Datasheet, t) => match t {
            Term::Quantization => (1.0, "m/s"),
            Term::WhiteNoise => (60.0, "m/s/√h"),
            Term::BiasInstability => (ug, "µg"),
            Term::RateRandomWalk => (ug, "µg/√s"),
            Term::RateRamp => (ug, "µg/s"),
        },
        (Quantity::Acceleration, _, t) => match t {
            Term::Quantization => (1.0, "m/s"),
            Term::WhiteNoise => (1.0, "m/s/√s"),
            Term::BiasInstability => (1.0, "m/s²"),
            Term::RateRandomWalk => (1.0, "m/s²/√s"),
            Term::RateRamp => (1.0, "m/s³"),
        },
        (_, _, t) => {
            let u = if data_unit.is_empty() { "1" } else { data_unit };
            let label = match t {
                Term::Quantization => format!("{u}·s"),
                Term::WhiteNoise => format!("{u}·√s"),
                Term::BiasInstability => u.to_string(),
                Term::RateRandomWalk => format!("{u}/√s"),
                Term::RateRamp => format!("{u}/s"),
            };
            return (1.0, label);
        }
    };
    (f, label.to_string())
}

/// N as the datasheets quote it (PS-MPU-9250A-01: °/s/√Hz for the gyro,
/// µg/√Hz for the accelerometer): the same number as N in per-√s units.
pub fn density_of(quantity: Quantity) -> Option<(f64, &'static str)> {
    match quantity {
        Quantity::AngularRate => Some((180.0 / PI, "°/s/√Hz")),
        Quantity::Acceleration => Some((1.0 / (STANDARD_GRAVITY * 1e-6), "µg/√Hz")),
        _ => None,
    }
}

/// Radians to degrees for angular rates, 1 otherwise: the thesis quotes
/// gyro terms in degrees.
pub fn deg(q: Quantity) -> f64 {
    if q == Quantity::AngularRate {
        180.0 / PI
    } else {
        1.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_gyro_white_noise_in_degrees_per_root_hour_is_60_times_degrees_per_root_second() {
        // IEEE 952 Annex C: N in °/√h = N in °/√s · √3600.
        let (f, label) = unit_of(Term::WhiteNoise, Quantity::AngularRate, "rad/s", Units::Datasheet);
        assert_eq!(label, "°/√h");
        assert!((f - 60.0 * 180.0 / PI).abs() < 1e-9);
        assert_eq!(si_unit(Term::BiasInstability, Quantity::Other, "V"), "V");
        assert_eq!(si_unit(Term::WhiteNoise, Quantity::Other, ""), "1·√s");
    }
}
