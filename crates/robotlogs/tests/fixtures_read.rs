//! The committed fixtures, read and checked against what their writers
//! hold: `truth.json` is written by `make_fixtures.py` from the samples it
//! gave to `rosbags`/`mcap` and from pymavlink's DFReader; `px4/
//! expected.json` is pyulog's reading of PX4's sample logs.

// Axes are compared by index with the JSON arrays.
#![allow(clippy::needless_range_loop)]

use std::path::{Path, PathBuf};

use imu::{ProblemKind, Recording, RecordingOptions};
use robotlogs::{Choice, LogErrorKind};
use serde_json::Value;

fn fixture(p: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fixtures")
        .join(p)
}

fn json(p: &str) -> Value {
    serde_json::from_str(&std::fs::read_to_string(fixture(p)).unwrap()).unwrap()
}

fn read(p: &str, choice: &Choice) -> robotlogs::Read {
    robotlogs::read(&fixture(p), &RecordingOptions::default(), choice).unwrap_or_else(|e| panic!("{p}: {e}"))
}

fn f64s(v: &Value) -> Vec<f64> {
    v.as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect()
}

/// accel x, y, z then gyro x, y, z, the gaps left out.
fn axes(rec: &Recording) -> Vec<Vec<f64>> {
    ["accel_x", "accel_y", "accel_z", "gyro_x", "gyro_y", "gyro_z"]
        .iter()
        .map(|n| {
            rec.channel(n)
                .unwrap()
                .data
                .iter()
                .copied()
                .filter(|v| !v.is_nan())
                .collect()
        })
        .collect()
}

fn close(a: f64, b: f64, rel: f64) -> bool {
    (a - b).abs() <= rel * a.abs().max(b.abs()).max(1e-9)
}

#[test]
fn every_ros_storage_gives_the_samples_the_writer_was_given() {
    let truth = &json("ros/truth.json")["static_5s"];
    let n = truth["messages"].as_u64().unwrap() as usize;
    for f in [
        "ros/imu_zstd.mcap",
        "ros/imu_lz4_big_endian.mcap",
        "ros/bag_mcap",
        "ros/bag_split",
        "ros/bag_sqlite3",
        "ros/bag_sqlite3/bag_sqlite3.db3",
        "ros/imu_none.bag",
        "ros/imu_bz2.bag",
        "ros/imu_lz4.bag",
    ] {
        let r = read(f, &Choice::default());
        let ax = axes(&r.recording);
        assert_eq!(r.recording.len(), n, "{f}");
        for k in 0..6 {
            assert_eq!(ax[k].len(), n, "{f}");
            // The messages carry f64 and nothing is converted; the margin
            // is serde_json's decimal parsing (last digit), not the reader's.
            assert!(close(ax[k][0], f64s(&truth["first"])[k], 1e-15), "{f} axis {k}");
            assert!(
                close(ax[k][n - 1], f64s(&truth["last"])[k], 1e-15),
                "{f} axis {k}"
            );
            let sum: f64 = ax[k].iter().sum();
            assert!(close(sum, f64s(&truth["sum"])[k], 1e-9), "{f} axis {k}: {sum}");
        }
        let rate = r.recording.rate_hz.unwrap();
        assert!(close(rate, 200.0, 1e-6), "{f}: {rate}");
        assert_eq!(r.recording.meta.get("time_source"), Some("header stamp"), "{f}");
        // Temperature topic at 1 Hz ramping 25 → 35 °C over 5 s, matched.
        let t = &r.recording.temperature().unwrap().data;
        assert!(
            close(t[0], 25.0, 1e-9) && close(t[n - 1], 25.0 + 10.0 * 4.995 / 5.0, 1e-6),
            "{f}"
        );
        assert!(r.report.problems.is_empty(), "{f}: {:?}", r.report.problems);
    }
}

#[test]
fn zero_stamps_fall_back_to_the_bag_time_and_say_so() {
    let r = read("ros/imu_zero_stamps.mcap", &Choice::default());
    assert_eq!(r.recording.meta.get("time_source"), Some("bag time"));
    assert!(
        r.recording
            .meta
            .get("time_source_reason")
            .unwrap()
            .contains("zero, negative or NaN in every message")
    );
    assert!(close(r.recording.rate_hz.unwrap(), 200.0, 1e-6));
}

