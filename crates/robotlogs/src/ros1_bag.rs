//! ROS 1 bags, format 2.0 (wiki.ros.org/Bags/Format/2.0): records of
//! `header_len, header fields (len, name=value), data_len, data`; messages
//! sit in chunks, uncompressed, bz2 or lz4 (roslz4 writes LZ4 frames). The
//! file is read a record at a time and a chunk is decompressed whole.

use std::collections::HashMap;
use std::fs::File;
use std::io::{BufReader, Read};
use std::path::Path;

use crate::error::{LogError, LogErrorKind, malformed};
use crate::ros_msgs::{self, Kind};
use crate::streams::{Decoded, Loss};

/// The first line of a bag.
pub const MAGIC: &[u8] = b"#ROSBAG V2.0\n";

const OP_MSG_DATA: u8 = 0x02;
const OP_CHUNK: u8 = 0x05;
const OP_CONNECTION: u8 = 0x07;

/// Records larger than this are corrupt, not data (rosbag's chunks are
/// 768 KiB by default).
const MAX_RECORD: usize = 1 << 30;

struct State {
    /// conn id → (topic, type, kind)
    conns: HashMap<u32, (String, String, Option<Kind>)>,
    messages: u64,
}

/// Reads the IMU and temperature messages of a ROS 1 bag into `out`.
///
/// `file` is `path` opened, at its start; `path` names the errors.
pub fn read(path: &Path, file: File, out: &mut Decoded) -> Result<(), LogError> {
    let mut r = BufReader::with_capacity(1 << 20, file);
    let mut magic = [0u8; 13];
    r.read_exact(&mut magic)
        .map_err(|e| LogError::new(path, e.into()))?;
    if magic != MAGIC {
        return Err(malformed(path, "ROS 1 bag", "no #ROSBAG V2.0 line"));
    }
    let mut state = State {
        conns: HashMap::new(),
        messages: 0,
    };
    let mut offset = MAGIC.len() as u64;
    loop {
        let at = offset;
        let Some((header, data)) = next_record(&mut r, &mut offset)
            .map_err(|w| malformed(path, "ROS 1 bag", w).at(format!("byte {at}")))?
        else {
            break;
        };
        let fields = fields(&header).map_err(|w| malformed(path, "ROS 1 bag", w).at(format!("byte {at}")))?;
        let op = field(&fields, "op").and_then(|v| v.first().copied());
        if op == Some(OP_CHUNK) {
            let compression = field(&fields, "compression").unwrap_or(b"none");
            let size = field(&fields, "size").and_then(le_u32);
            // A chunk whose bytes are not its codec's, or whose records do
            // not frame, is skipped whole and counted: its record's lengths
            // are intact (the next record starts where they say), and
            // nothing of it was used. A declaration refused (no size, too
            // large, another size than unpacked, an unknown codec) stays an
            // error, as does an outer length that lies.
            let lost = |why: String, out: &mut Decoded| {
                out.losses.push(Loss {
                    offset: at,
                    bytes: offset - at,
                    why: format!("a corrupt ROS 1 bag chunk: {why}"),
                });
            };
            let plain = match decompress(path, compression, &data, size) {
                Ok(p) => p,
                Err(LogError {
                    kind: LogErrorKind::Malformed { what, .. },
                    ..
                }) if crate::inflate::is_undecodable(&what) => {
                    lost(what, out);
                    continue;
                }
                Err(e) => return Err(e.at(format!("chunk at byte {at}"))),
            };
            let mut inner = plain.as_slice();
            let mut inner_off = 0u64;
            let mut records = Vec::new();
            let framed = loop {
                match next_record(&mut inner, &mut inner_off) {
                    Ok(Some(r)) => records.push(r),
                    Ok(None) => break Ok(()),
                    Err(w) => break Err(format!("its records do not frame at offset {inner_off}: {w}")),
                }
            };
            if let Err(why) = framed {
                lost(why, out);
                continue;
            }
            for (h, d) in records {
                handle(path, out, &mut state, &h, &d).map_err(|e| e.at(format!("chunk at byte {at}")))?;
            }
        } else {
            handle(path, out, &mut state, &header, &data).map_err(|e| e.at(format!("byte {at}")))?;
        }
    }
    Ok(())
}

fn decompress(path: &Path, compression: &[u8], data: &[u8], size: Option<u32>) -> Result<Vec<u8>, LogError> {
    if compression == b"none" {
        return Ok(data.to_vec());
    }
    // rosbag writes the unpacked size of every chunk (`size`): without
    // it a chunk could unpack to anything.
    let size =
        size.ok_or_else(|| malformed(path, "ROS 1 bag", "a compressed chunk without its size field"))?;
    let bounded = |stream: &mut dyn Read, codec: &str| {
        crate::inflate::bounded(stream, u64::from(size), codec).map_err(|w| malformed(path, "ROS 1 bag", w))
    };
    match compression {
        b"bz2" => bounded(&mut bzip2::read::BzDecoder::new(data), "bz2"),
        b"lz4" => bounded(&mut lz4_flex::frame::FrameDecoder::new(data), "lz4"),
        other => Err(LogError::new(
            path,
            LogErrorKind::Compression(String::from_utf8_lossy(other).into_owned()),
        )),
    }
}

