//! `imutherm noise` end to end.

use std::fmt::Write as _;

use predicates::prelude::*;

mod support;
use support::{Refused, cli, entry, imutherm, json_stdout, succeed};

const HEADER: &str = "mpu_accel_1[m/^2], mpu_accel_2[m/^2], mpu_accel_3[m/^2], mpu_gyro_1[rad/s], \
                      mpu_gyro_2[rad/s], mpu_gyro_3[rad/s], temp[degC]\n";

/// A log of white noise of density `n` (unit/√Hz) plus a rate random walk
/// `k` (unit/√s) on every axis, at 50 Hz.
fn log(seconds: usize, n: f64, k: f64, temp: f64, seed: u64) -> String {
    let rate = 50.0f64;
    let mut state = seed;
    let mut normal = move || {
        let mut u = || {
            state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
            let mut z = state;
            z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
            ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64 + 1e-18
        };
        let (a, b) = (u(), u());
        (-2.0 * a.ln()).sqrt() * (2.0 * std::f64::consts::PI * b).cos()
    };
    let mut s = format!("# sample_rate_hz: {rate}\n{HEADER}");
    let mut walk = [0.0; 6];
    for _ in 0..(seconds * rate as usize) {
        let sd = n * rate.sqrt();
        let v: Vec<f64> = (0..6)
            .map(|i| {
                walk[i] += k / rate.sqrt() * normal();
                sd * normal() + walk[i]
            })
            .collect();
        let _ = writeln!(
            s,
            "{}, {}, {}, {}, {}, {}, {temp}",
            v[0],
            v[1],
            9.8 + v[2],
            v[3],
            v[4],
            v[5]
        );
    }
    s
}

#[test]
fn terms_tables_json_and_kalibr() {
    let dir = tempfile::tempdir().unwrap();
    let a = dir.path().join("run34.txt");
    let b = dir.path().join("run82.txt");
    std::fs::write(&a, log(600, 2e-3, 0.0, 34.0, 1)).unwrap();
    std::fs::write(&b, log(600, 3e-3, 0.0, 82.0, 2)).unwrap();
    let yaml = dir.path().join("imu.yaml");

    let out = succeed(imutherm().arg("noise").arg(&a).arg(&b));
    let text = String::from_utf8_lossy(&out.stdout);
    // Thesis layout: one table per term, columns = mean temperatures.
    assert!(
        text.contains("Gyroscope — Angle random walk N [°/√s] (selected noise model)"),
        "{text}"
    );
    assert!(text.contains("34°C") && text.contains("82°C"), "{text}");
    assert!(
        text.contains("Accelerometer — Velocity random walk N [m/s/√s]"),
        "{text}"
    );
    // 10 minutes of white noise: the model is white noise alone, and K is
    // only bounded.
    assert!(text.contains("model (gyro_x): N ("), "{text}");
    assert!(text.contains("≤ not in the selected model"), "{text}");
    assert!(!text.contains("NaN"));

    let out = cli!["noise", "--json", "--units", "datasheet", "--kalibr", &yaml, &a]
        .output()
        .unwrap();
    // K is not identifiable in 10 minutes: the yaml is written all the
    // same, K as its upper bound and saying so, after the analysis.
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let written = std::fs::read_to_string(&yaml).unwrap();
    assert!(written.contains("upper bound"), "{written}");
    assert!(written.contains("update_rate: 50"), "{written}");
    serde_json::from_slice::<serde_json::Value>(&out.stdout).unwrap();

    let doc = json_stdout(imutherm().args(["noise", "--json"]).arg(&a));
    assert_eq!(doc["schema"], "imutherm.noise/1");
    let f = &doc["files"][0];
    assert_eq!(f["mean_temperature_c"], 34.0);
    let gx = entry(&f["channels"], "name", "gyro_x");
    let n_fit = entry(&gx["fit"], "term", "N");
    assert_eq!(n_fit["identified"], true);
    let n = &n_fit["si"];
    assert_eq!(n["unit"], "rad/√s");
    assert!(
        n["lo"].as_f64().unwrap() <= 2e-3 && 2e-3 <= n["hi"].as_f64().unwrap(),
        "{n}"
    );
    assert_eq!(n_fit["datasheet"]["unit"], "°/√h");
    // The datasheet's density: N = 2e-3 rad/√s is 0.1146 °/s/√Hz.
    assert_eq!(n_fit["density"]["unit"], "°/s/√Hz");
    let d = n_fit["density"]["value"].as_f64().unwrap();
    assert!((d / n["value"].as_f64().unwrap() - 180.0 / std::f64::consts::PI).abs() < 1e-9);
    let k_fit = entry(&gx["fit"], "term", "K");
    assert_eq!(k_fit["identified"], false);
    assert!(
        k_fit["reason"]
            .as_str()
            .unwrap()
            .contains("not in the selected model")
    );
    // The new fields: the model, the filters' parameters, the state space.
    assert_eq!(gx["model"]["label"], "N");
    assert_eq!(gx["model"]["fits"], true);
    let filters = gx["filters"].as_array().unwrap();
    let px4 = filters.iter().find(|f| f["filter"] == "px4_ekf2").unwrap();
    let gyr = entry(&px4["params"], "name", "EKF2_GYR_NOISE");
    // N/√Δt at EKF2's 10 ms.
    let want = n["value"].as_f64().unwrap() / 0.01f64.sqrt();
    assert!(
        (gyr["value"].as_f64().unwrap() / want - 1.0).abs() < 1e-12,
        "{gyr}"
    );
    assert_eq!(gyr["unit"], "rad/s");
    let ekf3 = filters.iter().find(|f| f["filter"] == "ardupilot_ekf3").unwrap();
    assert!(
        ekf3["params"]
            .as_array()
            .unwrap()
            .iter()
            .any(|p| p["name"] == "EK3_GBIAS_P_NSE")
    );
    assert_eq!(gx["state_space"][0]["kind"], "white_noise");
}

