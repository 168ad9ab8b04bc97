//! `sensor_msgs/Imu` and `sensor_msgs/Temperature` from their serialized
//! bytes: ROS 2's CDR (OMG DDS-XTypes 1.3, §7.4.3.5 "XCDR1": a 4-byte
//! encapsulation header, then each primitive aligned to its size counted
//! from the end of that header) and ROS 1's packed little-endian form
//! (wiki.ros.org/msg, "Serialization").
//!
//! The messages' layouts (common_interfaces, sensor_msgs/msg/Imu.msg and
//! Temperature.msg; std_msgs/msg/Header.msg):
//! Imu = header, orientation (4 × f64), its covariance (9 × f64),
//! angular_velocity (3 × f64), covariance (9), linear_acceleration (3),
//! covariance (9). Temperature = header, temperature (f64, °C), variance.

/// A decoded IMU message.
#[derive(Debug, Clone, PartialEq)]
pub struct ImuMsg {
    /// Header stamp in seconds; NaN when zero (not filled in).
    pub stamp: f64,
    /// header.frame_id.
    pub frame_id: String,
    /// rad/s.
    pub gyro: [f64; 3],
    /// m/s².
    pub accel: [f64; 3],
}

/// A decoded Temperature message.
#[derive(Debug, Clone, PartialEq)]
pub struct TempMsg {
    /// Header stamp in seconds; NaN when zero.
    pub stamp: f64,
    /// °C.
    pub celsius: f64,
}

/// Bytes read in order, with CDR's alignment or without (ROS 1).
struct Cursor<'a> {
    buf: &'a [u8],
    pos: usize,
    /// Where alignment counts from; `None` for ROS 1 (packed).
    origin: Option<usize>,
    little: bool,
}

impl<'a> Cursor<'a> {
    fn take(&mut self, n: usize) -> Result<&'a [u8], String> {
        if let Some(o) = self.origin {
            let rel = self.pos - o;
            let pad = (n.min(8) - rel % n.min(8)) % n.min(8);
            self.pos += pad;
        }
        let end = self
            .pos
            .checked_add(n)
            .filter(|&e| e <= self.buf.len())
            .ok_or_else(|| {
                format!(
                    "message of {} bytes ends before byte {} (field of {n} bytes)",
                    self.buf.len(),
                    self.pos
                )
            })?;
        let s = &self.buf[self.pos..end];
        self.pos = end;
        Ok(s)
    }

    fn u32(&mut self) -> Result<u32, String> {
        let b: [u8; 4] = self.take(4)?.try_into().map_err(|_| "short".to_string())?;
        Ok(if self.little {
            u32::from_le_bytes(b)
        } else {
            u32::from_be_bytes(b)
        })
    }

    fn f64(&mut self) -> Result<f64, String> {
        let b: [u8; 8] = self.take(8)?.try_into().map_err(|_| "short".to_string())?;
        Ok(if self.little {
            f64::from_le_bytes(b)
        } else {
            f64::from_be_bytes(b)
        })
    }

    /// Steps over `n` f64 fields (orientation, covariances) unread.
    fn skip_f64s(&mut self, n: usize) -> Result<(), String> {
        self.take(8)?;
        self.take_bytes(8 * (n - 1))?;
        Ok(())
    }

    fn f64s<const N: usize>(&mut self) -> Result<[f64; N], String> {
        let mut out = [0.0; N];
        for v in &mut out {
            *v = self.f64()?;
        }
        Ok(out)
    }

    /// Header: (seq in ROS 1), stamp, frame_id. Returns (stamp, frame_id).
    fn header(&mut self, ros1: bool) -> Result<(f64, String), String> {
        if ros1 {
            self.u32()?; // seq
        }
        let sec = self.u32()?;
        let nsec = self.u32()?;
        let len = self.u32()? as usize;
        let raw = self.take_bytes(len)?;
        // CDR strings carry their terminating NUL in the length.
        let text = raw.strip_suffix(&[0]).unwrap_or(raw);
        let frame = String::from_utf8_lossy(text).into_owned();
        // ROS 2 stamps' seconds are int32, ROS 1's uint32.
        let sec = if ros1 { sec as f64 } else { sec as i32 as f64 };
        let stamp = if sec == 0.0 && nsec == 0 {
            f64::NAN
        } else {
            sec + nsec as f64 * 1e-9
        };
        Ok((stamp, frame))
    }

    fn take_bytes(&mut self, n: usize) -> Result<&'a [u8], String> {
        let end = self
            .pos
            .checked_add(n)
            .filter(|&e| e <= self.buf.len())
            .ok_or_else(|| {
                format!(
                    "string of {n} bytes runs past the message's {} bytes",
                    self.buf.len()
                )
            })?;
        let s = &self.buf[self.pos..end];
        self.pos = end;
        Ok(s)
    }
}

/// The cursor after a CDR encapsulation header.
fn cdr(buf: &[u8]) -> Result<Cursor<'_>, String> {
    let little = match buf.get(..2) {
        Some([0, 1]) | Some([0, 3]) => true,
        Some([0, 0]) | Some([0, 2]) => false,
        Some(h) => return Err(format!("unknown CDR encapsulation {:02x}{:02x}", h[0], h[1])),
        None => return Err("message shorter than its CDR header".into()),
    };
    if buf.len() < 4 {
        return Err("message shorter than its CDR header".into());
    }
    Ok(Cursor {
        buf,
        pos: 4,
        origin: Some(4),
        little,
    })
}

