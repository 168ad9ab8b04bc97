//! Small fixtures, written here, each standing for a real log that misled
//! imutherm once, and what it must say of it now: a dead gyro, an
//! accelerometer reading 3.38 m/s², a driving robot, ArduPilot 3.4's
//! `Temp` and 3.2's `TimeMS`, an FMUv5 clock with unlogged messages, a
//! 32-bit µs counter that wraps, a clock that runs backwards; and the
//! clocks of PX4's real sample logs.
//!
//! The DataFlash logs follow ArduPilot's LogStructure.h of their version:
//! the `FMT` message (type 128, `BBnNZ`, 89 bytes) and the `IMU` message
//! as 3.2 (`Iffffff`, `TimeMS,GyrX,GyrY,GyrZ,AccX,AccY,AccZ`) and 3.3 to
//! 3.6 (`QffffffIIfBB`, `TimeUS,GyrX,…,AccZ,ErrG,ErrA,Temp,GyHlt,AcHlt`)
//! write it.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use predicates::prelude::*;

mod support;
use support::{Refused, cli, imutherm, json_stdout, stderr_of, succeed};

const G: f64 = 9.80665;

/// Near-normal noise of unit variance from a fixed seed (sum of 12
/// uniforms less 6).
fn noise(seed: u64) -> impl FnMut() -> f64 {
    let mut s = seed | 1;
    move || {
        (0..12)
            .map(|_| {
                s ^= s << 13;
                s ^= s >> 7;
                s ^= s << 17;
                (s >> 11) as f64 / (1u64 << 53) as f64
            })
            .sum::<f64>()
            - 6.0
    }
}

/// One `FMT` message describing message `ty`.
fn df_fmt(ty: u8, length: u8, name: &str, format: &str, labels: &str) -> Vec<u8> {
    let mut m = vec![0xA3, 0x95, 128, ty, length];
    let mut field = |s: &str, n: usize| {
        let mut b = s.as_bytes().to_vec();
        b.resize(n, 0);
        m.extend(b);
    };
    field(name, 4);
    field(format, 16);
    field(labels, 64);
    assert_eq!(m.len(), 89);
    m
}

/// The two `IMU` layouts: ArduCopter 3.2 (`TimeMS`, no temperature) and
/// 3.3 to 3.6 (`TimeUS`, `Temp`).
#[derive(Clone, Copy)]
enum DfLayout {
    Copter32,
    Copter34,
}

/// A DataFlash log of `IMU` messages: (time s, gyro, accel, temperature).
fn dataflash(path: &Path, layout: DfLayout, rows: &[(f64, [f64; 3], [f64; 3], f64)]) {
    const IMU: u8 = 131;
    let mut out = df_fmt(128, 89, "FMT", "BBnNZ", "Type,Length,Name,Format,Columns");
    out.extend(match layout {
        DfLayout::Copter32 => df_fmt(IMU, 31, "IMU", "Iffffff", "TimeMS,GyrX,GyrY,GyrZ,AccX,AccY,AccZ"),
        DfLayout::Copter34 => df_fmt(
            IMU,
            49,
            "IMU",
            "QffffffIIfBB",
            "TimeUS,GyrX,GyrY,GyrZ,AccX,AccY,AccZ,ErrG,ErrA,Temp,GyHlt,AcHlt",
        ),
    });
    for (t, g, a, temp) in rows {
        out.extend([0xA3, 0x95, IMU]);
        match layout {
            DfLayout::Copter32 => out.extend(((t * 1e3).round() as u32).to_le_bytes()),
            DfLayout::Copter34 => out.extend(((t * 1e6).round() as u64).to_le_bytes()),
        }
        for v in g.iter().chain(a) {
            out.extend((*v as f32).to_le_bytes());
        }
        if let DfLayout::Copter34 = layout {
            out.extend(0u32.to_le_bytes());
            out.extend(0u32.to_le_bytes());
            out.extend((*temp as f32).to_le_bytes());
            out.extend([1, 1]);
        }
    }
    std::fs::write(path, out).unwrap();
}

