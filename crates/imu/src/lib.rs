//! # imu — recordings and the files they live in
//!
//! The data side of imutherm: the [`Recording`] (named channels typed by
//! quantity — accelerometer axes in m/s², gyroscope axes in rad/s, the
//! temperature in °C, anything else in its own unit — a sample rate,
//! optional timestamps and metadata) and the files it is read from and
//! written to:
//! - the thesis log (`mpu_accel_1[m/^2], …, temp[degC]`, one row a sample),
//! - imutherm's own log (the same body after `# key: value` metadata),
//! - numeric columns (comma, tab or whitespace separated, optional header
//!   with `[unit]`s converted to SI, optional time column),
//! - any of them gzip-compressed, recognised by content.
//!
//! Files are streamed in blocks parsed on all cores. Every problem comes
//! back with its file, line and column: as a [`ReadError`] when the data
//! cannot be kept honestly, as a [`Problem`] in a [`ReadReport`] when it can
//! (NaN and infinite samples become gaps, a truncated last line is dropped,
//! rows out of time order are dropped, missing timestamps become gaps).
//!
//! Files are written through [`output`]: a temporary file renamed on
//! success, never onto an existing file unasked nor onto an input.
//!
//! **What it is not:** no statistics (the `allan` crate) and no printing.
//!
//! ```
//! use std::io::Write;
//! let mut f = tempfile::NamedTempFile::new().unwrap();
//! writeln!(f, "# a comment\ngyro_x, gyro_y\n0.1, 0.2\n0.3, 0.4").unwrap();
//! let reader = imu::table::TableReader::open(f.path()).unwrap();
//! assert_eq!(reader.names(), ["gyro_x", "gyro_y"]);
//! let table = reader.read(None).unwrap();
//! assert_eq!(table.columns[1], vec![0.2, 0.4]);
//! ```

pub mod clock_pattern;
mod decimal;
#[cfg(target_arch = "x86_64")]
mod decimal_x86;
pub mod error;
pub mod header;
pub mod log_file;
pub mod names;
pub mod output;
pub mod read_report;
pub mod recording;
pub mod setting;
pub mod table;
pub mod timing;
pub mod units;

pub use error::{ReadError, ReadErrorKind};
pub use log_file::{
    InstancePick, LogFormat, LogWriter, RecordingOptions, StreamChoice, read_recording,
    read_recording_with_report, write_recording,
};
pub use read_report::{FileFormat, Problem, ProblemKind, ReadReport};
pub use recording::{Axis, Channel, Metadata, Recording};
pub use setting::{Given, Setting, Value};
pub use units::{Quantity, Unit, UnitSource};