#[test]
fn a_gap_in_the_stamps_is_sized_and_reported_with_its_time() {
    let truth = &json("ros/truth.json")["gap"];
    let r = read("ros/gap.bag", &Choice::default());
    let gaps: Vec<_> = r
        .report
        .problems
        .iter()
        .filter(|p| p.kind == ProblemKind::TimeGap)
        .collect();
    assert_eq!(gaps.len(), 1, "{:?}", r.report.problems);
    assert_eq!(gaps[0].count as u64, truth["missing"].as_u64().unwrap());
    assert!(
        gaps[0]
            .message
            .contains(&format!("t = {:.6} s", truth["at_s"].as_f64().unwrap())),
        "{}",
        gaps[0].message
    );
    let after = truth["after_sample"].as_u64().unwrap() as usize;
    let gx = &r.recording.channel("gyro_x").unwrap().data;
    assert!(gx[after..after + 100].iter().all(|v| v.is_nan()));
    assert!(!gx[after - 1].is_nan() && !gx[after + 100].is_nan());
}

#[test]
fn several_imu_topics_need_a_choice_and_the_error_lists_them_with_rates() {
    let e = robotlogs::read(
        &fixture("ros/two_imus.mcap"),
        &RecordingOptions::default(),
        &Choice::default(),
    )
    .unwrap_err();
    let text = e.to_string();
    assert!(
        text.contains("choose one with the IMU topic")
            && text.contains("/imu0/data")
            && text.contains("/imu1/data"),
        "{text}"
    );
    assert!(text.contains("200 Hz") && text.contains("100 Hz"), "{text}");
    assert!(
        matches!(e, robotlogs::Error::Log(ref l) if matches!(l.kind, LogErrorKind::SeveralStreams { setting: imu::Setting::Topic, .. }))
    );
    let r = read(
        "ros/two_imus.mcap",
        &Choice {
            topic: Some("/imu1/data".into()),
            ..Choice::default()
        },
    );
    assert!(close(r.recording.rate_hz.unwrap(), 100.0, 1e-6));
    assert_eq!(r.streams.iter().filter(|s| s.kind == "imu").count(), 2);
}

#[test]
fn dataflash_reads_what_pymavlinks_dfreader_reads() {
    let truth = &json("ros/truth.json")["dataflash_dfreader"];
    for inst in [0u32, 1] {
        let t = &truth[inst.to_string()];
        let r = read(
            "ros/arducopter_imu.bin",
            &Choice {
                instance: Some(inst),
                ..Choice::default()
            },
        );
        let ax = axes(&r.recording);
        let n = t["messages"].as_u64().unwrap() as usize;
        for k in 0..6 {
            assert_eq!(ax[k].len(), n);
            // The log holds f32: DFReader widens them exactly as imutherm does.
            assert!(close(ax[k][0], f64s(&t["first"])[k], 1e-15));
            assert!(close(ax[k].iter().sum::<f64>(), f64s(&t["sum"])[k], 1e-9));
        }
        let temp = &r.recording.temperature().unwrap().data;
        let mean = temp.iter().sum::<f64>() / temp.len() as f64;
        assert!(close(mean, t["temp_mean"].as_f64().unwrap(), 1e-6));
        assert_eq!(r.recording.meta.get("instance"), Some(inst.to_string().as_str()));
    }
}

#[test]
fn px4_sample_logs_read_as_pyulog_reads_them() {
    let expected = json("px4/expected.json");
    for (file, topics) in expected.as_object().unwrap() {
        let r = read(&format!("px4/{file}"), &Choice::default());
        for (topic, e) in topics.as_object().unwrap() {
            if topic.starts_with("sensor_accel") {
                continue;
            }
            let s = r
                .streams
                .iter()
                .find(|s| &s.name == topic)
                .unwrap_or_else(|| panic!("{file}: {topic}"));
            assert_eq!(
                s.messages as u64,
                e["messages"].as_u64().unwrap(),
                "{file} {topic}"
            );
            if let Some(id) = e.get("device_id") {
                let key = format!("px4.{topic}.device_id");
                assert_eq!(
                    r.recording.meta.get(&key),
                    Some(id.to_string().as_str()),
                    "{file}"
                );
            }
        }
        // sensor_combined is read by default where the per-sensor topics
        // are not at full rate: every message a sample, none dropped.
        let e = &topics["sensor_combined"];
        assert_eq!(r.recording.meta.get("stream"), Some("sensor_combined"), "{file}");
        let ax = axes(&r.recording);
        assert_eq!(ax[3].len() as u64, e["messages"].as_u64().unwrap(), "{file}");
        for k in 0..3 {
            let sum: f64 = ax[3 + k].iter().sum();
            assert!(close(sum, f64s(&e["sum_xyz"])[k], 1e-6), "{file} gyro {k}: {sum}");
        }
    }
}