/// A static IMU at `rate` Hz for `n` samples: gyro white noise 2e-3 rad/s,
/// accelerometer 2e-2 m/s², g on z, a temperature ramp from 28.3 to 35.6 °C.
fn static_rows(n: usize, rate: f64, seed: u64) -> Vec<(f64, [f64; 3], [f64; 3], f64)> {
    let mut e = noise(seed);
    (0..n)
        .map(|k| {
            let g = [2e-3 * e(), 2e-3 * e(), 2e-3 * e()];
            let a = [0.05 + 2e-2 * e(), -0.03 + 2e-2 * e(), G + 2e-2 * e()];
            (
                10.0 + k as f64 / rate,
                g,
                a,
                28.3 + 7.3 * k as f64 / (n - 1) as f64,
            )
        })
        .collect()
}

/// A table with a time column `time_header` (values as given) and the six
/// inertial axes in SI.
fn table(path: &Path, time_header: &str, times: &[String], rows: &[(f64, [f64; 3], [f64; 3], f64)]) {
    let mut s = format!("{time_header},accel_x,accel_y,accel_z,gyro_x,gyro_y,gyro_z\n");
    for (t, (_, g, a, _)) in times.iter().zip(rows) {
        writeln!(s, "{t},{},{},{},{},{},{}", a[0], a[1], a[2], g[0], g[1], g[2]).unwrap();
    }
    std::fs::write(path, s).unwrap();
}

fn info(path: &Path) -> serde_json::Value {
    let doc = json_stdout(imutherm().args(["info", "--json"]).arg(path));
    doc["files"][0].clone()
}

fn kinds(f: &serde_json::Value) -> Vec<String> {
    f["checks"]["findings"]
        .as_array()
        .unwrap()
        .iter()
        .map(|x| x["kind"].as_str().unwrap().to_string())
        .collect()
}

fn dir() -> (tempfile::TempDir, PathBuf) {
    let d = tempfile::tempdir().unwrap();
    let p = d.path().to_path_buf();
    (d, p)
}

#[test]
fn a_dead_gyro_is_reported_and_noise_refuses_it() {
    // The real log: three gyros reading exactly 0.0 in all 8,578 messages.
    let (_d, dir) = dir();
    let path = dir.join("dead_gyro.bin");
    let mut rows = static_rows(8578, 50.0, 1);
    rows.iter_mut().for_each(|r| r.1 = [0.0; 3]);
    dataflash(&path, DfLayout::Copter34, &rows);
    let f = info(&path);
    assert_eq!(kinds(&f), ["stuck", "stuck", "stuck"]);
    let stuck = &f["checks"]["findings"][0];
    assert_eq!(
        (stuck["channel"].as_str(), stuck["value"].as_f64()),
        (Some("gyro_x"), Some(0.0))
    );
    assert_eq!(
        (stuck["samples"].as_u64(), stuck["of"].as_u64()),
        (Some(8578), Some(8578))
    );
    imutherm().arg("info").arg(&path).assert().success().stdout(
        predicate::str::contains("problems     3").and(predicate::str::contains(
            "gyro_x is stuck at zero in all 8578 samples",
        )),
    );
    cli!["noise", &path].refused(1, "gyro_x is stuck at zero in all 8578 samples");
    // Navigation prints its figures, never without the warning.
    let out = succeed(imutherm().args(["ins", "--horizon", "60"]).arg(&path));
    assert!(stderr_of(&out).contains("warning:") && stderr_of(&out).contains("gyro_z is stuck at zero"));
}

#[test]
fn an_accelerometer_of_3_38_m_s2_is_not_g() {
    // The real log: static, the accelerometer's norm 3.38 m/s².
    let (_d, dir) = dir();
    let path = dir.join("accel_3_38.csv");
    let mut rows = static_rows(20_000, 100.0, 2);
    let scale = 3.38 / G;
    for r in &mut rows {
        r.2.iter_mut().for_each(|v| *v *= scale);
    }
    let times: Vec<String> = rows.iter().map(|r| format!("{:.2}", r.0)).collect();
    table(&path, "time", &times, &rows);
    let f = info(&path);
    assert_eq!(kinds(&f), ["accel_norm"]);
    let norm = f["checks"]["findings"][0]["norm"].as_f64().unwrap();
    assert!((norm - 3.38).abs() < 0.01, "{norm}");
    let out = succeed(imutherm().args(["ins", "--horizon", "60"]).arg(&path));
    assert!(
        stderr_of(&out).contains("the accelerometer's norm at rest is 3.38"),
        "{}",
        stderr_of(&out)
    );
}

