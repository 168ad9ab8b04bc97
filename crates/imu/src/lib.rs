//! # imu — recordings and the files they live in
//!
//! The data side of imutherm: reading numeric sample files fast and honestly.
//! This first part reads the plain column files of frequency-stability tools
//! (comma, tab or whitespace separated, an optional header line, `#`
//! comments, optionally gzip-compressed), streaming the file in blocks that
//! are parsed on all cores.
//!
//! **What it is not:** no statistics (that is the `allan` crate) and no
//! printing. Every problem in a file comes back as a [`ReadError`] naming the
//! file, the line and the column.
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

pub mod error;
pub mod header;
pub mod log;
pub mod recording;
pub mod report;
pub mod table;
pub mod timing;
pub mod units;

pub use error::{ReadError, ReadErrorKind};
pub use log::{
    LogFormat, LogWriter, RecordingOptions, read_recording, read_recording_with_report, write_recording,
};
pub use recording::{Axis, Channel, Metadata, Recording};
pub use report::{Problem, ProblemKind, ReadReport};
pub use units::{Quantity, Unit};
