//! Headers as real loggers and people write them: each case names where
//! that convention is found. The expected SI values are worked out by hand
//! from the unit (1 °/s = π/180 rad/s, 1 g = 9.80665 m/s², 0 °C = 273.15 K).

use std::f64::consts::PI;
use std::path::PathBuf;

use imu::{Quantity, RecordingOptions, UnitSource, read_recording, read_recording_with_report};

mod common;
use common::{assert_no_note, assert_note};

fn file(dir: &tempfile::TempDir, name: &str, text: &str) -> PathBuf {
    let p = dir.path().join(name);
    std::fs::write(&p, text).unwrap();
    p
}

/// (case, header, body row, channel, expected SI value, source of unit)
const CASES: &[(&str, &str, &str, &str, f64, UnitSource)] = &[
    (
        "thesis log brackets",
        "mpu_gyro_1[deg/s]",
        "180",
        "gyro_x",
        PI,
        UnitSource::Header,
    ),
    (
        "spreadsheet parentheses",
        "gyro_y (deg/s)",
        "90",
        "gyro_y",
        PI / 2.0,
        UnitSource::Header,
    ),
    (
        "ADIS16405 export _dps",
        "gyro_x_dps",
        "180",
        "gyro_x",
        PI,
        UnitSource::Header,
    ),
    ("_degps", "gx_degps", "180", "gyro_x", PI, UnitSource::Header),
    ("_deg_s", "gyr_z_deg_s", "-180", "gyro_z", -PI, UnitSource::Header),
    ("_rads", "wx_rads", "0.5", "gyro_x", 0.5, UnitSource::Header),
    (
        "_rad_s",
        "omega_y_rad_s",
        "0.5",
        "gyro_y",
        0.5,
        UnitSource::Header,
    ),
    ("_radps", "rate_z_radps", "0.5", "gyro_z", 0.5, UnitSource::Header),
    (
        "ADIS16405 export _g",
        "acc_x_g",
        "1",
        "accel_x",
        9.80665,
        UnitSource::Header,
    ),
    ("_mg", "ay_mg", "1000", "accel_y", 9.80665, UnitSource::Header),
    ("_mps2", "accel_z_mps2", "9.5", "accel_z", 9.5, UnitSource::Header),
    ("_m_s2", "fx_m_s2", "9.5", "accel_x", 9.5, UnitSource::Header),
    ("_ms2", "acc_y_ms2", "9.5", "accel_y", 9.5, UnitSource::Header),
    ("_degc", "imu_temp_degc", "30", "temp", 30.0, UnitSource::Header),
    ("_c", "die_temp_c", "30", "temp", 30.0, UnitSource::Header),
    (
        "_k",
        "temperature_k",
        "300",
        "temp",
        300.0 - 273.15,
        UnitSource::Header,
    ),
    (
        "degF converted",
        "temp[degF]",
        "212",
        "temp",
        100.0,
        UnitSource::Header,
    ),
    (
        "ROS sensor_msgs/Imu, rostopic echo -p",
        "field.angular_velocity.x",
        "0.25",
        "gyro_x",
        0.25,
        UnitSource::Assumed,
    ),
    (
        "ROS linear_acceleration",
        "linear_acceleration.z",
        "9.8",
        "accel_z",
        9.8,
        UnitSource::Assumed,
    ),
    (
        "Excel UTF-8 with BOM",
        "\u{feff}gyro_x[deg/s]",
        "180",
        "gyro_x",
        PI,
        UnitSource::Header,
    ),
    (
        "quoted cells (pandas quoting=ALL)",
        "\"acc_z (g)\"",
        "1",
        "accel_z",
        9.80665,
        UnitSource::Header,
    ),
];

#[test]
fn headers_in_real_world_conventions() {
    let dir = tempfile::tempdir().unwrap();
    for (i, (case, header, row, channel, si, source)) in CASES.iter().enumerate() {
        // A second column keeps the file from being a single column of
        // numbers without a header.
        let p = file(
            &dir,
            &format!("h{i}.csv"),
            &format!("{header},other\n{row},0\n{row},0\n"),
        );
        let rec = read_recording(&p, &RecordingOptions::default()).unwrap_or_else(|e| panic!("{case}: {e}"));
        let ch = rec
            .channel(channel)
            .unwrap_or_else(|| panic!("{case}: no {channel} in {:?}", rec.channels));
        assert!((ch.data[0] - si).abs() < 1e-12, "{case}: {} ≠ {si}", ch.data[0]);
        assert_eq!(ch.unit_source, *source, "{case}");
    }
}

