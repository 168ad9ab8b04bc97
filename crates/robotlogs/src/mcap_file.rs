//! MCAP files (mcap.dev/spec), read record by record through the `mcap`
//! crate's sans-io reader, so that a chunk at a time is held, not the file.
//! Chunks are unpacked here rather than by the library, under
//! [`crate::inflate`]'s bound: a chunk may unpack to no more than it
//! declares, and declare no more than the limit.

use std::collections::HashMap;
use std::fs::File;
use std::io::Read;
use std::path::Path;

use mcap::records::Record;
use mcap::sans_io::linear_reader::{LinearReadEvent, LinearReader, LinearReaderOptions};

use crate::error::{LogError, LogErrorKind, malformed};
use crate::ros_msgs::{self, Kind};
use crate::streams::{BadMessage, Decoded, Loss};

/// The MCAP chunk record's opcode (spec: "Chunk (op=0x06)").
const OP_CHUNK: u8 = 0x06;

/// What the records read so far have declared.
struct State<'p> {
    path: &'p Path,
    schemas: HashMap<u16, String>,
    /// channel id → (topic, type, kind)
    channels: HashMap<u16, (String, String, Option<Kind>)>,
    messages: u64,
    /// Chunks skipped as corrupt: a channel they defined is unknown after.
    chunks_lost: bool,
    /// Messages on a channel no record defined, after a chunk was lost.
    orphans: usize,
}

/// Reads the IMU and temperature messages of one MCAP file into `out`.
///
/// `file` is `path` opened, at its start; `path` names the errors.
pub fn read(path: &Path, mut file: File, out: &mut Decoded) -> Result<(), LogError> {
    // No record of a file is longer than the file: a corrupt length is an
    // error, not a request for that many bytes of memory (found by fuzzing:
    // a record claiming 2.5e18 bytes aborted the process).
    let size = file.metadata().map_err(|e| LogError::new(path, e.into()))?.len();
    let limit = usize::try_from(size).unwrap_or(usize::MAX).max(1);
    let mut reader = LinearReader::new_with_options(
        LinearReaderOptions::default()
            .with_record_length_limit(limit)
            .with_emit_chunks(true),
    );
    let mut state = State {
        path,
        schemas: HashMap::new(),
        channels: HashMap::new(),
        messages: 0,
        chunks_lost: false,
        orphans: 0,
    };
    // Where the next record starts: after the magic, each record's opcode,
    // length and body (mcap.dev/spec, "Records").
    let mut at: u64 = crate::format::MCAP_MAGIC.len() as u64;
    let mut offset: u64 = 0;
    let mcap_err = |e: mcap::McapError, offset: u64| {
        LogError::new(path, LogErrorKind::Mcap(e.to_string())).at(format!("near byte {offset}"))
    };
    while let Some(event) = reader.next_event() {
        match event.map_err(|e| mcap_err(e, offset))? {
            LinearReadEvent::ReadRequest(n) => {
                let buf = reader.insert(n);
                let got = file.read(buf).map_err(|e| LogError::new(path, e.into()))?;
                reader.notify_read(got);
                offset += got as u64;
            }
            LinearReadEvent::Record { data, opcode } => {
                let start = at;
                let bytes = 9 + data.len() as u64;
                at += bytes;
                let record = mcap::parse_record(opcode, data).map_err(|e| mcap_err(e, offset))?;
                if let Record::Chunk { header, data } = record {
                    // A chunk whose bytes are not its codec's, or unpack to
                    // other bytes than its CRC says, is skipped whole and
                    // counted: its record's length is intact (the reader went
                    // past it by that length), so the next record reads, and
                    // nothing of it was decoded. A declaration refused (a
                    // size past the limit, or other than unpacked, an
                    // unknown codec) stays an error, as does a length that
                    // lies, which stops the reader.
                    let skip = |why: String, out: &mut Decoded, state: &mut State<'_>| {
                        out.losses.push(Loss {
                            offset: start,
                            bytes,
                            why: format!("a corrupt MCAP chunk: {why}"),
                        });
                        state.chunks_lost = true;
                    };
                    let plain = match unpack(&header.compression, &data, header.uncompressed_size) {
                        Ok(p) => p,
                        Err(why) if crate::inflate::is_undecodable(&why) => {
                            skip(why, out, &mut state);
                            continue;
                        }
                        Err(why) => {
                            return Err(malformed(path, "MCAP", why).at(format!("chunk near byte {offset}")));
                        }
                    };
                    let crc = crc32fast::hash(&plain);
                    if header.uncompressed_crc != 0 && header.uncompressed_crc != crc {
                        let why = format!(
                            "its records' CRC is {crc:#010x}, its header says {:#010x}",
                            header.uncompressed_crc
                        );
                        skip(why, out, &mut state);
                        continue;
                    }
                    chunk_records(&mut state, out, &plain)
                        .map_err(|e| e.at(format!("chunk near byte {offset}")))?;
                } else {
                    handle(&mut state, out, record)?;
                }
            }
        }
    }
    if state.orphans > 0 && out.imu.is_empty() {
        // Not "no IMU stream": there were messages, their channels lost.
        return Err(malformed(
            path,
            "MCAP",
            format!(
                "{} messages are on channels defined only in a corrupt chunk that was skipped ({}): none can be read",
                state.orphans,
                out.losses
                    .iter()
                    .map(|l| format!("bytes {}..{}", l.offset, l.offset + l.bytes))
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
        ));
    }
    if state.orphans > 0 {
        out.bad_messages.push(BadMessage {
            at: format!("{} messages", state.orphans),
            why: "their channel was defined in a corrupt chunk that was skipped".into(),
            count: state.orphans,
        });
    }
    Ok(())
}

