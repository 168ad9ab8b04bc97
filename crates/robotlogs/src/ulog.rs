//! PX4 ULog (docs.px4.io, "ULog File Format"; pyulog's `core.py` is the
//! reference reader): a 16-byte header, then messages of `u16 size, u8
//! type, body`. Formats (`F`) describe topics, subscriptions (`A`) give a
//! topic instance a message id, data (`D`) carries one sample. Appended
//! data (flag bits `B`, `incompat_flags[0]` bit 0) continues at the given
//! offsets.
//!
//! `sensor_gyro` and `sensor_accel` (PX4 `msg/SensorGyro.msg`,
//! `SensorAccel.msg`: `timestamp`, `timestamp_sample`, `device_id`, `x`,
//! `y`, `z` in rad/s and m/s², `temperature` in °C) give one stream per
//! instance; `sensor_combined` (`gyro_rad[3]`, `accelerometer_m_s2[3]`,
//! `accelerometer_timestamp_relative`) one more.

use std::collections::HashMap;
use std::fs::File;
use std::io::{BufReader, Read, Seek, SeekFrom};
use std::path::Path;

use crate::error::{LogError, malformed};
use crate::streams::{Decoded, Loss};

/// The first bytes of a ULog file.
pub const MAGIC: &[u8] = b"ULog\x01\x12\x35";

#[derive(Debug, Clone)]
struct Field {
    ty: String,
    count: usize,
    name: String,
}

/// A field's place in a topic's data.
#[derive(Debug, Clone, Copy)]
struct Slot {
    offset: usize,
    ty: Prim,
}

#[derive(Debug, Clone, Copy, PartialEq)]
enum Prim {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    I64,
    U64,
    F32,
    F64,
    Other,
}

fn prim(ty: &str) -> (Prim, Option<usize>) {
    match ty {
        "int8_t" => (Prim::I8, Some(1)),
        "uint8_t" | "bool" | "char" => (Prim::U8, Some(1)),
        "int16_t" => (Prim::I16, Some(2)),
        "uint16_t" => (Prim::U16, Some(2)),
        "int32_t" => (Prim::I32, Some(4)),
        "uint32_t" => (Prim::U32, Some(4)),
        "int64_t" => (Prim::I64, Some(8)),
        "uint64_t" => (Prim::U64, Some(8)),
        "float" => (Prim::F32, Some(4)),
        "double" => (Prim::F64, Some(8)),
        _ => (Prim::Other, None),
    }
}

impl Slot {
    fn get(self, b: &[u8], index: usize) -> Option<f64> {
        let size = match self.ty {
            Prim::I8 | Prim::U8 => 1,
            Prim::I16 | Prim::U16 => 2,
            Prim::I32 | Prim::U32 | Prim::F32 => 4,
            _ => 8,
        };
        let at = self.offset.checked_add(index * size)?;
        let s = b.get(at..at + size)?;
        Some(match self.ty {
            Prim::I8 => s[0] as i8 as f64,
            Prim::U8 => s[0] as f64,
            Prim::I16 => i16::from_le_bytes(s.try_into().ok()?) as f64,
            Prim::U16 => u16::from_le_bytes(s.try_into().ok()?) as f64,
            Prim::I32 => i32::from_le_bytes(s.try_into().ok()?) as f64,
            Prim::U32 => u32::from_le_bytes(s.try_into().ok()?) as f64,
            Prim::I64 => i64::from_le_bytes(s.try_into().ok()?) as f64,
            Prim::U64 => u64::from_le_bytes(s.try_into().ok()?) as f64,
            Prim::F32 => f32::from_le_bytes(s.try_into().ok()?) as f64,
            Prim::F64 => f64::from_le_bytes(s.try_into().ok()?),
            Prim::Other => return None,
        })
    }
}

/// The message types of the ULog format (docs.px4.io, "ULog File Format":
/// flag bits, format, info, multi info, parameter, default parameter, add
/// and remove subscription, data, logging, tagged logging, sync, dropout).
const MESSAGE_TYPES: &[u8] = b"BFIMPQARDLCSO";

/// The sync message's magic bytes (the same page, "Synchronization").
const SYNC_MAGIC: [u8; 8] = [0x2F, 0x73, 0x13, 0x20, 0x25, 0x0C, 0xBB, 0x12];

