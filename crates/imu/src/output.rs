//! Writing output files so that nothing is destroyed or mixed.
//!
//! Every file imutherm writes goes through here:
//! - an existing file is refused unless the caller allows replacing it
//!   (`--overwrite`);
//! - a file that is one of the command's own inputs — by any path: a
//!   symlink, a hard link, `./x` for `x` — is refused even then, since
//!   replacing it would destroy the data being read;
//! - the data go to a scratch file beside the target, which is synced and
//!   renamed onto the target only once complete, so a full disk, an error
//!   or a kill leaves the previous file as it was;
//! - the scratch file is this run's own: created under a name no file has
//!   (`FILE.<16 hex digits>.partial`, `O_CREAT|O_EXCL`, which never follows
//!   a link), so a file or link already there under any scratch name — the
//!   user's own, an input, a link to something else — is never opened,
//!   truncated or removed; only the scratch file the run created is
//!   removed when the run fails;
//! - the scratch file is locked while written (`flock`), and a writer that
//!   finds another scratch file of the same target locked is refused, so
//!   two writers never share one output. Two writers starting at the same
//!   instant may both be refused; neither writes. A scratch file left by a
//!   killed run holds no lock: it is left alone, never reused.
//!
//! Devices and pipes (`/dev/null`, a FIFO) are written in place: renaming
//! onto them would replace them.

use std::fs::{File, OpenOptions};
use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};

use crate::setting::Setting;

/// Why an output cannot be written.
#[derive(Debug, thiserror::Error)]
pub enum WriteError {
    /// The output exists and replacing it was not asked for.
    #[error(
        "{} already exists ({size} bytes): choose another name, or pass {} to replace it",
        path.display(),
        Setting::Overwrite
    )]
    Exists {
        /// The output.
        path: PathBuf,
        /// Its size, so the user sees what would be lost.
        size: u64,
    },
    /// The output is one of the inputs.
    #[error(
        "{} is the input {}: writing it would destroy the data being read (even with {}); choose another name",
        path.display(),
        input.display(),
        Setting::Overwrite
    )]
    IsInput {
        /// The output.
        path: PathBuf,
        /// The input it is, as the user named it.
        input: PathBuf,
    },
    /// Another process holds the output's lock.
    #[error("{} is being written by another process right now; wait for it to finish or choose another name", path.display())]
    Busy {
        /// The output.
        path: PathBuf,
    },
    /// The output is a directory.
    #[error("{} is a directory, not a file", path.display())]
    IsDirectory {
        /// The output.
        path: PathBuf,
    },
    /// The system refused.
    #[error("{action} {}", path.display())]
    Io {
        /// What was being done: `creating`, `writing`, `renaming … to`.
        action: String,
        /// The file.
        path: PathBuf,
        /// The system's error (printed once, as this error's source).
        #[source]
        source: io::Error,
    },
}

impl WriteError {
    fn io(action: impl Into<String>, path: &Path, source: io::Error) -> WriteError {
        WriteError::Io {
            action: action.into(),
            path: path.to_path_buf(),
            source,
        }
    }
}

/// What a command may do to its output.
#[derive(Debug, Clone, Copy, Default)]
pub struct OutputPolicy<'a> {
    /// Replace an existing output (`--overwrite`).
    pub overwrite: bool,
    /// The command's inputs (`-` is standard input): never written.
    pub inputs: &'a [PathBuf],
}

/// Checks that `target` may be written under `policy`, before any work is
/// done: a command refuses at once rather than after an hour of simulation.
/// [`AtomicFile::create`] checks again.
pub fn check_output(target: &Path, policy: &OutputPolicy<'_>) -> Result<(), WriteError> {
    let meta = match std::fs::metadata(target) {
        Ok(m) => m,
        Err(e) if e.kind() == io::ErrorKind::NotFound => return Ok(()),
        Err(e) => return Err(WriteError::io("checking", target, e)),
    };
    if meta.is_dir() {
        return Err(WriteError::IsDirectory {
            path: target.to_path_buf(),
        });
    }
    // A terminal is everyone's input and output at once.
    #[cfg(unix)]
    let terminal = {
        use std::os::unix::fs::FileTypeExt;
        meta.file_type().is_char_device()
    };
    #[cfg(not(unix))]
    let terminal = false;
    for input in policy.inputs.iter().filter(|_| !terminal) {
        if is_same_file(target, &meta, input) {
            return Err(WriteError::IsInput {
                path: target.to_path_buf(),
                input: input.clone(),
            });
        }
    }
    if meta.is_file() && !policy.overwrite {
        return Err(WriteError::Exists {
            path: target.to_path_buf(),
            size: meta.len(),
        });
    }
    // A running writer of the target itself (`imutherm record`) holds its
    // lock: replacing the file under it would lose its data.
    if meta.is_file()
        && let Ok(existing) = File::open(target)
        && let Err(std::fs::TryLockError::WouldBlock) = existing.try_lock_shared()
    {
        return Err(WriteError::Busy {
            path: target.to_path_buf(),
        });
    }
    Ok(())
}

