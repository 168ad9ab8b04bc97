//! What imutherm guarantees about files: outputs never replace an input or
//! an existing file unasked, never end up half-written or interleaved;
//! inputs are read once, whatever they are; a closed output ends the
//! program quietly.

use std::io::{Read, Write};
use std::path::{Path, PathBuf};
use std::process::{Command as Process, Stdio};

use assert_cmd::cargo::CommandCargoExt;
use predicates::prelude::*;

mod support;
use support::{
    Refused, Simulation, cli, imutherm, json_of, json_stdout, replaces_only_with_overwrite, scratch_files,
    stderr_of, tcal_fit, writing,
};

/// A temperature run to fit: 20 minutes at 2 Hz.
fn simulate(dir: &Path, name: &str, profile: &str) -> PathBuf {
    Simulation::new()
        .profile(profile)
        .duration("20m")
        .rate("2")
        .write(dir, name)
}

#[test]
fn simulate_refuses_an_existing_file_unless_overwrite() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("run.txt");
    std::fs::write(&out, "precious\n").unwrap();
    replaces_only_with_overwrite(
        &["simulate", "--duration", "10", "-o"],
        &out,
        &["already exists (9 bytes)", "--overwrite"],
    );
    assert!(
        std::fs::read_to_string(&out)
            .unwrap()
            .starts_with("# format: imutherm-log/1")
    );
    assert_eq!(
        scratch_files(dir.path()),
        Vec::<String>::new(),
        "scratch files left beside run.txt"
    );
}

#[test]
fn tcal_never_writes_onto_its_inputs_by_any_name() {
    let dir = tempfile::tempdir().unwrap();
    let run = simulate(dir.path(), "ramp.txt", "ramp:25:70:1200");
    let model = dir.path().join("model.json");
    tcal_fit(&model, &["--order", "2"], &[&run]);
    let before = std::fs::read(&run).unwrap();
    let hard = dir.path().join("hard.txt");
    std::fs::hard_link(&run, &hard).unwrap();
    let sym = dir.path().join("sym.txt");
    std::os::unix::fs::symlink(&run, &sym).unwrap();
    let dotted = dir.path().join(".").join("ramp.txt");
    for target in [&run, &hard, &sym, &dotted, &model] {
        let out = cli!["tcal", "apply", &model, &run, "-o", target, "--overwrite"]
            .output()
            .unwrap();
        assert_eq!(out.status.code(), Some(1), "{}", target.display());
        assert!(
            stderr_of(&out).contains("destroy the data being read"),
            "{}",
            stderr_of(&out)
        );
    }
    assert_eq!(std::fs::read(&run).unwrap(), before);
    // Fitting onto a run, and the --kalibr file onto a run, are refused too.
    cli!["tcal", "fit", "--overwrite", &run, "-o", &hard]
        .assert()
        .code(1);
    cli!["noise", "--overwrite", &run, "--kalibr", &sym]
        .assert()
        .code(1);
    assert_eq!(std::fs::read(&run).unwrap(), before);

    // Without --overwrite an existing model stays; with it, it is replaced.
    let old_model = std::fs::read(&model).unwrap();
    cli!["tcal", "fit", "--order", "1", &run, "-o", &model].refused(1, "already exists");
    assert_eq!(std::fs::read(&model).unwrap(), old_model);
    // Reading the input from standard input (`- < ramp.txt`) does not
    // hide it either.
    let out = Process::cargo_bin("imutherm")
        .unwrap()
        .args(["tcal", "apply"])
        .arg(&model)
        .arg("-")
        .arg("-o")
        .arg(&hard)
        .arg("--overwrite")
        .stdin(std::fs::File::open(&run).unwrap())
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1), "{}", stderr_of(&out));
    assert_eq!(std::fs::read(&run).unwrap(), before);
}

#[test]
fn a_full_device_is_named_once_and_exits_1() {
    let out = cli!["simulate", "--duration", "60", "-o", "/dev/full"]
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    let err = stderr_of(&out);
    assert!(err.contains("writing /dev/full"), "{err}");
    assert_eq!(err.matches("No space left on device").count(), 1, "{err}");

    let full = std::fs::OpenOptions::new().write(true).open("/dev/full").unwrap();
    let out = Process::cargo_bin("imutherm")
        .unwrap()
        .args(["simulate", "--print-config"])
        .stdout(full)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    let err = stderr_of(&out);
    assert!(!err.contains("panicked"), "{err}");
    assert!(
        err.contains("standard output") && err.contains("No space left"),
        "{err}"
    );

    // A missing input: the system's reason once, not twice.
    let out = cli!["info", "/nonexistent/run.txt"].output().unwrap();
    assert_eq!(out.status.code(), Some(1));
    assert_eq!(
        stderr_of(&out).matches("No such file").count(),
        1,
        "{}",
        stderr_of(&out)
    );
}

