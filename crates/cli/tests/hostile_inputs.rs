//! Hostile inputs and hostile directories, one named case per class: a
//! scratch name already taken (a link, a hard link, the user's own file,
//! an input), decompression bombs in every codec, ULog formats that nest
//! without end or contain themselves, offsets that point back, stamps that
//! give no clock, corrupt bytes inside a log, bags missing part of their
//! files, tables of absurd width.
//!
//! Every case is built here, tiny, and run under a 2 GiB address-space
//! limit and a 60 s time limit; each asserts the exit status, the message,
//! and what the directory holds afterwards (nothing written, nothing
//! destroyed).

use std::collections::BTreeMap;
use std::io::{Read, Write};
use std::os::unix::process::CommandExt;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use assert_cmd::cargo::CommandCargoExt;

mod support;
use support::scratch_files;

/// The address space each run may take: a bomb fails instead of paging.
const MEMORY: u64 = 2 << 30;
/// How long a run may take before it counts as a hang.
const TIME: Duration = Duration::from_secs(60);

struct Run {
    code: Option<i32>,
    stdout: String,
    stderr: String,
}

impl Run {
    /// Asserts the exit status and that stderr (or stdout) says each of `says`.
    fn expect(&self, code: i32, says: &[&str]) -> &Run {
        assert_eq!(
            self.code,
            Some(code),
            "stdout:\n{}\nstderr:\n{}",
            self.stdout,
            self.stderr
        );
        for s in says {
            assert!(
                self.stderr.contains(s) || self.stdout.contains(s),
                "expected {s:?}\nstdout:\n{}\nstderr:\n{}",
                self.stdout,
                self.stderr
            );
        }
        self
    }
}

/// Runs imutherm in `dir` under the memory and time limits.
fn run(dir: &Path, args: &[&str]) -> Run {
    let mut cmd = Command::cargo_bin("imutherm").unwrap();
    cmd.current_dir(dir)
        .args(args)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped());
    // SAFETY: setrlimit is async-signal-safe; nothing else runs between
    // fork and exec.
    unsafe {
        cmd.pre_exec(|| {
            let limit = libc::rlimit {
                rlim_cur: MEMORY,
                rlim_max: MEMORY,
            };
            if libc::setrlimit(libc::RLIMIT_AS, &limit) != 0 {
                return Err(std::io::Error::last_os_error());
            }
            Ok(())
        });
    }
    let mut child = cmd.spawn().unwrap();
    let drain = |mut r: Box<dyn Read + Send>| {
        std::thread::spawn(move || {
            let mut s = Vec::new();
            let _ = r.read_to_end(&mut s);
            String::from_utf8_lossy(&s).into_owned()
        })
    };
    let out = drain(Box::new(child.stdout.take().unwrap()));
    let err = drain(Box::new(child.stderr.take().unwrap()));
    let started = Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait().unwrap() {
            break status;
        }
        if started.elapsed() > TIME {
            let _ = child.kill();
            let _ = child.wait();
            panic!("imutherm {args:?} ran longer than {TIME:?}");
        }
        std::thread::sleep(Duration::from_millis(5));
    };
    Run {
        code: status.code(),
        stdout: out.join().unwrap(),
        stderr: err.join().unwrap(),
    }
}

/// Every entry of `dir` and below: its bytes, or where a link points.
fn snapshot(dir: &Path) -> BTreeMap<PathBuf, Vec<u8>> {
    let mut out = BTreeMap::new();
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        let meta = std::fs::symlink_metadata(&p).unwrap();
        if meta.file_type().is_symlink() {
            let mut v = b"link to ".to_vec();
            v.extend(std::fs::read_link(&p).unwrap().as_os_str().as_encoded_bytes());
            out.insert(p, v);
        } else if meta.is_dir() {
            out.extend(snapshot(&p));
        } else {
            out.insert(p.clone(), std::fs::read(&p).unwrap());
        }
    }
    out
}

/// A directory holding `files`.
fn dir_with(files: &[(&str, &[u8])]) -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    for (name, bytes) in files {
        let p = dir.path().join(name);
        if let Some(parent) = p.parent() {
            std::fs::create_dir_all(parent).unwrap();
        }
        std::fs::write(p, bytes).unwrap();
    }
    dir
}

/// Runs `args` on the files of `dir` and asserts that nothing in it changed.
fn read_only(dir: &tempfile::TempDir, args: &[&str]) -> Run {
    let before = snapshot(dir.path());
    let r = run(dir.path(), args);
    let after = snapshot(dir.path());
    let changed: Vec<&PathBuf> = before
        .keys()
        .chain(after.keys())
        .filter(|k| before.get(*k) != after.get(*k))
        .collect();
    assert!(changed.is_empty(), "{args:?} changed {changed:?}");
    r
}

/// PX4 ULog files (docs.px4.io, "ULog File Format").
mod ulog {
    pub const SYNC: [u8; 8] = [0x2F, 0x73, 0x13, 0x20, 0x25, 0x0C, 0xBB, 0x12];
    /// PX4's `msg/SensorCombined.msg`, 40 bytes of data.
    pub const COMBINED: &str = "sensor_combined:uint64_t timestamp;float[3] gyro_rad;uint32_t gyro_integral_dt;int32_t accelerometer_timestamp_relative;float[3] accelerometer_m_s2;";

    pub fn msg(ty: u8, body: &[u8]) -> Vec<u8> {
        let mut m = (body.len() as u16).to_le_bytes().to_vec();
        m.push(ty);
        m.extend_from_slice(body);
        m
    }

    pub fn header() -> Vec<u8> {
        let mut h = b"ULog\x01\x12\x35\x01".to_vec();
        h.extend(0u64.to_le_bytes());
        h
    }

    pub fn subscribe(name: &str) -> Vec<u8> {
        let mut b = vec![0u8, 0, 0];
        b.extend_from_slice(name.as_bytes());
        msg(b'A', &b)
    }

    /// One sensor_combined sample stamped `t_us`.
    pub fn sample(t_us: u64, k: usize) -> Vec<u8> {
        let mut b = 0u16.to_le_bytes().to_vec();
        b.extend(t_us.to_le_bytes());
        for axis in 0..3 {
            b.extend((((k * 7 + axis * 3) % 11) as f32 * 1e-3).to_le_bytes());
        }
        b.extend(4000u32.to_le_bytes());
        b.extend(0i32.to_le_bytes());
        // A still accelerometer: g on z, each axis with its own small
        // varying pattern, so that no channel check finds it stuck.
        for axis in 0..3 {
            let wobble = ((k * 5 + axis * 2) % 13) as f32 * 1e-3;
            b.extend((if axis == 2 { 9.81f32 + wobble } else { wobble }).to_le_bytes());
        }
        msg(b'D', &b)
    }

    /// A log of sensor_combined stamped `stamps` (µs), a sync message every
    /// 50 samples as PX4 writes them.
    pub fn log(stamps: &[u64]) -> Vec<u8> {
        let mut f = header();
        f.extend(msg(b'F', COMBINED.as_bytes()));
        f.extend(subscribe("sensor_combined"));
        for (k, &t) in stamps.iter().enumerate() {
            if k % 50 == 0 {
                f.extend(msg(b'S', &SYNC));
            }
            f.extend(sample(t, k));
        }
        f
    }

    /// `n` samples at 250 Hz.
    pub fn steady(n: usize) -> Vec<u64> {
        (0..n as u64).map(|k| 1_000_000 + 4000 * k).collect()
    }

    /// A log whose formats are `formats`, subscribing `topic`.
    pub fn with_formats(formats: &[String], topic: &str) -> Vec<u8> {
        let mut f = header();
        for x in formats {
            f.extend(msg(b'F', x.as_bytes()));
        }
        f.extend(subscribe(topic));
        f
    }
}

/// MCAP files (mcap.dev/spec).
mod mcap {
    pub fn record(op: u8, body: &[u8]) -> Vec<u8> {
        let mut r = vec![op];
        r.extend((body.len() as u64).to_le_bytes());
        r.extend_from_slice(body);
        r
    }

