//! Which kind of log a path holds, told by its content, not its name.

use std::fs::File;
use std::io::{Read, Seek, SeekFrom};
use std::path::{Path, PathBuf};

use crate::error::{LogError, malformed};

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
    sniff(&mut File::open(path).ok()?).ok()?
}

/// The format of an open file by its first bytes, the file rewound to its
/// start after, for its reader to read from the same handle.
pub fn sniff(file: &mut File) -> std::io::Result<Option<Format>> {
    let mut head = Vec::with_capacity(16);
    (&mut *file).take(16).read_to_end(&mut head)?;
    file.seek(SeekFrom::Start(0))?;
    Ok(of_bytes(&head))
}

/// The format of a gzip-compressed robot log, by the first bytes its
/// stream decompresses to; `None` for anything else. The file is rewound.
pub fn compressed_log(file: &mut File) -> Option<Format> {
    let mut head = Vec::with_capacity(16);
    let looked = (&mut *file).take(2).read_to_end(&mut head);
    let format = if looked.is_ok() && head == [0x1f, 0x8b] {
        file.seek(SeekFrom::Start(0)).ok()?;
        let mut inflated = Vec::with_capacity(16);
        flate2::read::GzDecoder::new(&mut *file)
            .take(16)
            .read_to_end(&mut inflated)
            .ok()
            .and_then(|_| of_bytes(&inflated))
    } else {
        None
    };
    file.seek(SeekFrom::Start(0)).ok()?;
    format
}

/// The storage files of a ROS 2 bag directory, in order: those listed
/// under `relative_file_paths` in `metadata.yaml` (rosbag2's
/// `BagMetadata`), and only those. The list is the bag's contract: a
/// listed file that is missing is an error (reading the rest would
/// silently lose its part of the data), a file it does not list is never
/// read, and a listed path leaving the directory is refused.
pub fn bag_files(dir: &Path) -> Result<Vec<PathBuf>, LogError> {
    Ok(bag_storage(dir, false)?.present)
}

/// The storage files of a bag: those there, and those listed but missing.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct BagStorage {
    /// The listed files that are there, in order.
    pub present: Vec<PathBuf>,
    /// The listed files that are not.
    pub missing: Vec<MissingFile>,
}

/// A storage file `metadata.yaml` lists that is not in the directory.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct MissingFile {
    /// Its name, as listed.
    pub name: String,
    /// The messages it held, by the `message_count` of its entry under
    /// `files` (rosbag2's `FileInformation`, written since metadata
    /// version 5); `None` when the metadata does not say.
    pub messages: Option<u64>,
}

/// [`bag_files`], or with `allow_partial` the files that are there and
/// those missing, for the caller to report. A bag with none of its files
/// is an error either way.
pub fn bag_storage(dir: &Path, allow_partial: bool) -> Result<BagStorage, LogError> {
    let yaml = dir.join("metadata.yaml");
    let meta = std::fs::read_to_string(&yaml).map_err(|e| LogError::new(&yaml, e.into()))?;
    let mut listed = Vec::new();
    let mut inside = false;
    for (number, line) in meta.lines().enumerate() {
        let t = line.trim();
        if t.starts_with("relative_file_paths:") {
            inside = true;
            continue;
        }
        if inside {
            let Some(p) = t.strip_prefix("- ") else {
                inside = false;
                continue;
            };
            let name = Path::new(p.trim().trim_matches(['"', '\'']));
            let plain = name
                .components()
                .all(|c| matches!(c, std::path::Component::Normal(_)));
            if !plain {
                return Err(malformed(
                    &yaml,
                    "ROS 2 bag",
                    format!(
                        "the storage file {} lies outside the bag directory",
                        name.display()
                    ),
                )
                .at(format!("line {}", number + 1)));
            }
            listed.push(dir.join(name));
        }
    }
    if listed.is_empty() {
        return Err(malformed(
            &yaml,
            "ROS 2 bag",
            "relative_file_paths lists no storage file",
        ));
    }
    let name_of = |p: &Path| {
        p.file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default()
    };
    let (present, missing): (Vec<PathBuf>, Vec<PathBuf>) = listed.into_iter().partition(|p| p.is_file());
    if let Some(first) = missing.first()
        && (!allow_partial || present.is_empty())
    {
        let why = if present.is_empty() && allow_partial {
            "every storage file it lists is missing, from".to_string()
        } else {
            "the storage file".to_string()
        };
        return Err(malformed(
            &yaml,
            "ROS 2 bag",
            format!(
                "{why} {} it lists is missing: the bag is incomplete",
                name_of(first)
            ),
        ));
    }
    let counts = file_message_counts(&meta);
    let missing = missing
        .iter()
        .map(|p| {
            let name = name_of(p);
            let messages = counts.iter().find(|(n, _)| *n == name).map(|&(_, c)| c);
            MissingFile { name, messages }
        })
        .collect();
    Ok(BagStorage { present, missing })
}