#[test]
fn a_driving_robot_is_refused_by_noise_and_ins_unless_allowed() {
    // The real bag: a robot driving, its gyro scattering by 0.1 rad/s.
    let (_d, dir) = dir();
    let path = dir.join("driving_robot.csv");
    let mut e = noise(3);
    let rows: Vec<_> = (0..12_000)
        .map(|k| {
            let turn = 0.3 * (k as f64 / 700.0).sin();
            let g = [0.1 * e(), 0.1 * e(), turn + 0.1 * e()];
            let a = [0.8 * e(), 0.8 * e(), G + 0.8 * e()];
            (k as f64 / 100.0, g, a, 25.0)
        })
        .collect();
    let times: Vec<String> = rows.iter().map(|r| format!("{:.2}", r.0)).collect();
    table(&path, "time", &times, &rows);
    let f = info(&path);
    assert_eq!(kinds(&f), ["motion"]);
    let m = &f["checks"]["findings"][0];
    assert!(m["moving_s"].as_f64().unwrap() >= 0.999 * m["total_s"].as_f64().unwrap());
    for cmd in [
        &["noise"][..],
        &["ins", "--horizon", "60"],
        &["tcal", "fit", "-o"],
    ] {
        let mut c = imutherm();
        c.args(cmd);
        if cmd[0] == "tcal" {
            c.arg(dir.join("model.json"));
        }
        c.arg(&path).assert().code(1).stdout("").stderr(
            predicate::str::contains("the sensor moves").and(predicate::str::contains("--allow-motion")),
        );
    }
    assert!(!dir.join("model.json").exists());
    let out = succeed(imutherm().args(["noise", "--allow-motion"]).arg(&path));
    assert!(stderr_of(&out).contains("analysed as if static though it moves"));
}

#[test]
fn arducopter_3_4_names_its_temperature_temp() {
    let (_d, dir) = dir();
    let path = dir.join("arducopter_3_4.bin");
    dataflash(&path, DfLayout::Copter34, &static_rows(3000, 50.0, 4));
    let f = info(&path);
    let t = &f["temperature_c"];
    assert!((t["min"].as_f64().unwrap() - 28.3).abs() < 1e-4, "{t}");
    assert!((t["max"].as_f64().unwrap() - 35.6).abs() < 1e-4, "{t}");
    assert_eq!(kinds(&f), Vec::<String>::new());
    let meta: Vec<(String, String)> = serde_json::from_value(f["log_metadata"].clone()).unwrap();
    assert!(
        meta.contains(&("time_source".into(), "TimeUS".into())),
        "{meta:?}"
    );
}

#[test]
fn arducopter_3_2_stamps_in_milliseconds_and_says_so() {
    let (_d, dir) = dir();
    let path = dir.join("arducopter_3_2.bin");
    dataflash(&path, DfLayout::Copter32, &static_rows(3000, 50.0, 5));
    let f = info(&path);
    let meta: Vec<(String, String)> = serde_json::from_value(f["log_metadata"].clone()).unwrap();
    assert!(
        meta.contains(&("time_source".into(), "TimeMS".into())),
        "{meta:?}"
    );
    assert_eq!(f["rate_hz"].as_f64().map(|r| (r * 1e6).round() / 1e6), Some(50.0));
    // 3.2 logs no temperature in IMU: none, truly.
    assert!(f["temperature_c"].is_null());
    assert!(
        (f["duration_s"].as_f64().unwrap() - 60.0).abs() < 1e-9,
        "{}",
        f["duration_s"]
    );
}