    pub fn string(s: &str) -> Vec<u8> {
        let mut b = (s.len() as u32).to_le_bytes().to_vec();
        b.extend_from_slice(s.as_bytes());
        b
    }

    /// Magic, header, and one chunk declaring `declared` bytes unpacked.
    pub fn with_chunk(declared: u64, compression: &str, data: &[u8]) -> Vec<u8> {
        let mut f = b"\x89MCAP0\r\n".to_vec();
        let mut h = string("ros2");
        h.extend(string("hostile"));
        f.extend(record(0x01, &h));
        let mut c = 0u64.to_le_bytes().to_vec();
        c.extend(1u64.to_le_bytes());
        c.extend(declared.to_le_bytes());
        c.extend(0u32.to_le_bytes());
        c.extend(string(compression));
        c.extend((data.len() as u64).to_le_bytes());
        c.extend_from_slice(data);
        f.extend(record(0x06, &c));
        f
    }
}

/// ROS 1 bags, format 2.0 (wiki.ros.org/Bags/Format/2.0).
mod bag {
    pub fn field(name: &str, value: &[u8]) -> Vec<u8> {
        let mut f = ((name.len() + 1 + value.len()) as u32).to_le_bytes().to_vec();
        f.extend_from_slice(name.as_bytes());
        f.push(b'=');
        f.extend_from_slice(value);
        f
    }

    pub fn record(header: &[u8], data: &[u8]) -> Vec<u8> {
        let mut r = (header.len() as u32).to_le_bytes().to_vec();
        r.extend_from_slice(header);
        r.extend((data.len() as u32).to_le_bytes());
        r.extend_from_slice(data);
        r
    }

    /// A bag of one chunk: `compression`, its `size` field, its data.
    pub fn with_chunk(compression: &str, size: Option<u32>, data: &[u8]) -> Vec<u8> {
        let mut f = b"#ROSBAG V2.0\n".to_vec();
        let mut h = field("op", &[0x05]);
        h.extend(field("compression", compression.as_bytes()));
        if let Some(s) = size {
            h.extend(field("size", &s.to_le_bytes()));
        }
        f.extend(record(&h, data));
        f
    }
}

fn bz2(data: &[u8]) -> Vec<u8> {
    let mut e = bzip2::write::BzEncoder::new(Vec::new(), bzip2::Compression::best());
    e.write_all(data).unwrap();
    e.finish().unwrap()
}

fn lz4(data: &[u8]) -> Vec<u8> {
    let mut e = lz4_flex::frame::FrameEncoder::new(Vec::new());
    e.write_all(data).unwrap();
    e.finish().unwrap()
}

fn zstd_of(data: &[u8]) -> Vec<u8> {
    zstd::encode_all(data, 19).unwrap()
}

/// A short simulated run, the input of the commands that write.
fn simulated(dir: &Path, name: &str) {
    run(
        dir,
        &[
            "simulate",
            "--duration",
            "20",
            "--rate",
            "50",
            "--seed",
            "1",
            "-o",
            name,
        ],
    )
    .expect(0, &[]);
}

// ---- scratch files ------------------------------------------------------

#[test]
fn scratch_old_name_symlinked_to_another_file_is_not_followed() {
    let dir = dir_with(&[("victim.txt", b"victim\n")]);
    std::os::unix::fs::symlink("victim.txt", dir.path().join("out.txt.partial")).unwrap();
    run(dir.path(), &["simulate", "--duration", "5", "-o", "out.txt"]).expect(0, &["wrote out.txt"]);
    assert_eq!(std::fs::read(dir.path().join("victim.txt")).unwrap(), b"victim\n");
    assert!(
        std::fs::symlink_metadata(dir.path().join("out.txt.partial"))
            .unwrap()
            .file_type()
            .is_symlink()
    );
}

#[test]
fn scratch_old_name_hard_linked_to_another_file_is_not_truncated() {
    let dir = dir_with(&[("victim.txt", b"victim\n")]);
    std::fs::hard_link(dir.path().join("victim.txt"), dir.path().join("out.txt.partial")).unwrap();
    run(dir.path(), &["simulate", "--duration", "5", "-o", "out.txt"]).expect(0, &[]);
    assert_eq!(std::fs::read(dir.path().join("victim.txt")).unwrap(), b"victim\n");
    assert_eq!(
        std::fs::read(dir.path().join("out.txt.partial")).unwrap(),
        b"victim\n"
    );
}

#[test]
fn scratch_name_holding_the_users_own_file_keeps_it() {
    let dir = dir_with(&[("out.txt.partial", b"my notes\n")]);
    run(dir.path(), &["simulate", "--duration", "5", "-o", "out.txt"]).expect(0, &[]);
    assert_eq!(
        std::fs::read(dir.path().join("out.txt.partial")).unwrap(),
        b"my notes\n"
    );
}

#[test]
fn scratch_name_of_a_killed_run_is_left_alone() {
    let stale = "out.txt.0123456789abcdef.partial";
    let dir = dir_with(&[(stale, b"half a run\n")]);
    run(dir.path(), &["simulate", "--duration", "5", "-o", "out.txt"]).expect(0, &[]);
    assert_eq!(std::fs::read(dir.path().join(stale)).unwrap(), b"half a run\n");
    assert_eq!(scratch_files(dir.path()), vec![stale.to_string()]);
}

#[test]
fn scratch_name_that_is_an_input_is_not_consumed() {
    let dir = tempfile::tempdir().unwrap();
    simulated(dir.path(), "run.txt.partial");
    let before = std::fs::read(dir.path().join("run.txt.partial")).unwrap();
    run(dir.path(), &["noise", "run.txt.partial", "--kalibr", "run.txt"]).expect(0, &[]);
    assert_eq!(std::fs::read(dir.path().join("run.txt.partial")).unwrap(), before);
    assert!(dir.path().join("run.txt").is_file());
}

#[test]
fn scratch_file_is_gone_after_a_write() {
    let dir = tempfile::tempdir().unwrap();
    run(dir.path(), &["simulate", "--duration", "5", "-o", "out.txt"]).expect(0, &[]);
    assert_eq!(scratch_files(dir.path()), Vec::<String>::new());
}

#[test]
fn output_onto_its_own_input_is_refused_by_a_hard_link() {
    let dir = tempfile::tempdir().unwrap();
    simulated(dir.path(), "run.txt");
    std::fs::hard_link(dir.path().join("run.txt"), dir.path().join("alias.txt")).unwrap();
    read_only(
        &dir,
        &["noise", "run.txt", "--kalibr", "alias.txt", "--overwrite"],
    )
    .expect(1, &["destroy the data being read"]);
}

#[test]
fn output_existing_is_refused_without_overwrite() {
    let dir = dir_with(&[("out.txt", b"precious\n")]);
    read_only(&dir, &["simulate", "--duration", "5", "-o", "out.txt"])
        .expect(1, &["already exists (9 bytes)"]);
}

#[test]
fn output_in_a_missing_directory_creates_nothing() {
    let dir = tempfile::tempdir().unwrap();
    read_only(
        &dir,
        &["simulate", "--duration", "5", "-o", "no/such/dir/out.txt"],
    )
    .expect(1, &["no/such/dir/out.txt"]);
}

// ---- decompression bombs -------------------------------------------------

#[test]
fn mcap_zstd_chunk_declaring_16_gib_is_refused_unread() {
    let dir = dir_with(&[(
        "bomb.mcap",
        &mcap::with_chunk(16 << 30, "zstd", &[0x28, 0xb5, 0x2f, 0xfd, 0, 0]),
    )]);
    read_only(&dir, &["info", "bomb.mcap"])
        .expect(1, &["17179869184 bytes uncompressed", "limit of 268435456"]);
}

