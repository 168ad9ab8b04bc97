//! ArduPilot DataFlash `.bin` logs (ArduPilot `libraries/AP_Logger/
//! LogStructure.h`): messages `0xA3 0x95 type body`, each type described by
//! a `FMT` message (type 128: `type u8, length u8, name char[4], format
//! char[16], labels char[64]`) earlier in the log. The `IMU` message
//! (`TimeUS,I,GyrX,GyrY,GyrZ,AccX,AccY,AccZ,…,T,…`, rad/s, m/s², °C)
//! gives one stream per instance `I`; older logs write `IMU2`, `IMU3`
//! instead of an instance field, `Temp` for `T` (3.3, 3.4) and, before
//! 3.3, `TimeMS` in milliseconds for `TimeUS`.

use std::collections::HashMap;
use std::fs::File;
use std::io::{BufReader, Read};
use std::path::Path;

use crate::error::{LogError, malformed};
use crate::streams::{Decoded, Loss};

/// The two bytes before each message.
pub const HEAD: [u8; 2] = [0xA3, 0x95];
/// The type of `FMT` messages.
pub const FMT_TYPE: u8 = 128;

#[derive(Debug, Clone)]
struct Format {
    name: String,
    length: usize,
    /// (label, offset in the message after its 3 header bytes, format char)
    fields: Vec<(String, usize, u8)>,
}

/// The size of a format character (LogStructure.h, "Format characters").
fn char_size(c: u8) -> Option<usize> {
    Some(match c {
        b'b' | b'B' | b'M' => 1,
        b'h' | b'H' | b'c' | b'C' | b'g' => 2,
        b'i' | b'I' | b'f' | b'e' | b'E' | b'L' | b'n' => 4,
        b'd' | b'q' | b'Q' => 8,
        b'N' => 16,
        b'Z' | b'a' => 64,
        _ => return None,
    })
}

/// A numeric field's value, scaled as LogStructure.h says (`c`, `C`, `e`,
/// `E` are hundredths; `L` is 1e-7 degrees).
fn value(c: u8, b: &[u8]) -> Option<f64> {
    let le2 = || b.get(..2).and_then(|s| s.try_into().ok());
    let le4 = || b.get(..4).and_then(|s| s.try_into().ok());
    let le8 = || b.get(..8).and_then(|s| s.try_into().ok());
    Some(match c {
        b'b' => *b.first()? as i8 as f64,
        b'B' | b'M' => *b.first()? as f64,
        b'h' => i16::from_le_bytes(le2()?) as f64,
        b'H' => u16::from_le_bytes(le2()?) as f64,
        b'c' => i16::from_le_bytes(le2()?) as f64 / 100.0,
        b'C' => u16::from_le_bytes(le2()?) as f64 / 100.0,
        b'i' => i32::from_le_bytes(le4()?) as f64,
        b'I' => u32::from_le_bytes(le4()?) as f64,
        b'e' => i32::from_le_bytes(le4()?) as f64 / 100.0,
        b'E' => u32::from_le_bytes(le4()?) as f64 / 100.0,
        b'L' => i32::from_le_bytes(le4()?) as f64 * 1e-7,
        b'f' => f32::from_le_bytes(le4()?) as f64,
        b'd' => f64::from_le_bytes(le8()?),
        b'q' => i64::from_le_bytes(le8()?) as f64,
        b'Q' => u64::from_le_bytes(le8()?) as f64,
        _ => return None,
    })
}

fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b.split(|&c| c == 0).next().unwrap_or_default()).into_owned()
}

fn parse_fmt(body: &[u8]) -> Option<(u8, Format)> {
    if body.len() < 86 {
        return None;
    }
    let ty = body[0];
    let length = body[1] as usize;
    let name = text(&body[2..6]);
    let fmt = text(&body[6..22]);
    let labels = text(&body[22..86]);
    let mut offset = 0;
    let mut fields = Vec::new();
    for (c, label) in fmt.bytes().zip(labels.split(',')) {
        fields.push((label.to_string(), offset, c));
        offset += char_size(c)?;
    }
    Some((ty, Format { name, length, fields }))
}

