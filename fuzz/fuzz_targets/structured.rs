//! Structure-aware inputs for the ULog and MCAP readers: the fuzzer's bytes
//! choose a structure instead of being the file, so that every run reaches
//! the decisions raw bytes rarely reach — ULog formats naming each other,
//! nested, repeated or containing themselves, appended-data offsets, blocks
//! of garbage between sync messages; MCAP chunks of every compression whose
//! declared size is right, wrong or absurd.

/// The fuzzer's bytes, read as numbers; zeros once they run out.
pub struct Bytes<'a>(&'a [u8]);

impl<'a> Bytes<'a> {
    pub fn new(b: &'a [u8]) -> Bytes<'a> {
        Bytes(b)
    }

    pub fn u8(&mut self) -> u8 {
        match self.0.split_first() {
            Some((&b, rest)) => {
                self.0 = rest;
                b
            }
            None => 0,
        }
    }

    pub fn u16(&mut self) -> u16 {
        u16::from_le_bytes([self.u8(), self.u8()])
    }

    pub fn u64(&mut self) -> u64 {
        (0..8).fold(0u64, |acc, k| acc | (self.u8() as u64) << (8 * k))
    }

    /// Up to `n` bytes.
    pub fn take(&mut self, n: usize) -> &'a [u8] {
        let n = n.min(self.0.len());
        let (head, rest) = self.0.split_at(n);
        self.0 = rest;
        head
    }
}

/// ULog (docs.px4.io, "ULog File Format").
pub mod ulog {
    use super::Bytes;

    const SYNC: [u8; 8] = [0x2F, 0x73, 0x13, 0x20, 0x25, 0x0C, 0xBB, 0x12];
    const PRIMS: [&str; 8] = ["uint8_t", "int16_t", "uint32_t", "int64_t", "uint64_t", "float", "double", "char"];

    fn msg(ty: u8, body: &[u8]) -> Vec<u8> {
        let mut m = (body.len().min(u16::MAX as usize) as u16).to_le_bytes().to_vec();
        m.push(ty);
        m.extend_from_slice(&body[..body.len().min(u16::MAX as usize)]);
        m
    }

    /// A ULog file whose formats, subscriptions and data the bytes choose.
    pub fn build(input: &[u8]) -> Vec<u8> {
        let mut b = Bytes::new(input);
        let mut f = b"ULog\x01\x12\x35\x01".to_vec();
        f.extend(0u64.to_le_bytes());
        let flags = b.u8();
        if flags & 1 != 0 {
            // Flag bits with appended-data offsets anywhere, backwards too.
            let mut bits = vec![0u8; 40];
            bits[8] = 1;
            for k in 0..3 {
                let o = if flags & 2 != 0 { b.u64() % 4096 } else { b.u64() };
                bits[16 + 8 * k..24 + 8 * k].copy_from_slice(&o.to_le_bytes());
            }
            f.extend(msg(b'B', &bits));
        }
        // Formats f0…fN whose fields are primitives or other formats, any
        // of them, itself included.
        let formats = (b.u8() % 8) as usize + 1;
        for i in 0..formats {
            let mut text = format!("f{i}:");
            for k in 0..(b.u8() % 6) as usize + 1 {
                let pick = b.u8() as usize % (PRIMS.len() + formats);
                let ty = match PRIMS.get(pick) {
                    Some(p) => p.to_string(),
                    None => format!("f{}", pick - PRIMS.len()),
                };
                let count = match b.u8() {
                    c if c >= 0xF0 => b.u16() as usize,
                    c => (c % 4) as usize + 1,
                };
                text.push_str(&format!("{ty}[{count}] x{k};"));
            }
            f.extend(msg(b'F', text.as_bytes()));
        }
        // The decoded topic, with a nested format in it when the bytes say.
        let nested = match b.u8() % 3 {
            0 => String::new(),
            _ => format!("f{} nested;", b.u8() as usize % formats),
        };
        let combined = format!(
            "sensor_combined:uint64_t timestamp;{nested}float[3] gyro_rad;uint32_t gyro_integral_dt;int32_t accelerometer_timestamp_relative;float[3] accelerometer_m_s2;"
        );
        f.extend(msg(b'F', combined.as_bytes()));
        let mut sub = vec![0u8, 0, 0];
        sub.extend_from_slice(b"sensor_combined");
        f.extend(msg(b'A', &sub));
        let mut sub = vec![0u8, 1, 0];
        sub.extend_from_slice(format!("f{}", b.u8() as usize % formats).as_bytes());
        f.extend(msg(b'A', &sub));
        // Data: steady, repeated, reversed or chosen stamps, with sync
        // messages, blocks of 0xFF and short messages among them.
        let step = b.u8() as u64 * 100;
        let mut t = 1_000_000u64;
        for k in 0..b.u16() % 2048 {
            match b.u8() {
                0xFF => f.extend(vec![0xFF; (b.u16() % 8192) as usize]),
                0xFE => f.extend(msg(b'S', &SYNC)),
                0xFD => t = b.u64(),
                0xFC => t = t.saturating_sub(step),
                _ => t = t.saturating_add(step),
            }
            let mut d = vec![0u8, 0];
            d.extend(t.to_le_bytes());
            // Sized for the topic without a nested format, with one, or
            // cut short.
            let body = b.take([32, 96, 4][(k % 3) as usize]);
            d.extend_from_slice(body);
            f.extend(msg(b'D', &d));
        }
        f
    }
}

