//! Text-table reading speed in MB/s per core, in-process, release build:
//! `cargo run --release -p imu --example table_parse [ROWS_1COL] [ROWS_7COL]`.
//!
//! Generates, in a temporary directory, a one-column file like
//! `make_data.py`'s (`{:.7f}` per line, default 10^7 rows) and a
//! seven-column file in the thesis log's layout (a header, full-precision
//! cells separated by `, `, default 10^6 rows), warms the page cache, and
//! reads each with `TableReader` on a one-thread pool (best of 5): bytes
//! of the file over wall seconds, and over the CPU seconds all threads
//! spent (the per-core figure that a busy machine does not distort). A
//! two-thread figure follows for reference.
//!
//! `table_parse --file PATH` reads a given file instead (best of 5, one
//! thread) and prints one line, `PATH: … MB/s, … MB/CPU-s`, for
//! `bench/ratios.sh` to set beside pandas on the same bytes.

use std::fmt::Write as _;
use std::io::Write as _;
use std::path::Path;
use std::time::Instant;

use imu::table::TableReader;

/// SplitMix64 uniform in [−0.5, 0.5): reproducible, no dependency.
fn uniform(state: &mut u64) -> f64 {
    *state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
    let mut z = *state;
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64 - 0.5
}

fn one_column(rows: usize) -> String {
    let mut s = 0x1234_u64;
    let mut text = String::with_capacity(rows * 11);
    let mut bias = 0.0123;
    for _ in 0..rows {
        bias += 1e-7 * uniform(&mut s);
        let _ = writeln!(text, "{:.7}", bias + 1e-3 * uniform(&mut s));
    }
    text
}

fn seven_columns(rows: usize) -> String {
    let mut s = 0x5678_u64;
    let mut text = String::with_capacity(rows * 140);
    text.push_str(
        "mpu_accel_1[m/^2], mpu_accel_2[m/^2], mpu_accel_3[m/^2], mpu_gyro_1[rad/s], mpu_gyro_2[rad/s], mpu_gyro_3[rad/s], temp[degC]\n",
    );
    let centre = [0.88, 0.21, 9.36, -0.036, 0.023, 0.019, 34.0];
    let spread = [0.05, 0.05, 0.05, 0.002, 0.002, 0.002, 0.01];
    let mut buf = ryu::Buffer::new();
    for _ in 0..rows {
        for k in 0..7 {
            if k > 0 {
                text.push_str(", ");
            }
            text.push_str(buf.format(centre[k] + spread[k] * uniform(&mut s)));
        }
        text.push('\n');
    }
    text
}

/// CPU time of all the process's threads so far, in seconds, from Linux's
/// per-thread scheduler statistics (nanoseconds on the CPU, first field):
/// on a shared machine it counts the reader's work, not the wait for a core.
fn cpu_seconds() -> f64 {
    let Ok(tasks) = std::fs::read_dir("/proc/self/task") else {
        return f64::NAN;
    };
    tasks
        .filter_map(|t| std::fs::read_to_string(t.ok()?.path().join("schedstat")).ok())
        .filter_map(|s| s.split_whitespace().next()?.parse::<f64>().ok())
        .sum::<f64>()
        / 1e9
}

/// Best of `reps` reads of `path` on `pool`: MB/s of wall time and MB per
/// CPU-second (the pools live through the whole run, so no thread's time
/// leaves the sum while a read is measured).
fn speed(path: &Path, pool: &rayon::ThreadPool, reps: usize, rows: usize) -> (f64, f64) {
    let bytes = std::fs::metadata(path).expect("bench file").len() as f64;
    let (wall, cpu) = (0..reps)
        .map(|_| {
            pool.install(|| {
                let (t0, c0) = (Instant::now(), cpu_seconds());
                let table = TableReader::open(path)
                    .and_then(|r| r.read(None))
                    .expect("bench file reads");
                let secs = (t0.elapsed().as_secs_f64(), cpu_seconds() - c0);
                assert_eq!(table.rows(), rows);
                std::hint::black_box(&table);
                secs
            })
        })
        .fold((f64::INFINITY, f64::INFINITY), |(w, c), (a, b)| {
            (w.min(a), c.min(b))
        });
    (bytes / 1e6 / wall, bytes / 1e6 / cpu)
}

fn main() {
    let mut args = std::env::args().skip(1).peekable();
    if args.peek().is_some_and(|a| a == "--file") {
        let path = std::path::PathBuf::from(args.nth(1).expect("--file PATH"));
        let rows = TableReader::open(&path)
            .and_then(|r| r.read(None))
            .expect("the file reads")
            .rows();
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(1)
            .build()
            .expect("thread pool");
        let (wall, cpu) = speed(&path, &pool, 5, rows);
        println!("{}: {wall:.0} MB/s, {cpu:.0} MB/CPU-s", path.display());
        return;
    }
    let rows1: usize = args.next().map_or(10_000_000, |a| a.parse().expect("ROWS_1COL"));
    let rows7: usize = args.next().map_or(1_000_000, |a| a.parse().expect("ROWS_7COL"));
    let dir = tempfile::tempdir().expect("temporary directory");
    let pool = |n| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .expect("thread pool")
    };
    let (pool1, pool2) = (pool(1), pool(2));
    for (name, rows, text) in [
        ("one column", rows1, one_column(rows1)),
        ("seven columns (thesis)", rows7, seven_columns(rows7)),
    ] {
        let path = dir.path().join("bench.txt");
        std::fs::File::create(&path)
            .and_then(|mut f| f.write_all(text.as_bytes()))
            .expect("write bench file");
        drop(text);
        let mb = std::fs::metadata(&path).expect("bench file").len() as f64 / 1e6;
        let (one, one_cpu) = speed(&path, &pool1, 5, rows);
        let (two, two_cpu) = speed(&path, &pool2, 3, rows);
        println!(
            "{name:<22} {rows:>8} rows {mb:>6.1} MB | 1 thread {one:>5.0} MB/s, {one_cpu:>5.0} MB/CPU-s | 2 threads {two:>5.0} MB/s, {two_cpu:>5.0} MB/CPU-s"
        );
    }
}
