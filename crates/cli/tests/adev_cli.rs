//! `imutherm adev` end to end: output contract, reference values, bad input.

use predicates::prelude::*;

mod support;
use support::{Refused, cli, file, imutherm, json_of, json_stdout, succeed};

/// NIST SP 1065 Table 30 input.
const NBS14_10: &str = "892\n809\n823\n798\n671\n644\n883\n903\n677\n";

#[test]
fn json_document_follows_the_schema_and_table_30() {
    let (_d, p) = file("nbs14.txt", NBS14_10);
    let doc = json_stdout(imutherm().args(["adev", "--stat", "adev", "--json"]).arg(&p));
    assert_eq!(doc["schema"], "imutherm.adev/1");
    assert_eq!(doc["stat"], "adev");
    assert_eq!(doc["data_type"], "freq");
    assert_eq!(doc["rate_hz"], 1.0);
    let ch = &doc["channels"][0];
    assert_eq!(ch["name"], "col1");
    assert_eq!(ch["unit"], "");
    let pts = ch["points"].as_array().unwrap();
    assert_eq!(pts.len(), 2);
    // SP 1065 Table 30: ADEV 91.22945 at τ = 1, 115.8082 at τ = 2.
    for (p, want) in pts.iter().zip([91.22945, 115.8082]) {
        let dev = p["dev"].as_f64().unwrap();
        assert!(((dev - want) / want).abs() < 1e-6);
        for key in ["tau", "m", "n", "edf", "dev_lo", "dev_hi"] {
            assert!(p[key].is_number(), "{key} missing");
        }
        assert!(p["dev_lo"].as_f64().unwrap() < dev && dev < p["dev_hi"].as_f64().unwrap());
    }
    assert_eq!(pts[1]["tau"], 2.0);
    assert_eq!(pts[1]["m"], 2);
    assert_eq!(pts[1]["n"], 3);
}

#[test]
fn header_names_units_channel_selection_and_rate() {
    let mut body = String::from("# rate 10 Hz\ngyro_x[rad/s], temp[degC]\n");
    for i in 0..400 {
        body.push_str(&format!(
            "{}, {}\n",
            ((i * 7919) % 101) as f64 * 1e-3,
            20.0 + i as f64 * 1e-3
        ));
    }
    let (_d, p) = file("imu.csv", &body);
    let doc = json_stdout(
        imutherm()
            .args([
                "adev",
                "--channels",
                "gyro_x",
                "--rate",
                "10",
                "--taus",
                "0.1,0.4,1",
                "--json",
            ])
            .arg(&p),
    );
    let chans = doc["channels"].as_array().unwrap();
    assert_eq!(chans.len(), 1);
    assert_eq!(chans[0]["name"], "gyro_x");
    assert_eq!(chans[0]["unit"], "rad/s");
    let taus: Vec<f64> = chans[0]["points"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| p["tau"].as_f64().unwrap())
        .collect();
    assert_eq!(taus, [0.1, 0.4, 1.0]);

    // The readable table carries units and the statistic.
    cli!["adev", "--rate", "10", &p]
        .assert()
        .success()
        .stdout(predicate::str::contains("oadev [rad/s]").and(predicate::str::contains("tau [s]")));
}

/// A headerless column of `rows` values `value(i)`, but for the one row
/// `odd.0`, which reads `odd.1`.
fn one_column(rows: usize, odd: (usize, &str), value: impl Fn(usize) -> f64) -> String {
    (0..rows)
        .map(|i| {
            if i == odd.0 {
                format!("{}\n", odd.1)
            } else {
                format!("{}\n", value(i))
            }
        })
        .collect()
}

#[test]
fn gaps_are_counted_and_reported() {
    let body = one_column(300, (120, "nan"), |i| ((i * 31) % 17) as f64);
    let (_d, p) = file("gap.txt", &body);
    let out = succeed(imutherm().args(["adev", "--json"]).arg(&p));
    let doc = json_of(&out);
    assert_eq!(doc["channels"][0]["nan_samples"], 1);
    assert!(String::from_utf8_lossy(&out.stderr).contains("1 NaN samples treated as gaps"));
}

#[test]
fn bad_input_names_file_line_and_column() {
    let (_d, p) = file("bad.txt", "a,b\n1,2\n3,4\n5,x\n");
    cli!["adev", &p].refused(1, "bad.txt:4: column 2: cannot read 'x' as a number");

    let (_d, p) = file("empty.txt", "");
    cli!["adev", &p]
        .assert()
        .code(1)
        .stderr(predicate::str::contains("empty.txt").and(predicate::str::contains("no data rows")));

    let (_d, p) = file("short.txt", "1\n2\n");
    imutherm().arg("adev").arg(&p).assert().code(1).stderr(
        predicate::str::contains("short.txt: column 1 (col1)")
            .and(predicate::str::contains("data ends at line 2"))
            .and(predicate::str::contains("needs at least")),
    );

    let (_d, p) = file("ragged.txt", "1 2\n3 4\n5\n6 7\n");
    cli!["adev", &p].refused(1, "ragged.txt:3: expected 2 fields, found 1");

    cli!["adev", "/nonexistent/file.txt"].refused(1, "/nonexistent/file.txt");
}

#[test]
fn usage_errors_and_bad_flag_values_exit_2() {
    imutherm().arg("adev").assert().code(2);
    imutherm().args(["adev", "--bogus", "x"]).assert().code(2);
    let (_d, p) = file("ok.txt", NBS14_10);
    cli!["adev", "--stat", "fastdev", &p].refused(2, "unknown statistic 'fastdev'");
    cli!["adev", "--rate", "0", &p].refused(2, "--rate");
    cli!["adev", "--channels", "nope", &p].refused(1, "no column 'nope'");
}