/// The offset of the next sync message's header at or after `from`, read
/// a block at a time; `None` when there is none.
fn find_sync<R: Read + Seek>(r: &mut R, from: u64) -> std::io::Result<Option<u64>> {
    r.seek(SeekFrom::Start(from))?;
    let mut block = vec![0u8; 1 << 16];
    // Bytes carried over from the last block, so that a magic across two
    // blocks is found; `base` is the offset of `block[0]`.
    let mut kept = 0usize;
    let mut base = from;
    loop {
        let n = r.read(&mut block[kept..])?;
        if n == 0 {
            return Ok(None);
        }
        let filled = kept + n;
        // The header (u16 size, b'S') sits just before the magic.
        let found = block[..filled]
            .windows(SYNC_MAGIC.len())
            .enumerate()
            .filter(|(_, w)| *w == SYNC_MAGIC)
            .map(|(i, _)| base + i as u64)
            .find(|&magic_at| magic_at >= from + 3);
        if let Some(magic_at) = found {
            return Ok(Some(magic_at - 3));
        }
        kept = (SYNC_MAGIC.len() - 1).min(filled);
        block.copy_within(filled - kept..filled, 0);
        base += (filled - kept) as u64;
    }
}

/// Formats nested deeper than this are corrupt: PX4's messages nest a few
/// levels at most.
const MAX_NESTING: usize = 32;

/// Why a topic's format cannot be laid out.
#[derive(Debug, Clone, PartialEq)]
enum FormatFault {
    /// The format contains itself, directly or through others.
    Contains(String),
    /// Formats nested deeper than [`MAX_NESTING`].
    TooDeep(String),
    /// Sizes beyond any message (a u16 bounds a message's size).
    TooLarge(String),
}

impl std::fmt::Display for FormatFault {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            FormatFault::Contains(t) => write!(f, "the format '{t}' contains itself"),
            FormatFault::TooDeep(t) => {
                write!(f, "the format '{t}' nests formats more than {MAX_NESTING} deep")
            }
            FormatFault::TooLarge(t) => write!(f, "the format '{t}' is larger than any message"),
        }
    }
}

/// The sizes of formats, each computed once: nested formats are walked in
/// time linear in their fields, however they repeat one another.
struct Sizes<'a> {
    formats: &'a HashMap<String, Vec<Field>>,
    known: HashMap<String, Option<usize>>,
    open: Vec<String>,
}

impl<'a> Sizes<'a> {
    fn new(formats: &'a HashMap<String, Vec<Field>>) -> Sizes<'a> {
        Sizes {
            formats,
            known: HashMap::new(),
            open: Vec::new(),
        }
    }

    /// The size of `ty`; `None` for a type no format describes.
    fn of(&mut self, ty: &str) -> Result<Option<usize>, FormatFault> {
        if let (_, Some(s)) = prim(ty) {
            return Ok(Some(s));
        }
        if let Some(&s) = self.known.get(ty) {
            return Ok(s);
        }
        if self.open.iter().any(|o| o == ty) {
            return Err(FormatFault::Contains(ty.to_string()));
        }
        if self.open.len() >= MAX_NESTING {
            return Err(FormatFault::TooDeep(self.open[0].clone()));
        }
        let Some(fields) = self.formats.get(ty) else {
            return Ok(None);
        };
        self.open.push(ty.to_string());
        let mut total = Some(0usize);
        for f in fields {
            let Some(size) = self.of(&f.ty)? else {
                total = None;
                break;
            };
            total = size
                .checked_mul(f.count)
                .and_then(|s| total?.checked_add(s))
                .filter(|&t| t <= u16::MAX as usize);
            if total.is_none() {
                return Err(FormatFault::TooLarge(ty.to_string()));
            }
        }
        self.open.pop();
        self.known.insert(ty.to_string(), total);
        Ok(total)
    }
}

/// A topic's fields, each with its slot, and the size of its data when
/// every field's type is known.
#[derive(Debug, Clone, Default)]
struct Layout {
    slots: HashMap<String, Slot>,
    size: Option<usize>,
}

/// The slot of each top-level field of `topic`. A field of a type no
/// format describes ends the layout: what follows cannot be placed.
fn layout(topic: &str, formats: &HashMap<String, Vec<Field>>) -> Result<Layout, FormatFault> {
    let mut sizes = Sizes::new(formats);
    let mut out = Layout::default();
    let mut offset = 0usize;
    let Some(fields) = formats.get(topic) else {
        return Ok(out);
    };
    sizes.open.push(topic.to_string());
    for f in fields {
        let Some(size) = sizes.of(&f.ty)? else {
            return Ok(out);
        };
        out.slots.insert(
            f.name.clone(),
            Slot {
                offset,
                ty: prim(&f.ty).0,
            },
        );
        offset = size
            .checked_mul(f.count)
            .and_then(|s| offset.checked_add(s))
            .filter(|&t| t <= u16::MAX as usize)
            .ok_or_else(|| FormatFault::TooLarge(topic.to_string()))?;
    }
    out.size = Some(offset);
    Ok(out)
}

/// The fields each decoded topic must have, by the PX4 messages.
fn required_fields(topic: &str) -> &'static [&'static str] {
    match topic {
        "sensor_gyro" | "sensor_accel" => &["timestamp", "x", "y", "z"],
        "sensor_combined" => &["timestamp", "gyro_rad", "accelerometer_m_s2"],
        _ => &[],
    }
}

