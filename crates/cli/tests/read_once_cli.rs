//! Each command reads each input once: fed a named pipe, which gives its
//! bytes to one reader once, a command that opened or read its input a
//! second time would wait for a writer that never comes (or read nothing).
//! So each analysis must give through a FIFO exactly what it gives from
//! the file, within a deadline; the commands that do read an input twice
//! refuse a FIFO before touching it, saying why.

#![cfg(unix)]

mod support;

use std::path::{Path, PathBuf};
use std::process::{Command as Process, Output, Stdio};
use std::time::{Duration, Instant};

use support::Simulation;

/// Far above any of these runs' times in a debug build: past it, the
/// command is taken to be waiting for a second read of the pipe.
const DEADLINE: Duration = Duration::from_secs(120);

fn mkfifo(path: &Path) {
    assert!(Process::new("mkfifo").arg(path).status().unwrap().success());
}

/// `imutherm ARGS INPUT` run in `dir` to its end, or killed at the
/// deadline. Its output goes to files (a full pipe would stall it).
fn run(dir: &Path, args: &[&str], input: &Path) -> Output {
    let capture = tempfile::tempdir().unwrap();
    let (out, err) = (capture.path().join("out"), capture.path().join("err"));
    let mut child = Process::new(env!("CARGO_BIN_EXE_imutherm"))
        .current_dir(dir)
        .args(args)
        .arg(input)
        .stdin(Stdio::null())
        .stdout(std::fs::File::create(&out).unwrap())
        .stderr(std::fs::File::create(&err).unwrap())
        .spawn()
        .unwrap();
    let start = Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait().unwrap() {
            break status;
        }
        if start.elapsed() > DEADLINE {
            child.kill().unwrap();
            panic!(
                "imutherm {} {} did not finish in {DEADLINE:?}: it waits for a second read of its input",
                args.join(" "),
                input.display()
            );
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    Output {
        status,
        stdout: std::fs::read(out).unwrap(),
        stderr: std::fs::read(err).unwrap(),
    }
}

/// The output of `args` on `file` given through a FIFO, the FIFO written
/// once from the file.
fn through_fifo(dir: &Path, args: &[&str], file: &Path) -> Output {
    let fifo = dir.join("pipe.txt");
    mkfifo(&fifo);
    let bytes = std::fs::read(file).unwrap();
    // Opening the FIFO to write waits for the command to open it to read;
    // the thread is left behind only when the test already fails.
    let writer = {
        let fifo = fifo.clone();
        std::thread::spawn(move || std::fs::write(fifo, bytes))
    };
    let out = run(dir, args, &fifo);
    writer.join().unwrap().unwrap();
    std::fs::remove_file(&fifo).unwrap();
    out
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

/// A short constant-temperature run and a cooling run with a model fitted
/// on it.
fn runs() -> (tempfile::TempDir, PathBuf, PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let sim = |profile: &str, seed: &str, name: &str| {
        Simulation::new()
            .profile(profile)
            .duration("300")
            .rate("20")
            .seed(seed)
            .write(dir.path(), name)
    };
    let constant = sim("constant:34", "1", "run.txt");
    let cooling = sim("cooling:80:20:150", "3", "cool.txt");
    let fit = run(dir.path(), &["tcal", "fit", "-o", "model.json"], &cooling);
    assert!(fit.status.success(), "{}", text(&fit.stderr));
    (dir, constant, cooling)
}

#[test]
fn every_analysis_gives_through_a_fifo_what_it_gives_from_the_file() {
    let (dir, constant, cooling) = runs();
    let d = dir.path();
    let out = d.join("compensated.txt");
    let commands: [(&[&str], &Path); 8] = [
        (&["info"], &constant),
        (&["info", "--json"], &cooling),
        (&["adev", "--json"], &constant),
        (&["noise", "--json"], &constant),
        (&["noise"], &constant),
        (&["ins", "--json", "--horizon", "20", "--runs", "50"], &constant),
        (&["thermal", "--json"], &cooling),
        (
            &[
                "tcal",
                "apply",
                "--overwrite",
                "-o",
                "compensated.txt",
                "model.json",
            ],
            &cooling,
        ),
    ];
    for (args, file) in commands {
        let from_file = run(d, args, file);
        assert!(
            from_file.status.success(),
            "{args:?}: {}",
            text(&from_file.stderr)
        );
        let written = std::fs::read(&out).ok();
        let piped = through_fifo(d, args, file);
        assert!(
            piped.status.success(),
            "{args:?} through a FIFO: {}",
            text(&piped.stderr)
        );
        // The same output; only the input's name differs.
        let name = file.file_name().unwrap().to_str().unwrap();
        let same = |o: &Output| {
            text(&o.stdout)
                .replace(name, "INPUT")
                .replace("pipe.txt", "INPUT")
        };
        assert_eq!(same(&piped), same(&from_file), "{args:?}");
        if let Some(written) = written {
            assert_eq!(
                std::fs::read(&out).unwrap(),
                written,
                "{args:?}: the file written"
            );
            std::fs::remove_file(&out).unwrap();
        }
    }
}

#[test]
fn the_commands_that_read_an_input_twice_refuse_a_fifo_before_opening_it() {
    let (dir, _, _) = runs();
    let d = dir.path();
    let fifo = d.join("pipe.txt");
    mkfifo(&fifo);
    // No writer: a command that opened the FIFO would wait until the
    // deadline.
    for (args, says) in [
        (
            &["report", "--out", "page"][..],
            "the report reads each recording more than once",
        ),
        (
            &["tcal", "fit", "-o", "m.json"][..],
            "the model keeps a digest of each fitted run",
        ),
        (&["tcal", "eval", "model.json"][..], "a digest of its bytes"),
    ] {
        let o = run(d, args, &fifo);
        let err = text(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{args:?}: {err}");
        assert!(
            err.contains(says) && err.contains("pipe.txt: ") && err.contains("save it to a file first"),
            "{args:?}: {err}"
        );
        assert!(!d.join("page").exists() && !d.join("m.json").exists(), "{args:?}");
    }
}
