//! The recorder's `# trailer:` line: found at the end of a file, split into
//! its fields.

use std::path::Path;

/// Metadata key under which readers keep the logger's `# trailer:` line.
pub const TRAILER_KEY: &str = "trailer";

/// How far from the end of a file the trailer is looked for.
const TRAILER_WINDOW: u64 = 64 * 1024;

/// The value of the last `# trailer:` line in the file's last 64 KiB (what
/// `imutherm record` counted: samples, gaps, overflows, bus errors…), or
/// `None` (no trailer, a gzip file, not a regular file, unreadable). Reads
/// only that tail, of a regular file only: a pipe or a device cannot be read
/// again (the readers take the trailer from the stream, [`crate::table::Table::trailer`]).
pub fn read_trailer(path: &Path) -> Option<String> {
    use std::io::{Read, Seek, SeekFrom};
    if !std::fs::metadata(path).ok()?.is_file() {
        return None;
    }
    let mut f = std::fs::File::open(path).ok()?;
    let len = f.metadata().ok()?.len();
    let mut magic = [0u8; 2];
    if f.read_exact(&mut magic).is_ok() && magic == [0x1f, 0x8b] {
        return None;
    }
    f.seek(SeekFrom::Start(len.saturating_sub(TRAILER_WINDOW))).ok()?;
    let mut tail = Vec::new();
    f.take(TRAILER_WINDOW).read_to_end(&mut tail).ok()?;
    String::from_utf8_lossy(&tail)
        .lines()
        .rev()
        .find_map(|l| l.trim().strip_prefix("# trailer:").map(|v| v.trim().to_string()))
}

/// The `key=value` fields of a trailer.
pub fn trailer_fields(trailer: &str) -> Vec<(&str, &str)> {
    trailer
        .split_whitespace()
        .filter_map(|f| f.split_once('='))
        .collect()
}