#[test]
fn mcap_zstd_chunk_unpacking_past_its_declaration_is_refused() {
    let data = zstd_of(&vec![0u8; 64 << 20]);
    let dir = dir_with(&[("bomb.mcap", &mcap::with_chunk(1024, "zstd", &data))]);
    read_only(&dir, &["adev", "bomb.mcap"])
        .expect(1, &["zstd chunk unpacks to more than the 1024 bytes it declares"]);
}

#[test]
fn mcap_lz4_chunk_unpacking_past_its_declaration_is_refused() {
    let data = lz4(&vec![0u8; 64 << 20]);
    let dir = dir_with(&[("bomb.mcap", &mcap::with_chunk(4096, "lz4", &data))]);
    read_only(&dir, &["info", "bomb.mcap"])
        .expect(1, &["lz4 chunk unpacks to more than the 4096 bytes it declares"]);
}

#[test]
fn mcap_chunk_of_an_unknown_compression_is_named() {
    let dir = dir_with(&[("odd.mcap", &mcap::with_chunk(10, "brotli", b"0123456789"))]);
    read_only(&dir, &["info", "odd.mcap"]).expect(1, &["compressed with 'brotli'"]);
}

#[test]
fn mcap_chunk_shorter_than_its_declaration_is_refused() {
    let data = lz4(&[1u8; 100]);
    let dir = dir_with(&[("short.mcap", &mcap::with_chunk(1000, "lz4", &data))]);
    read_only(&dir, &["info", "short.mcap"]).expect(1, &["unpacks to 100 bytes, not the 1000 it declares"]);
}

#[test]
fn ros1_bz2_chunk_declaring_4_gib_is_refused_unread() {
    let dir = dir_with(&[("bomb.bag", &bag::with_chunk("bz2", Some(u32::MAX), b"BZh9"))]);
    read_only(&dir, &["info", "bomb.bag"]).expect(1, &["4294967295 bytes uncompressed", "limit of"]);
}

#[test]
fn ros1_bz2_chunk_unpacking_past_its_declaration_is_refused() {
    let data = bz2(&vec![0u8; 32 << 20]);
    let dir = dir_with(&[("bomb.bag", &bag::with_chunk("bz2", Some(1000), &data))]);
    read_only(&dir, &["info", "bomb.bag"])
        .expect(1, &["bz2 chunk unpacks to more than the 1000 bytes it declares"]);
}

#[test]
fn ros1_lz4_chunk_unpacking_past_its_declaration_is_refused() {
    let data = lz4(&vec![0u8; 64 << 20]);
    let dir = dir_with(&[("bomb.bag", &bag::with_chunk("lz4", Some(1000), &data))]);
    read_only(&dir, &["info", "bomb.bag"])
        .expect(1, &["lz4 chunk unpacks to more than the 1000 bytes it declares"]);
}

#[test]
fn ros1_compressed_chunk_without_its_size_is_refused() {
    let dir = dir_with(&[("nosize.bag", &bag::with_chunk("lz4", None, &lz4(b"x")))]);
    read_only(&dir, &["info", "nosize.bag"]).expect(1, &["a compressed chunk without its size field"]);
}

#[test]
fn ros1_chunk_of_an_unknown_compression_is_named() {
    let dir = dir_with(&[("odd.bag", &bag::with_chunk("xz", Some(1), b"x"))]);
    read_only(&dir, &["info", "odd.bag"]).expect(1, &["unsupported compression 'xz'"]);
}

// ---- ULog formats and offsets ------------------------------------------

#[test]
fn ulog_format_containing_itself_is_refused() {
    let f = ulog::with_formats(
        &["sensor_combined:uint64_t timestamp;sensor_combined inner;".into()],
        "sensor_combined",
    );
    let dir = dir_with(&[("loop.ulg", &f)]);
    read_only(&dir, &["info", "loop.ulg"]).expect(1, &["the format 'sensor_combined' contains itself"]);
}

#[test]
fn ulog_formats_containing_each_other_are_refused() {
    let f = ulog::with_formats(
        &[
            "a:uint8_t x;b y;".into(),
            "b:a z;".into(),
            "sensor_combined:uint64_t timestamp;a w;".into(),
        ],
        "sensor_combined",
    );
    let dir = dir_with(&[("cycle.ulg", &f)]);
    read_only(&dir, &["info", "cycle.ulg"]).expect(1, &["contains itself"]);
}

#[test]
fn ulog_formats_nested_exponentially_end_at_once() {
    // 30 levels, each holding the next four times: 4^30 visits if walked.
    let mut formats: Vec<String> = (0..30)
        .map(|k| format!("n{k}:n{0} a;n{0} b;n{0} c;n{0} d;", k + 1))
        .collect();
    formats.push("n30:uint8_t x;".into());
    formats.push("sensor_combined:uint64_t timestamp;n0 deep;".into());
    let dir = dir_with(&[("nest.ulg", &ulog::with_formats(&formats, "sensor_combined"))]);
    read_only(&dir, &["info", "nest.ulg"]).expect(1, &["larger than any message"]);
}

#[test]
fn ulog_formats_nested_too_deep_are_refused() {
    let mut formats: Vec<String> = (0..100).map(|k| format!("d{k}:d{} a;", k + 1)).collect();
    formats.push("d100:uint8_t x;".into());
    formats.push("sensor_combined:uint64_t timestamp;d0 deep;".into());
    let dir = dir_with(&[("deep.ulg", &ulog::with_formats(&formats, "sensor_combined"))]);
    read_only(&dir, &["info", "deep.ulg"]).expect(1, &["nests formats more than 32 deep"]);
}

#[test]
fn ulog_appended_offset_pointing_back_is_refused() {
    let mut f = ulog::header();
    let mut bits = vec![0u8; 40];
    bits[8] = 1;
    bits[16..24].copy_from_slice(&5u64.to_le_bytes());
    f.extend(ulog::msg(b'B', &bits));
    f.extend(ulog::log(&ulog::steady(10))[16..].to_vec());
    let dir = dir_with(&[("back.ulg", &f)]);
    read_only(&dir, &["info", "back.ulg"])
        .expect(1, &["appended-data offset (5) points back to before byte 59"]);
}

#[test]
fn ulog_format_lacking_a_field_names_the_format() {
    let f = ulog::with_formats(
        &["sensor_combined:uint64_t timestamp;float[3] gyro_rad;".into()],
        "sensor_combined",
    );
    let dir = dir_with(&[("lacking.ulg", &f)]);
    read_only(&dir, &["info", "lacking.ulg"]).expect(
        1,
        &["the format of sensor_combined has no field 'accelerometer_m_s2'"],
    );
}

#[test]
fn ulog_message_shorter_than_its_format_says_so() {
    let mut f = ulog::log(&[]);
    let mut short = 0u16.to_le_bytes().to_vec();
    short.extend([0u8; 20]);
    f.extend(ulog::msg(b'D', &short));
    let dir = dir_with(&[("short.ulg", &f)]);
    read_only(&dir, &["info", "short.ulg"]).expect(
        1,
        &["a sensor_combined message of 20 bytes is shorter than its format's 40 bytes"],
    );
}

#[test]
fn ulog_block_of_0xff_is_skipped_to_the_next_sync_and_counted() {
    let mut f = ulog::log(&ulog::steady(2000));
    let middle = f.len() / 2;
    f[middle..middle + 4096].fill(0xFF);
    let dir = dir_with(&[("ff.ulg", &f)]);
    let r = read_only(&dir, &["info", "ff.ulg"]);
    r.expect(
        0,
        &[
            "skipped: a message of unknown type 0xff, skipped to the next sync message",
            "% of the log",
        ],
    );
    assert!(!r.stdout.contains("problems     none"), "{}", r.stdout);
}

// ---- stamps --------------------------------------------------------------

#[test]
fn ulog_stamps_all_equal_are_refused_without_a_rate() {
    let dir = dir_with(&[("equal.ulg", &ulog::log(&[5_000_000; 300]))]);
    read_only(&dir, &["adev", "equal.ulg"]).expect(
        1,
        &["cannot time it", "299 repeat the previous stamp", "--rate HZ"],
    );
}

