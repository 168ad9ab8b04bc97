//! Which kind of log a path holds, told by its content, not its name.

use std::fs::File;
use std::io::Read;
use std::path::{Path, PathBuf};

/// The robot-log formats.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    /// A ROS 2 bag directory (`metadata.yaml` and its storage files).
    Ros2BagDir,
    /// An MCAP file.
    Mcap,
    /// A ROS 2 SQLite3 bag file (`.db3`).
    Sqlite,
    /// A ROS 1 bag, format 2.0.
    Ros1Bag,
    /// A PX4 ULog file.
    ULog,
    /// An ArduPilot DataFlash log.
    DataFlash,
}

impl Format {
    /// The name written into the recording's metadata.
    pub fn name(self) -> &'static str {
        match self {
            Format::Ros2BagDir => "ROS 2 bag",
            Format::Mcap => "MCAP",
            Format::Sqlite => "ROS 2 SQLite3 bag",
            Format::Ros1Bag => "ROS 1 bag",
            Format::ULog => "PX4 ULog",
            Format::DataFlash => "ArduPilot DataFlash",
        }
    }
}

/// The MCAP magic (mcap.dev/spec, "Magic").
pub const MCAP_MAGIC: &[u8] = b"\x89MCAP0\r\n";
/// The SQLite file header (sqlite.org/fileformat.html, 1.3).
pub const SQLITE_MAGIC: &[u8] = b"SQLite format 3\0";

/// The format of the bytes `head` (the start of a file).
pub fn of_bytes(head: &[u8]) -> Option<Format> {
    if head.starts_with(MCAP_MAGIC) {
        Some(Format::Mcap)
    } else if head.starts_with(SQLITE_MAGIC) {
        Some(Format::Sqlite)
    } else if head.starts_with(crate::ros1_bag::MAGIC) {
        Some(Format::Ros1Bag)
    } else if head.starts_with(crate::ulog::MAGIC) {
        Some(Format::ULog)
    } else if head.len() >= 3 && head[..2] == crate::dataflash::HEAD && head[2] == crate::dataflash::FMT_TYPE
    {
        // A DataFlash log opens with the FMT message describing FMT.
        Some(Format::DataFlash)
    } else {
        None
    }
}

/// The format of `path`; `None` for anything else (a text log, a pipe).
/// Only regular files are opened to look: a pipe, a FIFO or a device can
/// be read once, and that once belongs to the text reader.
pub fn detect(path: &Path) -> Option<Format> {
    let meta = std::fs::metadata(path).ok()?;
    if meta.is_dir() {
        return path.join("metadata.yaml").is_file().then_some(Format::Ros2BagDir);
    }
    if !meta.is_file() {
        return None;
    }
    let mut head = [0u8; 16];
    let mut f = File::open(path).ok()?;
    let mut n = 0;
    while n < head.len() {
        match f.read(&mut head[n..]) {
            Ok(0) | Err(_) => break,
            Ok(k) => n += k,
        }
    }
    of_bytes(&head[..n])
}

/// The storage files of a ROS 2 bag directory, in order: those listed
/// under `relative_file_paths` in `metadata.yaml` (rosbag2's
/// `BagMetadata`), or failing that every `.mcap`/`.db3` file in it, sorted.
pub fn bag_files(dir: &Path) -> std::io::Result<Vec<PathBuf>> {
    let meta = std::fs::read_to_string(dir.join("metadata.yaml"))?;
    let mut listed = Vec::new();
    let mut inside = false;
    for line in meta.lines() {
        let t = line.trim();
        if t.starts_with("relative_file_paths:") {
            inside = true;
            continue;
        }
        if inside {
            match t.strip_prefix("- ") {
                Some(p) => listed.push(dir.join(p.trim().trim_matches(['"', '\'']))),
                None => inside = false,
            }
        }
    }
    if listed.is_empty() || !listed.iter().all(|p| p.is_file()) {
        listed = std::fs::read_dir(dir)?
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| matches!(p.extension().and_then(|e| e.to_str()), Some("mcap" | "db3")))
            .collect();
        listed.sort();
    }
    Ok(listed)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn formats_are_told_by_their_first_bytes() {
        assert_eq!(of_bytes(b"\x89MCAP0\r\n\x01"), Some(Format::Mcap));
        assert_eq!(of_bytes(b"SQLite format 3\0"), Some(Format::Sqlite));
        assert_eq!(of_bytes(b"#ROSBAG V2.0\n"), Some(Format::Ros1Bag));
        assert_eq!(of_bytes(b"ULog\x01\x12\x35\x01"), Some(Format::ULog));
        assert_eq!(of_bytes(&[0xA3, 0x95, 128, 128]), Some(Format::DataFlash));
        assert_eq!(of_bytes(&[0xA3, 0x95, 4]), None);
        assert_eq!(of_bytes(b"gyro_x,gyro_y\n"), None);
        assert_eq!(of_bytes(b""), None);
    }

    #[cfg(unix)]
    #[test]
    fn a_fifo_is_not_opened_to_look() {
        let dir = tempfile::tempdir().unwrap();
        let fifo = dir.path().join("pipe");
        let made = std::process::Command::new("mkfifo").arg(&fifo).status();
        if !made.is_ok_and(|s| s.success()) {
            eprintln!("skipped: mkfifo is not available");
            return;
        }
        // Opening a FIFO without a writer would block: detect must return.
        assert_eq!(detect(&fifo), None);
    }
}
