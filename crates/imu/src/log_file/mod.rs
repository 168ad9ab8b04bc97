//! The thesis log and imutherm's own log: writing, and reading into a
//! [`Recording`](crate::Recording).
//!
//! The thesis log is a header line
//! `mpu_accel_1[m/^2], …, mpu_gyro_3[rad/s], temp[degC]` and one
//! comma-separated row per sample, with no time column. imutherm's log is the
//! same body after `# key: value` metadata lines (format, sample rate,
//! device, configuration, start time, version): anything that reads the
//! thesis format after skipping `#` lines reads it.
//!
//! [`writer`] writes both; [`columns`] classifies a header's columns;
//! [`reader`] reads either (or any numeric table with a header) and says
//! which it found, in stages: `layout` (the header, units and time column),
//! `gaps` (the channels and their gaps), `time_axis` (the time column and
//! rate); [`trailer`] finds the recorder's closing line.

pub mod columns;
mod gaps;
mod layout;
pub mod reader;
mod time_axis;
pub mod trailer;
pub mod writer;

pub use columns::*;
pub use reader::*;
pub use trailer::*;
pub use writer::*;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::read_report::ProblemKind;
    use crate::recording::{Axis, Channel, Metadata, Recording};
    use crate::units::Quantity;

    /// The first rows of the thesis's own log (slides, "Software Design").
    const THESIS_ROWS: &str = "mpu_accel_1[m/^2], mpu_accel_2[m/^2], mpu_accel_3[m/^2], mpu_gyro_1[rad/s], mpu_gyro_2[rad/s], mpu_gyro_3[rad/s], temp[degC]
