//! What a column's name says it measures, in the ways IMU loggers name
//! their columns: the thesis's `mpu_gyro_1`, `gx`, `gyro_x`, `wx`,
//! `omega_x`, `rate_x`, ROS's `angular_velocity.x` (sensor_msgs/Imu as
//! `rostopic echo -p` flattens it), `ax`, `acc_x`, `fx`,
//! `linear_acceleration.x`, `temp`, `imu_temp`, `die_temp`, and time
//! columns `t`, `time`, `timestamp`, `stamp`, `sec`, `seconds`.

use crate::recording::Axis;
use crate::units::Quantity;

/// A name in lower case with `.`, `-` and spaces as `_`, and without a
/// leading `%` or `field.` (as `rostopic echo -p` writes them).
fn normalise(name: &str) -> String {
    let lower: String = name
        .trim()
        .to_ascii_lowercase()
        .chars()
        .map(|c| {
            if matches!(c, '.' | '-' | ' ' | '/') {
                '_'
            } else {
                c
            }
        })
        .collect();
    let lower = lower.trim_start_matches('%');
    lower.strip_prefix("field_").unwrap_or(lower).to_string()
}

/// The axis a name ends in (`x`/`1` …), and the stem before it without a
/// trailing `_`.
fn axis_of(n: &str) -> Option<(Axis, &str)> {
    let axis = match n.chars().last()? {
        '1' | 'x' => Axis::X,
        '2' | 'y' => Axis::Y,
        '3' | 'z' => Axis::Z,
        _ => return None,
    };
    Some((axis, n[..n.len() - 1].trim_end_matches('_')))
}

/// Whether the name is one of a time column's.
pub fn is_time_name(name: &str) -> bool {
    let n = normalise(name);
    matches!(
        n.as_str(),
        "t" | "time" | "timestamp" | "time_stamp" | "stamp" | "sec" | "secs" | "seconds" | "header_stamp"
    )
}

/// The quantity (and axis) a name says, or `None` when it says none.
///
/// ```
/// use imu::names::quantity_of_name;
/// use imu::{Axis, Quantity};
/// assert_eq!(quantity_of_name("angular_velocity.x"), Some((Quantity::AngularRate, Some(Axis::X))));
/// assert_eq!(quantity_of_name("fz"), Some((Quantity::Acceleration, Some(Axis::Z))));
/// assert_eq!(quantity_of_name("die_temp"), Some((Quantity::Temperature, None)));
/// assert_eq!(quantity_of_name("pressure"), None);
/// ```
pub fn quantity_of_name(name: &str) -> Option<(Quantity, Option<Axis>)> {
    let n = normalise(name);
    if is_time_name(&n) {
        return Some((Quantity::Time, None));
    }
    if n.starts_with("temp") || n.ends_with("temp") || n.contains("temperature") {
        return Some((Quantity::Temperature, None));
    }
    // Bookkeeping beside the samples in the same record (PX4's
    // `gyro_integral_dt`, `accelerometer_timestamp_relative`, counters) is
    // no inertial axis, whatever sensor its name starts with.
    let bookkeeping = [
        "dt",
        "time",
        "timestamp",
        "stamp",
        "relative",
        "integral",
        "count",
        "clipping",
        "status",
        "id",
    ];
    if n.split('_').any(|t| bookkeeping.contains(&t)) {
        return None;
    }
    let (axis, stem) = match axis_of(&n) {
        Some((a, s)) => (Some(a), s),
        None => (None, n.as_str()),
    };
    let gyro_stems = [
        "g",
        "w",
        "omega",
        "rate",
        "angular_velocity",
        "angular_rate",
        "gyr",
        "gyro",
    ];
    let accel_stems = ["a", "f", "acc", "accel", "linear_acceleration", "specific_force"];
    let ends_with_stem = |stems: &[&str]| {
        stems
            .iter()
            .any(|s| stem == *s || stem.ends_with(&format!("_{s}")))
    };
    let gyro = n.contains("gyr") || (axis.is_some() && ends_with_stem(&gyro_stems));
    let accel = n.contains("acc") || (axis.is_some() && ends_with_stem(&accel_stems));
    match (gyro, accel) {
        (true, false) => Some((Quantity::AngularRate, axis)),
        (false, true) => Some((Quantity::Acceleration, axis)),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_loggers_use() {
        let gyro = |a| Some((Quantity::AngularRate, Some(a)));
        let accel = |a| Some((Quantity::Acceleration, Some(a)));
        for (name, want) in [
            ("mpu_gyro_1", gyro(Axis::X)),
            ("gx", gyro(Axis::X)),
            ("gyr_y", gyro(Axis::Y)),
            ("wz", gyro(Axis::Z)),
            ("omega_x", gyro(Axis::X)),
            ("rate_y", gyro(Axis::Y)),
            ("field.angular_velocity.z", gyro(Axis::Z)),
            ("mpu_accel_3", accel(Axis::Z)),
            ("ax", accel(Axis::X)),
            ("accel_y", accel(Axis::Y)),
            ("fx", accel(Axis::X)),
            ("linear_acceleration.y", accel(Axis::Y)),
            ("imu_temp", Some((Quantity::Temperature, None))),
            ("Temperature", Some((Quantity::Temperature, None))),
            ("%time", Some((Quantity::Time, None))),
            ("stamp", Some((Quantity::Time, None))),
            ("x", None),
            ("sample_rate", None),
            ("host_time", None),
            ("gyro_integral_dt", None),
            ("accelerometer_timestamp_relative", None),
        ] {
            assert_eq!(quantity_of_name(name), want, "{name}");
        }
    }
}