#[test]
fn help_has_an_example() {
    cli!["adev", "--help"]
        .assert()
        .success()
        .stdout(predicate::str::contains("Examples:").and(predicate::str::contains("imutherm adev")));
}

#[test]
fn imu_logs_default_to_the_inertial_channels_with_rate_from_metadata() {
    let mut body = String::from(
        "# format: imutherm-log/1\n# sample_rate_hz: 50\nmpu_accel_1[m/^2], mpu_accel_2[m/^2], mpu_accel_3[m/^2], \
         mpu_gyro_1[rad/s], mpu_gyro_2[rad/s], mpu_gyro_3[rad/s], temp[degC]\n",
    );
    for i in 0..500 {
        let v = ((i * 7919) % 97) as f64 * 1e-3;
        body.push_str(&format!("{v}, {v}, {}, {v}, {v}, {v}, 30.0\n", 9.8 + v));
    }
    let (_d, p) = file("imu.txt", &body);
    let doc = json_stdout(imutherm().args(["adev", "--json"]).arg(&p));
    let names: Vec<&str> = doc["channels"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| c["name"].as_str().unwrap())
        .collect();
    assert_eq!(
        names,
        ["accel_x", "accel_y", "accel_z", "gyro_x", "gyro_y", "gyro_z"]
    );
    assert_eq!(doc["rate_hz"], 50.0);
    assert_eq!(doc["channels"][0]["unit"], "m/s^2");
    assert_eq!(doc["channels"][0]["points"][0]["tau"], 0.02);

    // A group, and a unit override converting deg/s to rad/s.
    let doc = json_stdout(
        imutherm()
            .args(["adev", "--json", "--channels", "gyro", "--unit", "gyro_x=deg/s"])
            .arg(&p),
    );
    let ch = doc["channels"].as_array().unwrap();
    assert_eq!(ch.len(), 3);
    let ratio = ch[0]["points"][0]["dev"].as_f64().unwrap() / ch[1]["points"][0]["dev"].as_f64().unwrap();
    assert!((ratio - std::f64::consts::PI / 180.0).abs() < 1e-12, "{ratio}");

    cli!["adev", "--unit", "gyro_x=furlong", &p].refused(2, "unknown unit 'furlong'");
}

#[test]
fn skip_bad_lines_keeps_time_right_and_truncation_is_dropped() {
    let mut body = one_column(200, (77, "oops"), |i| ((i * 13) % 7) as f64);
    body.push_str("1.2e"); // a logger killed mid-write
    let (_d, p) = file("bad.txt", &body);
    cli!["adev", &p].refused(1, "bad.txt:78: column 1: cannot read 'oops'");
    let out = succeed(imutherm().args(["adev", "--skip-bad-lines", "--json"]).arg(&p));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("bad.txt:78: column 1") && err.contains("skipped as a gap"),
        "{err}"
    );
    assert!(
        err.contains("bad.txt:201: truncated last line") && err.contains("dropped"),
        "{err}"
    );
    let doc = json_of(&out);
    assert_eq!(doc["channels"][0]["samples"], 200);
    assert_eq!(doc["channels"][0]["nan_samples"], 1);
}

#[test]
fn time_column_gives_the_rate_and_its_gaps_become_gaps() {
    let mut body = String::from("t[s],gyro_x[rad/s]\n");
    for i in 0..400 {
        if (200..203).contains(&i) {
            continue; // three samples lost
        }
        body.push_str(&format!(
            "{},{}\n",
            i as f64 * 0.01,
            ((i * 37) % 11) as f64 * 1e-3
        ));
    }
    let (_d, p) = file("timed.csv", &body);
    let out = succeed(imutherm().args(["adev", "--json"]).arg(&p));
    let doc = json_of(&out);
    let ch = &doc["channels"][0];
    assert_eq!(ch["name"], "gyro_x");
    assert_eq!(ch["samples"], 400);
    assert_eq!(ch["nan_samples"], 3);
    assert!((ch["rate_hz"].as_f64().unwrap() - 100.0).abs() < 1e-6);
    assert!(String::from_utf8_lossy(&out.stderr).contains("timed.csv:202: 3 missing samples"));
}

#[test]
fn json_stays_one_clean_document_while_the_total_deviations_run() {
    // Every τ of MTOTDEV and Thêo1: the statistics that report progress
    // block by block. Whatever goes to stderr, stdout is the JSON alone.
    let body: String = (0..900)
        .map(|i| format!("{}\n", ((i * 7919) % 101) as f64 / 101.0))
        .collect();
    let (_d, p) = file("walk.txt", body);
    for stat in ["mtotdev", "theo1"] {
        let out = succeed(
            imutherm()
                .args(["adev", "--stat", stat, "--taus", "all", "--json"])
                .arg(&p),
        );
        let text = String::from_utf8(out.stdout.clone()).unwrap();
        assert!(
            text.starts_with('{') && text.ends_with("}\n"),
            "{stat}: {text:.80}"
        );
        assert_eq!(text.matches('\n').count(), 1, "{stat}");
        assert!(!text.contains(['\r', '\u{1b}']), "{stat}");
        let doc = json_of(&out);
        assert_eq!(doc["stat"], stat);
        assert!(
            doc["channels"][0]["points"].as_array().unwrap().len() > 100,
            "{stat}"
        );
        // Not a terminal: no bar, so no control characters on stderr either.
        assert!(!support::stderr_of(&out).contains('\u{1b}'), "{stat}");
    }
}