/// A PXF log (erle-robotics, copter 23-9-2014/53.BIN) logs IMU only part
/// of the time: 866 messages at 50 Hz over a 131 s span. The stream table
/// once gave the mean over the span (6.59 Hz) beside `rate 50 Hz`; it now
/// gives the rate between messages, the clock's, and says the gaps.
#[test]
fn a_stream_logged_part_of_the_time_shows_its_rate_and_its_gaps() {
    let (_d, dir) = dir();
    let path = dir.join("partly_logged.bin");
    // 25 Hz for 40 s, nothing for 340 s, 25 Hz for 40 s: 420 s in all.
    let rows = static_rows(2000, 25.0, 9);
    let rows: Vec<_> = rows[..1000]
        .iter()
        .cloned()
        .chain(rows[1000..].iter().map(|r| (r.0 + 340.0, r.1, r.2, r.3)))
        .collect();
    dataflash(&path, DfLayout::Copter34, &rows);
    let f = info(&path);
    let imu = &f["streams"][0];
    let span = rows.last().unwrap().0 - rows[0].0;
    assert!(
        (imu["rate_hz"].as_f64().unwrap() - 1999.0 / span).abs() < 1e-6,
        "{imu}"
    );
    assert!(
        (imu["step_rate_hz"].as_f64().unwrap() - 25.0).abs() < 1e-6,
        "{imu}"
    );
    let text = String::from_utf8(succeed(&mut cli!["info", &path]).stdout).unwrap();
    let row = text.lines().find(|l| l.starts_with("  read IMU/0")).unwrap();
    assert!(row.contains(" 25 Hz"), "{text}");
    assert!(
        text.contains(
            "IMU/0 logs at 25 Hz for about 19 % of its 420.0 s (4.75998 Hz on average): the rest are gaps"
        ),
        "{text}"
    );
    assert!(text.contains("  rate         25 Hz"), "{text}");
}

#[test]
fn an_fmuv5_clock_with_unlogged_messages_keeps_its_rate() {
    // sensor_combined as an FMUv5 logged it: 5 ms steps, with stretches
    // of 4.5 ms ones (20 in every 100 here: a true mean step of 4.9 ms),
    // 101 messages not logged. The clock fit once dropped the 4.5 ms
    // steps: on this file it said 203.57 Hz for 204.07, and a duration of
    // 9.005 s for 1838 slots (9.029 s at its own rate).
    let (_d, dir) = dir();
    let path = dir.join("fmuv5_sensor_combined.csv");
    let mut t_us: Vec<f64> = (0..1737 + 101)
        .scan(1_000_000.0, |now, k| {
            *now += if k % 100 >= 80 { 4500.0 } else { 5000.0 };
            Some(*now)
        })
        .collect();
    let mut s = 0x9e37_79b9_7f4a_7c15u64;
    for _ in 0..101 {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        let k = 1 + (s % (t_us.len() as u64 - 2)) as usize;
        t_us.remove(k);
    }
    assert_eq!(t_us.len(), 1737);
    let rows = static_rows(t_us.len(), 200.0, 7);
    let times: Vec<String> = t_us.iter().map(|t| format!("{t:.0}")).collect();
    table(&path, "timestamp[us]", &times, &rows);
    let f = info(&path);
    // The mean gap-free step, read here: every step under 7 ms.
    let steps: Vec<f64> = t_us
        .windows(2)
        .map(|w| (w[1] - w[0]) * 1e-6)
        .filter(|d| *d < 7e-3)
        .collect();
    let mean_step = steps.iter().sum::<f64>() / steps.len() as f64;
    let rate = f["rate_hz"].as_f64().unwrap();
    assert!(
        (rate * mean_step - 1.0).abs() < 0.002,
        "{rate} Hz against a mean step of {mean_step} s"
    );
    // The unlogged messages are gaps (their steps, 9 to 10 ms, are sums
    // of two, too few at any one value to be a step the publisher makes).
    let gaps = f["problems"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|p| p["kind"] == "time_gap")
        .map(|p| p["count"].as_u64().unwrap())
        .sum::<u64>();
    assert_eq!(gaps, 101);
    assert_eq!(f["samples"].as_u64(), Some(1737 + gaps));
    // Steps of 4.5 and 5 ms are no one clock's: the duration is the
    // stamps' span, not the slots over the mean rate.
    assert_eq!(f["clock"]["pattern"]["kind"], "irregular");
    let duration = f["duration_s"].as_f64().unwrap();
    let span = (t_us[t_us.len() - 1] - t_us[0]) * 1e-6;
    assert!((duration - span).abs() < 1e-9, "{duration} against {span}");
}

