//! Column headers: a name with an optional unit in brackets, as the thesis
//! log writes them (`mpu_gyro_1[rad/s]`).

/// Splits `name[unit]` into its name and unit; a header without brackets has
/// an empty unit. Whitespace around both parts is dropped.
///
/// ```
/// assert_eq!(imu::header::split_name_unit("mpu_gyro_1[rad/s]"), ("mpu_gyro_1", "rad/s"));
/// assert_eq!(imu::header::split_name_unit(" col1 "), ("col1", ""));
/// ```
pub fn split_name_unit(header: &str) -> (&str, &str) {
    let h = header.trim();
    match (h.find('['), h.ends_with(']')) {
        (Some(open), true) if open > 0 => (h[..open].trim(), h[open + 1..h.len() - 1].trim()),
        _ => (h, ""),
    }
}

#[cfg(test)]
mod tests {
    use super::split_name_unit;

    #[test]
    fn splits_thesis_headers() {
        assert_eq!(split_name_unit("mpu_accel_1[m/^2]"), ("mpu_accel_1", "m/^2"));
        assert_eq!(split_name_unit("temp [degC]"), ("temp", "degC"));
        assert_eq!(split_name_unit("[odd]"), ("[odd]", ""));
        assert_eq!(split_name_unit("a[b"), ("a[b", ""));
    }
}