/// MCAP (mcap.dev/spec).
pub mod mcap {
    use std::io::Write;

    use super::Bytes;

    fn record(op: u8, body: &[u8]) -> Vec<u8> {
        let mut r = vec![op];
        r.extend((body.len() as u64).to_le_bytes());
        r.extend_from_slice(body);
        r
    }

    fn string(s: &[u8]) -> Vec<u8> {
        let mut b = (s.len() as u32).to_le_bytes().to_vec();
        b.extend_from_slice(s);
        b
    }

    /// A schema, a channel of `sensor_msgs/msg/Imu` over CDR, and messages
    /// whose bodies the bytes give.
    fn records(b: &mut Bytes<'_>) -> Vec<u8> {
        let mut out = Vec::new();
        let mut schema = 1u16.to_le_bytes().to_vec();
        schema.extend(string(b"sensor_msgs/msg/Imu"));
        schema.extend(string(b"ros2msg"));
        schema.extend(string(b""));
        out.extend(record(0x03, &schema));
        let mut channel = 1u16.to_le_bytes().to_vec();
        channel.extend(1u16.to_le_bytes());
        channel.extend(string(b"/imu"));
        channel.extend(string(b"cdr"));
        channel.extend(0u32.to_le_bytes());
        out.extend(record(0x04, &channel));
        for k in 0..b.u8() % 32 {
            let mut m = 1u16.to_le_bytes().to_vec();
            m.extend((k as u32).to_le_bytes());
            let t = b.u64();
            m.extend(t.to_le_bytes());
            m.extend(t.to_le_bytes());
            // Little-endian CDR's encapsulation, then the body.
            m.extend([0, 1, 0, 0]);
            let n = b.u8() as usize * 2;
            m.extend_from_slice(b.take(n));
            out.extend(record(0x05, &m));
        }
        out
    }

    /// An MCAP file of chunks whose compression and declared size the
    /// bytes choose: exact, off by some bytes, or absurd.
    pub fn build(input: &[u8]) -> Vec<u8> {
        let mut b = Bytes::new(input);
        let mut f = b"\x89MCAP0\r\n".to_vec();
        let mut header = string(b"ros2");
        header.extend(string(b"fuzz"));
        f.extend(record(0x01, &header));
        for _ in 0..b.u8() % 4 + 1 {
            let plain = records(&mut b);
            let (compression, data): (&[u8], Vec<u8>) = match b.u8() % 4 {
                0 => (b"", plain.clone()),
                1 => {
                    let mut e = lz4_flex::frame::FrameEncoder::new(Vec::new());
                    let _ = e.write_all(&plain);
                    (b"lz4", e.finish().unwrap_or_default())
                }
                2 => (b"zstd", zstd::encode_all(&plain[..], 1).unwrap_or_default()),
                _ => (b"zstd", b.take(64).to_vec()),
            };
            let declared = match b.u8() {
                0xFF => b.u64(),
                0xFE => plain.len() as u64 + b.u16() as u64,
                0xFD => (plain.len() as u64).saturating_sub(b.u16() as u64),
                _ => plain.len() as u64,
            };
            let mut c = 0u64.to_le_bytes().to_vec();
            c.extend(u64::MAX.to_le_bytes());
            c.extend(declared.to_le_bytes());
            c.extend(0u32.to_le_bytes());
            c.extend(string(compression));
            c.extend((data.len() as u64).to_le_bytes());
            c.extend(data);
            f.extend(record(0x06, &c));
        }
        f.extend(record(0x02, &[0u8; 20]));
        f.extend(b"\x89MCAP0\r\n");
        f
    }
}