#[test]
fn ulog_stamps_all_zero_are_refused_without_a_rate() {
    let dir = dir_with(&[("zero.ulg", &ulog::log(&[0; 300]))]);
    read_only(&dir, &["adev", "zero.ulg"]).expect(1, &["cannot time it"]);
}

#[test]
fn ulog_stamps_reversed_are_refused_without_a_rate() {
    let mut t = ulog::steady(300);
    t.reverse();
    let dir = dir_with(&[("reversed.ulg", &ulog::log(&t))]);
    read_only(&dir, &["adev", "reversed.ulg"]).expect(1, &["cannot time it", "299 step back"]);
}

#[test]
fn ulog_stamps_all_equal_take_the_rate_given_and_say_so() {
    let dir = dir_with(&[("equal.ulg", &ulog::log(&[5_000_000; 300]))]);
    let r = read_only(&dir, &["adev", "equal.ulg", "--rate", "250"]);
    r.expect(0, &["cannot time it", "placed one per 1/250 s (--rate 250)"]);
    assert!(!r.stderr.contains("assuming 1 Hz"), "{}", r.stderr);
}

#[test]
fn ulog_one_stamp_back_is_a_problem_with_its_message_number() {
    let mut t = ulog::steady(300);
    t[100] = t[98];
    let dir = dir_with(&[("back.ulg", &ulog::log(&t))]);
    read_only(&dir, &["info", "back.ulg"]).expect(0, &["message 101"]);
}

#[test]
fn ulog_steady_stamps_read_without_a_problem() {
    let dir = dir_with(&[("good.ulg", &ulog::log(&ulog::steady(300)))]);
    read_only(&dir, &["info", "good.ulg"]).expect(0, &["250 Hz", "problems     none"]);
}

// ---- ROS 2 bag directories ----------------------------------------------

const YAML: &[u8] = b"rosbag2_bagfile_information:\n  version: 5\n  storage_identifier: mcap\n  relative_file_paths:\n    - part_0.mcap\n    - part_1.mcap\n  duration:\n    nanoseconds: 1\n";

#[test]
fn bag_missing_a_listed_file_is_refused() {
    let dir = dir_with(&[("bag/metadata.yaml", YAML), ("bag/part_0.mcap", b"\x89MCAP0\r\n")]);
    read_only(&dir, &["info", "bag"]).expect(1, &["the storage file part_1.mcap it lists is missing"]);
}

#[test]
fn bag_missing_every_listed_file_never_reads_a_stray_one() {
    let dir = dir_with(&[("bag/metadata.yaml", YAML), ("bag/stray.mcap", b"\x89MCAP0\r\n")]);
    let r = read_only(&dir, &["info", "bag"]);
    r.expect(1, &["part_0.mcap it lists is missing"]);
    assert!(!r.stderr.contains("stray"), "{}", r.stderr);
}

#[test]
fn bag_listing_a_path_outside_itself_is_refused() {
    let yaml = b"rosbag2_bagfile_information:\n  relative_file_paths:\n    - ../outside.mcap\n";
    let dir = dir_with(&[("bag/metadata.yaml", yaml), ("outside.mcap", b"\x89MCAP0\r\n")]);
    read_only(&dir, &["info", "bag"]).expect(1, &["lies outside the bag directory", "line 3"]);
}

#[test]
fn bag_listing_no_file_is_refused() {
    let dir = dir_with(&[
        (
            "bag/metadata.yaml",
            b"rosbag2_bagfile_information:\n  version: 5\n",
        ),
        ("bag/stray.mcap", b"x"),
    ]);
    read_only(&dir, &["info", "bag"]).expect(1, &["relative_file_paths lists no storage file"]);
}

// ---- tables --------------------------------------------------------------

#[test]
fn table_of_60000_columns_is_read_in_linear_time() {
    // Looked up column by column, 60 000 columns took over a minute.
    let row = vec!["1"; 60_000].join(",") + "\n";
    let dir = dir_with(&[("wide.csv", row.repeat(40).as_bytes())]);
    let started = Instant::now();
    read_only(&dir, &["adev", "wide.csv", "--rate", "100", "--json"]).expect(0, &[]);
    assert!(
        started.elapsed() < Duration::from_secs(30),
        "{:?}",
        started.elapsed()
    );
}

/// A gzip table of `rows` rows of `columns` zeros, 4 MB at most: one
/// member repeated (members read as their concatenation), so that each
/// kilobyte stands for a megabyte of text and four of samples.
fn gzip_of_long_rows(columns: usize, rows: usize) -> Vec<u8> {
    let row = vec!["0"; columns].join(",") + "\n";
    let mut e = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::best());
    e.write_all(row.as_bytes()).unwrap();
    let member = e.finish().unwrap();
    let bytes = member.repeat(rows);
    assert!(bytes.len() <= 4 << 20, "{}", bytes.len());
    bytes
}

#[test]
fn gzip_of_long_rows_unpacking_past_the_memory_limit_is_refused_at_its_line() {
    // 2 GB of text, 8 GB of samples: the columns read stop at a quarter of
    // the address space this run may take, at the line that crosses it,
    // where the allocator used to abort.
    let dir = dir_with(&[("long.csv.gz", &gzip_of_long_rows(20_000, 50_000))]);
    let r = read_only(&dir, &["adev", "long.csv.gz", "--rate", "100"]);
    r.expect(1, &["MiB a read may take", "read fewer columns"]);
    let line: u64 = r
        .stderr
        .split("long.csv.gz:")
        .nth(1)
        .and_then(|s| s.split(':').next())
        .and_then(|l| l.parse().ok())
        .unwrap_or_else(|| panic!("no line in {:?}", r.stderr));
    // 512 MiB of samples are 3355 rows of 20 000.
    assert!((3000..=3400).contains(&line), "{line}");
}

#[test]
fn gzip_of_long_rows_within_the_limit_reads_whole() {
    let dir = dir_with(&[("long.csv.gz", &gzip_of_long_rows(100_000, 40))]);
    read_only(&dir, &["info", "long.csv.gz"]).expect(0, &["samples      40 (40 lines)"]);
}

// ---- absurd numbers on the command line ---------------------------------

#[test]
fn simulate_profile_at_1e308_degrees_is_a_usage_error() {
    let dir = tempfile::tempdir().unwrap();
    read_only(
        &dir,
        &[
            "simulate",
            "--profile",
            "constant:1e308",
            "--duration",
            "5",
            "-o",
            "x.txt",
        ],
    )
    .expect(2, &["--profile", "is beyond physics"]);
}

#[test]
fn simulate_profile_below_absolute_zero_is_a_usage_error() {
    let dir = tempfile::tempdir().unwrap();
    read_only(
        &dir,
        &[
            "simulate",
            "--profile",
            "ramp:-300:20:60",
            "--duration",
            "5",
            "-o",
            "x.txt",
        ],
    )
    .expect(2, &["profile.from_c = -300", "absolute zero"]);
}

#[test]
fn tcal_reference_temperature_beyond_physics_is_a_usage_error() {
    let dir = tempfile::tempdir().unwrap();
    simulated(dir.path(), "run.txt");
    read_only(&dir, &["tcal", "fit", "run.txt", "--tref", "1e6", "-o", "m.json"])
        .expect(2, &["between absolute zero (-273.15) and 1000"]);
}

#[test]
fn ins_alignment_shorter_than_a_sample_is_a_usage_error() {
    let dir = tempfile::tempdir().unwrap();
    simulated(dir.path(), "run.txt");
    read_only(&dir, &["ins", "run.txt", "--align", "1e-9"])
        .expect(2, &["--align", "shorter than one sample of run.txt (50 Hz"]);
}

// ---- ambiguity -------------------------------------------------------------