/// `name:type field;type[n] field;…`
fn parse_format(s: &str) -> Option<(String, Vec<Field>)> {
    let (name, body) = s.split_once(':')?;
    let fields = body
        .split(';')
        .filter(|f| !f.trim().is_empty())
        .filter_map(|f| {
            let (ty, name) = f.trim().split_once(' ')?;
            let (ty, count) = match ty.split_once('[') {
                Some((t, n)) => (t, n.trim_end_matches(']').parse().ok()?),
                None => (ty, 1),
            };
            Some(Field {
                ty: ty.to_string(),
                count,
                name: name.to_string(),
            })
        })
        .collect();
    Some((name.to_string(), fields))
}

#[derive(Default)]
struct Sensor {
    t_sample: Vec<f64>,
    t_log: Vec<f64>,
    xyz: [Vec<f64>; 3],
    temp: Vec<f64>,
    device_id: Option<u64>,
}

/// Reads the IMU topics of a ULog file into `out`.
///
/// `file` is `path` opened, at its start; `path` names the errors.
pub fn read(path: &Path, file: File, out: &mut Decoded) -> Result<(), LogError> {
    let mut r = BufReader::with_capacity(1 << 20, file);
    let mut head = [0u8; 16];
    r.read_exact(&mut head)
        .map_err(|_| malformed(path, "ULog", "shorter than its 16-byte header"))?;
    if &head[..7] != MAGIC {
        return Err(malformed(path, "ULog", "no ULog magic"));
    }
    let mut formats: HashMap<String, Vec<Field>> = HashMap::new();
    // msg_id → (topic, multi_id, layout)
    let mut subs: HashMap<u16, (String, u8, Layout)> = HashMap::new();
    let mut gyro: HashMap<u8, Sensor> = HashMap::new();
    let mut accel: HashMap<u8, Sensor> = HashMap::new();
    // sensor_combined: the gyroscope in `xyz`, the accelerometer's three
    // axes one after another in `accel3` (both sampled for the same message).
    let mut combined = Sensor::default();
    let mut accel3: Vec<f64> = Vec::new();
    let mut appended: Vec<u64> = Vec::new();
    let mut pos: u64 = 16;
    let mut dropouts = (0usize, 0u64);
    let mut buf = Vec::with_capacity(1024);
    loop {
        // The main section ends where appended data begins. Offsets only
        // ever move forward (checked when read), so reading ends.
        if let Some(&next) = appended.first()
            && pos >= next
        {
            appended.remove(0);
        }
        let mut h = [0u8; 3];
        match r.read_exact(&mut h) {
            Ok(()) => {}
            Err(e) if e.kind() == std::io::ErrorKind::UnexpectedEof => break,
            Err(e) => return Err(LogError::new(path, e.into())),
        }
        let size = u16::from_le_bytes([h[0], h[1]]) as usize;
        let ty = h[2];
        if !MESSAGE_TYPES.contains(&ty) {
            // Not a message: corrupt bytes. Reading resumes at the next
            // sync message, as pyulog does (`ULog._find_sync`), and the
            // stretch skipped is counted.
            let resume = find_sync(&mut r, pos + 1).map_err(|e| LogError::new(path, e.into()))?;
            let end = match resume {
                Some(at) => at,
                None => r
                    .seek(SeekFrom::End(0))
                    .map_err(|e| LogError::new(path, e.into()))?,
            };
            out.losses.push(Loss {
                offset: pos,
                bytes: end - pos,
                why: format!(
                    "a message of unknown type 0x{ty:02x}{}",
                    if resume.is_some() {
                        ", skipped to the next sync message"
                    } else {
                        ", with no sync message after it"
                    }
                ),
            });
            r.seek(SeekFrom::Start(end))
                .map_err(|e| LogError::new(path, e.into()))?;
            pos = end;
            continue;
        }
        if let Some(&next) = appended.first()
            && pos + 3 + size as u64 > next
        {
            // A message cut off where the appended data starts: pyulog
            // (`ULog._read_file_data`) skips to the offset the same way.
            r.seek(SeekFrom::Start(next))
                .map_err(|e| LogError::new(path, e.into()))?;
            pos = next;
            continue;
        }
        buf.resize(size, 0);
        if r.read_exact(&mut buf).is_err() {
            out.notes.push(format!(
                "the log ends inside a message at byte {pos} (cut off while writing); the messages before it are read"
            ));
            break;
        }
        let at = pos;
        pos += 3 + size as u64;
        match ty {
            b'B' if buf.len() >= 40 && buf[8] & 1 != 0 => {
                appended = (0..3)
                    .map(|k| u64::from_le_bytes(buf[16 + 8 * k..24 + 8 * k].try_into().unwrap_or_default()))
                    .filter(|&o| o > 0)
                    .collect();
                // Each offset lies ahead of the last: one pointing back
                // would read the same bytes for ever.
                let mut from = pos;
                for &o in &appended {
                    if o < from {
                        return Err(malformed(
                            path,
                            "ULog",
                            format!("an appended-data offset ({o}) points back to before byte {from}"),
                        )
                        .at(format!("byte {at}")));
                    }
                    from = o;
                }
            }
            b'F' => {
                if let Some((name, fields)) = parse_format(&String::from_utf8_lossy(&buf)) {
                    formats.insert(name, fields);
                }
            }
            b'I' if !buf.is_empty() => {
                let klen = buf[0] as usize;
                if let Some(key) = buf.get(1..1 + klen) {
                    let key = String::from_utf8_lossy(key);
                    if let Some((kty, kname)) = key.split_once(' ')
                        && kty.starts_with("char[")
                        && matches!(kname, "ver_hw" | "sys_name" | "ver_sw_release_str" | "sys_uuid")
                    {
                        let v = String::from_utf8_lossy(&buf[1 + klen..])
                            .trim_end_matches('\0')
                            .to_string();
                        out.entries.push((format!("px4.{kname}"), v));
                    }
                }
            }
            b'A' if buf.len() >= 3 => {
                let multi = buf[0];
                let id = u16::from_le_bytes([buf[1], buf[2]]);
                let name = String::from_utf8_lossy(&buf[3..])
                    .trim_end_matches('\0')
                    .to_string();
                let needed = required_fields(&name);
                let lay = match layout(&name, &formats) {
                    Ok(lay) => lay,
                    // A topic imutherm does not decode may be laid out
                    // however it likes; one it decodes must make sense.
                    Err(_) if needed.is_empty() => Layout::default(),
                    Err(fault) => {
                        return Err(malformed(path, "ULog", format!("the format of {name}: {fault}"))
                            .at(format!("byte {at}")));
                    }
                };
                if let Some(missing) = needed.iter().find(|f| !lay.slots.contains_key(**f))
                    && formats.contains_key(&name)
                {
                    return Err(malformed(
                        path,
                        "ULog",
                        format!("the format of {name} has no field '{missing}' (or one of a type no format describes before it)"),
                    )
                    .at(format!("byte {at}")));
                }
                subs.insert(id, (name, multi, lay));
            }
            b'O' if buf.len() >= 2 => {
                dropouts.0 += 1;
                dropouts.1 += u16::from_le_bytes([buf[0], buf[1]]) as u64;
            }
            b'D' if buf.len() >= 2 => {
                let id = u16::from_le_bytes([buf[0], buf[1]]);
                let Some((name, multi, lay)) = subs.get(&id) else {
                    continue;
                };
                let data = &buf[2..];
                let get = |f: &str, i: usize| lay.slots.get(f).and_then(|s| s.get(data, i));
                let short = || {
                    let what = match lay.size {
                        None if lay.slots.is_empty() => {
                            format!("{name} has data but no format (F message) before it describing them")
                        }
                        Some(size) if data.len() < size => format!(
                            "a {name} message of {} bytes is shorter than its format's {size} bytes",
                            data.len()
                        ),
                        _ => format!("a {name} message of {} bytes is cut short", data.len()),
                    };
                    malformed(path, "ULog", what).at(format!("byte {at}"))
                };
                match name.as_str() {
                    "sensor_gyro" | "sensor_accel" => {
                        let map = if name == "sensor_gyro" {
                            &mut gyro
                        } else {
                            &mut accel
                        };
                        let s = map.entry(*multi).or_default();
                        let t_log = get("timestamp", 0).ok_or_else(short)? * 1e-6;
                        let t_sample = get("timestamp_sample", 0)
                            .map_or(f64::NAN, |v| if v > 0.0 { v * 1e-6 } else { f64::NAN });
                        s.t_log.push(t_log);
                        s.t_sample.push(t_sample);
                        for (k, f) in ["x", "y", "z"].iter().enumerate() {
                            s.xyz[k].push(get(f, 0).ok_or_else(short)?);
                        }
                        s.temp.push(get("temperature", 0).unwrap_or(f64::NAN));
                        if s.device_id.is_none() {
                            s.device_id = get("device_id", 0).map(|v| v as u64);
                        }
                    }
                    "sensor_combined" if *multi == 0 => {
                        let t = get("timestamp", 0).ok_or_else(short)?;
                        combined.t_log.push(t * 1e-6);
                        combined.t_sample.push(f64::NAN);
                        for k in 0..3 {
                            combined.xyz[k].push(get("gyro_rad", k).ok_or_else(short)?);
                            accel3.push(get("accelerometer_m_s2", k).ok_or_else(short)?);
                        }
                    }
                    _ => {}
                }
            }
            _ => {}
        }
    }
    if dropouts.0 > 0 {
        out.notes.push(format!(
            "the logger dropped data {} times ({} ms in all): gaps in every topic",
            dropouts.0, dropouts.1
        ));
    }
    let mut instances: Vec<u8> = gyro.keys().copied().collect();
    instances.sort_unstable();
    for i in instances {
        let Some(g) = gyro.remove(&i) else { continue };
        let a = accel.remove(&i).unwrap_or_default();
        let name = format!("sensor_gyro/{i}");
        let s = out.imu_mut(&name, "px4 sensor_gyro + sensor_accel");
        s.instance = Some(i as u32);
        s.stamp_name = "timestamp_sample";
        s.log_time_name = "timestamp";
        s.device_id = g.device_id;
        s.axis_fields = Some([
            ["sensor_accel.x", "sensor_accel.y", "sensor_accel.z"],
            ["sensor_gyro.x", "sensor_gyro.y", "sensor_gyro.z"],
        ]);
        let a_t = if a.t_sample.iter().all(|v| v.is_finite()) {
            &a.t_sample
        } else {
            &a.t_log
        };
        let g_t = if g.t_sample.iter().all(|v| v.is_finite()) {
            &g.t_sample
        } else {
            &g.t_log
        };
        let acc = nearest(a_t, &a.xyz, g_t);
        for (k, (&ts, &tl)) in g.t_sample.iter().zip(&g.t_log).enumerate() {
            let at = |v: &[Vec<f64>; 3]| [v[0][k], v[1][k], v[2][k]];
            s.push(ts, tl, at(&g.xyz), at(&acc), Some(g.temp[k]));
        }
        if let Some(id) = a.device_id {
            out.entries
                .push((format!("px4.sensor_accel/{i}.device_id"), id.to_string()));
        }
        if let Some(id) = g.device_id {
            out.entries
                .push((format!("px4.sensor_gyro/{i}.device_id"), id.to_string()));
        }
    }
    if !combined.t_log.is_empty() {
        let s = out.imu_mut("sensor_combined", "px4 sensor_combined");
        s.stamp_name = "timestamp";
        s.log_time_name = "timestamp";
        s.axis_fields = Some([
            [
                "accelerometer_m_s2[0]",
                "accelerometer_m_s2[1]",
                "accelerometer_m_s2[2]",
            ],
            ["gyro_rad[0]", "gyro_rad[1]", "gyro_rad[2]"],
        ]);
        let n = combined.t_log.len();
        for k in 0..n {
            let acc = [accel3[3 * k], accel3[3 * k + 1], accel3[3 * k + 2]];
            s.push(
                combined.t_log[k],
                combined.t_log[k],
                [combined.xyz[0][k], combined.xyz[1][k], combined.xyz[2][k]],
                acc,
                None,
            );
        }
    }
    Ok(())
}