fn handle(
    path: &Path,
    out: &mut Decoded,
    st: &mut State,
    header: &[u8],
    data: &[u8],
) -> Result<(), LogError> {
    let f = fields(header).map_err(|w| malformed(path, "ROS 1 bag", w))?;
    match field(&f, "op").and_then(|v| v.first().copied()) {
        Some(OP_CONNECTION) => {
            let conn = field(&f, "conn").and_then(le_u32).unwrap_or(u32::MAX);
            let topic = String::from_utf8_lossy(field(&f, "topic").unwrap_or_default()).into_owned();
            let cf = fields(data).map_err(|w| malformed(path, "ROS 1 bag connection", w))?;
            let ty = String::from_utf8_lossy(field(&cf, "type").unwrap_or_default()).into_owned();
            let kind = ros_msgs::kind_of(&ty);
            st.conns.insert(conn, (topic, ty, kind));
        }
        Some(OP_MSG_DATA) => {
            st.messages += 1;
            let conn = field(&f, "conn").and_then(le_u32).unwrap_or(u32::MAX);
            if let Some((topic, ty, Some(kind))) = st.conns.get(&conn) {
                let time = field(&f, "time")
                    .filter(|t| t.len() == 8)
                    .map(|t| le_u32(&t[..4]).unwrap_or(0) as f64 + le_u32(&t[4..]).unwrap_or(0) as f64 * 1e-9)
                    .unwrap_or(f64::NAN);
                ros_msgs::add(out, *kind, topic, ty, data, time, true).map_err(|what| {
                    malformed(path, "ROS 1 message", what).at(format!("message {} on {topic}", st.messages))
                })?;
            }
        }
        _ => {}
    }
    Ok(())
}

fn le_u32(b: &[u8]) -> Option<u32> {
    Some(u32::from_le_bytes(b.get(..4)?.try_into().ok()?))
}

fn read_u32(r: &mut impl Read) -> Result<Option<u32>, String> {
    let mut b = [0u8; 4];
    let mut got = 0;
    while got < 4 {
        match r.read(&mut b[got..]) {
            Ok(0) if got == 0 => return Ok(None),
            Ok(0) => return Err("the file ends inside a record's length".into()),
            Ok(n) => got += n,
            Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
            Err(e) => return Err(e.to_string()),
        }
    }
    Ok(Some(u32::from_le_bytes(b)))
}

fn read_block(r: &mut impl Read, offset: &mut u64) -> Result<Option<Vec<u8>>, String> {
    let Some(len) = read_u32(r)? else {
        return Ok(None);
    };
    let len = len as usize;
    if len > MAX_RECORD {
        return Err(format!("a record field of {len} bytes"));
    }
    let mut buf = Vec::new();
    r.take(len as u64)
        .read_to_end(&mut buf)
        .map_err(|e| e.to_string())?;
    if buf.len() != len {
        return Err(format!(
            "the file ends inside a record ({} of {len} bytes)",
            buf.len()
        ));
    }
    *offset += 4 + len as u64;
    Ok(Some(buf))
}

/// The next record's header and data; `None` at the end.
/// A record's header and data.
type RawRecord = (Vec<u8>, Vec<u8>);

/// A header's fields, name and value.
type Fields<'a> = Vec<(&'a [u8], &'a [u8])>;

fn next_record(r: &mut impl Read, offset: &mut u64) -> Result<Option<RawRecord>, String> {
    let Some(header) = read_block(r, offset)? else {
        return Ok(None);
    };
    let data = read_block(r, offset)?.ok_or("the file ends after a record header")?;
    Ok(Some((header, data)))
}

/// `len, name=value` fields.
fn fields(mut b: &[u8]) -> Result<Fields<'_>, String> {
    let mut out = Vec::new();
    while !b.is_empty() {
        let len = le_u32(b).ok_or("a header field cut short")? as usize;
        let end = len.checked_add(4).ok_or("a header field of impossible length")?;
        let body = b.get(4..end).ok_or("a header field runs past its header")?;
        let eq = body
            .iter()
            .position(|&c| c == b'=')
            .ok_or("a header field without '='")?;
        out.push((&body[..eq], &body[eq + 1..]));
        b = &b[end..];
    }
    Ok(out)
}

fn field<'a>(f: &[(&'a [u8], &'a [u8])], name: &str) -> Option<&'a [u8]> {
    f.iter().find(|(k, _)| *k == name.as_bytes()).map(|(_, v)| *v)
}