/// Whether `a` and `b` name one file: the same device and inode, under any
/// name or hard link (elsewhere, the same canonical path). `-` stands for
/// standard input, whatever file it was redirected from. A path that does
/// not exist is no file.
pub fn same_file(a: &Path, b: &Path) -> bool {
    let meta = if a == Path::new("-") {
        std::fs::metadata("/dev/stdin")
    } else {
        std::fs::metadata(a)
    };
    meta.is_ok_and(|meta| is_same_file(a, &meta, b))
}

/// Whether `input` names the file `target` (whose metadata is `meta`).
fn is_same_file(target: &Path, meta: &std::fs::Metadata, input: &Path) -> bool {
    // Standard input is whatever file descriptor 0 is: a redirected file
    // (`< x.txt`) must not be written either.
    let input_meta = if input == Path::new("-") {
        std::fs::metadata("/dev/stdin")
    } else {
        std::fs::metadata(input)
    };
    let Ok(input_meta) = input_meta else {
        return false;
    };
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        let _ = target;
        // Device and inode: the same file under any name, hard links included.
        meta.dev() == input_meta.dev() && meta.ino() == input_meta.ino()
    }
    #[cfg(not(unix))]
    {
        let _ = (meta, input_meta);
        match (std::fs::canonicalize(target), std::fs::canonicalize(input)) {
            (Ok(a), Ok(b)) => a == b,
            _ => false,
        }
    }
}

/// An output being written: to a scratch file of its own beside `FILE`,
/// renamed onto `FILE` by [`AtomicFile::commit`]. Dropped without a commit,
/// it removes the scratch file it created and leaves `FILE` as it was.
#[derive(Debug)]
pub struct AtomicFile {
    target: PathBuf,
    /// The scratch file, or `None` for a device or pipe written in place.
    temp: Option<PathBuf>,
    out: BufWriter<File>,
    committed: bool,
}

impl AtomicFile {
    /// Checks `target` under `policy` ([`check_output`]) and creates its
    /// scratch file, locked. A symlink at `target` is followed: the file it
    /// points to is replaced, the link kept. Scratch files are never
    /// followed.
    pub fn create(target: &Path, policy: &OutputPolicy<'_>) -> Result<AtomicFile, WriteError> {
        check_output(target, policy)?;
        let special = std::fs::metadata(target).is_ok_and(|m| !m.is_file());
        if special {
            let file = OpenOptions::new()
                .write(true)
                .open(target)
                .map_err(|e| WriteError::io("opening", target, e))?;
            return Ok(AtomicFile {
                target: target.to_path_buf(),
                temp: None,
                out: BufWriter::with_capacity(1 << 20, file),
                committed: false,
            });
        }
        let real = match std::fs::symlink_metadata(target) {
            Ok(m) if m.file_type().is_symlink() => {
                std::fs::canonicalize(target).map_err(|e| WriteError::io("resolving", target, e))?
            }
            _ => target.to_path_buf(),
        };
        let (file, temp) = create_scratch(&real, policy.inputs).map_err(|e| match e {
            ScratchError::Busy => WriteError::Busy {
                path: target.to_path_buf(),
            },
            ScratchError::IsInput(input) => WriteError::IsInput {
                path: target.to_path_buf(),
                input,
            },
            ScratchError::Io(path, e) => WriteError::io("creating", &path, e),
        })?;
        // A replaced file keeps its permissions (a shared log stays shared).
        if let Ok(m) = std::fs::metadata(&real) {
            let _ = file.set_permissions(m.permissions());
        }
        Ok(AtomicFile {
            target: real,
            temp: Some(temp),
            out: BufWriter::with_capacity(1 << 20, file),
            committed: false,
        })
    }

    /// The file the data will end up in.
    pub fn target(&self) -> &Path {
        &self.target
    }