#[test]
fn a_micros_counter_wrapping_at_71_6_min_is_unwrapped_and_said() {
    // An Arduino's micros() at 100 Hz, 60 s around its wrap at 2^32 µs.
    let (_d, dir) = dir();
    let path = dir.join("micros_wrap.csv");
    let start = 4_294_967_296u64 - 30_000_000;
    let rows = static_rows(6000, 100.0, 8);
    let times: Vec<String> = (0..rows.len() as u64)
        .map(|k| ((start + k * 10_000) % 4_294_967_296).to_string())
        .collect();
    table(&path, "time_us", &times, &rows);
    let f = info(&path);
    assert_eq!(
        f["rate_hz"].as_f64().map(|r| (r * 1e6).round() / 1e6),
        Some(100.0)
    );
    assert_eq!(f["problems"].as_array().unwrap().len(), 0, "{}", f["problems"]);
    assert!((f["duration_s"].as_f64().unwrap() - 60.0).abs() < 1e-9);
    let notes = f["notes"].to_string();
    // The header is on line 1: the wrap is at row 3000, line 3002.
    assert!(
        notes.contains("32-bit counter") && notes.contains("line 3002: unwrapped"),
        "{notes}"
    );
}

#[test]
fn a_clock_running_backwards_is_refused_with_its_line() {
    // The real file: a time column from 50 s down to 0.01 s.
    let (_d, dir) = dir();
    let path = dir.join("backwards_clock.csv");
    let rows = static_rows(5000, 100.0, 9);
    let times: Vec<String> = (0..rows.len())
        .map(|k| format!("{:.2}", 50.0 - k as f64 * 0.01))
        .collect();
    table(&path, "time", &times, &rows);
    cli!["info", &path].assert().code(1).stdout("").stderr(
        predicate::str::contains("backwards_clock.csv:3: column 1")
            .and(predicate::str::contains("runs backwards")),
    );
}

#[test]
fn real_px4_clocks_run_at_their_mean_gap_free_step() {
    // PX4/pyulog's sample logs (BSD-3, in robotlogs' fixtures). The rates
    // are pyulog 1.3.0's sensor_combined timestamps read with NumPy 2.4: the mean of
    // the steps within (0.5, 1.5) of that mean, iterated from the median.
    let px4 = Path::new(env!("CARGO_MANIFEST_DIR")).join("../robotlogs/tests/fixtures/px4");
    for (file, rate) in [
        ("sample_log_small.ulg", 204.582_619_096_366_73),
        ("sample_appended_multiple.ulg", 247.039_744_629_699_9),
        ("sample_logging_tagged_and_default_params.ulg", 250.0),
    ] {
        let f = info(&px4.join(file));
        let r = f["rate_hz"].as_f64().unwrap();
        assert!((r / rate - 1.0).abs() < 1e-9, "{file}: {r} Hz, not {rate}");
        // The slots over the rate, or for a publisher on several steps
        // (sample_appended_multiple: 4 and 4.8 ms) the stamps' span.
        let slots = f["samples"].as_f64().unwrap();
        let duration = match f["clock"]["pattern"]["span_s"].as_f64() {
            Some(span) => span,
            None => slots / r,
        };
        assert_eq!(
            f["clock"].get("pattern").is_some(),
            file == "sample_appended_multiple.ulg",
            "{file}"
        );
        assert!(
            (f["duration_s"].as_f64().unwrap() - duration).abs() < 1e-9,
            "{file}"
        );
    }
}