/// Reads the `IMU` messages of a DataFlash log into `out`.
///
/// `file` is `path` opened, at its start; `path` names the errors.
pub fn read(path: &Path, file: File, out: &mut Decoded) -> Result<(), LogError> {
    let mut bytes = BufReader::with_capacity(1 << 20, file).bytes();
    let mut formats: HashMap<u8, Format> = HashMap::new();
    let mut ids: HashMap<String, f64> = HashMap::new();
    let mut pos: u64 = 0;
    let mut skipped: u64 = 0;
    // The stretch of bytes being skipped: its offset and length.
    let mut stretch: Option<(u64, u64)> = None;
    let mut body = Vec::with_capacity(256);
    let mut prev = None;
    let io = |e: std::io::Error| LogError::new(path, e.into());
    // Resynchronise on the two head bytes: a log cut by a reset or a
    // corrupt block goes on after it.
    while let Some(b) = bytes.next() {
        let b = b.map_err(io)?;
        pos += 1;
        if !(prev == Some(HEAD[0]) && b == HEAD[1]) {
            if prev.is_some() {
                skipped += 1;
                // The byte `prev`, at pos - 2, belongs to no message.
                match &mut stretch {
                    Some((_, len)) => *len += 1,
                    None => stretch = Some((pos - 2, 1)),
                }
            }
            prev = Some(b);
            continue;
        }
        prev = None;
        if let Some((offset, bytes)) = stretch.take() {
            out.losses.push(Loss {
                offset,
                bytes,
                why: "bytes outside any message (a corrupt block, or a message longer or shorter than its FMT says)".into(),
            });
        }
        let at = pos - 2;
        let Some(ty) = bytes.next() else { break };
        let ty = ty.map_err(io)?;
        pos += 1;
        let len = if ty == FMT_TYPE {
            89
        } else {
            match formats.get(&ty) {
                Some(f) => f.length,
                None => {
                    return Err(malformed(
                        path,
                        "DataFlash",
                        format!("message type {ty} has no FMT before it"),
                    )
                    .at(format!("byte {at}")));
                }
            }
        };
        if len < 3 {
            return Err(malformed(
                path,
                "DataFlash",
                format!("FMT gives type {ty} a length of {len}"),
            )
            .at(format!("byte {at}")));
        }
        body.clear();
        for _ in 0..len - 3 {
            match bytes.next() {
                Some(b) => body.push(b.map_err(io)?),
                None => break,
            }
        }
        pos += body.len() as u64;
        if body.len() < len - 3 {
            out.notes.push(format!(
                "the log ends inside a message at byte {at}; the messages before it are read"
            ));
            break;
        }
        if ty == FMT_TYPE {
            match parse_fmt(&body) {
                Some((t, f)) => {
                    let fields_end = f
                        .fields
                        .last()
                        .and_then(|&(_, o, c)| Some(o + char_size(c)?))
                        .unwrap_or(0);
                    if fields_end + 3 != f.length {
                        // The length decides where the next message
                        // starts (pymavlink's DFReader reads by it too);
                        // a wrong one shows as bytes skipped after each
                        // such message, counted as losses.
                        out.notes.push(format!(
                            "the FMT of {} (type {t}) at byte {at} gives a length of {} bytes, but its fields take {}",
                            f.name,
                            f.length,
                            fields_end + 3
                        ));
                    }
                    formats.insert(t, f);
                }
                None => {
                    return Err(malformed(
                        path,
                        "DataFlash",
                        "an FMT message with an unknown format character",
                    )
                    .at(format!("byte {at}")));
                }
            }
            continue;
        }
        let Some(f) = formats.get(&ty) else { continue };
        if f.name == "PARM" {
            if let Some((name, v)) = parameter(f, &body).filter(|(n, _)| is_imu_id(n)) {
                ids.insert(name, v);
            }
            continue;
        }
        let instance_from_name = match f.name.as_str() {
            "IMU" => Some(0),
            "IMU2" => Some(1),
            "IMU3" => Some(2),
            _ => None,
        };
        let Some(name_instance) = instance_from_name else {
            continue;
        };
        let field = |label: &str| {
            f.fields
                .iter()
                .find(|(l, _, _)| l == label)
                .and_then(|&(_, o, c)| value(c, body.get(o..)?))
        };
        let instance = field("I").map_or(name_instance, |v| v as u32);
        // ArduPilot before 3.3 stamps in milliseconds (`TimeMS`, a u32);
        // pymavlink's DFReader scales it by 0.001 (`DFReaderClock_msec`).
        let (time_name, time_us) = match field("TimeUS") {
            Some(v) => ("TimeUS", Some(v)),
            None => ("TimeMS", field("TimeMS").map(|v| v * 1e3)),
        };
        let (Some(t_us), Some(gx), Some(gy), Some(gz), Some(ax), Some(ay), Some(az)) = (
            time_us,
            field("GyrX"),
            field("GyrY"),
            field("GyrZ"),
            field("AccX"),
            field("AccY"),
            field("AccZ"),
        ) else {
            return Err(malformed(
                path,
                "DataFlash",
                format!("{} lacks TimeUS (or TimeMS) or a gyro/accel field", f.name),
            )
            .at(format!("byte {at}")));
        };
        // Later logs label the temperature `T` (`…,EG,EA,T,GH,AH,GHz,AHz`);
        // ArduCopter 3.3 and 3.4 and Solo label it `Temp` (LogStructure.h:
        // `IMU` `QffffffIIfBB` `TimeUS,…,ErrG,ErrA,Temp,GyHlt,AcHlt`).
        let temp = field("T").or_else(|| field("Temp"));
        let s = out.imu_mut(&format!("IMU/{instance}"), "ArduPilot IMU");
        s.instance = Some(instance);
        s.stamp_name = time_name;
        s.log_time_name = time_name;
        s.axis_fields = Some([["AccX", "AccY", "AccZ"], ["GyrX", "GyrY", "GyrZ"]]);
        s.push(t_us * 1e-6, t_us * 1e-6, [gx, gy, gz], [ax, ay, az], temp);
    }
    if let Some((offset, _)) = stretch {
        // Up to the end of the file, the last byte read included.
        out.losses.push(Loss {
            offset,
            bytes: pos - offset,
            why: "bytes outside any message, up to the end of the log".into(),
        });
    }
    if skipped > 0 {
        out.notes
            .push(format!("{skipped} bytes outside any message skipped"));
    }
    for s in &mut out.imu {
        // ArduPilot keeps ids for three IMUs only; a higher instance
        // (possible in a damaged log) has no parameter to look up.
        let suffix = match s.instance {
            Some(0) => "",
            Some(1) => "2",
            Some(2) => "3",
            _ => continue,
        };
        for (sensor, is_gyro) in [("GYR", true), ("ACC", false)] {
            let name = format!("INS_{sensor}{suffix}_ID");
            // An id of 0 is ArduPilot's "no sensor there".
            let Some(&v) = ids.get(&name).filter(|&&v| v > 0.0 && v <= u32::MAX as f64) else {
                continue;
            };
            let id = v as u32;
            out.entries.push((format!("ardupilot.{name}"), id.to_string()));
            if is_gyro {
                s.device_id = Some(u64::from(id));
            }
        }
    }
    Ok(())
}

