//! Column headers: a name with an optional unit, written the ways loggers
//! and people write them: in brackets as the thesis log does
//! (`mpu_gyro_1[rad/s]`), in parentheses (`gyro_x (deg/s)`), or as a
//! suffix (`gyro_x_dps`, `t_s`, `timestamp_us`). A UTF-8 byte order mark
//! and quotes around the cell are not part of the name.

/// The header cell without a byte order mark, surrounding quotes or
/// whitespace.
///
/// ```
/// assert_eq!(imu::header::clean_cell("\u{feff}\"gyro_x\" "), "gyro_x");
/// ```
pub fn clean_cell(cell: &str) -> &str {
    let c = cell.trim().trim_start_matches('\u{feff}').trim();
    let unquoted = ['"', '\'']
        .iter()
        .find_map(|q| c.strip_prefix(*q).and_then(|s| s.strip_suffix(*q)));
    unquoted.unwrap_or(c).trim()
}

/// Splits `name[unit]` or `name(unit)` into its name and unit; a header
/// without either has an empty unit. Whitespace around both parts is
/// dropped.
///
/// ```
/// assert_eq!(imu::header::split_name_unit("mpu_gyro_1[rad/s]"), ("mpu_gyro_1", "rad/s"));
/// assert_eq!(imu::header::split_name_unit("gyro_x (deg/s)"), ("gyro_x", "deg/s"));
/// assert_eq!(imu::header::split_name_unit(" col1 "), ("col1", ""));
/// ```
pub fn split_name_unit(header: &str) -> (&str, &str) {
    let h = clean_cell(header);
    for (open, close) in [('[', ']'), ('(', ')')] {
        if let (Some(at), true) = (h.rfind(open), h.ends_with(close))
            && at > 0
        {
            return (h[..at].trim(), h[at + 1..h.len() - 1].trim());
        }
    }
    (h, "")
}

/// Unit suffixes after an underscore, longest first so that `_rad_s` is
/// not read as `_s`. Each is a unit text [`crate::units::parse_unit`]
/// knows.
const SUFFIXES: &[(&str, &str)] = &[
    ("_deg_s", "deg/s"),
    ("_rad_s", "rad/s"),
    ("_m_s2", "m/s^2"),
    ("_degps", "deg/s"),
    ("_radps", "rad/s"),
    ("_mps2", "m/s^2"),
    ("_degc", "degC"),
    ("_degf", "degF"),
    ("_rads", "rad/s"),
    ("_ms2", "m/s^2"),
    ("_dps", "deg/s"),
    // PX4's uORB fields: `gyro_rad` is in rad/s.
    ("_rad", "rad/s"),
    ("_mg", "mg"),
    ("_ms", "ms"),
    ("_us", "us"),
    ("_ns", "ns"),
    ("_g", "g"),
    ("_c", "degC"),
    ("_k", "K"),
    ("_s", "s"),
];

/// Splits a unit suffix off a name (`gyro_x_dps` → `gyro_x`, `deg/s`),
/// or `None` when the name ends in none.
///
/// ```
/// assert_eq!(imu::header::split_unit_suffix("t_s"), Some(("t", "s")));
/// assert_eq!(imu::header::split_unit_suffix("gyro_x"), None);
/// ```
pub fn split_unit_suffix(name: &str) -> Option<(&str, &'static str)> {
    let lower = name.to_ascii_lowercase();
    SUFFIXES.iter().find_map(|(suffix, unit)| {
        (lower.len() > suffix.len() && lower.ends_with(suffix))
            .then(|| (&name[..name.len() - suffix.len()], *unit))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn splits_thesis_headers() {
        assert_eq!(split_name_unit("mpu_accel_1[m/^2]"), ("mpu_accel_1", "m/^2"));
        assert_eq!(split_name_unit("temp [degC]"), ("temp", "degC"));
        assert_eq!(split_name_unit("[odd]"), ("[odd]", ""));
        assert_eq!(split_name_unit("a[b"), ("a[b", ""));
    }

    #[test]
    fn reads_parentheses_quotes_and_a_bom() {
        assert_eq!(split_name_unit("\u{feff}\"acc_x (g)\""), ("acc_x", "g"));
        assert_eq!(split_name_unit("'temp'"), ("temp", ""));
        assert_eq!(split_unit_suffix("gyro_z_rad_s"), Some(("gyro_z", "rad/s")));
        assert_eq!(split_unit_suffix("timestamp_us"), Some(("timestamp", "us")));
        assert_eq!(split_unit_suffix("_s"), None);
    }
}