    /// Flushes, syncs and renames the scratch file onto the target. On
    /// error the target is left as it was.
    pub fn commit(mut self) -> Result<(), WriteError> {
        // Errors name the file the user asked for, not its scratch file.
        let target = self.target.clone();
        self.out
            .flush()
            .map_err(|e| WriteError::io("writing", &target, e))?;
        let Some(temp) = self.temp.clone() else {
            self.committed = true;
            return Ok(());
        };
        // Synced before the rename: after a power cut the target is the
        // old file or the whole new one, never a renamed empty file.
        self.out
            .get_ref()
            .sync_all()
            .map_err(|e| WriteError::io("writing", &target, e))?;
        std::fs::rename(&temp, &self.target)
            .map_err(|e| WriteError::io(format!("renaming {} to", temp.display()), &self.target, e))?;
        self.committed = true;
        // The rename itself reaches the disk with the directory; a
        // filesystem that cannot sync a directory has nothing more to offer.
        if let Some(dir) = self.target.parent() {
            let dir = if dir.as_os_str().is_empty() {
                Path::new(".")
            } else {
                dir
            };
            if let Ok(d) = File::open(dir) {
                let _ = d.sync_all();
            }
        }
        Ok(())
    }
}

impl Write for AtomicFile {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        self.out.write(buf)
    }

    fn write_all(&mut self, buf: &[u8]) -> io::Result<()> {
        self.out.write_all(buf)
    }

    fn flush(&mut self) -> io::Result<()> {
        self.out.flush()
    }
}

impl Drop for AtomicFile {
    fn drop(&mut self) {
        if !self.committed
            && let Some(temp) = &self.temp
        {
            // Nothing to report from a drop: the error that caused it is
            // the one the user sees.
            let _ = std::fs::remove_file(temp);
        }
    }
}

/// Whether `name` is a scratch file name of the output `target`:
/// `FILE.<16 hex digits>.partial` in the same directory.
pub fn is_scratch_of(target: &Path, name: &Path) -> bool {
    let (Some(file), Some(candidate)) = (target.file_name(), name.file_name()) else {
        return false;
    };
    if target.parent() != name.parent() {
        return false;
    }
    let (file, candidate) = (file.as_encoded_bytes(), candidate.as_encoded_bytes());
    candidate.len() == file.len() + 1 + TAG_DIGITS + SCRATCH_SUFFIX.len()
        && candidate.starts_with(file)
        && candidate[file.len()] == b'.'
        && candidate[file.len() + 1..file.len() + 1 + TAG_DIGITS]
            .iter()
            .all(u8::is_ascii_hexdigit)
        && candidate.ends_with(SCRATCH_SUFFIX.as_bytes())
}

const TAG_DIGITS: usize = 16;
const SCRATCH_SUFFIX: &str = ".partial";

/// A fresh scratch name for `target`: random, so that a name planted in
/// advance is unlikely to be hit, and harmless when it is (the creation
/// fails and another name is drawn).
fn scratch_name(target: &Path, attempt: u32) -> PathBuf {
    use std::hash::{BuildHasher, Hasher};
    // `RandomState` is seeded from the system's randomness once per
    // process; the time, the process and the attempt vary it further.
    let mut h = std::collections::hash_map::RandomState::new().build_hasher();
    h.write_u32(std::process::id());
    h.write_u32(attempt);
    if let Ok(t) = std::time::SystemTime::now().duration_since(std::time::UNIX_EPOCH) {
        h.write_u128(t.as_nanos());
    }
    let mut name = target.as_os_str().to_os_string();
    name.push(format!(".{:016x}{SCRATCH_SUFFIX}", h.finish()));
    PathBuf::from(name)
}

enum ScratchError {
    Busy,
    IsInput(PathBuf),
    Io(PathBuf, io::Error),
}