#[test]
fn adis16405_csv_from_smac_imudata() {
    // The header of the static ADIS16405 run as a user converts it to CSV:
    // t_s is the time axis (not a channel), °/s and g are converted.
    let dir = tempfile::tempdir().unwrap();
    let mut text = String::from("t_s,gyro_x_dps,gyro_y_dps,gyro_z_dps,acc_x_g,acc_y_g,acc_z_g\n");
    for k in 0..500 {
        text.push_str(&format!("{:.2},0.1,0.2,0.3,0.0,0.0,1.0\n", k as f64 * 0.01));
    }
    let p = file(&dir, "adis.csv", &text);
    let (rec, report) = read_recording_with_report(&p, &RecordingOptions::default()).unwrap();
    assert!((rec.rate_hz.unwrap() - 100.0).abs() < 0.05, "{:?}", rec.rate_hz);
    assert!(rec.channel("t").is_none() && rec.channel("t_s").is_none());
    assert_eq!(rec.inertial().len(), 6);
    assert!((rec.channel("gyro_x").unwrap().data[0] - 0.1 * PI / 180.0).abs() < 1e-15);
    assert!((rec.channel("accel_z").unwrap().data[0] - 9.80665).abs() < 1e-12);
    assert_no_note(&report, "looks like");
}

#[test]
fn an_accelerometer_in_g_without_a_unit_is_flagged() {
    // A phone app's export: ax, ay, az in g with no unit anywhere.
    let dir = tempfile::tempdir().unwrap();
    let p = file(&dir, "phone.csv", "ax,ay,az\n0.01,0.02,0.99\n0.01,0.02,1.01\n");
    let (rec, report) = read_recording_with_report(&p, &RecordingOptions::default()).unwrap();
    assert_eq!(rec.channel("accel_z").unwrap().unit_source, UnitSource::Assumed);
    assert_note(&report, "looks like g");
    let p = file(&dir, "mg.csv", "ax,ay,az\n10,20,990\n10,20,1010\n");
    let (_, report) = read_recording_with_report(&p, &RecordingOptions::default()).unwrap();
    assert_note(&report, "looks like mg");
}

#[test]
fn unknown_units_and_missing_columns_are_errors() {
    let dir = tempfile::tempdir().unwrap();
    let p = file(&dir, "foo.csv", "gyro_x[foo],b\n1,2\n");
    let e = read_recording(&p, &RecordingOptions::default())
        .unwrap_err()
        .to_string();
    assert!(e.contains("gyro_x[foo]") && e.contains("foo"), "{e}");
    // A column imutherm does not know keeps its own unit.
    let p = file(&dir, "p.csv", "pressure[hPa],gx\n1013,0\n");
    let rec = read_recording(&p, &RecordingOptions::default()).unwrap();
    assert_eq!(rec.channel("pressure").unwrap().quantity, Quantity::Other);
    let opts = RecordingOptions {
        units: vec!["gyro_q=deg/s".parse().unwrap()],
        ..RecordingOptions::default()
    };
    let e = read_recording(&p, &opts).unwrap_err().to_string();
    assert!(e.contains("gyro_q"), "{e}");
    let opts = RecordingOptions {
        units: vec!["gx=deg/s".parse().unwrap()],
        ..RecordingOptions::default()
    };
    let rec = read_recording(&p, &opts).unwrap();
    assert_eq!(rec.channel("gyro_x").unwrap().unit_source, UnitSource::Flag);
}

#[test]
fn units_written_in_the_metadata() {
    let dir = tempfile::tempdir().unwrap();
    let p = file(&dir, "m.txt", "# unit.gx: deg/s\ngx,gy\n180,0\n");
    let rec = read_recording(&p, &RecordingOptions::default()).unwrap();
    let g = rec.channel("gyro_x").unwrap();
    assert_eq!(g.unit_source, UnitSource::Metadata);
    assert!((g.data[0] - PI).abs() < 1e-15);
    assert_eq!(rec.channel("gyro_y").unwrap().unit_source, UnitSource::Assumed);
}