/// The accelerometer sample nearest in time to each gyroscope sample (the
/// two are sampled apart, often at different rates).
fn nearest(t: &[f64], xyz: &[Vec<f64>; 3], at: &[f64]) -> [Vec<f64>; 3] {
    let mut out: [Vec<f64>; 3] = Default::default();
    let mut j = 0;
    for &x in at {
        while j + 1 < t.len() && (t[j + 1] - x).abs() <= (t[j] - x).abs() {
            j += 1;
        }
        for k in 0..3 {
            out[k].push(if t.is_empty() { f64::NAN } else { xyz[k][j] });
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn formats_and_nested_layouts() {
        let mut f = HashMap::new();
        let (n, v) = parse_format("inner:uint16_t a;float[2] b;").unwrap();
        f.insert(n, v);
        let (n, v) = parse_format("outer:uint64_t timestamp;inner[2] c;float x;").unwrap();
        f.insert(n, v);
        let l = layout("outer", &f).unwrap();
        assert_eq!(l.slots["timestamp"].offset, 0);
        assert_eq!(l.slots["c"].offset, 8);
        assert_eq!(l.slots["x"].offset, 8 + 2 * 10);
        assert_eq!(l.size, Some(8 + 2 * 10 + 4));
    }

    fn formats(lines: &[&str]) -> HashMap<String, Vec<Field>> {
        lines.iter().map(|l| parse_format(l).unwrap()).collect()
    }

    #[test]
    fn a_format_containing_itself_is_refused() {
        let f = formats(&["loop:uint64_t timestamp;loop a;"]);
        assert_eq!(
            layout("loop", &f).unwrap_err(),
            FormatFault::Contains("loop".into())
        );
        let f = formats(&["a:uint8_t x;b y;", "b:a z;", "t:a w;"]);
        assert!(matches!(layout("t", &f), Err(FormatFault::Contains(_))));
    }

    #[test]
    fn nested_formats_are_laid_out_once_each() {
        // Twenty levels of formats each holding the next three times:
        // walked field by field this is 3^20 visits; each size is
        // computed once.
        let mut lines: Vec<String> = (0..20)
            .map(|k| format!("n{k}:n{} a;n{} b;n{} c;", k + 1, k + 1, k + 1))
            .collect();
        lines.push("n20:uint8_t x;".into());
        let refs: Vec<&str> = lines.iter().map(String::as_str).collect();
        let f = formats(&refs);
        let started = std::time::Instant::now();
        // 3^20 bytes: larger than any message.
        assert!(matches!(layout("n0", &f), Err(FormatFault::TooLarge(_))));
        assert!(started.elapsed() < std::time::Duration::from_secs(1));
        let deep: Vec<String> = (0..40).map(|k| format!("d{k}:d{} a;", k + 1)).collect();
        let refs: Vec<&str> = deep.iter().map(String::as_str).collect();
        assert!(matches!(
            layout("d0", &formats(&refs)),
            Err(FormatFault::TooDeep(_))
        ));
    }
}