/// A chunk's records, unpacked under the bound.
fn unpack(compression: &str, data: &[u8], declared: u64) -> Result<Vec<u8>, String> {
    match compression {
        "" => Ok(data.to_vec()),
        "zstd" => {
            let decoder = zstd::stream::read::Decoder::new(data)
                .map_err(|e| format!("a zstd chunk does not decompress: {e}"))?;
            crate::inflate::bounded(decoder, declared, "zstd")
        }
        "lz4" => crate::inflate::bounded(lz4_flex::frame::FrameDecoder::new(data), declared, "lz4"),
        other => Err(format!(
            "a chunk compressed with '{other}', which MCAP readers do not know"
        )),
    }
}

/// The records of an unpacked chunk: `opcode u8, length u64, body`.
fn chunk_records(state: &mut State<'_>, out: &mut Decoded, mut rest: &[u8]) -> Result<(), LogError> {
    let path = state.path;
    while !rest.is_empty() {
        let (Some(&opcode), Some(len)) = (rest.first(), rest.get(1..9)) else {
            return Err(malformed(
                path,
                "MCAP",
                "a record's opcode and length cut short by the end of its chunk",
            ));
        };
        let len = u64::from_le_bytes(len.try_into().unwrap_or_default());
        let body = usize::try_from(len)
            .ok()
            .and_then(|len| rest.get(9..9usize.checked_add(len)?))
            .ok_or_else(|| {
                malformed(
                    path,
                    "MCAP",
                    format!("a record of {len} bytes runs past the end of its chunk"),
                )
            })?;
        if opcode == OP_CHUNK {
            return Err(malformed(path, "MCAP", "a chunk inside a chunk"));
        }
        let record = mcap::parse_record(opcode, body)
            .map_err(|e| LogError::new(path, LogErrorKind::Mcap(e.to_string())))?;
        handle(state, out, record)?;
        rest = &rest[9 + body.len()..];
    }
    Ok(())
}

/// One record outside or inside a chunk.
fn handle(state: &mut State<'_>, out: &mut Decoded, record: Record<'_>) -> Result<(), LogError> {
    match record {
        Record::Schema { header, .. } => {
            state.schemas.insert(header.id, header.name);
        }
        Record::Channel(ch) => {
            let ty = state.schemas.get(&ch.schema_id).cloned().unwrap_or_default();
            let kind = if ch.message_encoding == "cdr" {
                ros_msgs::kind_of(&ty)
            } else {
                None
            };
            state.channels.insert(ch.id, (ch.topic, ty, kind));
        }
        Record::Message { header, data } => {
            state.messages += 1;
            if state.chunks_lost && !state.channels.contains_key(&header.channel_id) {
                state.orphans += 1;
            }
            if let Some((topic, ty, Some(kind))) = state.channels.get(&header.channel_id) {
                ros_msgs::add(out, *kind, topic, ty, &data, header.log_time as f64 * 1e-9, false).map_err(
                    |what| {
                        malformed(state.path, "CDR message", what)
                            .at(format!("message {} on {topic}", state.messages))
                    },
                )?;
            }
        }
        _ => {}
    }
    Ok(())
}
