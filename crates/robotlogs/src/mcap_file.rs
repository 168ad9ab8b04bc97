//! MCAP files (mcap.dev/spec), read record by record through the `mcap`
//! crate's sans-io reader, so that a chunk at a time is held, not the file.

use std::collections::HashMap;
use std::fs::File;
use std::io::Read;
use std::path::Path;

use mcap::records::Record;
use mcap::sans_io::linear_reader::{LinearReadEvent, LinearReader, LinearReaderOptions};

use crate::error::{LogError, LogErrorKind};
use crate::ros_msgs::{self, Kind};
use crate::streams::Decoded;

/// Reads the IMU and temperature messages of one MCAP file into `out`.
pub fn read(path: &Path, out: &mut Decoded) -> Result<(), LogError> {
    let mut file = File::open(path).map_err(|e| LogError::new(path, e.into()))?;
    // No record of a file is longer than the file: a corrupt length is an
    // error, not a request for that many bytes of memory (found by fuzzing:
    // a record claiming 2.5e18 bytes aborted the process).
    let size = file.metadata().map_err(|e| LogError::new(path, e.into()))?.len();
    let limit = usize::try_from(size).unwrap_or(usize::MAX).max(1);
    let mut reader =
        LinearReader::new_with_options(LinearReaderOptions::default().with_record_length_limit(limit));
    let mut schemas: HashMap<u16, String> = HashMap::new();
    // channel id → (topic, type, kind)
    let mut channels: HashMap<u16, (String, String, Option<Kind>)> = HashMap::new();
    let mut offset: u64 = 0;
    let mut messages: u64 = 0;
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
                match mcap::parse_record(opcode, data).map_err(|e| mcap_err(e, offset))? {
                    Record::Schema { header, .. } => {
                        schemas.insert(header.id, header.name);
                    }
                    Record::Channel(ch) => {
                        let ty = schemas.get(&ch.schema_id).cloned().unwrap_or_default();
                        let kind = if ch.message_encoding == "cdr" {
                            ros_msgs::kind_of(&ty)
                        } else {
                            None
                        };
                        channels.insert(ch.id, (ch.topic, ty, kind));
                    }
                    Record::Message { header, data } => {
                        messages += 1;
                        if let Some((topic, ty, Some(kind))) = channels.get(&header.channel_id) {
                            ros_msgs::add(out, *kind, topic, ty, &data, header.log_time as f64 * 1e-9, false)
                                .map_err(|what| {
                                    crate::error::malformed(path, "CDR message", what)
                                        .at(format!("message {messages} on {topic}"))
                                })?;
                        }
                    }
                    _ => {}
                }
            }
        }
    }
    Ok(())
}