fn ros1(buf: &[u8]) -> Cursor<'_> {
    Cursor {
        buf,
        pos: 0,
        origin: None,
        little: true,
    }
}

fn imu(mut c: Cursor<'_>, is_ros1: bool) -> Result<ImuMsg, String> {
    let (stamp, frame_id) = c.header(is_ros1)?;
    // orientation (4) and its covariance (9), unused; once aligned, f64
    // arrays are contiguous.
    c.skip_f64s(4 + 9)?;
    let gyro = c.f64s::<3>()?;
    c.skip_f64s(9)?;
    let accel = c.f64s::<3>()?;
    Ok(ImuMsg {
        stamp,
        frame_id,
        gyro,
        accel,
    })
}

fn temp(mut c: Cursor<'_>, is_ros1: bool) -> Result<TempMsg, String> {
    let (stamp, _) = c.header(is_ros1)?;
    Ok(TempMsg {
        stamp,
        celsius: c.f64()?,
    })
}

/// A ROS 2 `sensor_msgs/msg/Imu` in CDR, either byte order.
pub fn imu_cdr(buf: &[u8]) -> Result<ImuMsg, String> {
    imu(cdr(buf)?, false)
}

/// A ROS 2 `sensor_msgs/msg/Temperature` in CDR.
pub fn temp_cdr(buf: &[u8]) -> Result<TempMsg, String> {
    temp(cdr(buf)?, false)
}

/// A ROS 1 `sensor_msgs/Imu`.
pub fn imu_ros1(buf: &[u8]) -> Result<ImuMsg, String> {
    imu(ros1(buf), true)
}

/// A ROS 1 `sensor_msgs/Temperature`.
pub fn temp_ros1(buf: &[u8]) -> Result<TempMsg, String> {
    temp(ros1(buf), true)
}

/// What a message type is to imutherm.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// sensor_msgs Imu.
    Imu,
    /// sensor_msgs Temperature.
    Temperature,
}

/// The kind of a type name, ROS 1 (`sensor_msgs/Imu`) or ROS 2
/// (`sensor_msgs/msg/Imu`).
pub fn kind_of(type_name: &str) -> Option<Kind> {
    match type_name {
        "sensor_msgs/msg/Imu" | "sensor_msgs/Imu" => Some(Kind::Imu),
        "sensor_msgs/msg/Temperature" | "sensor_msgs/Temperature" => Some(Kind::Temperature),
        _ => None,
    }
}

/// Adds one serialized message of `kind` on `topic` to `out`.
pub(crate) fn add(
    out: &mut crate::streams::Decoded,
    kind: Kind,
    topic: &str,
    type_name: &str,
    data: &[u8],
    log_time_s: f64,
    is_ros1: bool,
) -> Result<(), String> {
    match kind {
        Kind::Imu => {
            let m = if is_ros1 { imu_ros1(data)? } else { imu_cdr(data)? };
            let s = out.imu_mut(topic, type_name);
            if s.is_empty() {
                s.stamp_name = "header stamp";
                s.log_time_name = "bag time";
                s.frame_id = Some(m.frame_id.clone());
            }
            s.push(m.stamp, log_time_s, m.gyro, m.accel, None);
        }
        Kind::Temperature => {
            let m = if is_ros1 {
                temp_ros1(data)?
            } else {
                temp_cdr(data)?
            };
            let s = out.temp_mut(topic);
            if s.msg_type.is_empty() {
                s.msg_type = type_name.to_string();
            }
            s.stamp.push(m.stamp);
            s.log_time.push(log_time_s);
            s.value.push(m.celsius);
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A CDR Imu written by hand the way the standard lays it out.
    fn imu_bytes(little: bool, frame: &str) -> Vec<u8> {
        let mut b = vec![0, if little { 1 } else { 0 }, 0, 0];
        let u = |b: &mut Vec<u8>, v: u32| b.extend(if little { v.to_le_bytes() } else { v.to_be_bytes() });
        u(&mut b, 12);
        u(&mut b, 500_000_000);
        u(&mut b, frame.len() as u32 + 1);
        b.extend(frame.as_bytes());
        b.push(0);
        while (b.len() - 4) % 8 != 0 {
            b.push(0);
        }
        for k in 0..37 {
            let v = k as f64;
            b.extend(if little { v.to_le_bytes() } else { v.to_be_bytes() });
        }
        b
    }

    #[test]
    fn cdr_imu_both_byte_orders_with_alignment() {
        for little in [true, false] {
            for frame in ["", "imu", "imu_link"] {
                let m = imu_cdr(&imu_bytes(little, frame)).unwrap();
                assert_eq!(m.stamp, 12.5);
                assert_eq!(m.frame_id, frame);
                // orientation 0..4, covariance 4..13, angular velocity 13..16.
                assert_eq!(m.gyro, [13.0, 14.0, 15.0]);
                assert_eq!(m.accel, [25.0, 26.0, 27.0]);
            }
        }
        let b = imu_bytes(true, "x");
        assert!(imu_cdr(&b[..b.len() - 100]).is_err());
        assert!(imu_cdr(&[7, 7, 0, 0]).is_err());
    }
}
