//! The data model: a recording of named, typed channels at a sample rate.

use std::path::PathBuf;

use crate::units::{Quantity, UnitSource};

/// A sensor axis.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Axis {
    /// x (the thesis's `_1`).
    X,
    /// y (`_2`).
    Y,
    /// z (`_3`).
    Z,
}

impl Axis {
    /// All three, in order.
    pub const ALL: [Axis; 3] = [Axis::X, Axis::Y, Axis::Z];

    /// `x`, `y` or `z`.
    pub fn letter(self) -> char {
        match self {
            Axis::X => 'x',
            Axis::Y => 'y',
            Axis::Z => 'z',
        }
    }
}

/// One channel: a named series of samples of one quantity, in SI.
#[derive(Debug, Clone, PartialEq)]
pub struct Channel {
    /// imutherm's name: `accel_x` … `gyro_z`, `temp`, or the file's own name
    /// for any other channel.
    pub name: String,
    /// The column header it came from, unit included (`mpu_gyro_1[rad/s]`).
    pub source_name: String,
    /// What it measures.
    pub quantity: Quantity,
    /// The axis, for inertial channels.
    pub axis: Option<Axis>,
    /// The unit of `data`: SI for known quantities, the file's own otherwise.
    pub unit: String,
    /// Where the unit of the file came from (header, flag, metadata) or
    /// that it was assumed.
    pub unit_source: UnitSource,
    /// The samples; NaN marks a missing sample (a gap).
    pub data: Vec<f64>,
}

impl Channel {
    /// A channel of a known quantity, named the imutherm way.
    pub fn inertial(quantity: Quantity, axis: Axis, data: Vec<f64>) -> Channel {
        let name = standard_name(quantity, Some(axis));
        Channel {
            source_name: name.clone(),
            name,
            quantity,
            axis: Some(axis),
            unit: quantity.si_unit().to_string(),
            unit_source: UnitSource::Header,
            data,
        }
    }

    /// The temperature channel, °C.
    pub fn temperature(data: Vec<f64>) -> Channel {
        Channel {
            name: "temp".to_string(),
            source_name: "temp".to_string(),
            quantity: Quantity::Temperature,
            axis: None,
            unit: Quantity::Temperature.si_unit().to_string(),
            unit_source: UnitSource::Header,
            data,
        }
    }

    /// Whether this is an accelerometer or gyroscope axis.
    pub fn is_inertial(&self) -> bool {
        matches!(self.quantity, Quantity::Acceleration | Quantity::AngularRate) && self.axis.is_some()
    }
}

/// imutherm's name for a channel of `quantity` on `axis`: `accel_x`,
/// `gyro_z`, `temp`.
pub fn standard_name(quantity: Quantity, axis: Option<Axis>) -> String {
    let stem = match quantity {
        Quantity::Acceleration => "accel",
        Quantity::AngularRate => "gyro",
        Quantity::Temperature => return "temp".to_string(),
        Quantity::Time => return "time".to_string(),
        Quantity::Other => "other",
    };
    match axis {
        Some(a) => format!("{stem}_{}", a.letter()),
        None => stem.to_string(),
    }
}

/// What is known about how and where a recording was made.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Metadata {
    /// The sensor (`MPU-9250`, `sim:mpu9250-thesis`, …).
    pub device: Option<String>,
    /// When the recording started (ISO 8601 as written by the logger).
    pub start_time: Option<String>,
    /// The file it was read from.
    pub source: Option<PathBuf>,
    /// Every `key: value` metadata entry, in file order (sample rate, full
    /// scale, DLPF, version, true simulation parameters, …).
    pub entries: Vec<(String, String)>,
}

impl Metadata {
    /// The value of the first entry named `key`.
    pub fn get(&self, key: &str) -> Option<&str> {
        self.entries
            .iter()
            .find(|(k, _)| k == key)
            .map(|(_, v)| v.as_str())
    }

    /// Sets `key` (replacing an earlier value).
    pub fn set(&mut self, key: impl Into<String>, value: impl Into<String>) {
        let key = key.into();
        let value = value.into();
        match self.entries.iter_mut().find(|(k, _)| *k == key) {
            Some(e) => e.1 = value,
            None => self.entries.push((key, value)),
        }
    }
}

/// A recording: channels of equal length at one sample rate.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Recording {
    /// The channels, in file order.
    pub channels: Vec<Channel>,
    /// Sample rate in Hz, given or derived; `None` when unknown.
    pub rate_hz: Option<f64>,
    /// Per-sample timestamps in seconds, when the file has them, one per
    /// row read (not per slot of the channels); Unix epoch stamps are
    /// counted from the first one, so that their steps keep their digits.
    pub timestamps: Option<Vec<f64>>,
    /// Metadata.
    pub meta: Metadata,
}

impl Recording {
    /// Number of samples (of the first channel; all have the same length).
    pub fn len(&self) -> usize {
        self.channels.first().map_or(0, |c| c.data.len())
    }

    /// Whether there are no samples.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Duration in seconds: the samples over the rate, the gaps' empty
    /// slots among them (so count / rate plus the gaps); without a rate,
    /// the span of increasing timestamps.
    pub fn duration_s(&self) -> Option<f64> {
        if let Some(r) = self.rate_hz {
            return Some(self.len() as f64 / r);
        }
        let t = self.timestamps.as_ref()?;
        let (a, b) = (
            t.iter().find(|v| v.is_finite())?,
            t.iter().rev().find(|v| v.is_finite())?,
        );
        (b > a).then(|| b - a)
    }

    /// The channel named `name` (imutherm's name or the file's header).
    pub fn channel(&self, name: &str) -> Option<&Channel> {
        self.channels
            .iter()
            .find(|c| c.name.eq_ignore_ascii_case(name) || c.source_name.eq_ignore_ascii_case(name))
    }

    /// The channels of one quantity, in file order.
    pub fn of_quantity(&self, quantity: Quantity) -> Vec<&Channel> {
        self.channels.iter().filter(|c| c.quantity == quantity).collect()
    }

    /// The accelerometer and gyroscope axes.
    pub fn inertial(&self) -> Vec<&Channel> {
        self.channels.iter().filter(|c| c.is_inertial()).collect()
    }

    /// The temperature channel, if any.
    pub fn temperature(&self) -> Option<&Channel> {
        self.channels.iter().find(|c| c.quantity == Quantity::Temperature)
    }
}