/// 400 rows of two gyro columns: the first in deg/s, the second in rad/s.
fn two_gyro_x(header: &str) -> Vec<u8> {
    let mut t = format!("{header}\n");
    for k in 0..400 {
        t.push_str(&format!(
            "{},{}\n",
            (k % 7) as f64 - 3.0,
            ((k % 5) as f64 - 2.0) * 0.017
        ));
    }
    t.into_bytes()
}

#[test]
fn two_columns_with_units_resolving_to_one_channel_are_refused() {
    let dir = dir_with(&[("dup.csv", &two_gyro_x("gyro_x[deg/s],gyro_x[rad/s]"))]);
    read_only(
        &dir,
        &["adev", "dup.csv", "--rate", "100", "--channels", "gyro_x"],
    )
    .expect(
        1,
        &["columns 1 ('gyro_x[deg/s]') and 2 ('gyro_x[rad/s]') resolve to one channel, gyro_x"],
    );
}

#[test]
fn two_columns_resolving_to_one_channel_are_refused_by_default() {
    let dir = dir_with(&[("gx.csv", &two_gyro_x("gx,gyro_x"))]);
    read_only(&dir, &["adev", "gx.csv", "--rate", "100"])
        .expect(1, &["columns 1 ('gx') and 2 ('gyro_x')", "--channels 'gx'"]);
}

#[test]
fn a_full_header_names_its_column_among_look_alikes() {
    let dir = dir_with(&[("dup.csv", &two_gyro_x("gyro_x[deg/s],gyro_x[rad/s]"))]);
    read_only(
        &dir,
        &["adev", "dup.csv", "--rate", "100", "--channels", "gyro_x[rad/s]"],
    )
    .expect(0, &["column 2 'gyro_x' [rad/s]"]);
    let dir = dir_with(&[("gx.csv", &two_gyro_x("gx,gyro_x"))]);
    read_only(&dir, &["adev", "gx.csv", "--rate", "100", "--channels", "gyro_x"])
        .expect(0, &["column 2 'gyro_x'"]);
}

// ---- DataFlash -------------------------------------------------------------

/// ArduPilot DataFlash logs (ArduPilot `libraries/AP_Logger/LogStructure.h`).
mod dataflash {
    fn fmt(ty: u8, length: u8, name: &str, format: &str, labels: &str) -> Vec<u8> {
        let mut m = vec![0xA3, 0x95, 128, ty, length];
        let pad = |s: &str, n: usize| {
            let mut b = s.as_bytes().to_vec();
            b.resize(n, 0);
            b
        };
        m.extend(pad(name, 4));
        m.extend(pad(format, 16));
        m.extend(pad(labels, 64));
        m
    }

    /// A log of `n` IMU messages at 400 Hz whose FMT gives IMU `length`
    /// bytes (36 is right: 3 head bytes, `Q`, `B` and six `f`).
    pub fn log(n: usize, length: u8) -> Vec<u8> {
        let mut f = fmt(128, 89, "FMT", "BBnNZ", "Type,Length,Name,Format,Columns");
        f.extend(fmt(
            129,
            length,
            "IMU",
            "QBffffff",
            "TimeUS,I,GyrX,GyrY,GyrZ,AccX,AccY,AccZ",
        ));
        for k in 0..n {
            f.extend([0xA3, 0x95, 129]);
            f.extend((1_000_000 + 2500 * k as u64).to_le_bytes());
            f.push(0);
            // Gyros near zero, a still accelerometer with g on z.
            for axis in 0..6 {
                let g = if axis == 5 { 9.81f32 } else { 0.0 };
                f.extend((g + ((k * 7 + axis * 3) % 11) as f32 * 1e-3).to_le_bytes());
            }
        }
        f
    }
}

#[test]
fn dataflash_read_whole_without_a_problem() {
    let dir = dir_with(&[("good.bin", &dataflash::log(400, 36))]);
    read_only(&dir, &["info", "good.bin"]).expect(0, &["400 Hz", "problems     none"]);
}

#[test]
fn dataflash_fmt_lying_about_a_length_is_named_and_its_losses_counted() {
    let dir = dir_with(&[("lying.bin", &dataflash::log(400, 56))]);
    let r = read_only(&dir, &["info", "lying.bin"]);
    r.expect(
        0,
        &[
            "the FMT of IMU (type 129)",
            "gives a length of 56 bytes, but its fields take 36",
            "% of the log",
        ],
    );
    assert!(!r.stdout.contains("problems     none"), "{}", r.stdout);
}

// ---- models and streams ------------------------------------------------------

#[test]
fn model_in_furlongs_is_refused_before_it_touches_data() {
    let dir = tempfile::tempdir().unwrap();
    run(
        dir.path(),
        &[
            "simulate",
            "--profile",
            "ramp:25:70:1200",
            "--duration",
            "20m",
            "--rate",
            "2",
            "-o",
            "ramp.txt",
        ],
    )
    .expect(0, &[]);
    run(
        dir.path(),
        &["tcal", "fit", "ramp.txt", "--order", "2", "-o", "model.json"],
    )
    .expect(0, &[]);
    let text = std::fs::read_to_string(dir.path().join("model.json")).unwrap();
    let spoilt = text.replacen("\"unit\": \"m/s^2\"", "\"unit\": \"furlong\"", 1);
    assert_ne!(spoilt, text);
    std::fs::write(dir.path().join("model.json"), spoilt).unwrap();
    read_only(
        &dir,
        &["tcal", "apply", "model.json", "ramp.txt", "-o", "out.txt"],
    )
    .expect(1, &["channels[0].unit is 'furlong', not m/s^2"]);
}

// ---- more of each class --------------------------------------------------

/// A fixture of the robotlogs crate: real logs from PX4 and ROS.
fn fixture(path: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../robotlogs/tests/fixtures")
        .join(path)
}

#[test]
fn scratch_file_locked_by_a_running_writer_refuses_a_second() {
    let dir = tempfile::tempdir().unwrap();
    let other = dir.path().join("out.txt.0123456789abcdef.partial");
    let held = std::fs::File::create(&other).unwrap();
    held.lock().unwrap();
    read_only(&dir, &["simulate", "--duration", "5", "-o", "out.txt"])
        .expect(1, &["being written by another process"]);
    drop(held);
}

#[test]
fn mcap_chunk_inside_a_chunk_is_refused() {
    let inner = mcap::record(0x06, &[0u8; 40]);
    let dir = dir_with(&[("nested.mcap", &mcap::with_chunk(inner.len() as u64, "", &inner))]);
    read_only(&dir, &["info", "nested.mcap"]).expect(1, &["a chunk inside a chunk"]);
}

#[test]
fn mcap_record_running_past_its_chunk_is_refused() {
    let mut inner = vec![0x03u8];
    inner.extend(u64::MAX.to_le_bytes());
    let dir = dir_with(&[("past.mcap", &mcap::with_chunk(inner.len() as u64, "", &inner))]);
    read_only(&dir, &["info", "past.mcap"]).expect(1, &["runs past the end of its chunk"]);
}

#[test]
fn bag_listing_an_absolute_path_is_refused() {
    let yaml = b"rosbag2_bagfile_information:\n  relative_file_paths:\n    - /etc/passwd\n";
    let dir = dir_with(&[("bag/metadata.yaml", yaml)]);
    read_only(&dir, &["info", "bag"]).expect(1, &["/etc/passwd lies outside the bag directory"]);
}

#[test]
fn bag_reads_its_listed_file_and_never_a_corrupt_stray_one() {
    let bag = fixture("ros/bag_mcap");
    let dir = dir_with(&[
        (
            "bag/metadata.yaml",
            &std::fs::read(bag.join("metadata.yaml")).unwrap(),
        ),
        (
            "bag/bag_mcap.mcap",
            &std::fs::read(bag.join("bag_mcap.mcap")).unwrap(),
        ),
        ("bag/zz_stray.mcap", b"\x89MCAP0\r\n garbage"),
    ]);
    read_only(&dir, &["info", "bag"]).expect(0, &["problems     none"]);
}

