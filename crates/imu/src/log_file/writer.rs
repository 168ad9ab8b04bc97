//! Writing the thesis log and imutherm's log: the header, metadata, rows
//! in their shortest exact form, comments among the rows and the trailer.

use std::io::{self, Write};

use crate::recording::{Axis, Metadata, Recording, standard_name};
use crate::units::Quantity;

/// The thesis log's header, exactly as its logger wrote it (with the `m/^2`
/// misprint, which readers of that format expect).
pub const THESIS_HEADER: &str = "mpu_accel_1[m/^2], mpu_accel_2[m/^2], mpu_accel_3[m/^2], \
mpu_gyro_1[rad/s], mpu_gyro_2[rad/s], mpu_gyro_3[rad/s], temp[degC]";

/// The value of imutherm's `# format:` line.
pub const IMUTHERM_FORMAT: &str = "imutherm-log/1";

/// Metadata key of the sample rate.
pub const KEY_RATE: &str = "sample_rate_hz";

/// Which flavour to write.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LogFormat {
    /// Header and rows only.
    Thesis,
    /// `# key: value` metadata, then the thesis body.
    Imutherm,
}

/// Writes IMU samples row by row: accel x/y/z (m/s²), gyro x/y/z (rad/s),
/// temperature (°C). Numbers are written in their shortest exact form, so
/// reading the file back gives the same bits.
pub struct LogWriter<W: Write> {
    out: W,
    line: Vec<u8>,
    rows: u64,
    extra: usize,
    full: Vec<f64>,
}

impl<W: Write> LogWriter<W> {
    /// Starts a log: metadata (imutherm format only) and the header.
    /// `rate_hz` goes into the metadata as `sample_rate_hz`.
    pub fn new(out: W, format: LogFormat, meta: &Metadata, rate_hz: Option<f64>) -> io::Result<Self> {
        Self::with_columns(out, format, meta, rate_hz, &[])
    }

    /// [`LogWriter::new`] with more columns after the seven of the thesis
    /// (headers such as `host_time[s]`), written by
    /// [`LogWriter::write_row_with`].
    pub fn with_columns(
        mut out: W,
        format: LogFormat,
        meta: &Metadata,
        rate_hz: Option<f64>,
        extra: &[&str],
    ) -> io::Result<Self> {
        if format == LogFormat::Imutherm {
            writeln!(out, "# format: {IMUTHERM_FORMAT}")?;
            if let Some(r) = rate_hz {
                writeln!(out, "# {KEY_RATE}: {r}")?;
            }
            if let Some(d) = &meta.device {
                writeln!(out, "# device: {}", one_line(d))?;
            }
            if let Some(t) = &meta.start_time {
                writeln!(out, "# start_time: {}", one_line(t))?;
            }
            for (k, v) in &meta.entries {
                let reserved = ["format", KEY_RATE, "device", "start_time"];
                if !reserved.contains(&k.as_str()) {
                    writeln!(out, "# {}: {}", one_line(k).replace(':', "_"), one_line(v))?;
                }
            }
        }
        write!(out, "{THESIS_HEADER}")?;
        for h in extra {
            write!(out, ", {}", one_line(h).replace(',', "_"))?;
        }
        writeln!(out)?;
        Ok(LogWriter {
            out,
            line: Vec::with_capacity(192),
            rows: 0,
            extra: extra.len(),
            full: Vec::with_capacity(7 + extra.len()),
        })
    }

    /// Writes one sample: `[ax, ay, az, gx, gy, gz, temp]` in SI (and NaN
    /// in any extra column).
    pub fn write_row(&mut self, row: &[f64; 7]) -> io::Result<()> {
        self.write_row_with(row, &[])
    }

