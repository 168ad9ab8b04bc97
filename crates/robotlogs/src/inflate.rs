//! Decompression that cannot run away: every compressed chunk (MCAP zstd
//! and lz4, ROS 1 bz2 and lz4) is unpacked only up to the size its record
//! declares, and no chunk may declare more than [`MAX_CHUNK`]. A chunk of
//! a few kilobytes that would unpack to gigabytes is an error naming the
//! sizes, found before the memory or the time is spent.

use std::io::Read;

/// The most a chunk may unpack to. Writers keep chunks small so that a
/// reader can seek: rosbag's default is 768 KiB, the MCAP library's and
/// rosbag2's 4 to 8 MiB; this leaves a wide margin and bounds the memory
/// a chunk takes.
pub const MAX_CHUNK: u64 = 256 << 20;

/// Unpacks `stream`, which its record says unpacks to `declared` bytes:
/// refused when `declared` exceeds [`MAX_CHUNK`], or when the stream
/// unpacks to more or fewer bytes than declared. Reads at most one byte
/// past `declared`.
pub fn bounded(stream: impl Read, declared: u64, codec: &str) -> Result<Vec<u8>, String> {
    if declared > MAX_CHUNK {
        return Err(format!(
            "a {codec} chunk declares {declared} bytes uncompressed, more than the limit of {MAX_CHUNK} bytes per chunk"
        ));
    }
    let mut plain = Vec::with_capacity(declared as usize);
    stream
        .take(declared + 1)
        .read_to_end(&mut plain)
        .map_err(|e| format!("a {codec} chunk does not decompress: {e}"))?;
    let got = plain.len() as u64;
    if got > declared {
        return Err(format!(
            "a {codec} chunk unpacks to more than the {declared} bytes it declares"
        ));
    }
    if got < declared {
        return Err(format!(
            "a {codec} chunk unpacks to {got} bytes, not the {declared} it declares"
        ));
    }
    Ok(plain)
}

/// Whether a [`bounded`] error says the bytes are not the codec's (a
/// corrupt stream), rather than a declaration refused (a size past the
/// limit, or other than unpacked).
pub fn is_undecodable(error: &str) -> bool {
    error.contains(" chunk does not decompress")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_chunk_unpacks_to_exactly_its_declared_size() {
        let data = vec![7u8; 1000];
        assert_eq!(bounded(&data[..], 1000, "test").unwrap(), data);
        let e = bounded(&data[..], 999, "test").unwrap_err();
        assert!(e.contains("more than the 999 bytes"), "{e}");
        let e = bounded(&data[..], 1001, "test").unwrap_err();
        assert!(e.contains("1000 bytes, not the 1001"), "{e}");
    }

    #[test]
    fn a_bomb_is_refused_by_its_declaration_and_read_no_further() {
        let e = bounded(std::io::repeat(0), 16 << 30, "zstd").unwrap_err();
        assert!(e.contains("17179869184 bytes uncompressed"), "{e}");
        // A stream that never ends is read one byte past its declaration.
        let e = bounded(std::io::repeat(0), 1 << 20, "bz2").unwrap_err();
        assert!(e.contains("more than the 1048576 bytes"), "{e}");
    }
}