/// Creates a scratch file for `target` that no one else has: exclusively
/// (`O_CREAT|O_EXCL`: an existing name, a link included, is never opened),
/// locked, and checked against the inputs like the output itself. Refused
/// as busy when another writer holds the lock of a scratch file of the same
/// target.
fn create_scratch(target: &Path, inputs: &[PathBuf]) -> Result<(File, PathBuf), ScratchError> {
    let mut attempt = 0;
    let (file, temp) = loop {
        let temp = scratch_name(target, attempt);
        let mut options = OpenOptions::new();
        options.write(true).create_new(true);
        #[cfg(unix)]
        {
            use std::os::unix::fs::OpenOptionsExt;
            options.custom_flags(libc::O_NOFOLLOW);
        }
        match options.open(&temp) {
            Ok(f) => break (f, temp),
            Err(e) if e.kind() == io::ErrorKind::AlreadyExists && attempt < 16 => attempt += 1,
            Err(e) => return Err(ScratchError::Io(temp, e)),
        }
    };
    // From here on the file is the run's own: removed on every error.
    let refuse = |e: ScratchError| {
        let _ = std::fs::remove_file(&temp);
        Err(e)
    };
    match file.try_lock() {
        Ok(()) => {}
        Err(std::fs::TryLockError::WouldBlock) => return refuse(ScratchError::Busy),
        Err(std::fs::TryLockError::Error(e)) => return refuse(ScratchError::Io(temp.clone(), e)),
    }
    let meta = match file.metadata() {
        Ok(m) => m,
        Err(e) => return refuse(ScratchError::Io(temp.clone(), e)),
    };
    if let Some(input) = inputs.iter().find(|i| is_same_file(&temp, &meta, i)) {
        return refuse(ScratchError::IsInput(input.clone()));
    }
    if another_writer(target, &temp) {
        return refuse(ScratchError::Busy);
    }
    Ok((file, temp))
}

/// Whether a scratch file of `target` other than `own` is locked by a
/// running writer. Candidates are only looked at: opened read-only, never
/// through a link, never blocking, never changed.
fn another_writer(target: &Path, own: &Path) -> bool {
    let dir = match target.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    let Ok(entries) = std::fs::read_dir(dir) else {
        return false;
    };
    entries.flatten().any(|entry| {
        // Beside the target, spelled as the target is (`out.txt` and
        // `./out.txt.….partial` would compare as different directories).
        let path = target.with_file_name(entry.file_name());
        if path.file_name() == own.file_name()
            || !is_scratch_of(target, &path)
            || !entry.file_type().is_ok_and(|t| t.is_file())
        {
            return false;
        }
        let mut options = OpenOptions::new();
        options.read(true);
        #[cfg(unix)]
        {
            use std::os::unix::fs::OpenOptionsExt;
            options.custom_flags(libc::O_NOFOLLOW | libc::O_NONBLOCK);
        }
        options
            .open(&path)
            .is_ok_and(|f| matches!(f.try_lock_shared(), Err(std::fs::TryLockError::WouldBlock)))
    })
}

enum LockedOpenError {
    Busy,
    Io(io::Error),
}

/// Opens `path` for writing under an exclusive lock, creating it, and
/// empties it once the lock is held (never before: that would destroy what
/// the lock holder is writing).
fn open_locked(path: &Path, create: bool) -> Result<File, LockedOpenError> {
    let file = OpenOptions::new()
        .write(true)
        .create(create)
        .truncate(false)
        .open(path)
        .map_err(LockedOpenError::Io)?;
    match file.try_lock() {
        Ok(()) => {}
        Err(std::fs::TryLockError::WouldBlock) => return Err(LockedOpenError::Busy),
        Err(std::fs::TryLockError::Error(e)) => return Err(LockedOpenError::Io(e)),
    }
    file.set_len(0).map_err(LockedOpenError::Io)?;
    Ok(file)
}

/// Opens a file written in place, record by record, so that a kill or a
/// power cut leaves everything written so far at its name (the recorder's
/// log): an existing file is refused unless `overwrite`, and the file is
/// locked for as long as the returned handle lives, so a second writer is
/// refused instead of interleaving its rows. The lock is taken before the
/// file is emptied.
pub fn create_in_place(target: &Path, overwrite: bool) -> Result<File, WriteError> {
    check_output(
        target,
        &OutputPolicy {
            overwrite,
            inputs: &[],
        },
    )?;
    let created = if overwrite {
        open_locked(target, true)
    } else {
        match OpenOptions::new().write(true).create_new(true).open(target) {
            Ok(f) => match f.try_lock() {
                Ok(()) => Ok(f),
                Err(std::fs::TryLockError::WouldBlock) => Err(LockedOpenError::Busy),
                Err(std::fs::TryLockError::Error(e)) => Err(LockedOpenError::Io(e)),
            },
            Err(e) if e.kind() == io::ErrorKind::AlreadyExists => {
                return Err(WriteError::Exists {
                    path: target.to_path_buf(),
                    size: std::fs::metadata(target).map_or(0, |m| m.len()),
                });
            }
            Err(e) => Err(LockedOpenError::Io(e)),
        }
    };
    created.map_err(|e| match e {
        LockedOpenError::Busy => WriteError::Busy {
            path: target.to_path_buf(),
        },
        LockedOpenError::Io(e) => WriteError::io("creating", target, e),
    })
}