#[test]
fn a_full_filesystem_keeps_the_old_file() {
    // A 64 KiB tmpfs, where one can be mounted (root, Linux); elsewhere
    // the /dev/full case above is the check.
    let dir = tempfile::tempdir().unwrap();
    let mounted = Process::new("mount")
        .args(["-t", "tmpfs", "-o", "size=64k", "tmpfs"])
        .arg(dir.path())
        .stderr(Stdio::null())
        .status()
        .is_ok_and(|s| s.success());
    if !mounted {
        eprintln!("no tmpfs could be mounted: skipped");
        return;
    }
    let out = dir.path().join("run.txt");
    std::fs::write(&out, "the old run\n").unwrap();
    let result = cli!["simulate", "--duration", "60", "--overwrite", "-o", &out]
        .output()
        .unwrap();
    let kept = std::fs::read_to_string(&out).unwrap();
    let leftovers: Vec<_> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    let _ = Process::new("umount").arg(dir.path()).status();
    assert_eq!(result.status.code(), Some(1));
    let err = stderr_of(&result);
    assert!(err.contains(&format!("writing {}", out.display())), "{err}");
    assert_eq!(err.matches("No space left on device").count(), 1, "{err}");
    assert_eq!(kept, "the old run\n");
    assert_eq!(leftovers, [std::ffi::OsString::from("run.txt")]);
}

#[test]
fn two_recorders_never_share_one_file() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("rec.txt");
    let mut first = Process::cargo_bin("imutherm")
        .unwrap()
        .args([
            "record",
            "--device",
            "sim",
            "--rate",
            "100",
            "--duration",
            "3s",
            "-o",
        ])
        .arg(&out)
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    // Until the first has its file (it configures the chip first).
    let t0 = std::time::Instant::now();
    while !std::fs::read_to_string(&out).is_ok_and(|t| t.contains("mpu_accel_1")) {
        assert!(t0.elapsed().as_secs() < 20, "the first recorder never wrote");
        std::thread::sleep(std::time::Duration::from_millis(50));
    }
    for args in [
        &[
            "record",
            "--device",
            "sim",
            "--duration",
            "1s",
            "--overwrite",
            "-o",
        ][..],
        &["simulate", "--duration", "5", "--overwrite", "-o"],
    ] {
        imutherm()
            .args(args)
            .arg(&out)
            .assert()
            .code(1)
            .stderr(predicate::str::contains("being written by another process"));
    }
    assert!(first.wait().unwrap().success());
    let text = std::fs::read_to_string(&out).unwrap();
    assert_eq!(text.matches("# format:").count(), 1);
    assert!(text.contains("# trailer: samples=300 "), "{text}");
}

#[test]
fn standard_input_and_fifos_are_read_once_with_their_trailer() {
    let dir = tempfile::tempdir().unwrap();
    let rec = dir.path().join("rec.txt");
    let args = ["--device", "sim", "--rate", "200", "--duration", "1s"];
    writing("record", &args, &rec).assert().success();
    let direct = json_stdout(imutherm().args(["info", "--json"]).arg(&rec));
    let direct = &direct["files"][0];
    assert_eq!(direct["logger"]["samples"], 200, "{direct}");

    let piped = json_stdout(imutherm().args(["info", "--json", "-"]).pipe_stdin(&rec).unwrap());
    let piped = &piped["files"][0];
    for key in ["logger", "samples", "channels"] {
        assert_eq!(piped[key], direct[key], "{key}");
    }

    // adev through a FIFO gives the file's numbers exactly.
    let fifo = dir.path().join("fifo");
    assert!(Process::new("mkfifo").arg(&fifo).status().unwrap().success());
    let writer = {
        let (fifo, rec) = (fifo.clone(), rec.clone());
        std::thread::spawn(move || std::fs::write(fifo, std::fs::read(rec).unwrap()).unwrap())
    };
    let through_fifo = imutherm().args(["adev", "--json"]).arg(&fifo).output().unwrap();
    writer.join().unwrap();
    let from_file = imutherm().args(["adev", "--json"]).arg(&rec).output().unwrap();
    assert!(through_fifo.status.success(), "{}", stderr_of(&through_fifo));
    let (mut a, mut b) = (json_of(&through_fifo), json_of(&from_file));
    // The same numbers; only the file's name differs.
    for doc in [&mut a, &mut b] {
        for c in doc["channels"].as_array_mut().unwrap() {
            c.as_object_mut().unwrap().remove("file");
        }
    }
    assert_eq!(a["channels"].as_array().unwrap().len(), 6);
    assert_eq!(a["channels"], b["channels"]);
}