    /// Writes one sample and the values of the extra columns (missing ones
    /// as NaN, surplus ones ignored).
    pub fn write_row_with(&mut self, row: &[f64; 7], extra: &[f64]) -> io::Result<()> {
        self.line.clear();
        if self.extra == 0 {
            format_row(row, &mut self.line);
        } else {
            self.full.clear();
            self.full.extend_from_slice(row);
            self.full
                .extend((0..self.extra).map(|i| extra.get(i).copied().unwrap_or(f64::NAN)));
            format_row(&self.full, &mut self.line);
        }
        self.rows += 1;
        self.out.write_all(&self.line)
    }

    /// Writes a `# key: value` comment line among the rows (a gap's cause,
    /// say), which readers skip.
    pub fn write_comment(&mut self, key: &str, value: &str) -> io::Result<()> {
        self.write_trailer(key, value)
    }

    /// Writes rows formatted beforehand with [`format_row`] (so that long
    /// runs can be formatted on all cores); `rows` is how many they are.
    pub fn write_formatted(&mut self, text: &[u8], rows: u64) -> io::Result<()> {
        self.rows += rows;
        self.out.write_all(text)
    }

    /// The underlying writer (to sync a file to disk, say).
    pub fn get_mut(&mut self) -> &mut W {
        &mut self.out
    }

    /// Writes a `# key: value` line after the rows: a trailer that readers
    /// skip as a comment.
    pub fn write_trailer(&mut self, key: &str, value: &str) -> io::Result<()> {
        writeln!(self.out, "# {}: {}", one_line(key), one_line(value))
    }

    /// Rows written so far.
    pub fn rows(&self) -> u64 {
        self.rows
    }

    /// Flushes the underlying writer.
    pub fn flush(&mut self) -> io::Result<()> {
        self.out.flush()
    }

    /// Gives the writer back.
    pub fn into_inner(self) -> W {
        self.out
    }
}

/// Appends one log row (`v, v, …, v\n`) to `out`, each number in its
/// shortest form that reads back to the same bits; non-finite values as `nan`.
pub fn format_row(row: &[f64], out: &mut Vec<u8>) {
    let mut buf = ryu::Buffer::new();
    for (i, v) in row.iter().enumerate() {
        if i > 0 {
            out.extend_from_slice(b", ");
        }
        let text = if v.is_finite() {
            buf.format_finite(*v)
        } else {
            "nan"
        };
        out.extend_from_slice(text.as_bytes());
    }
    out.push(b'\n');
}

fn one_line(s: &str) -> String {
    s.replace(['\n', '\r'], " ")
}

/// Writes a whole recording that has the six inertial channels and the
/// temperature. Missing channels are an error, not zeros.
pub fn write_recording<W: Write>(out: W, rec: &Recording, format: LogFormat) -> io::Result<W> {
    let order = [
        (Quantity::Acceleration, Axis::X),
        (Quantity::Acceleration, Axis::Y),
        (Quantity::Acceleration, Axis::Z),
        (Quantity::AngularRate, Axis::X),
        (Quantity::AngularRate, Axis::Y),
        (Quantity::AngularRate, Axis::Z),
    ];
    let mut cols: Vec<&[f64]> = Vec::with_capacity(7);
    for (q, a) in order {
        let ch = rec
            .channels
            .iter()
            .find(|c| c.quantity == q && c.axis == Some(a))
            .ok_or_else(|| {
                io::Error::new(
                    io::ErrorKind::InvalidInput,
                    format!("the recording has no {} channel", standard_name(q, Some(a))),
                )
            })?;
        cols.push(&ch.data);
    }
    let temp = rec.temperature().ok_or_else(|| {
        io::Error::new(
            io::ErrorKind::InvalidInput,
            "the recording has no temperature channel",
        )
    })?;
    cols.push(&temp.data);
    let mut w = LogWriter::new(out, format, &rec.meta, rec.rate_hz)?;
    for i in 0..rec.len() {
        let mut row = [0.0; 7];
        for (dst, col) in row.iter_mut().zip(&cols) {
            *dst = col.get(i).copied().unwrap_or(f64::NAN);
        }
        w.write_row(&row)?;
    }
    w.flush()?;
    Ok(w.into_inner())
}