#[test]
fn bag_of_two_files_missing_its_second_is_refused() {
    let bag = fixture("ros/bag_split");
    let dir = dir_with(&[
        (
            "bag/metadata.yaml",
            &std::fs::read(bag.join("metadata.yaml")).unwrap(),
        ),
        (
            "bag/bag_split_0.mcap",
            &std::fs::read(bag.join("bag_split_0.mcap")).unwrap(),
        ),
    ]);
    read_only(&dir, &["info", "bag"]).expect(1, &["the storage file bag_split_1.mcap it lists is missing"]);
}

/// The split bag without its second file, its metadata.yaml given the
/// per-file counts rosbag2 writes (`files:`, `rosbag2_storage/yaml.hpp`).
fn split_bag_missing_its_second() -> tempfile::TempDir {
    let bag = fixture("ros/bag_split");
    let mut yaml = std::fs::read(bag.join("metadata.yaml")).unwrap();
    yaml.extend(b"  files:\n    - path: bag_split_0.mcap\n      message_count: 503\n    - path: bag_split_1.mcap\n      message_count: 503\n");
    dir_with(&[
        ("bag/metadata.yaml", &yaml),
        (
            "bag/bag_split_0.mcap",
            &std::fs::read(bag.join("bag_split_0.mcap")).unwrap(),
        ),
    ])
}

#[test]
fn bag_missing_a_listed_file_reads_the_rest_with_allow_partial_and_counts_the_loss() {
    let dir = split_bag_missing_its_second();
    read_only(&dir, &["info", "bag"]).expect(1, &["bag_split_1.mcap it lists is missing"]);
    read_only(&dir, &["info", "bag", "--allow-partial"]).expect(
        0,
        &[
            "500 messages read",
            "problems     1",
            "the storage file bag_split_1.mcap that metadata.yaml lists is missing, read without it as allowed: its 503 messages (by metadata.yaml) are not read",
        ],
    );
    let r = read_only(&dir, &["info", "bag", "--allow-partial", "--json"]);
    r.expect(0, &[]);
    let doc: serde_json::Value = serde_json::from_str(&r.stdout).unwrap();
    let problems = doc["files"][0]["problems"].as_array().unwrap();
    assert!(
        problems.iter().any(|p| p["kind"] == "skipped_data"
            && p["count"] == 503
            && p["message"].as_str().unwrap().contains("bag_split_1.mcap")),
        "{problems:?}"
    );
    // An analysis reads the same and warns of the same loss.
    read_only(&dir, &["adev", "bag", "--allow-partial"]).expect(0, &["bag_split_1.mcap"]);
}

#[test]
fn bag_missing_every_listed_file_is_refused_even_with_allow_partial() {
    let dir = dir_with(&[("bag/metadata.yaml", YAML), ("bag/stray.mcap", b"\x89MCAP0\r\n")]);
    let r = read_only(&dir, &["info", "bag", "--allow-partial"]);
    r.expect(1, &["every storage file it lists is missing, from part_0.mcap"]);
    assert!(!r.stderr.contains("stray"), "{}", r.stderr);
}

#[test]
fn allow_partial_on_a_text_log_is_refused_by_name() {
    let dir = dir_with(&[("t.csv", b"gyro_x\n1\n2\n3\n")]);
    read_only(&dir, &["info", "t.csv", "--allow-partial"])
        .expect(1, &["--allow-partial applies to robot logs"]);
}

/// A log of sensor_combined whose timestamp is a double (µs), so that a
/// stamp can be NaN.
fn ulog_double_stamps(stamps: &[f64]) -> Vec<u8> {
    let mut f = ulog::header();
    let format = ulog::COMBINED.replace("uint64_t timestamp", "double timestamp");
    f.extend(ulog::msg(b'F', format.as_bytes()));
    f.extend(ulog::subscribe("sensor_combined"));
    for (k, &t) in stamps.iter().enumerate() {
        let mut d = ulog::sample(0, k);
        d[5..13].copy_from_slice(&t.to_le_bytes());
        f.extend(d);
    }
    f
}

#[test]
fn ulog_stamps_all_nan_are_refused_and_called_nan() {
    let dir = dir_with(&[("nan.ulg", &ulog_double_stamps(&[f64::NAN; 300]))]);
    read_only(&dir, &["adev", "nan.ulg"])
        .expect(1, &["cannot time it", "300 have a zero, negative or NaN stamp"]);
}

#[test]
fn ulog_one_nan_stamp_is_a_problem_with_its_message_number() {
    let mut t: Vec<f64> = (0..300).map(|k| 1e6 + 4000.0 * k as f64).collect();
    t[41] = f64::NAN;
    let dir = dir_with(&[("one_nan.ulg", &ulog_double_stamps(&t))]);
    read_only(&dir, &["info", "one_nan.ulg"])
        .expect(0, &["message 42 has no usable stamp (zero, negative or NaN)"]);
}

#[test]
fn ulog_stamps_reversed_take_the_rate_given_and_say_so() {
    let mut t = ulog::steady(300);
    t.reverse();
    let dir = dir_with(&[("reversed.ulg", &ulog::log(&t))]);
    read_only(&dir, &["adev", "reversed.ulg", "--rate", "250"])
        .expect(0, &["299 step back", "placed one per 1/250 s"]);
}

#[test]
fn ulog_appended_offsets_out_of_order_are_refused() {
    let mut f = ulog::header();
    let mut bits = vec![0u8; 40];
    bits[8] = 1;
    bits[16..24].copy_from_slice(&5000u64.to_le_bytes());
    bits[24..32].copy_from_slice(&4000u64.to_le_bytes());
    f.extend(ulog::msg(b'B', &bits));
    f.extend(ulog::log(&ulog::steady(300))[16..].to_vec());
    let dir = dir_with(&[("order.ulg", &f)]);
    read_only(&dir, &["info", "order.ulg"]).expect(
        1,
        &["appended-data offset (4000) points back to before byte 5000"],
    );
}

#[test]
fn ulog_garbage_with_no_sync_after_it_is_counted_to_the_end() {
    let mut f = ulog::log(&ulog::steady(300));
    let good = f.len();
    f.extend([0xEEu8; 2000]);
    let dir = dir_with(&[("tail.ulg", &f)]);
    read_only(&dir, &["info", "tail.ulg"]).expect(
        0,
        &[
            &format!("bytes {good}..{} (2000 bytes) skipped", good + 2000),
            "with no sync message after it",
        ],
    );
}

#[test]
fn ulog_real_px4_log_with_a_block_of_0xff_reports_what_it_skipped() {
    let mut bytes = std::fs::read(fixture("px4/sample_log_small.ulg")).unwrap();
    let middle = bytes.len() / 2;
    bytes[middle..middle + 4096].fill(0xFF);
    let dir = dir_with(&[("px4.ulg", &bytes)]);
    let r = read_only(&dir, &["info", "px4.ulg"]);
    r.expect(
        0,
        &["skipped: a message of unknown type 0xff, skipped to the next sync message"],
    );
    assert!(!r.stdout.contains("problems     none"), "{}", r.stdout);
}

#[test]
fn tcal_reference_below_absolute_zero_is_a_usage_error() {
    let dir = tempfile::tempdir().unwrap();
    simulated(dir.path(), "run.txt");
    read_only(&dir, &["tcal", "fit", "run.txt", "--tref=-300", "-o", "m.json"]).expect(2, &["--tref"]);
}

#[test]
fn simulate_steps_beyond_physics_is_a_usage_error() {
    let dir = tempfile::tempdir().unwrap();
    read_only(
        &dir,
        &[
            "simulate",
            "--profile",
            "steps:30,2000:60",
            "--duration",
            "5",
            "-o",
            "x.txt",
        ],
    )
    .expect(2, &["profile.levels_c = 2000", "beyond physics"]);
}

