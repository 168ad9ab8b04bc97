//! Time columns as real loggers write them. Each fixture is a sequence
//! number in the data column, so that a test can tell which samples were
//! kept and where: every real sample must keep its slot, in order, and the
//! rate must be the clock's within 0.05 %.

use std::path::PathBuf;

use imu::{ProblemKind, ReadReport, Recording, RecordingOptions, read_recording_with_report};

mod common;
use common::assert_note;

/// Deterministic standard normal deviates (xorshift64* and Box–Muller).
struct Gauss(u64);

impl Gauss {
    fn uniform(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        ((self.0.wrapping_mul(0x2545_f491_4f6c_dd1d) >> 11) as f64 + 0.5) / (1u64 << 53) as f64
    }
    fn next(&mut self) -> f64 {
        let (u, v) = (self.uniform(), self.uniform());
        (-2.0 * u.ln()).sqrt() * (2.0 * std::f64::consts::PI * v).cos()
    }
}

fn write(name: &str, header: &str, rows: &[(String, usize)]) -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join(name);
    let mut text = format!("{header},gyro_x[rad/s],gyro_y[rad/s]\n");
    for (t, seq) in rows {
        text.push_str(&format!("{t},{seq},0\n"));
    }
    std::fs::write(&p, text).unwrap();
    (dir, p)
}

fn read(p: &std::path::Path) -> (Recording, ReadReport) {
    read_recording_with_report(p, &RecordingOptions::default()).unwrap()
}

/// Fails unless the rate read is `hz` within 0.05 %.
#[track_caller]
fn assert_rate(rec: &Recording, hz: f64) {
    let rate = rec.rate_hz.unwrap();
    assert!((rate / hz - 1.0).abs() < 5e-4, "{rate} Hz against {hz} Hz");
}

/// The sequence numbers in slot order, gaps left out.
fn kept(rec: &Recording) -> Vec<usize> {
    rec.channel("gyro_x")
        .unwrap()
        .data
        .iter()
        .filter(|v| v.is_finite())
        .map(|v| *v as usize)
        .collect()
}

#[test]
fn a_chip_running_0_3_percent_fast_stamped_in_integer_ms() {
    // 200 Hz nominal, 200.6 Hz real, a 36 108-sample record as in the
    // report this case comes from.
    let rate = 200.0 * 1.003;
    let rows: Vec<(String, usize)> = (0..36_108)
        .map(|k| (format!("{}", (k as f64 / rate * 1e3).floor() as u64), k))
        .collect();
    let (_d, p) = write("fast.csv", "timestamp", &rows);
    let (rec, report) = read(&p);
    assert_rate(&rec, rate);
    assert_eq!(kept(&rec), (0..36_108).collect::<Vec<_>>());
    assert_eq!(rec.len(), 36_108, "no gap invented");
    assert_eq!(report.count(ProblemKind::TimeGap), 0);
    assert_note(&report, "unit ms");
}

#[test]
fn gaussian_stamp_jitter_of_0_2_ms_at_200_hz() {
    let mut g = Gauss(0x1234_5678);
    let rows: Vec<(String, usize)> = (0..40_000)
        .map(|k| (format!("{:.6}", k as f64 / 200.0 + 2e-4 * g.next()), k))
        .collect();
    let (_d, p) = write("jitter.csv", "time", &rows);
    let (rec, report) = read(&p);
    assert_rate(&rec, 200.0);
    assert_eq!(kept(&rec), (0..40_000).collect::<Vec<_>>());
    assert_eq!(rec.len(), 40_000);
    let jitter = report.timing.as_ref().unwrap().jitter_s;
    assert!((1.5e-4..2.5e-4).contains(&jitter), "jitter {jitter}");
}

#[test]
fn unix_epoch_stamps_in_ns_with_a_2_5_s_gap_and_duplicated_lines() {
    // A ROS bag exported to CSV: header.stamp in epoch ns at 100 Hz; the
    // logger stalled 2.5 s after sample 3000 and wrote lines 5000 and
    // 7000 twice.
    let t0: u64 = 1_700_000_000_000_000_000;
    let mut rows = Vec::new();
    for k in 0..10_000usize {
        let t = t0 + k as u64 * 10_000_000 + if k >= 3000 { 2_500_000_000 } else { 0 };
        rows.push((format!("{t}"), k));
        if k == 5000 || k == 7000 {
            rows.push((format!("{t}"), k));
        }
    }
    let (_d, p) = write("epoch.csv", "stamp", &rows);
    let (rec, report) = read(&p);
    assert_rate(&rec, 100.0);
    assert_eq!(kept(&rec), (0..10_000).collect::<Vec<_>>());
    // 2.5 s more than one period: 250 missing samples, at line 3002.
    let gap = report
        .problems
        .iter()
        .find(|p| p.kind == ProblemKind::TimeGap)
        .unwrap();
    assert_eq!((gap.line, gap.count), (Some(3002), 250));
    assert_eq!(rec.len(), 10_250);
    assert_eq!(report.count(ProblemKind::DuplicateTime), 2);
    assert_eq!(report.dropped_samples, 2);
    assert_note(&report, "epoch");
}

#[test]
fn duplicate_stamps_on_distinct_samples_are_kept() {
    // A 1 kHz chip stamped by a 1 ms host tick now and then repeats a
    // stamp: the samples are real and kept.
    let rows: Vec<(String, usize)> = (0..5000)
        .map(|k| {
            let t = if k % 100 == 50 { k - 1 } else { k };
            (format!("{t}"), k)
        })
        .collect();
    let (_d, p) = write("dups.csv", "t_ms", &rows);
    let (rec, report) = read(&p);
    assert_eq!(kept(&rec), (0..5000).collect::<Vec<_>>());
    assert_eq!(rec.len(), 5000);
    assert_eq!(report.count(ProblemKind::DuplicateTime), 50);
    assert_eq!(report.count(ProblemKind::TimeGap), 0, "{:?}", report.problems);
    assert_rate(&rec, 1000.0);
}

#[test]
fn a_nan_time_is_named_and_its_row_kept_where_its_neighbours_place_it() {
    // Line 5 (row 3) has no time; lines 52 and 53 have none either, and
    // neither can place the other.
    let rows: Vec<(String, usize)> = (0..200)
        .map(|k| {
            let t = if matches!(k, 3 | 50 | 51) {
                "nan".to_string()
            } else {
                format!("{:.3}", k as f64 * 0.01)
            };
            (t, k)
        })
        .collect();
    let (_dir, p) = write("nan_time.csv", "time[s]", &rows);
    let (rec, report) = read(&p);
    assert_rate(&rec, 100.0);
    let nan = |line: u64| {
        report
            .problems
            .iter()
            .find(|q| q.kind == ProblemKind::NoStamp && q.line == Some(line))
    };
    let placed = nan(5).expect("line 5 reported");
    assert!(
        placed.message.contains("the time is not a number") && placed.message.contains("t = 0.030000 s"),
        "{}",
        placed.message
    );
    let lost = nan(52).expect("line 52 reported");
    assert!(
        lost.message.contains("the slot after the previous one"),
        "{}",
        lost.message
    );
    // Every row in its slot, in order.
    let seq = kept(&rec);
    assert_eq!(seq, (0..200).collect::<Vec<_>>());
    assert!(
        !report
            .problems
            .iter()
            .any(|q| q.kind == ProblemKind::TimeGap && q.line == Some(6)),
        "no gap before line 6: {:?}",
        report.problems
    );
}