#[test]
fn the_thesis_sample_rows_give_a_table() {
    // The rows printed on the thesis's "Software Design" slide; the seventh
    // has lost a field in the slide and is skipped as a gap.
    let rows = "0.8786720092773437, 0.19632453613281248, 9.344569079589844, -0.03677179134860051, 0.022649291772688717, 0.01891882018659881, 4.062269745709408
0.8810662109374999, 0.22026655273437498, 9.363722692871093, -0.036238866836301946, 0.023182216284987275, 0.01945174469889737, 4.074250456764609
0.8810662109374999, 0.22505495605468748, 9.425971936035156, -0.037038253604749785, 0.023448678541136553, 0.02078405597964376, 4.053284212418006
0.9169792358398436, 0.2346317626953125, 9.397241516113281, -0.03543948006785411, 0.02424806530958439, 0.019984669211195925, 4.071255279000809
0.8810662109374999, 0.22266075439453123, 9.349357482910156, -0.034640093299406274, 0.02424806530958439, 0.019984669211195925, 4.0682601012370085
0.8930372192382812, 0.20350714111328125, 9.37808790283203, -0.03543948006785411, 0.02184990500424088, 0.01865235793044953, 4.0682601012370085
0.8834604125976562, 0.2050013427734375, 9.392453112792968, -0.03677179134860051, 0.023715140797285, 0.01918528244274809, 4.056279390181807
0.91219083251951, 0.22266075439453123, 9.359375, 9.4044241, 0.035173017811704836, 0.0251131467345204
0.857120092773437, 0.210697449157718437, 9.349357482910156, -0.036238866836301946, 0.02424806530958439, 0.019984669211195925, 4.0682601012370085
0.8786720092773437, 0.2106974609375, 9.279925634765624, -0.03677179134860051, 0.02398160305343511, 0.019718206955046648, 4.0772456345241
0.8930372192382812, 0.20829554443359374, 9.344569079589844, -0.03490655555555555, 0.021050518235793042, 0.020251131467345206, 4.083235990056011
0.8212111694335937, 0.2537853759765625, 9.373299499511718, -0.035705942324003384, 0.02424806530958439, 0.01865235793044953, 4.059274567945607
";
    let dir = tempfile::tempdir().unwrap();
    let thesis = dir.path().join("thesis.txt");
    std::fs::write(&thesis, format!("{HEADER}{rows}")).unwrap();
    let sim = dir.path().join("sim.txt");
    std::fs::write(&sim, log(120, 2e-3, 0.0, 43.0, 3)).unwrap();
    cli!["noise", "--rate", "50", "--skip-bad-lines", &thesis, &sim]
        .assert()
        .success()
        .stdout(
            predicate::str::contains("Gyroscope — Angle random walk N")
                .and(predicate::str::contains("4°C"))
                .and(predicate::str::contains("43°C"))
                .and(predicate::str::contains("gyro_z")),
        )
        .stderr(predicate::str::contains(
            "thesis.txt:9: expected 7 fields, found 6",
        ));
}

#[test]
fn an_unknown_header_is_a_clear_error() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("mystery.csv");
    std::fs::write(&p, "alpha,beta\n1,2\n3,4\n5,6\n").unwrap();
    cli!["noise", "--rate", "1", &p]
        .refused(1, "mystery.csv: no accelerometer or gyroscope column recognised");
}

/// The four values of a Kalibr yaml.
fn kalibr_values(text: &str) -> Vec<(String, f64)> {
    text.lines()
        .filter(|l| !l.starts_with('#'))
        .filter_map(|l| {
            let (k, v) = l.split_once(':')?;
            let v = v.split('#').next()?.trim().parse::<f64>().ok()?;
            k.ends_with("_noise_density")
                .then_some(())
                .or(k.ends_with("_random_walk").then_some(()))
                .map(|_| (k.to_string(), v))
        })
        .collect()
}

#[test]
fn kalibr_on_a_30_minute_recording_always_writes() {
    // 30 min at 50 Hz, N = 2e-3 and K = 2e-5 on every axis: K is at most
    // barely visible; the file must hold four positive values, each random
    // walk at or above the truth.
    let (n, k) = (2e-3, 2e-5);
    let dir = tempfile::tempdir().unwrap();
    let a = dir.path().join("run.txt");
    std::fs::write(&a, log(1800, n, k, 34.0, 7)).unwrap();
    let yaml = dir.path().join("imu.yaml");
    let out = succeed(imutherm().arg("noise").arg(&a).arg("--kalibr").arg(&yaml));
    // The table comes first, on stdout.
    let table = String::from_utf8_lossy(&out.stdout);
    assert!(
        table.contains("gyro_x") && table.contains("N [rad/√s]"),
        "{table}"
    );
    let text = std::fs::read_to_string(&yaml).unwrap();
    let values = kalibr_values(&text);
    assert_eq!(values.len(), 4, "{text}");
    for (key, v) in &values {
        assert!(*v > 0.0, "{key}: {v}");
        if key.ends_with("_random_walk") {
            assert!(*v >= k, "{key}: {v} below the truth {k}\n{text}");
        }
    }
    assert!(text.contains("rostopic: /imu0  # check"), "{text}");
}