#[test]
fn a_cut_last_line_is_named_and_dropped() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("cut.txt");
    // 3.14159 cut to 3.1 by a power loss: a number still, but no newline.
    std::fs::write(&p, "# sample_rate_hz: 10\ngyro_x,gyro_y\n1,2\n3,4\n5,3.1").unwrap();
    let doc = json_stdout(imutherm().args(["info", "--json"]).arg(&p));
    let doc = &doc["files"][0];
    assert_eq!(doc["samples"], 2);
    let problems = doc["problems"].to_string();
    assert!(
        problems.contains("truncated_last_line") && problems.contains("\"line\":5"),
        "{problems}"
    );
}

#[test]
fn a_duplicated_column_name_never_picks_the_wrong_column() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("dup.txt");
    std::fs::write(&p, "# sample_rate_hz: 10\ngyro_x,gyro_x\n1,2\n3,4\n").unwrap();
    for channel in ["2", "gyro_x"] {
        cli!["adev", "--channels", channel, &p].refused(1, "columns 1 and 2 are both named 'gyro_x'");
    }
}

/// Runs `imutherm ARGS` with its standard output closed before it writes:
/// the reader has gone, as `| head -1` leaves it.
fn with_closed_stdout(args: &[&str]) -> (Option<i32>, String) {
    let mut child = Process::cargo_bin("imutherm")
        .unwrap()
        .args(args)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    drop(child.stdout.take());
    let mut err = String::new();
    child.stderr.take().unwrap().read_to_string(&mut err).unwrap();
    (child.wait().unwrap().code(), err)
}

#[test]
fn a_closed_standard_output_ends_quietly_with_status_0() {
    let dir = tempfile::tempdir().unwrap();
    let run = Simulation::new().duration("30").write(dir.path(), "run.txt");
    let run = run.to_str().unwrap();
    for args in [
        &["adev", run][..],
        &["info", run, "--json"],
        &["info", run],
        &["simulate", "--print-config"],
    ] {
        let (code, err) = with_closed_stdout(args);
        assert_eq!(code, Some(0), "{args:?}: {err}");
        assert!(
            !err.contains("panicked") && !err.contains("error"),
            "{args:?}: {err}"
        );
    }
    // And the usual `| head -1`, where the reader leaves after a line.
    let mut child = Process::cargo_bin("imutherm")
        .unwrap()
        .args(["adev", run])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut first = [0u8; 1];
    child.stdout.as_mut().unwrap().read_exact(&mut first).unwrap();
    drop(child.stdout.take());
    let status = child.wait().unwrap();
    assert_eq!(status.code(), Some(0));
}

#[test]
fn report_never_replaces_an_input_in_its_directory() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("rep");
    std::fs::create_dir(&out).unwrap();
    // A recording that happens to be called report.html in DIR.
    let input = simulate(&out, "report.html", "constant:30");
    let before = std::fs::read(&input).unwrap();
    let mut stray = std::fs::File::create(out.join("notes.txt")).unwrap();
    stray.write_all(b"mine").unwrap();
    cli!["report", &input, "--out", &out].refused(1, "destroy the data being read");
    assert_eq!(std::fs::read(&input).unwrap(), before);
    assert_eq!(std::fs::read(out.join("notes.txt")).unwrap(), b"mine");
    // Read from standard input, the same recording is still not written
    // over the file that happens to hold it.
    cli!["report", "-", "--out", &out]
        .pipe_stdin(&input)
        .unwrap()
        .assert()
        .code(1)
        .stderr(predicate::str::contains("was not written by imutherm"));
    assert_eq!(std::fs::read(&input).unwrap(), before);
}

#[test]
fn output_directories_replace_only_imutherms_own_files() {
    let dir = tempfile::tempdir().unwrap();
    let run = simulate(dir.path(), "run.txt", "constant:30");
    let out = dir.path().join("rep");
    for _ in 0..2 {
        // Run again into the same directory: its own report is replaced.
        cli!["report", &run, "--out", &out].assert().success();
    }
    let page = out.join("report.html");
    std::fs::write(&page, "my notes\n").unwrap();
    cli!["report", &run, "--out", &out].refused(1, "was not written by imutherm");
    assert_eq!(std::fs::read_to_string(&page).unwrap(), "my notes\n");

    // The demo checks all its names before simulating anything.
    let demo = dir.path().join("demo");
    std::fs::create_dir(&demo).unwrap();
    std::fs::write(demo.join("run_62C.txt"), "a run of my own\n").unwrap();
    let t0 = std::time::Instant::now();
    cli!["demo", "--quick", "--out", &demo].refused(1, "run_62C.txt exists and was not written by imutherm");
    assert!(t0.elapsed().as_secs_f64() < 5.0);
    assert_eq!(std::fs::read_dir(&demo).unwrap().count(), 1);
}