/// Writes `bytes` to `target` through an [`AtomicFile`].
pub fn write_file(target: &Path, bytes: &[u8], policy: &OutputPolicy<'_>) -> Result<(), WriteError> {
    let mut f = AtomicFile::create(target, policy)?;
    f.write_all(bytes)
        .map_err(|e| WriteError::io("writing", target, e))?;
    f.commit()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A file `name` in `dir` holding `content`.
    fn file_in(dir: &tempfile::TempDir, name: &str, content: &[u8]) -> PathBuf {
        let p = dir.path().join(name);
        std::fs::write(&p, content).unwrap();
        p
    }

    #[test]
    fn same_file_is_the_file_under_any_name_and_never_a_copy() {
        let dir = tempfile::tempdir().unwrap();
        let a = dir.path().join("a.txt");
        std::fs::write(&a, "gyro_x\n1\n").unwrap();
        let link = dir.path().join("link.txt");
        std::fs::hard_link(&a, &link).unwrap();
        let copy = dir.path().join("copy.txt");
        std::fs::copy(&a, &copy).unwrap();
        assert!(same_file(&a, &link) && same_file(&link, &a));
        assert!(same_file(&a, &dir.path().join(".").join("a.txt")));
        assert!(!same_file(&a, &copy));
        let missing = dir.path().join("missing.txt");
        assert!(!same_file(&a, &missing) && !same_file(&missing, &a));
    }

    fn policy(overwrite: bool, inputs: &[PathBuf]) -> OutputPolicy<'_> {
        OutputPolicy { overwrite, inputs }
    }

    #[test]
    fn an_existing_file_is_replaced_only_when_asked() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("out.txt");
        write_file(&p, b"first\n", &policy(false, &[])).unwrap();
        let e = write_file(&p, b"second\n", &policy(false, &[])).unwrap_err();
        assert!(matches!(e, WriteError::Exists { size: 6, .. }), "{e}");
        assert!(
            e.to_string()
                .contains("pass the choice to overwrite to replace it"),
            "{e}"
        );
        assert_eq!(std::fs::read(&p).unwrap(), b"first\n");
        write_file(&p, b"second\n", &policy(true, &[])).unwrap();
        assert_eq!(std::fs::read(&p).unwrap(), b"second\n");
        assert_eq!(scratch_files(&p), Vec::<PathBuf>::new());
    }

    /// The scratch files of `target` in its directory.
    fn scratch_files(target: &Path) -> Vec<PathBuf> {
        let dir = target.parent().unwrap();
        std::fs::read_dir(dir)
            .unwrap()
            .map(|e| dir.join(e.unwrap().file_name()))
            .filter(|p| is_scratch_of(target, p))
            .collect()
    }

    #[test]
    fn an_input_is_never_written_by_any_of_its_names() {
        let dir = tempfile::tempdir().unwrap();
        let input = file_in(&dir, "in.txt", b"data\n");
        let hard = dir.path().join("hard.txt");
        std::fs::hard_link(&input, &hard).unwrap();
        let sym = dir.path().join("sym.txt");
        std::os::unix::fs::symlink(&input, &sym).unwrap();
        let dotted = dir.path().join(".").join("in.txt");
        let inputs = [input.clone()];
        for target in [&input, &hard, &sym, &dotted] {
            let e = write_file(target, b"x", &policy(true, &inputs)).unwrap_err();
            assert!(
                matches!(e, WriteError::IsInput { .. }),
                "{}: {e}",
                target.display()
            );
        }
        assert_eq!(std::fs::read(&input).unwrap(), b"data\n");
    }

    #[test]
    fn a_symlinked_output_replaces_the_file_it_points_to() {
        let dir = tempfile::tempdir().unwrap();
        let real = file_in(&dir, "real.txt", b"old");
        let link = dir.path().join("link.txt");
        std::os::unix::fs::symlink(&real, &link).unwrap();
        write_file(&link, b"new", &policy(true, &[])).unwrap();
        assert!(std::fs::symlink_metadata(&link).unwrap().file_type().is_symlink());
        assert_eq!(std::fs::read(&real).unwrap(), b"new");
    }

    #[test]
    fn an_unfinished_write_leaves_the_old_file() {
        let dir = tempfile::tempdir().unwrap();
        let p = file_in(&dir, "out.txt", b"old");
        {
            let mut f = AtomicFile::create(&p, &policy(true, &[])).unwrap();
            f.write_all(b"half of the new").unwrap();
            // Dropped without commit: an error in the middle.
        }
        assert_eq!(std::fs::read(&p).unwrap(), b"old");
        assert_eq!(scratch_files(&p), Vec::<PathBuf>::new());
    }

    #[test]
    fn two_writers_of_one_output_are_refused() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("out.txt");
        let mut first = AtomicFile::create(&p, &policy(true, &[])).unwrap();
        first.write_all(b"one").unwrap();
        let e = AtomicFile::create(&p, &policy(true, &[])).unwrap_err();
        assert!(matches!(e, WriteError::Busy { .. }), "{e}");
        first.commit().unwrap();
        assert_eq!(std::fs::read(&p).unwrap(), b"one");

        // In place: the second --overwrite is refused and the first's data kept.
        let rec = dir.path().join("rec.txt");
        let mut a = create_in_place(&rec, false).unwrap();
        a.write_all(b"rows\n").unwrap();
        let e = create_in_place(&rec, true).unwrap_err();
        assert!(matches!(e, WriteError::Busy { .. }), "{e}");
        let e = write_file(&rec, b"x", &policy(true, &[])).unwrap_err();
        assert!(matches!(e, WriteError::Busy { .. }), "{e}");
        assert_eq!(std::fs::read(&rec).unwrap(), b"rows\n");
        drop(a);
        create_in_place(&rec, true).unwrap();
    }

    #[test]
    fn files_under_scratch_names_are_never_touched() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("out.txt");
        // The old fixed scratch name, a link under it, and a scratch file
        // left by a killed run: all someone else's, all left as they were.
        let victim = file_in(&dir, "victim.txt", b"victim");
        let old_name = dir.path().join("out.txt.partial");
        std::os::unix::fs::symlink(&victim, &old_name).unwrap();
        let hard = dir.path().join("out.txt.00000000000000ff.partial");
        std::fs::hard_link(&victim, &hard).unwrap();
        let stale = file_in(&dir, "out.txt.0123456789abcdef.partial", b"left by a killed run");
        write_file(&p, b"new", &policy(false, &[])).unwrap();
        assert_eq!(std::fs::read(&p).unwrap(), b"new");
        assert_eq!(std::fs::read(&victim).unwrap(), b"victim");
        assert_eq!(std::fs::read(&stale).unwrap(), b"left by a killed run");
        assert!(
            std::fs::symlink_metadata(&old_name)
                .unwrap()
                .file_type()
                .is_symlink()
        );
        let mut left = scratch_files(&p);
        left.sort();
        assert_eq!(left, vec![hard, stale]);
    }

    #[test]
    fn a_scratch_name_is_the_targets_own() {
        let t = Path::new("d/run.txt");
        assert!(is_scratch_of(t, &scratch_name(t, 0)));
        assert_ne!(scratch_name(t, 0), scratch_name(t, 1));
        for other in [
            "d/run.txt.partial",
            "run.txt.0123456789abcdef.partial",
            "d/run.txt.0123456789abcdeg.partial",
            "d/xrun.txt.0123456789abcdef.partial",
            "d/run.txt.0123456789abcdef.partial.png",
        ] {
            assert!(!is_scratch_of(t, Path::new(other)), "{other}");
        }
    }

    #[test]
    fn a_full_disk_names_the_file_and_keeps_the_old_one() {
        // /dev/full fails every write with ENOSPC: written in place (it is
        // a device), the error must name it.
        let full = Path::new("/dev/full");
        if !full.exists() {
            return;
        }
        let e = write_file(full, &[b'x'; 1 << 21], &policy(false, &[])).unwrap_err();
        let WriteError::Io { path, source, .. } = &e else {
            panic!("{e}");
        };
        assert_eq!(path, full);
        assert_eq!(source.raw_os_error(), Some(28), "{e}");
    }

    #[test]
    fn a_directory_is_not_a_file() {
        let dir = tempfile::tempdir().unwrap();
        let e = write_file(dir.path(), b"x", &policy(true, &[])).unwrap_err();
        assert!(matches!(e, WriteError::IsDirectory { .. }), "{e}");
    }
}