#[test]
fn simulate_cooling_from_1e308_is_a_usage_error() {
    let dir = tempfile::tempdir().unwrap();
    read_only(
        &dir,
        &[
            "simulate",
            "--profile",
            "cooling:1e308:20:60",
            "--duration",
            "5",
            "-o",
            "x.txt",
        ],
    )
    .expect(2, &["profile.start_c", "beyond physics"]);
}

#[test]
fn model_in_degrees_per_second_is_refused_for_data_in_radians() {
    let dir = tempfile::tempdir().unwrap();
    run(
        dir.path(),
        &[
            "simulate",
            "--profile",
            "ramp:25:70:1200",
            "--duration",
            "20m",
            "--rate",
            "2",
            "-o",
            "ramp.txt",
        ],
    )
    .expect(0, &[]);
    run(
        dir.path(),
        &["tcal", "fit", "ramp.txt", "--order", "2", "-o", "model.json"],
    )
    .expect(0, &[]);
    let text = std::fs::read_to_string(dir.path().join("model.json")).unwrap();
    let spoilt = text.replacen("\"unit\": \"rad/s\"", "\"unit\": \"deg/s\"", 1);
    assert_ne!(spoilt, text);
    std::fs::write(dir.path().join("model.json"), spoilt).unwrap();
    read_only(&dir, &["tcal", "eval", "model.json", "ramp.txt"]).expect(1, &["is 'deg/s', not rad/s"]);
}

#[test]
fn info_of_values_near_the_largest_double_names_the_overflow() {
    let mut t = String::from("gyro_x\n");
    for k in 0..40 {
        t.push_str(if k % 2 == 0 { "1e308\n" } else { "-1e308\n" });
    }
    let dir = dir_with(&[("big.csv", t.as_bytes())]);
    let r = read_only(&dir, &["info", "big.csv"]);
    r.expect(
        0,
        &["gyro_x: its values (-1e308 to 1e308) overflow double precision"],
    );
    assert!(!r.stdout.contains("problems     none"), "{}", r.stdout);
}

/// 300 rows of a gyro whose time column is `t(k)`.
fn timed(t: impl Fn(usize) -> f64) -> Vec<u8> {
    let mut s = String::from("time_s,gyro_x\n");
    for k in 0..300 {
        s.push_str(&format!("{},{}\n", t(k), (k % 7) as f64 * 0.01));
    }
    s.into_bytes()
}

#[test]
fn table_time_column_all_zero_is_refused_not_taken_for_1_hz() {
    let dir = dir_with(&[("zero.csv", &timed(|_| 0.0))]);
    let r = read_only(&dir, &["adev", "zero.csv"]);
    r.expect(
        1,
        &[
            "the time column cannot time the samples",
            "299 repeat the previous stamp",
            "--rate HZ",
        ],
    );
    assert!(!r.stderr.contains("assuming 1 Hz"), "{}", r.stderr);
}

#[test]
fn table_time_column_running_backwards_is_refused_not_taken_for_1_hz() {
    let dir = dir_with(&[("back.csv", &timed(|k| 300.0 - 0.01 * k as f64))]);
    read_only(&dir, &["adev", "back.csv"]).expect(
        1,
        &["back.csv:3", "runs backwards", "299 of its 299 steps go back"],
    );
    // A given rate does not make the rows' order right: still refused.
    read_only(&dir, &["adev", "back.csv", "--rate", "100"]).expect(1, &["back.csv:3", "runs backwards"]);
}

#[test]
fn sqlite_bag_with_a_text_timestamp_names_the_column() {
    let dir = tempfile::tempdir().unwrap();
    let db = rusqlite::Connection::open(dir.path().join("bag.db3")).unwrap();
    db.execute_batch(
        "CREATE TABLE topics(id INTEGER PRIMARY KEY, name TEXT, type TEXT, serialization_format TEXT);
         CREATE TABLE messages(id INTEGER PRIMARY KEY, topic_id INTEGER, timestamp INTEGER, data BLOB);
         INSERT INTO topics VALUES (1, '/imu', 'sensor_msgs/msg/Imu', 'cdr');
         INSERT INTO messages VALUES (1, 1, 'yesterday', x'00');",
    )
    .unwrap();
    drop(db);
    read_only(&dir, &["info", "bag.db3"]).expect(
        1,
        &["(message 1): SQLite: the timestamp column of the messages table holds Text, not INTEGER"],
    );
}

#[test]
fn sqlite_bag_with_one_row_that_cannot_decode_skips_it_and_counts_it() {
    // The fixture's rows, one of them given a text timestamp and another
    // a cut message: each stands alone in its row, so the rest reads.
    let dir = tempfile::tempdir().unwrap();
    let bag = dir.path().join("bag.db3");
    std::fs::copy(fixture("ros/bag_sqlite3/bag_sqlite3.db3"), &bag).unwrap();
    let db = rusqlite::Connection::open(&bag).unwrap();
    let (a, b): (i64, i64) = db
        .query_row(
            "SELECT min(id), max(id) FROM messages WHERE topic_id = (SELECT id FROM topics WHERE type = 'sensor_msgs/msg/Imu')",
            [],
            |r| Ok((r.get(0)?, r.get(1)?)),
        )
        .unwrap();
    let (text, cut) = (a + 10, (a + b) / 2);
    db.execute(
        "UPDATE messages SET timestamp = 'yesterday' WHERE id = ?1",
        [text],
    )
    .unwrap();
    db.execute("UPDATE messages SET data = x'000100' WHERE id = ?1", [cut])
        .unwrap();
    drop(db);
    let r = read_only(&dir, &["info", "bag.db3"]);
    r.expect(
        0,
        &[
            "998 messages read",
            // The two skipped, and the two gaps they leave on the clock.
            "problems     4",
            &format!("(row id {text}) skipped: SQLite: the timestamp column of the messages table holds Text, not INTEGER"),
            &format!("(row id {cut}) on /imu/data skipped: malformed CDR message"),
        ],
    );
    assert!(!r.stdout.contains("problems     none"), "{}", r.stdout);
}

/// The records of an MCAP file after its magic: (opcode, start, length).
fn mcap_records(f: &[u8]) -> Vec<(u8, usize, usize)> {
    let mut out = Vec::new();
    let mut at = 8;
    while at + 9 <= f.len() {
        let len = u64::from_le_bytes(f[at + 1..at + 9].try_into().unwrap()) as usize;
        out.push((f[at], at, len));
        if f[at] == 0x02 {
            break;
        }
        at += 9 + len;
    }
    out
}

#[test]
fn mcap_chunk_of_corrupt_bytes_is_skipped_by_its_length_and_counted() {
    let mut f = std::fs::read(fixture("ros/imu_zstd.mcap")).unwrap();
    let chunks: Vec<(usize, usize)> = mcap_records(&f)
        .into_iter()
        .filter(|r| r.0 == 0x06)
        .map(|r| (r.1, r.2))
        .collect();
    assert_eq!(chunks.len(), 6);
    let (start, len) = chunks[1];
    // Its compressed records, in the last part of the record, garbled.
    for b in &mut f[start + 9 + len / 2..start + 9 + len / 2 + 64] {
        *b ^= 0x5a;
    }
    let dir = dir_with(&[("corrupt.mcap", &f)]);
    let end = start + 9 + len;
    read_only(&dir, &["info", "corrupt.mcap"]).expect(
        0,
        &[&format!(
            "bytes {start}..{end} ({} bytes) skipped: a corrupt MCAP chunk",
            9 + len
        )],
    );
}

#[test]
fn mcap_first_chunk_corrupt_with_the_channels_in_it_says_so() {
    let mut f = std::fs::read(fixture("ros/imu_zstd.mcap")).unwrap();
    let (_, start, len) = mcap_records(&f).into_iter().find(|r| r.0 == 0x06).unwrap();
    for b in &mut f[start + 9 + len / 2..start + 9 + len / 2 + 64] {
        *b ^= 0x5a;
    }
    let dir = dir_with(&[("corrupt.mcap", &f)]);
    read_only(&dir, &["info", "corrupt.mcap"]).expect(
        1,
        &[&format!(
            "are on channels defined only in a corrupt chunk that was skipped (bytes {start}..{}): none can be read",
            start + 9 + len
        )],
    );
}

