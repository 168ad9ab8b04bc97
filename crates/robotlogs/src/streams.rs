//! The messages of a log decoded into per-stream columns, before a stream is
//! chosen and placed on its clock.

/// Where a stream's temperature comes from.
#[derive(Debug, Clone, PartialEq)]
pub enum TempSource {
    /// In the IMU message itself (PX4 `sensor_gyro.temperature`, ArduPilot
    /// `IMU.T`).
    Inline(String),
    /// A temperature topic, matched by time.
    Topic(String),
    /// None.
    None,
}

impl std::fmt::Display for TempSource {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            TempSource::Inline(s) => write!(f, "{s} (in the message)"),
            TempSource::Topic(s) => write!(f, "{s} (matched by time)"),
            TempSource::None => f.write_str("none"),
        }
    }
}

/// IMU samples of one stream, in SI: rad/s, m/s², °C; times in seconds.
#[derive(Debug, Clone, Default)]
pub struct ImuStream {
    /// Topic (`/imu/data`) or instance name (`sensor_gyro/1`, `IMU/0`).
    pub name: String,
    /// The PX4/ArduPilot instance, when the log has instances.
    pub instance: Option<u32>,
    /// The message type (`sensor_msgs/msg/Imu`).
    pub msg_type: String,
    /// The sensor's own stamp (ROS header stamp, PX4 `timestamp_sample`);
    /// NaN where the message has none or it is zero.
    pub stamp: Vec<f64>,
    /// The log's time of the message (bag receive time, PX4 `timestamp`,
    /// ArduPilot `TimeUS`).
    pub log_time: Vec<f64>,
    /// Angular rate x, y, z.
    pub gyro: [Vec<f64>; 3],
    /// Acceleration x, y, z.
    pub accel: [Vec<f64>; 3],
    /// Temperature carried in the message, when it carries one.
    pub temp: Option<Vec<f64>>,
    /// What `stamp` is called in this format.
    pub stamp_name: &'static str,
    /// What `log_time` is called in this format.
    pub log_time_name: &'static str,
    /// Device id (PX4 `device_id`), when the log gives one.
    pub device_id: Option<u64>,
    /// Frame id (ROS `header.frame_id`) of the first message.
    pub frame_id: Option<String>,
    /// The log's own names of the accelerometer and gyroscope axes
    /// (`AccX`, `sensor_gyro.x`); ROS's field names when empty.
    pub axis_fields: Option<[[&'static str; 3]; 2]>,
}

impl ImuStream {
    /// Messages decoded.
    pub fn len(&self) -> usize {
        self.log_time.len()
    }

    /// Whether no message was decoded.
    pub fn is_empty(&self) -> bool {
        self.log_time.is_empty()
    }

    /// Appends one message.
    pub(crate) fn push(
        &mut self,
        stamp: f64,
        log_time: f64,
        gyro: [f64; 3],
        accel: [f64; 3],
        temp: Option<f64>,
    ) {
        self.stamp.push(stamp);
        self.log_time.push(log_time);
        for k in 0..3 {
            self.gyro[k].push(gyro[k]);
            self.accel[k].push(accel[k]);
        }
        // A stream whose messages carry a temperature only now and then
        // keeps one value per message, NaN where there is none.
        match (temp, &mut self.temp) {
            (Some(t), Some(v)) => v.push(t),
            (Some(t), None) => {
                let mut v = vec![f64::NAN; self.log_time.len() - 1];
                v.push(t);
                self.temp = Some(v);
            }
            (None, Some(v)) => v.push(f64::NAN),
            (None, None) => {}
        }
    }

    /// Mean rate over the log, messages per second of log time.
    pub fn mean_rate_hz(&self) -> Option<f64> {
        mean_rate(&self.log_time)
    }
}

/// Temperature messages of one topic.
#[derive(Debug, Clone, Default)]
pub struct TempStream {
    /// Topic.
    pub name: String,
    /// The message type.
    pub msg_type: String,
    /// Stamp (NaN where zero), as [`ImuStream::stamp`].
    pub stamp: Vec<f64>,
    /// Log time, as [`ImuStream::log_time`].
    pub log_time: Vec<f64>,
    /// °C.
    pub value: Vec<f64>,
}

/// Messages per second between the first and the last time.
pub(crate) fn mean_rate(t: &[f64]) -> Option<f64> {
    let (a, b) = (t.first()?, t.last()?);
    (t.len() > 1 && b > a).then(|| (t.len() - 1) as f64 / (b - a))
}

/// Everything decoded from a log.
#[derive(Debug, Clone, Default)]
pub struct Decoded {
    /// IMU streams, in the order found.
    pub imu: Vec<ImuStream>,
    /// Temperature topics.
    pub temps: Vec<TempStream>,
    /// Metadata entries of the log (PX4 `ver_hw`, ArduPilot firmware).
    pub entries: Vec<(String, String)>,
    /// Things found wrong that did not stop the reading (a message too
    /// short, a dropout), for the report.
    pub notes: Vec<String>,
    /// Stretches of the log skipped because they could not be decoded.
    pub losses: Vec<Loss>,
    /// Messages skipped because they could not be decoded, where the
    /// format keeps each in a record of its own (a SQLite row), so that the
    /// next one reads.
    pub bad_messages: Vec<BadMessage>,
}

/// A message skipped as undecodable: which, and why.
#[derive(Debug, Clone, PartialEq)]
pub struct BadMessage {
    /// Where it is (`message 12 (row id 40)`).
    pub at: String,
    /// Why it was skipped.
    pub why: String,
    /// The messages it stands for.
    pub count: usize,
}

/// A stretch of a log skipped as undecodable: where, and how much.
#[derive(Debug, Clone, PartialEq)]
pub struct Loss {
    /// The byte offset where the stretch starts.
    pub offset: u64,
    /// Its length in bytes.
    pub bytes: u64,
    /// Why it was skipped.
    pub why: String,
}

impl Decoded {
    /// The IMU stream named `name`, created when new.
    pub(crate) fn imu_mut(&mut self, name: &str, msg_type: &str) -> &mut ImuStream {
        match self.imu.iter().position(|s| s.name == name) {
            Some(i) => &mut self.imu[i],
            None => {
                self.imu.push(ImuStream {
                    name: name.to_string(),
                    msg_type: msg_type.to_string(),
                    ..ImuStream::default()
                });
                self.imu.last_mut().expect("just pushed")
            }
        }
    }

    /// The temperature stream named `name`, created when new.
    pub(crate) fn temp_mut(&mut self, name: &str) -> &mut TempStream {
        match self.temps.iter().position(|s| s.name == name) {
            Some(i) => &mut self.temps[i],
            None => {
                self.temps.push(TempStream {
                    name: name.to_string(),
                    ..TempStream::default()
                });
                self.temps.last_mut().expect("just pushed")
            }
        }
    }
}
