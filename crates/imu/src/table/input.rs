//! The bytes of a table: a file, standard input, a pipe or a device, read
//! once from start to end; gzip members decompressed on the fly (found by
//! their magic bytes, not the name); the stream's tail kept as it goes by,
//! for the trailer.

use std::fs::File;
use std::io::{BufRead, BufReader, Read};
use std::path::Path;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex};

use super::MAX_LINE_BYTES;
use crate::error::{ReadError, ReadErrorKind};

/// How much of the end of the stream is kept to find the trailer in (the
/// recorder writes it last).
const TAIL_BYTES: usize = 64 * 1024;

/// An input opened for reading.
pub(super) struct Input {
    /// The decoded bytes.
    pub reader: Box<dyn BufRead + Send>,
    /// The file's size when it is a regular, uncompressed file (a pipe's
    /// or a gzip file's size says nothing of the data).
    pub file_bytes: Option<u64>,
    /// What of the stream has gone by.
    pub seen: Arc<Seen>,
}

/// What of a stream has gone by, shared with its reader.
#[derive(Debug, Default)]
pub(super) struct Seen {
    /// The last bytes of the stream read so far.
    pub tail: Mutex<Vec<u8>>,
    /// The bytes of the stream read so far, decompressed: what bounds the
    /// columns of an input of unknown size.
    pub bytes: AtomicU64,
}

impl Seen {
    /// The bytes read so far.
    pub fn bytes(&self) -> u64 {
        self.bytes.load(Ordering::Relaxed)
    }
}

/// Opens `path` (`-`: standard input), decompressing gzip.
pub(super) fn open(path: &Path) -> Result<Input, ReadError> {
    if path == Path::new("-") {
        return from_raw(path, Box::new(std::io::stdin()), None);
    }
    let file = File::open(path).map_err(|e| ReadError::new(path, ReadErrorKind::Io(e)))?;
    from_file(path, file)
}

/// [`open`] of `file`, already opened from `path` and at its start: the
/// file is not opened again.
pub(super) fn from_file(path: &Path, file: File) -> Result<Input, ReadError> {
    let meta = file
        .metadata()
        .map_err(|e| ReadError::new(path, ReadErrorKind::Io(e)))?;
    if meta.is_dir() {
        return Err(ReadError::new(path, ReadErrorKind::IsDirectory));
    }
    let size = meta.is_file().then_some(meta.len());
    from_raw(path, Box::new(file), size)
}

pub(super) fn from_raw(
    path: &Path,
    raw_input: Box<dyn Read + Send>,
    regular_bytes: Option<u64>,
) -> Result<Input, ReadError> {
    let io_err = |e: std::io::Error| ReadError::new(path, ReadErrorKind::Io(e));
    let mut buffered = BufReader::with_capacity(1 << 16, raw_input);
    let gz = buffered.fill_buf().map_err(io_err)?.starts_with(&[0x1f, 0x8b]);
    let decoded: Box<dyn Read + Send> = if gz {
        Box::new(GzipMembers::new(buffered))
    } else {
        Box::new(buffered)
    };
    let seen = Arc::new(Seen::default());
    let reader = Box::new(BufReader::with_capacity(
        1 << 16,
        TailKeeper {
            inner: decoded,
            seen: Arc::clone(&seen),
        },
    ));
    Ok(Input {
        reader,
        file_bytes: if gz { None } else { regular_bytes },
        seen,
    })
}

/// The value of the last `# trailer:` line in `tail`.
pub(super) fn find_trailer(tail: &[u8]) -> Option<String> {
    String::from_utf8_lossy(tail)
        .lines()
        .rev()
        .find_map(|l| l.trim().strip_prefix("# trailer:").map(|v| v.trim().to_string()))
}

/// How a bounded line read ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum LineRead {
    /// At its newline.
    Whole,
    /// At the end of the input, without a newline (or nothing was left).
    Unterminated,
    /// At [`MAX_LINE_BYTES`], without a newline.
    TooLong,
}

/// Reads one line into `raw` (cleared first), newline included, stopping
/// at [`MAX_LINE_BYTES`].
pub(super) fn read_line_bounded(input: &mut dyn BufRead, raw: &mut Vec<u8>) -> std::io::Result<LineRead> {
    raw.clear();
    loop {
        let buf = input.fill_buf()?;
        if buf.is_empty() {
            return Ok(LineRead::Unterminated);
        }
        let room = MAX_LINE_BYTES + 1 - raw.len();
        let (take, done) = match memchr::memchr(b'\n', buf) {
            Some(nl) if nl < room => (nl + 1, Some(LineRead::Whole)),
            _ if buf.len() >= room => (room, Some(LineRead::TooLong)),
            _ => (buf.len(), None),
        };
        raw.extend_from_slice(&buf[..take]);
        input.consume(take);
        if let Some(how) = done {
            return Ok(how);
        }
    }
}

/// Passes a stream through, counting its bytes and keeping its last [`TAIL_BYTES`]: the trailer
/// is found there without reading the input a second time (which a pipe
/// cannot give, and a live stream would lose bytes to).
struct TailKeeper {
    inner: Box<dyn Read + Send>,
    seen: Arc<Seen>,
}

impl Read for TailKeeper {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        let n = self.inner.read(buf)?;
        self.seen.bytes.fetch_add(n as u64, Ordering::Relaxed);
        let mut tail = self.seen.tail.lock().unwrap_or_else(|p| p.into_inner());
        // Only the last TAIL_BYTES of a read can still be the tail: a block
        // read of a megabyte copies 64 KiB, not all of it (the copy was a
        // tenth of the reading time).
        let keep = &buf[n.saturating_sub(TAIL_BYTES)..n];
        if keep.len() == TAIL_BYTES {
            tail.clear();
        }
        tail.extend_from_slice(keep);
        if tail.len() > 2 * TAIL_BYTES {
            let cut = tail.len() - TAIL_BYTES;
            tail.drain(..cut);
        }
        Ok(n)
    }
}

/// Gzip members one after another, as `gzip -d` reads them: a file of
/// several members is their concatenation, and zero bytes after the last
/// member (padding a tape or a block device adds) are ignored. Other bytes
/// after it are an error rather than data dropped unseen.
struct GzipMembers<R: BufRead> {
    member: Option<flate2::bufread::GzDecoder<R>>,
}

impl<R: BufRead> GzipMembers<R> {
    fn new(input: R) -> Self {
        GzipMembers {
            member: Some(flate2::bufread::GzDecoder::new(input)),
        }
    }
}

impl<R: BufRead> Read for GzipMembers<R> {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        loop {
            let Some(member) = self.member.as_mut() else {
                return Ok(0);
            };
            let n = member.read(buf)?;
            if n > 0 || buf.is_empty() {
                return Ok(n);
            }
            // The member ended (its CRC and length checked): what follows?
            let Some(member) = self.member.take() else {
                return Ok(0);
            };
            let mut rest = member.into_inner();
            let mut padding = false;
            loop {
                let next = rest.fill_buf()?;
                if next.is_empty() {
                    return Ok(0);
                }
                if !padding && next[0] == 0x1f {
                    // gzip(1) reads a member's magic byte by byte too.
                    self.member = Some(flate2::bufread::GzDecoder::new(rest));
                    break;
                }
                // Zero padding runs to the end, or it is not padding.
                if next.iter().any(|&b| b != 0) {
                    return Err(std::io::Error::new(
                        std::io::ErrorKind::InvalidData,
                        "data after the end of the gzip stream that is neither another member nor zero padding",
                    ));
                }
                let n = next.len();
                rest.consume(n);
                padding = true;
            }
        }
    }
}