#[test]
fn px4_instances_are_chosen_by_number_and_keep_their_device_id() {
    let expected = json("px4/expected.json");
    let e = &expected["sample_log_small.ulg"]["sensor_gyro/2"];
    let r = read(
        "px4/sample_log_small.ulg",
        &Choice {
            instance: Some(2),
            ..Choice::default()
        },
    );
    assert_eq!(r.recording.meta.get("stream"), Some("sensor_gyro/2"));
    assert_eq!(
        r.recording.meta.get("device_id"),
        Some(e["device_id"].to_string().as_str())
    );
    assert!(r.recording.temperature().is_some());
}

#[test]
fn a_stream_choice_on_a_text_log_is_an_error() {
    let mut f = tempfile::NamedTempFile::new().unwrap();
    std::io::Write::write_all(&mut f, b"gyro_x\n0.1\n0.2\n").unwrap();
    let c = Choice {
        topic: Some("/imu".into()),
        ..Choice::default()
    };
    let e = robotlogs::read(f.path(), &RecordingOptions::default(), &c).unwrap_err();
    assert!(
        matches!(e, robotlogs::Error::Log(ref l) if matches!(l.kind, LogErrorKind::NotARobotLog(imu::Setting::Topic))),
        "{e}"
    );
    assert!(robotlogs::read(f.path(), &RecordingOptions::default(), &Choice::default()).is_ok());
}

#[test]
fn a_stream_choice_on_a_compressed_ulog_names_the_compression() {
    let mut f = tempfile::NamedTempFile::new().unwrap();
    let log = std::fs::read(fixture("px4/sample_log_small.ulg")).unwrap();
    let mut gz = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::fast());
    std::io::Write::write_all(&mut gz, &log).unwrap();
    std::io::Write::write_all(&mut f, &gz.finish().unwrap()).unwrap();
    let c = Choice {
        topic: Some("sensor_combined".into()),
        ..Choice::default()
    };
    let e = robotlogs::read(f.path(), &RecordingOptions::default(), &c).unwrap_err();
    let text = e.to_string();
    assert!(
        matches!(e, robotlogs::Error::Log(ref l) if matches!(l.kind, LogErrorKind::ChoiceForTextInput { setting: imu::Setting::Topic, .. })),
        "{text}"
    );
    assert!(
        text.contains("gzip-compressed PX4 ULog") && text.contains("decompress it first"),
        "{text}"
    );
}

#[test]
fn truncated_and_corrupt_logs_are_errors_naming_the_file_not_panics() {
    let dir = tempfile::tempdir().unwrap();
    for f in [
        "ros/imu_zstd.mcap",
        "ros/imu_bz2.bag",
        "ros/imu_lz4.bag",
        "ros/arducopter_imu.bin",
        "px4/sample_log_small.ulg",
    ] {
        let bytes = std::fs::read(fixture(f)).unwrap();
        for cut in [bytes.len() / 3, bytes.len() / 2 + 7] {
            let p = dir.path().join(format!("cut_{cut}"));
            std::fs::write(&p, &bytes[..cut]).unwrap();
            if let Err(e) = robotlogs::read(
                &p,
                &RecordingOptions::default(),
                &Choice {
                    first_if_several: true,
                    ..Choice::default()
                },
            ) {
                assert!(e.to_string().contains(&p.display().to_string()), "{f}: {e}");
            }
        }
    }
}