/// The device-id parameters of the IMUs, `INS_GYR_ID`, `INS_GYR2_ID`,
/// `INS_GYR3_ID`, `INS_ACC_ID`, `INS_ACC2_ID`, `INS_ACC3_ID`
/// (`AP_InertialSensor.cpp`, `var_info`: `_gyro_id[0..2]`,
/// `_accel_id[0..2]`), which ArduPilot logs in its PARM messages.
fn is_imu_id(name: &str) -> bool {
    ["GYR", "ACC"]
        .iter()
        .any(|s| ["", "2", "3"].iter().any(|n| name == format!("INS_{s}{n}_ID")))
}

/// A PARM message's name and value (`LogStructure.h`, `log_Parameter`:
/// `QNf` `TimeUS,Name,Value`, later `QNff` with `Default`). The ids are
/// int32 parameters logged as float, exact below 2^24, which holds every
/// ArduPilot device id (`AP_HAL/Device.h`, `DeviceStructure`: bus type 3
/// bits, bus 5, address 8, device type 8).
fn parameter(f: &Format, body: &[u8]) -> Option<(String, f64)> {
    let field = |label: &str| {
        f.fields
            .iter()
            .find(|(l, _, _)| l == label)
            .map(|&(_, at, c)| (at, c))
    };
    let (at, c) = field("Name")?;
    if c != b'N' {
        return None;
    }
    let name = text(body.get(at..at + 16)?);
    let (at, c) = field("Value")?;
    Some((name, value(c, body.get(at..)?)?))
}