/// Each `path` under `files` with its `message_count`, as rosbag2 writes
/// them (`rosbag2_storage/yaml.hpp`, `convert<FileInformation>::encode`:
/// `path`, `starting_time`, `duration`, `message_count`). The bag's own
/// `message_count` and the topics' lie outside the `files` block.
fn file_message_counts(meta: &str) -> Vec<(String, u64)> {
    let indent = |l: &str| l.len() - l.trim_start().len();
    let mut out = Vec::new();
    let mut block: Option<usize> = None;
    let mut path: Option<String> = None;
    for line in meta.lines() {
        let t = line.trim();
        if t.is_empty() {
            continue;
        }
        if t == "files:" {
            block = Some(indent(line));
            continue;
        }
        let Some(at) = block else { continue };
        if indent(line) <= at && !t.starts_with('-') {
            block = None;
            continue;
        }
        let entry = t.strip_prefix("- ").unwrap_or(t);
        if let Some(p) = entry.strip_prefix("path:") {
            path = Some(p.trim().trim_matches(['"', '\'']).to_string());
        } else if let (Some(c), Some(p)) = (entry.strip_prefix("message_count:"), &path)
            && let Ok(c) = c.trim().parse()
        {
            out.push((p.clone(), c));
            path = None;
        }
    }
    out
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

    fn bag(yaml: &str, files: &[&str]) -> tempfile::TempDir {
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(dir.path().join("metadata.yaml"), yaml).unwrap();
        for f in files {
            std::fs::write(dir.path().join(f), b"").unwrap();
        }
        dir
    }

    #[test]
    fn a_bag_is_its_listed_files_all_of_them_and_only_them() {
        let yaml = "rosbag2_bagfile_information:\n  relative_file_paths:\n    - a_0.mcap\n    - a_1.mcap\n  duration: 1\n";
        let dir = bag(yaml, &["a_0.mcap", "a_1.mcap", "stray.mcap"]);
        let files = bag_files(dir.path()).unwrap();
        assert_eq!(
            files,
            vec![dir.path().join("a_0.mcap"), dir.path().join("a_1.mcap")]
        );

        let dir = bag(yaml, &["a_0.mcap", "stray.mcap"]);
        let e = bag_files(dir.path()).unwrap_err().to_string();
        assert!(e.contains("a_1.mcap it lists is missing"), "{e}");

        let dir = bag("relative_file_paths:\n  - ../x.mcap\n", &[]);
        let e = bag_files(dir.path()).unwrap_err().to_string();
        assert!(
            e.contains("outside the bag directory") && e.contains("line 2"),
            "{e}"
        );

        let dir = bag("storage_identifier: mcap\n", &["stray.mcap"]);
        let e = bag_files(dir.path()).unwrap_err().to_string();
        assert!(e.contains("lists no storage file"), "{e}");
    }

    /// rosbag2's layout (`rosbag2_storage/yaml.hpp`): the bag's count,
    /// the topics' counts, then one entry per file.
    const SPLIT: &str = "rosbag2_bagfile_information:
  version: 5
  storage_identifier: mcap
  relative_file_paths:
    - a_0.mcap
    - a_1.mcap
    - a_2.mcap
  message_count: 900
  topics_with_message_count:
    - topic_metadata:
        name: /imu
      message_count: 900
  files:
    - path: a_0.mcap
      starting_time:
        nanoseconds_since_epoch: 1
      duration:
        nanoseconds: 2
      message_count: 300
    - path: a_1.mcap
      starting_time:
        nanoseconds_since_epoch: 3
      duration:
        nanoseconds: 4
      message_count: 250
  compression_format: zstd
";

    #[test]
    fn a_partial_bag_reads_the_files_there_and_names_those_missing_with_their_counts() {
        let dir = bag(SPLIT, &["a_0.mcap"]);
        let e = bag_storage(dir.path(), false).unwrap_err().to_string();
        assert!(e.contains("a_1.mcap it lists is missing"), "{e}");
        let s = bag_storage(dir.path(), true).unwrap();
        assert_eq!(s.present, vec![dir.path().join("a_0.mcap")]);
        assert_eq!(
            s.missing,
            vec![
                MissingFile {
                    name: "a_1.mcap".into(),
                    messages: Some(250)
                },
                MissingFile {
                    name: "a_2.mcap".into(),
                    messages: None
                },
            ]
        );
        let dir = bag(SPLIT, &[]);
        let e = bag_storage(dir.path(), true).unwrap_err().to_string();
        assert!(e.contains("every storage file it lists is missing"), "{e}");
    }
}
