//! Each command reads each input once. Fed a named pipe, which gives its
//! bytes to one reader once, a command that opened or read its input a
//! second time would wait for a writer that never comes (or read nothing):
//! so each command must give through a FIFO exactly what it gives from the
//! file, within a deadline. And every open of every input file, a robot
//! log's and each file of a ROS 2 bag included, is counted as the kernel
//! sees it.

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
fn report_and_the_compensation_read_a_fifo_as_they_read_the_file() {
    let (dir, constant, cooling) = runs();
    let d = dir.path();
    let same = |bytes: &[u8], name: &str| text(bytes).replace(name, "INPUT").replace("pipe.txt", "INPUT");

    // The fit keeps the run's digest: taken from the bytes the pipe gave,
    // it is the file's.
    let fit = |model: &str| ["tcal", "fit", "--overwrite", "-o", model].map(String::from);
    let o = run(d, &fit("from_file.json").each_ref().map(String::as_str), &cooling);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let o = through_fifo(d, &fit("from_pipe.json").each_ref().map(String::as_str), &cooling);
    assert!(o.status.success(), "through a FIFO: {}", text(&o.stderr));
    let from_file = std::fs::read(d.join("from_file.json")).unwrap();
    let from_pipe = std::fs::read(d.join("from_pipe.json")).unwrap();
    assert_eq!(same(&from_pipe, "cool.txt"), same(&from_file, "cool.txt"));
    assert!(text(&from_pipe).contains("\"fnv1a64:"), "{}", text(&from_pipe));

    // The evaluation knows the fitted run through the pipe by its digest.
    let args = ["tcal", "eval", "--json", "model.json"];
    let (file_eval, pipe_eval) = (run(d, &args, &cooling), through_fifo(d, &args, &cooling));
    assert!(pipe_eval.status.success(), "{}", text(&pipe_eval.stderr));
    assert_eq!(
        same(&pipe_eval.stdout, "cool.txt"),
        same(&file_eval.stdout, "cool.txt")
    );
    assert!(text(&pipe_eval.stdout).contains("\"held_out\": false"));

    // The report's page, every section of it from the one read.
    let (file_report, pipe_report) = (
        run(d, &["report", "--out", "from_file"], &constant),
        through_fifo(d, &["report", "--out", "from_pipe"], &constant),
    );
    assert!(file_report.status.success(), "{}", text(&file_report.stderr));
    assert!(pipe_report.status.success(), "{}", text(&pipe_report.stderr));
    let page = |out: &str| {
        let html = std::fs::read(d.join(out).join("report.html")).unwrap();
        same(&html, "run.txt").replace(out, "OUT")
    };
    assert_eq!(page("from_pipe"), page("from_file"));
    assert_eq!(
        same(&pipe_report.stderr, "run.txt").replace("from_pipe", "OUT"),
        same(&file_report.stderr, "run.txt").replace("from_file", "OUT")
    );
}

/// Counts the opens of the files in some directories through inotify
/// (inotify(7)): the kernel reports each `open` of a watched directory's
/// file as it happens, whoever opens it. Reads and closes are watched too,
/// so that two opens of one file are never merged into one event (the
/// kernel merges an event only with an identical one just before it).
struct Opens {
    fd: std::os::fd::OwnedFd,
    dirs: std::collections::HashMap<i32, PathBuf>,
}

impl Opens {
    fn watch(dirs: &[&Path]) -> Opens {
        use std::os::fd::FromRawFd;
        // SAFETY: inotify_init1 takes flags only; the descriptor it returns
        // is owned here and closed on drop.
        let raw = unsafe { libc::inotify_init1(libc::IN_NONBLOCK | libc::IN_CLOEXEC) };
        assert!(raw >= 0, "inotify: {}", std::io::Error::last_os_error());
        let fd = unsafe { std::os::fd::OwnedFd::from_raw_fd(raw) };
        let mut watched = std::collections::HashMap::new();
        for dir in dirs {
            let name = std::ffi::CString::new(dir.as_os_str().as_encoded_bytes()).unwrap();
            let mask = libc::IN_OPEN | libc::IN_ACCESS | libc::IN_CLOSE;
            // SAFETY: the descriptor is inotify's, the name a C string
            // that outlives the call.
            let wd = unsafe { libc::inotify_add_watch(raw, name.as_ptr(), mask) };
            assert!(
                wd >= 0,
                "inotify {}: {}",
                dir.display(),
                std::io::Error::last_os_error()
            );
            watched.insert(wd, dir.to_path_buf());
        }
        Opens { fd, dirs: watched }
    }

    /// The opens since the last call, by path (files only).
    fn take(&self) -> std::collections::BTreeMap<PathBuf, usize> {
        use std::os::fd::AsRawFd;
        const HEAD: usize = size_of::<libc::inotify_event>();
        let mut counts = std::collections::BTreeMap::new();
        let mut buf = vec![0u8; 1 << 16];
        loop {
            // SAFETY: reads into `buf`, which is as long as it is told.
            let n = unsafe { libc::read(self.fd.as_raw_fd(), buf.as_mut_ptr().cast(), buf.len()) };
            if n < 0 {
                let e = std::io::Error::last_os_error();
                assert_eq!(e.kind(), std::io::ErrorKind::WouldBlock, "inotify: {e}");
                return counts;
            }
            let mut at = 0;
            while at + HEAD <= n as usize {
                let field = |k: usize| u32::from_ne_bytes(buf[at + k..at + k + 4].try_into().unwrap());
                let (wd, mask, len) = (field(0) as i32, field(4), field(12) as usize);
                assert_eq!(mask & libc::IN_Q_OVERFLOW, 0, "inotify's queue overflowed");
                let name = &buf[at + HEAD..at + HEAD + len];
                let name = &name[..name.iter().position(|&b| b == 0).unwrap_or(len)];
                if mask & libc::IN_OPEN != 0 && mask & libc::IN_ISDIR == 0 && !name.is_empty() {
                    let path = self.dirs[&wd].join(std::str::from_utf8(name).unwrap());
                    *counts.entry(path).or_insert(0) += 1;
                }
                at += HEAD + len;
            }
        }
    }
}

