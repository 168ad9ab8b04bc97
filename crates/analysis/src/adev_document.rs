//! The `imutherm.adev/1` JSON document of `imutherm adev --json`, as
//! types: each channel's deviation curve with its intervals and noise
//! identification. Field names, nesting and order are the schema's: it
//! only gains fields.

use allan::{Curve, Options, Point};
use serde::Serialize;

use crate::selection::SelectedChannel;

/// The schema's name and version.
pub const SCHEMA: &str = "imutherm.adev/1";

/// The whole document.
#[derive(Debug, Serialize)]
pub struct AdevDocument {
    /// [`SCHEMA`].
    pub schema: &'static str,
    /// The writing imutherm's version.
    pub imutherm_version: &'static str,
    /// The statistic (`oadev`, `mtotdev`, …).
    pub stat: &'static str,
    /// `freq` or `phase`.
    pub data_type: &'static str,
    /// The first channel's rate, Hz (every channel carries its own).
    pub rate_hz: f64,
    /// Confidence of every interval.
    pub confidence: f64,
    /// One entry per channel, in the order read.
    pub channels: Vec<AdevChannel>,
    /// What reading the files found and said (an override against a file,
    /// a clock, problems), as the text output prints them.
    pub notes: Vec<String>,
}

/// One channel's curve.
#[derive(Debug, Serialize)]
pub struct AdevChannel {
    /// Its name.
    pub name: String,
    /// The data's unit.
    pub unit: String,
    /// Where the file's unit came from: header, flag, metadata or assumed.
    pub unit_source: &'static str,
    /// The file it was read from.
    pub file: String,
    /// 1-based column.
    pub column: usize,
    /// Its rate, Hz.
    pub rate_hz: f64,
    /// Samples analysed.
    pub samples: usize,
    /// NaN samples treated as gaps.
    pub nan_samples: usize,
    /// The curve.
    pub points: Vec<Point>,
}

impl AdevDocument {
    /// The document of `curves`, computed with `opts` from `channels`
    /// (one curve per channel, in order), written by imutherm `version`.
    pub fn new(
        imutherm_version: &'static str,
        opts: &Options,
        channels: &[SelectedChannel],
        curves: &[Curve],
    ) -> Self {
        AdevDocument {
            schema: SCHEMA,
            imutherm_version,
            stat: opts.stat.name(),
            data_type: opts.data_type.name(),
            rate_hz: curves.first().map_or(opts.rate_hz, |c| c.rate_hz),
            confidence: opts.confidence,
            channels: channels
                .iter()
                .zip(curves)
                .map(|(ch, c)| AdevChannel::of(ch, c))
                .collect(),
            notes: Vec::new(),
        }
    }

    /// The document with the reading's notes.
    pub fn with_notes(mut self, notes: Vec<String>) -> Self {
        self.notes = notes;
        self
    }
}

impl AdevChannel {
    fn of(ch: &SelectedChannel, c: &Curve) -> Self {
        AdevChannel {
            name: ch.name.clone(),
            unit: ch.unit.clone(),
            unit_source: ch.unit_source.name(),
            file: ch.file.display().to_string(),
            column: ch.column,
            rate_hz: c.rate_hz,
            samples: c.samples,
            nan_samples: c.nan_samples,
            points: c.points.clone(),
        }
    }
}