/// The chunk records of a ROS 1 bag (format 2.0): (start, end, where
/// the data starts).
fn ros1_chunks(f: &[u8]) -> Vec<(usize, usize, usize)> {
    let u32_at = |at: usize| u32::from_le_bytes(f[at..at + 4].try_into().unwrap()) as usize;
    let mut out = Vec::new();
    let mut at = 13;
    while at + 4 <= f.len() {
        let header = &f[at + 4..at + 4 + u32_at(at)];
        let data_at = at + 4 + header.len();
        let end = data_at + 4 + u32_at(data_at);
        if header.windows(4).any(|w| w == b"op=\x05") {
            out.push((at, end, data_at + 4));
        }
        at = end;
    }
    out
}

#[test]
fn ros1_chunk_of_corrupt_bytes_is_skipped_by_its_lengths_and_counted() {
    // The fixture's one chunk, then a copy of it garbled (imutherm reads
    // a bag from start to end, not by its index).
    let bag = std::fs::read(fixture("ros/imu_bz2.bag")).unwrap();
    let (first, first_end, _) = ros1_chunks(&bag)[0];
    let mut f = bag[..first_end].to_vec();
    f.extend_from_slice(&bag[first..first_end]);
    f.extend_from_slice(&bag[first_end..]);
    let chunks = ros1_chunks(&f);
    assert_eq!(chunks.len(), 2, "{chunks:?}");
    // Its bz2 stream's first bytes garbled: not bz2 at all. (Garbled
    // further in, bz2 unpacks to another size than the chunk declares,
    // which stays an error like every declaration that does not hold.)
    let (start, end, data) = chunks[1];
    for b in &mut f[data..data + 64] {
        *b ^= 0x5a;
    }
    let dir = dir_with(&[("corrupt.bag", &f)]);
    read_only(&dir, &["info", "corrupt.bag"]).expect(
        0,
        &[&format!(
            "bytes {start}..{end} ({} bytes) skipped: a corrupt ROS 1 bag chunk",
            end - start
        )],
    );
}

#[test]
fn ros1_uncompressed_chunk_whose_records_do_not_frame_is_skipped_and_counted() {
    let bag = std::fs::read(fixture("ros/imu_none.bag")).unwrap();
    let (first, first_end, _) = ros1_chunks(&bag)[0];
    let mut f = bag[..first_end].to_vec();
    f.extend_from_slice(&bag[first..first_end]);
    f.extend_from_slice(&bag[first_end..]);
    let (start, end, data) = ros1_chunks(&f)[1];
    // The first record inside claims a header of 4 GiB.
    f[data..data + 4].copy_from_slice(&0xFFFF_FF00u32.to_le_bytes());
    let dir = dir_with(&[("corrupt.bag", &f)]);
    read_only(&dir, &["info", "corrupt.bag"]).expect(
        0,
        &[&format!(
            "bytes {start}..{end} ({} bytes) skipped: a corrupt ROS 1 bag chunk: its records do not frame",
            end - start
        )],
    );
}

#[test]
fn adev_of_values_near_the_largest_double_says_overflow() {
    let mut t = String::from("gyro_x\n");
    for k in 0..600 {
        t.push_str(if k % 2 == 0 { "1e308\n" } else { "-1e308\n" });
    }
    let dir = dir_with(&[("big.csv", t.as_bytes())]);
    let r = read_only(&dir, &["adev", "big.csv", "--rate", "100"]);
    r.expect(
        1,
        &["column 1 (gyro_x): a value of 1e308 overflows double precision"],
    );
    assert!(!r.stderr.contains("no requested tau"), "{}", r.stderr);
}

/// A still six-axis record with a temperature warming by 10 °C, its
/// gyro_y at ±1e308: what each static analysis reads.
fn six_axes_with_gyro_y_at_1e308() -> tempfile::TempDir {
    let mut t = String::from("gyro_x,gyro_y,gyro_z,accel_x,accel_y,accel_z,temp\n");
    for k in 0..2000 {
        let w = |a: usize| (((k * 7 + a * 3) % 11) as f64 - 5.0) * 1e-4;
        let big = if k % 2 == 0 { "1e308" } else { "-1e308" };
        t.push_str(&format!(
            "{},{big},{},{},{},{},{}\n",
            w(0),
            w(2),
            w(3),
            w(4),
            9.81 + w(5),
            25.0 + k as f64 * 0.005
        ));
    }
    dir_with(&[("big.csv", t.as_bytes())])
}

const GYRO_Y_OVERFLOWS: &str = "column 2 (gyro_y): a value of 1e308 overflows double precision";

#[test]
fn noise_of_values_near_the_largest_double_says_overflow() {
    let dir = six_axes_with_gyro_y_at_1e308();
    let r = read_only(&dir, &["noise", "big.csv", "--rate", "100"]);
    r.expect(1, &[GYRO_Y_OVERFLOWS]);
    assert!(
        !r.stdout.contains("NaN") && !r.stdout.contains("inf"),
        "{}",
        r.stdout
    );
}

#[test]
fn thermal_of_values_near_the_largest_double_says_overflow() {
    let dir = six_axes_with_gyro_y_at_1e308();
    read_only(&dir, &["thermal", "big.csv", "--rate", "100"]).expect(1, &[GYRO_Y_OVERFLOWS]);
}

#[test]
fn tcal_fit_of_values_near_the_largest_double_says_overflow_and_writes_nothing() {
    let dir = six_axes_with_gyro_y_at_1e308();
    read_only(
        &dir,
        &["tcal", "fit", "big.csv", "--rate", "100", "-o", "model.json"],
    )
    .expect(1, &[GYRO_Y_OVERFLOWS]);
    assert!(!dir.path().join("model.json").exists());
}

#[test]
fn ins_of_values_near_the_largest_double_says_overflow() {
    let dir = six_axes_with_gyro_y_at_1e308();
    read_only(&dir, &["ins", "big.csv", "--rate", "100"]).expect(1, &[GYRO_Y_OVERFLOWS]);
}

#[test]
fn ulog_data_without_a_format_names_the_missing_format() {
    let mut f = ulog::header();
    f.extend(ulog::subscribe("sensor_combined"));
    f.extend(ulog::sample(1_000_000, 0));
    let dir = dir_with(&[("noformat.ulg", &f)]);
    read_only(&dir, &["info", "noformat.ulg"]).expect(
        1,
        &["sensor_combined has data but no format (F message) before it"],
    );
}

#[test]
fn ulog_empty_per_sensor_topics_never_hide_the_stream_with_data() {
    // sensor_gyro instances subscribed, one message each, and
    // sensor_combined holding the data: read without a choice.
    let gyro = "sensor_gyro:uint64_t timestamp;uint64_t timestamp_sample;uint32_t device_id;float x;float y;float z;float temperature;";
    let mut f = ulog::log(&ulog::steady(300));
    f.extend(ulog::msg(b'F', gyro.as_bytes()));
    for i in 0..3u8 {
        let mut sub = vec![i, 1 + i, 0];
        sub.extend_from_slice(b"sensor_gyro");
        f.extend(ulog::msg(b'A', &sub));
        let mut d = vec![1 + i, 0];
        d.extend(2_000_000u64.to_le_bytes());
        d.extend(2_000_000u64.to_le_bytes());
        d.extend([0u8; 4 + 16]);
        f.extend(ulog::msg(b'D', &d));
    }
    let dir = dir_with(&[("empty_gyros.ulg", &f)]);
    let r = read_only(&dir, &["adev", "empty_gyros.ulg", "--json"]);
    r.expect(0, &["\"samples\":300", "(250 Hz, jitter"]);
}