0.8786720092773437, 0.19632453613281248, 9.344569079589844, -0.03677179134860051, 0.022649291772688717, 0.01891882018659881, 4.062269745709408
0.8810662109374999, 0.22026655273437498, 9.363722692871093, -0.036238866836301946, 0.023182216284987275, 0.01945174469889737, 4.074250456764609
";

    #[test]
    fn rates_are_printed_to_sensible_digits() {
        assert_eq!(round_rate(99.99999999781721), "100");
        assert_eq!(round_rate(200.60180541624874), "200.602");
        assert_eq!(round_rate(248.53871), "248.539");
        assert_eq!(round_rate(0.5), "0.5");
        assert_eq!(round_rate(1000.0), "1000");
    }

    #[test]
    fn reads_the_thesis_log() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("thesis.txt");
        std::fs::write(&p, THESIS_ROWS).unwrap();
        let rec = read_recording(&p, &RecordingOptions::default()).unwrap();
        let names: Vec<&str> = rec.channels.iter().map(|c| c.name.as_str()).collect();
        assert_eq!(
            names,
            [
                "accel_x", "accel_y", "accel_z", "gyro_x", "gyro_y", "gyro_z", "temp"
            ]
        );
        assert_eq!(rec.inertial().len(), 6);
        assert_eq!(rec.channel("gyro_x").unwrap().data[1], -0.036238866836301946);
        assert_eq!(rec.channel("mpu_gyro_1[rad/s]").unwrap().unit, "rad/s");
        assert_eq!(rec.channel("accel_z").unwrap().unit, "m/s^2");
        assert_eq!(rec.rate_hz, None);
        assert_eq!(rec.len(), 2);
    }

    #[test]
    fn imutherm_log_round_trips_bit_for_bit() {
        let mut meta = Metadata {
            device: Some("sim:mpu9250-thesis".into()),
            start_time: Some("2026-11-22T10:00:00Z".into()),
            ..Metadata::default()
        };
        meta.set("gyro_full_scale_dps", "250");
        let mut rec = Recording {
            rate_hz: Some(200.0),
            meta,
            ..Recording::default()
        };
        let vals = |k: f64| {
            (0..5)
                .map(|i| (i as f64 + k) * 0.1 + 1e-9 / 3.0)
                .collect::<Vec<_>>()
        };
        for (i, q) in [Quantity::Acceleration, Quantity::AngularRate]
            .into_iter()
            .enumerate()
        {
            for (j, a) in Axis::ALL.into_iter().enumerate() {
                rec.channels
                    .push(Channel::inertial(q, a, vals((3 * i + j) as f64)));
            }
        }
        rec.channels.push(Channel::temperature(vals(40.0)));
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("log.txt");
        write_recording(std::fs::File::create(&p).unwrap(), &rec, LogFormat::Imutherm).unwrap();
        let back = read_recording(&p, &RecordingOptions::default()).unwrap();
        assert_eq!(back.rate_hz, Some(200.0));
        assert_eq!(back.meta.device.as_deref(), Some("sim:mpu9250-thesis"));
        assert_eq!(back.meta.get("gyro_full_scale_dps"), Some("250"));
        for (a, b) in rec.channels.iter().zip(&back.channels) {
            assert_eq!(a.name, b.name);
            assert_eq!(a.data, b.data);
        }
        // Still a thesis file once the comments are skipped.
        let text = std::fs::read_to_string(&p).unwrap();
        let body: Vec<&str> = text.lines().filter(|l| !l.starts_with('#')).collect();
        assert_eq!(body[0], THESIS_HEADER);
    }

    #[test]
    fn a_host_time_column_is_kept_but_never_the_time_axis_unless_named() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("host.txt");
        let mut w = LogWriter::with_columns(
            Vec::new(),
            LogFormat::Imutherm,
            &Metadata::default(),
            Some(100.0),
            &["host_time[s]"],
        )
        .unwrap();
        // Host times jitter by more than half a period; a gap of two rows.
        let times = [0.0, 0.016, 0.019, f64::NAN, f64::NAN, 0.052];
        for (i, t) in times.iter().enumerate() {
            let v = if t.is_nan() { f64::NAN } else { i as f64 };
            w.write_row_with(&[v; 7], &[*t]).unwrap();
            if i == 2 {
                w.write_comment("gap", "2 samples lost (FIFO overflow)").unwrap();
            }
        }
        w.write_trailer("trailer", "samples=4 gap_samples=2").unwrap();
        std::fs::write(&p, w.into_inner()).unwrap();
        let text = std::fs::read_to_string(&p).unwrap();
        assert!(text.contains("temp[degC], host_time[s]\n"), "{text}");
        let (rec, report) = read_recording_with_report(&p, &RecordingOptions::default()).unwrap();
        // Six rows, in file order: the host time did not move any.
        assert_eq!(rec.len(), 6);
        assert!(report.timing.is_none());
        assert_eq!(rec.rate_hz, Some(100.0));
        assert_eq!(rec.channel("gyro_x").unwrap().data[5], 5.0);
        assert_eq!(rec.channel("host_time").unwrap().data[2], 0.019);
        // The NaN run is named at its line (after the gap comment).
        let gap = report
            .problems
            .iter()
            .find(|p| p.kind == ProblemKind::NanRun)
            .unwrap();
        assert_eq!(gap.line, Some(8));
        // Named, it is the time axis.
        let opts = RecordingOptions {
            time_column: Some("host_time".into()),
            ..RecordingOptions::default()
        };
        let (_, report) = read_recording_with_report(&p, &opts).unwrap();
        assert!(report.timing.is_some());
    }

    /// An imutherm log at 100 Hz of these rows.
    fn imutherm_log_of(rows: impl IntoIterator<Item = [f64; 7]>) -> Vec<u8> {
        let mut w =
            LogWriter::new(Vec::new(), LogFormat::Imutherm, &Metadata::default(), Some(100.0)).unwrap();
        for row in rows {
            w.write_row(&row).unwrap();
        }
        w.into_inner()
    }

    #[test]
    fn a_gap_after_a_bad_line_is_still_reported() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("bad_then_gap.txt");
        let mut text = imutherm_log_of([[1.0; 7]; 3]);
        text.extend_from_slice(b"1, 2, garbled\n");
        let mut w = LogWriter::new(Vec::new(), LogFormat::Thesis, &Metadata::default(), None).unwrap();
        w.write_comment("gap", "5 samples lost").unwrap();
        for _ in 0..5 {
            w.write_row(&[f64::NAN; 7]).unwrap();
        }
        w.write_row(&[2.0; 7]).unwrap();
        let tail = w.into_inner();
        // Without the second writer's header line.
        let tail = &tail[tail.iter().position(|&b| b == b'\n').unwrap() + 1..];
        text.extend_from_slice(tail);
        std::fs::write(&p, &text).unwrap();
        let opts = RecordingOptions {
            skip_bad_lines: true,
            ..RecordingOptions::default()
        };
        let (rec, report) = read_recording_with_report(&p, &opts).unwrap();
        assert_eq!(rec.len(), 10);
        assert_eq!(report.count(ProblemKind::BadLine), 1);
        let gaps: Vec<_> = report
            .problems
            .iter()
            .filter(|p| p.kind == ProblemKind::NanRun)
            .collect();
        // Lines: 2 metadata, header, 3 rows (4-6), the bad line 7, the
        // comment 8, the gap from line 9.
        assert_eq!(gaps.len(), 1, "{:?}", report.problems);
        assert_eq!((gaps[0].line, gaps[0].count), (Some(9), 5));
    }

    #[test]
    fn many_logger_gaps_are_each_listed_once() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("gaps.txt");
        let rows = (0..600).map(|i| [if i % 3 == 1 { f64::NAN } else { 1.0 }; 7]);
        std::fs::write(&p, imutherm_log_of(rows)).unwrap();
        let (_, report) = read_recording_with_report(&p, &RecordingOptions::default()).unwrap();
        assert_eq!(report.count(ProblemKind::NanRun), 200);
        assert_eq!(report.unlisted, 0);
        assert!(
            report
                .problems
                .iter()
                .all(|p| p.channel.is_none() && p.count == 1)
        );
    }

    #[test]
    fn units_convert_and_can_be_overridden() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("g.csv");
        std::fs::write(&p, "gyro_x[deg/s],acc_z[g],gyro_y,pressure[hPa]\n180,1,90,1013\n").unwrap();
        let opts = RecordingOptions {
            units: vec!["gyro_y=deg/s".parse().unwrap()],
            ..RecordingOptions::default()
        };
        let rec = read_recording(&p, &opts).unwrap();
        assert!((rec.channel("gyro_x").unwrap().data[0] - std::f64::consts::PI).abs() < 1e-15);
        assert!((rec.channel("accel_z").unwrap().data[0] - 9.80665).abs() < 1e-15);
        assert!((rec.channel("gyro_y").unwrap().data[0] - std::f64::consts::FRAC_PI_2).abs() < 1e-15);
        let p_ch = rec.channel("pressure").unwrap();
        assert_eq!((p_ch.quantity, p_ch.unit.as_str()), (Quantity::Other, "hPa"));
        // A unit imutherm does not convert cannot be given at all.
        let e = "gyro_y=parsec".parse::<crate::units::UnitOverride>().unwrap_err();
        assert!(e.to_string().contains("parsec"), "{e}");
    }

    #[test]
    fn report_names_every_problem_with_its_line() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("t.csv");
        // 100 Hz in nanoseconds: a gap of 2 samples after line 4, a
        // duplicate at line 6, a step back at line 8, NaN and inf cells.
        let body = "time_ns,gyro_x[deg/s],temp\n\
                    0,1,20\n10000000,2,20\n20000000,nan,20\n50000000,4,20\n\
                    50000000,5,20\n60000000,inf,20\n55000000,7,20\n70000000,8,20\n";
        std::fs::write(&p, body).unwrap();
        let (rec, report) = read_recording_with_report(&p, &RecordingOptions::default()).unwrap();
        assert!((rec.rate_hz.unwrap() - 100.0).abs() < 1e-9);
        let timing = report.timing.as_ref().unwrap();
        assert_eq!(timing.gaps, vec![(3, 2)]);
        let found: Vec<(ProblemKind, Option<u64>)> =
            report.problems.iter().map(|p| (p.kind, p.line)).collect();
        for want in [
            (ProblemKind::NanRun, Some(4)),
            (ProblemKind::Infinite, Some(7)),
            (ProblemKind::TimeGap, Some(5)),
            (ProblemKind::DuplicateTime, Some(6)),
            (ProblemKind::BackwardsTime, Some(8)),
        ] {
            assert!(found.contains(&want), "{want:?} not in {found:?}");
        }
        // Every sample keeps a slot: the gap of two before line 5 is
        // filled, the duplicate (line 6, another value) and the step back
        // (line 8) are kept in the slots after their predecessors. Slot 2
        // (NaN) and 7 (inf) are gaps of the file itself.
        let g = &rec.channel("gyro_x").unwrap().data;
        assert_eq!(g.len(), 10);
        assert_eq!(report.dropped_samples, 0);
        assert!((g[1] - 2.0f64.to_radians()).abs() < 1e-15);
        assert!(g[2].is_nan() && g[3].is_nan() && g[4].is_nan() && g[7].is_nan());
        for (slot, deg) in [(5, 4.0), (6, 5.0), (8, 7.0), (9, 8.0)] {
            assert!((g[slot] - f64::to_radians(deg)).abs() < 1e-15, "slot {slot}");
        }
        assert_eq!(rec.timestamps.as_ref().unwrap()[1], 0.01);
    }

    #[test]
    fn an_unusable_rate_in_the_metadata_is_a_problem_naming_its_line() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("meta.txt");
        for (value, bad) in [
            ("abc", true),
            ("-5", true),
            ("nan", true),
            ("", true),
            ("200", false),
        ] {
            std::fs::write(
                &p,
                format!("# device: bench\n\n# sample_rate_hz: {value}\na,b\n1,2\n3,4\n"),
            )
            .unwrap();
            let (rec, report) = read_recording_with_report(&p, &RecordingOptions::default()).unwrap();
            let found = report
                .problems
                .iter()
                .find(|p| p.kind == ProblemKind::BadMetadata);
            if bad {
                let found = found.unwrap_or_else(|| panic!("{value}: {:?}", report.problems));
                assert_eq!(found.line, Some(3), "{value}");
                assert!(
                    found.message.contains(&format!("sample_rate_hz: {value}'")),
                    "{}",
                    found.message
                );
                assert_eq!(rec.rate_hz, None);
            } else {
                assert!(found.is_none(), "{:?}", report.problems);
                assert_eq!(rec.rate_hz, Some(200.0));
            }
        }
    }

    #[test]
    fn the_reader_says_which_format_it_found() {
        let dir = tempfile::tempdir().unwrap();
        let thesis = dir.path().join("thesis.txt");
        std::fs::write(&thesis, THESIS_ROWS).unwrap();
        let ours = dir.path().join("ours.txt");
        std::fs::write(
            &ours,
            format!("# format: imutherm-log/1\n# sample_rate_hz: 200\n{THESIS_ROWS}"),
        )
        .unwrap();
        let columns = dir.path().join("columns.csv");
        std::fs::write(&columns, "gyro_x, gyro_y\n0.1, 0.2\n0.3, 0.4\n").unwrap();
        let opts = RecordingOptions {
            rate_hz: Some(100.0),
            ..RecordingOptions::default()
        };
        for (path, want) in [
            (&thesis, crate::FileFormat::ThesisLog),
            (&ours, crate::FileFormat::ImuthermLog),
            (&columns, crate::FileFormat::Columns),
        ] {
            let (_, report) = read_recording_with_report(path, &opts).unwrap();
            assert_eq!(report.format, want, "{}", path.display());
        }
    }
}