/// A copy of a robot-log fixture (a file or a bag directory) in `dir`.
fn fixture(dir: &Path, name: &str) -> PathBuf {
    let from = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../robotlogs/tests/fixtures")
        .join(name);
    let to = dir.join(from.file_name().unwrap());
    if from.is_dir() {
        std::fs::create_dir(&to).unwrap();
        for e in std::fs::read_dir(&from).unwrap() {
            let e = e.unwrap();
            std::fs::copy(e.path(), to.join(e.file_name())).unwrap();
        }
    } else {
        std::fs::copy(&from, &to).unwrap();
    }
    to
}

#[test]
fn each_command_opens_each_input_file_once() {
    let (dir, constant, cooling) = runs();
    let d = dir.path();
    let gzip = d.join("cool.txt.gz");
    {
        use std::io::Write;
        let mut z =
            flate2::write::GzEncoder::new(std::fs::File::create(&gzip).unwrap(), flate2::Compression::fast());
        z.write_all(&std::fs::read(&cooling).unwrap()).unwrap();
        z.finish().unwrap();
    }
    let logs = tempfile::tempdir().unwrap();
    let l = logs.path();
    let ulog = fixture(l, "px4/sample_log_small.ulg");
    let mcap = fixture(l, "ros/imu_zstd.mcap");
    let ros1 = fixture(l, "ros/imu_bz2.bag");
    let dataflash = fixture(l, "ros/arducopter_imu.bin");
    let sqlite_bag = fixture(l, "ros/bag_sqlite3");
    let split_bag = fixture(l, "ros/bag_split");
    let text_commands: &[&[&str]] = &[
        &["info"],
        &["adev", "--json"],
        &["noise", "--json"],
        &["ins", "--json", "--horizon", "20", "--runs", "50"],
        &["report", "--out", "page"],
    ];
    // A run whose temperature changes, for the commands that model it.
    let thermal_commands: &[&[&str]] = &[
        &["thermal", "--json"],
        &["tcal", "fit", "--overwrite", "-o", "refit.json"],
        &["tcal", "eval", "--json", "model.json"],
        &[
            "tcal",
            "apply",
            "--overwrite",
            "-o",
            "compensated.txt",
            "model.json",
        ],
    ];
    // The analyses all read through one selection (`adev` stands for
    // `noise`, `ins`, `thermal`); `info` and `report` read their own way.
    let log_commands: &[&[&str]] = &[
        &["info"],
        &["adev", "--json", "--instance", "0"],
        &["report", "--instance", "0", "--out", "page"],
    ];
    // A flight controller's log of two IMUs: a fit for the firmware and
    // its evaluation take every instance from one read of the log.
    let dataflash_commands: &[&[&str]] = &[
        &["info"],
        &["adev", "--json", "--instance", "0"],
        &["report", "--instance", "0", "--out", "page"],
        &[
            "tcal",
            "fit",
            "--for",
            "ardupilot",
            "--overwrite",
            "-o",
            "vehicle.json",
        ],
        &["tcal", "eval", "--json", "vehicle.json"],
    ];
    let ros_commands: &[&[&str]] = &[&["info"], &["adev", "--json"], &["report", "--out", "page"]];
    // A gzip file is unpacked by the text reader, after the one open.
    let gzip_commands: &[&[&str]] = &[
        &["thermal", "--json"],
        &["tcal", "fit", "--overwrite", "-o", "refit.json"],
    ];
    let inputs: [(&str, &Path, &[&[&str]]); 9] = [
        ("text", &constant, text_commands),
        ("text, cooling", &cooling, thermal_commands),
        ("gzip text, cooling", &gzip, gzip_commands),
        ("ULog", &ulog, log_commands),
        ("MCAP", &mcap, ros_commands),
        ("ROS 1 bag", &ros1, ros_commands),
        ("DataFlash", &dataflash, dataflash_commands),
        ("ROS 2 bag (SQLite3)", &sqlite_bag, ros_commands),
        ("ROS 2 bag (MCAP, split)", &split_bag, ros_commands),
    ];
    let opens = Opens::watch(&[d, l, &sqlite_bag, &split_bag]);
    let mut table = Vec::new();
    for (kind, input, commands) in inputs {
        // The files of the input: a bag's every file, read once each.
        let files: Vec<PathBuf> = if input.is_dir() {
            let mut f: Vec<PathBuf> = std::fs::read_dir(input)
                .unwrap()
                .map(|e| e.unwrap().path())
                .collect();
            f.sort();
            f
        } else {
            vec![input.to_path_buf()]
        };
        for args in commands.iter() {
            opens.take();
            let o = run(d, args, input);
            assert!(o.status.success(), "{kind}: {args:?}: {}", text(&o.stderr));
            let counted = opens.take();
            let each: Vec<usize> = files
                .iter()
                .map(|f| counted.get(f).copied().unwrap_or(0))
                .collect();
            table.push(format!("{kind:<24} {:<40} {each:?}", args.join(" ")));
            assert!(
                each.iter().all(|&n| n == 1),
                "{kind}: imutherm {} opened its input files {each:?} times ({files:?}); every open: {counted:?}",
                args.join(" ")
            );
        }
    }
    // The count, for the record: kind, command, opens of each file.
    println!("{}", table.join("\n"));
}
