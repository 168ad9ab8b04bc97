//! What the CLI's integration tests share: the command, simulated runs,
//! files to read, and the JSON a command prints.

// Every file in `tests/` is its own crate and uses only part of this
// module; the rest would warn as dead code in that crate.
#![allow(dead_code)]

pub mod chromium;

use std::path::{Path, PathBuf};
use std::process::Output;

use assert_cmd::Command;
use assert_cmd::assert::Assert;
use serde_json::Value;

/// The scratch files (`*.partial`) in `dir`, sorted: a finished run leaves
/// none of its own.
pub fn scratch_files(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".partial"))
        .collect();
    v.sort();
    v
}

/// The `imutherm` binary built with these tests.
pub fn imutherm() -> Command {
    Command::cargo_bin("imutherm").unwrap()
}

/// `imutherm COMMAND ARGS -o OUT`.
pub fn writing(command: &str, args: &[&str], out: &Path) -> Command {
    let mut cmd = imutherm();
    cmd.arg(command).args(args).arg("-o").arg(out);
    cmd
}

/// `imutherm` with these arguments, words and paths alike, in order.
#[allow(unused_macros)]
macro_rules! cli {
    ($($arg:expr),* $(,)?) => {{
        let mut cmd = $crate::support::imutherm();
        $(cmd.arg($arg);)*
        cmd
    }};
}
#[allow(unused_imports)]
pub(crate) use cli;

/// A command that must be refused.
pub trait Refused {
    /// Runs the command, which must exit with `code` and say `says` on
    /// standard error.
    fn refused(&mut self, code: i32, says: impl Into<String>) -> Assert;
}

impl Refused for Command {
    fn refused(&mut self, code: i32, says: impl Into<String>) -> Assert {
        self.assert()
            .code(code)
            .stderr(predicates::str::contains(says.into()))
    }
}

/// An `imutherm simulate` run: the profile, duration, rate and seed a test
/// names, anything else as extra arguments; the rest stays at the
/// simulator's defaults.
#[derive(Default)]
pub struct Simulation {
    args: Vec<String>,
}

impl Simulation {
    pub fn new() -> Self {
        Self::default()
    }

    fn flag(mut self, flag: &str, value: &str) -> Self {
        self.args.extend([flag.to_string(), value.to_string()]);
        self
    }

    pub fn profile(self, profile: &str) -> Self {
        self.flag("--profile", profile)
    }

    pub fn duration(self, duration: &str) -> Self {
        self.flag("--duration", duration)
    }

    pub fn rate(self, rate: &str) -> Self {
        self.flag("--rate", rate)
    }

    pub fn seed(self, seed: &str) -> Self {
        self.flag("--seed", seed)
    }

    pub fn args(mut self, args: &[&str]) -> Self {
        self.args.extend(args.iter().map(|a| a.to_string()));
        self
    }

    /// `imutherm simulate … -o OUT`, for a test that checks more than success.
    pub fn command(&self, out: &Path) -> Command {
        let mut cmd = imutherm();
        cmd.arg("simulate").args(&self.args).arg("-o").arg(out);
        cmd
    }

    /// Writes the run to `dir/name`, which must succeed.
    pub fn write(&self, dir: &Path, name: &str) -> PathBuf {
        let p = dir.join(name);
        self.command(&p).assert().success();
        p
    }
}

/// `imutherm tcal fit ARGS -o MODEL RUNS…`, which must succeed.
pub fn tcal_fit(model: &Path, args: &[&str], runs: &[&Path]) -> Assert {
    imutherm()
        .args(["tcal", "fit"])
        .args(args)
        .arg("-o")
        .arg(model)
        .args(runs)
        .assert()
        .success()
}

/// `imutherm ARGS OUT` where OUT already exists: refused with exit status
/// 1, the message holding every one of `says`, OUT left as it was; then
/// `imutherm ARGS OUT --overwrite` replaces it.
pub fn replaces_only_with_overwrite(args: &[&str], out: &Path, says: &[&str]) {
    let before = std::fs::read(out).unwrap();
    let refused = imutherm().args(args).arg(out).output().unwrap();
    let err = stderr_of(&refused);
    assert_eq!(refused.status.code(), Some(1), "{err}");
    for s in says {
        assert!(err.contains(s), "{s:?} not in: {err}");
    }
    assert_eq!(std::fs::read(out).unwrap(), before);
    imutherm()
        .args(args)
        .arg(out)
        .arg("--overwrite")
        .assert()
        .success();
}

/// Runs `cmd` and fails the test, showing its standard error, unless it
/// exits 0.
pub fn succeed(cmd: &mut Command) -> Output {
    let out = cmd.output().unwrap();
    assert!(out.status.success(), "{}", stderr_of(&out));
    out
}

/// The standard output of `cmd`, which must succeed, read as JSON.
pub fn json_stdout(cmd: &mut Command) -> Value {
    json_of(&succeed(cmd))
}

/// The standard output of a finished command, read as JSON.
pub fn json_of(out: &Output) -> Value {
    serde_json::from_slice(&out.stdout).unwrap()
}

/// The element of the JSON array `list` whose `key` is `value`, which must
/// be there.
pub fn entry<'a>(list: &'a Value, key: &str, value: &str) -> &'a Value {
    list.as_array()
        .unwrap()
        .iter()
        .find(|e| e[key] == value)
        .unwrap_or_else(|| panic!("no {key} {value:?} in {list}"))
}

/// (kind, line) of every problem of one file of an `info --json` document
/// that names a line.
pub fn problem_lines(file: &Value) -> Vec<(String, u64)> {
    file["problems"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|p| !p["line"].is_null())
        .map(|p| {
            (
                p["kind"].as_str().unwrap().to_string(),
                p["line"].as_u64().unwrap(),
            )
        })
        .collect()
}

/// A JSON file.
pub fn read_json(path: &Path) -> Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

pub fn stderr_of(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// A file `name` holding `content` in a fresh directory; the directory is
/// returned to keep it alive.
pub fn file(name: &str, content: impl AsRef<[u8]>) -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join(name);
    std::fs::write(&path, content).unwrap();
    (dir, path)
}