#[test]
fn a_block_of_0xff_in_a_ulog_loses_only_itself_and_is_counted() {
    // PX4's sample log with 4 KiB of 0xFF written over its middle: the
    // reader resumes at the next sync message, as pyulog does, and the
    // stretch skipped is a problem naming its bytes.
    let src = fixture("px4/sample_log_small.ulg");
    let mut bytes = std::fs::read(&src).unwrap();
    let middle = bytes.len() / 2;
    bytes[middle..middle + 4096].fill(0xFF);
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("ff.ulg");
    std::fs::write(&p, &bytes).unwrap();
    let whole = read("px4/sample_log_small.ulg", &Choice::default());
    let hit = robotlogs::read(&p, &RecordingOptions::default(), &Choice::default()).unwrap();
    let count = |r: &robotlogs::Read| {
        r.streams
            .iter()
            .find(|s| s.name == "sensor_combined")
            .unwrap()
            .messages
    };
    let (before, after) = (count(&whole), count(&hit));
    // This log has a sync message every 70 KB or so: what lies between
    // the block and the next one is lost (about 6 % here), the rest read.
    assert!(
        after < before && after as f64 > 0.9 * before as f64,
        "{after} of {before}"
    );
    let magic = [0x2F, 0x73, 0x13, 0x20, 0x25, 0x0C, 0xBB, 0x12];
    let next_sync = middle
        + 4096
        + bytes[middle + 4096..]
            .windows(8)
            .position(|w| w == magic)
            .unwrap()
        - 3;
    let skipped: Vec<&imu::Problem> = hit
        .report
        .problems
        .iter()
        .filter(|p| p.kind == ProblemKind::SkippedData)
        .collect();
    assert!(!skipped.is_empty());
    let m = &skipped[0].message;
    let start: usize = m["bytes ".len()..m.find("..").unwrap()].parse().unwrap();
    assert!((middle..middle + 4096).contains(&start), "{m}");
    assert!(m.starts_with(&format!("bytes {start}..{next_sync} ")), "{m}");
    assert!(
        m.contains("unknown type 0xff, skipped to the next sync message"),
        "{m}"
    );
}

#[test]
fn every_instance_from_one_decode_is_each_instance_read_alone() {
    // The two IMUs of an ArduPilot log: assembled from one decode, each
    // is the recording, report and stream list of a read of that instance
    // alone; instances asked twice (a stream taken by two choices) too.
    let p = fixture("ros/arducopter_imu.bin");
    let opts = RecordingOptions::default();
    let alone = |n: u32| {
        read(
            "ros/arducopter_imu.bin",
            &Choice {
                instance: Some(n),
                ..Choice::default()
            },
        )
    };
    let same = |a: &robotlogs::Read, b: &robotlogs::Read| {
        assert_eq!(format!("{:?}", a.recording), format!("{:?}", b.recording));
        assert_eq!(format!("{:?}", a.report), format!("{:?}", b.report));
        assert_eq!(format!("{:?}", a.streams), format!("{:?}", b.streams));
    };
    let open = || robotlogs::Log::open(&p, robotlogs::Format::DataFlash).unwrap();
    let all =
        robotlogs::read_log_each(&p, open(), &opts, &Choice::default(), &imu::InstancePick::All).unwrap();
    assert_eq!(
        all.iter().map(|(n, _)| *n).collect::<Vec<_>>(),
        [Some(0), Some(1)]
    );
    for (n, r) in &all {
        same(r, &alone(n.unwrap()));
    }
    let twice = imu::InstancePick::These(vec![1, 0, 1]);
    let got = robotlogs::read_log_each(&p, open(), &opts, &Choice::default(), &twice).unwrap();
    assert_eq!(
        got.iter().map(|(n, _)| *n).collect::<Vec<_>>(),
        [Some(1), Some(0), Some(1)]
    );
    for (n, r) in &got {
        same(r, &alone(n.unwrap()));
    }
    // A log of two IMUs holds several: each is read.
    let several =
        robotlogs::read_log_each(&p, open(), &opts, &Choice::default(), &imu::InstancePick::Several).unwrap();
    assert_eq!(several.len(), 2);
    let missing = robotlogs::read_log_each(
        &p,
        open(),
        &opts,
        &Choice::default(),
        &imu::InstancePick::These(vec![0, 7]),
    );
    assert!(matches!(missing, Err(robotlogs::Error::Log(_))));
}
