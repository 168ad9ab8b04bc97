//! How a recording is read: the reader's options from what a user gives
//! (`--rate`, `--unit COL=UNIT`, the time column), and a unit as shown.

use imu::units::{UnitOverride, parse_unit};
use imu::{Quantity, RecordingOptions, Setting, Value};

use crate::AnalysisError;

/// What a user may say about how to read a file, before it is checked.
#[derive(Debug, Clone, Default)]
pub struct ReadingChoices {
    /// The sample rate, Hz, overriding the file's.
    pub rate_hz: Option<f64>,
    /// `COLUMN=UNIT` pairs as typed, overriding the header's units; parsed
    /// here, once (a caller holding them parsed sets
    /// [`RecordingOptions::units`] instead).
    pub units: Vec<String>,
    /// The time column's name.
    pub time_column: Option<String>,
    /// The time column's unit when its header has none.
    pub time_unit: Option<String>,
    /// Malformed rows become gaps instead of errors.
    pub skip_bad_lines: bool,
    /// The stream of a robot log (`--topic`, `--instance`, `--temp-topic`).
    pub stream: imu::StreamChoice,
    /// `--max-grid-factor`: how far gaps may stretch the time grid.
    pub max_grid_factor: Option<usize>,
}

/// Checks the choices and turns them into the reader's options; every
/// error names the setting and the value at fault.
pub fn recording_options(c: &ReadingChoices) -> Result<RecordingOptions, AnalysisError> {
    let refuse = |setting: Setting, value: Value, problem: String| AnalysisError::Setting {
        given: setting.given(value),
        problem,
    };
    if let Some(r) = c.rate_hz
        && !(r.is_finite() && r > 0.0)
    {
        return Err(refuse(
            Setting::SampleRate,
            Value::number(r),
            "the sample rate must be a positive number of Hz".into(),
        ));
    }
    if let Some(u) = &c.time_unit
        && parse_unit(u).is_none_or(|u| u.quantity != Quantity::Time)
    {
        return Err(refuse(
            Setting::TimeUnit,
            Value::text(u.as_str()),
            "expected s, ms, us or ns".into(),
        ));
    }
    let units = c
        .units
        .iter()
        .map(|p| {
            p.parse::<UnitOverride>()
                .map_err(|e| refuse(Setting::UnitOverride, Value::text(p.as_str()), e.to_string()))
        })
        .collect::<Result<Vec<_>, _>>()?;
    Ok(RecordingOptions {
        rate_hz: c.rate_hz,
        units,
        scales: Vec::new(),
        time_column: c.time_column.clone(),
        time_unit: c.time_unit.clone(),
        skip_bad_lines: c.skip_bad_lines,
        stream: c.stream.clone(),
        max_grid_factor: c.max_grid_factor,
    })
}

/// A unit as printed beside a channel: `rad/s`, or `rad/s (assumed)` when
/// nothing in the file or on the command line gave it and imutherm took
/// the channel as SI by its name (a channel of unknown quantity keeps its
/// own unit, assumed nothing).
pub fn unit_text(unit: &str, source: &str, quantity: &str) -> String {
    let u = if unit.is_empty() { "-" } else { unit };
    if source == imu::UnitSource::Assumed.name() && quantity != Quantity::Other.name() {
        format!("{u} (assumed)")
    } else {
        u.to_string()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_bad_choice_names_its_setting_and_a_good_one_passes() {
        let bad_rate = ReadingChoices {
            rate_hz: Some(-1.0),
            ..Default::default()
        };
        let e = recording_options(&bad_rate).unwrap_err();
        assert!(
            matches!(&e, AnalysisError::Setting { given, .. }
                if given.setting == Setting::SampleRate && given.value == Value::number(-1)),
            "{e}"
        );
        let bad_unit = ReadingChoices {
            units: vec!["gyro_x=furlong".into()],
            ..Default::default()
        };
        assert!(
            recording_options(&bad_unit)
                .unwrap_err()
                .to_string()
                .contains("unknown unit 'furlong'")
        );
        let good = ReadingChoices {
            units: vec![" gyro_x = deg/s".into()],
            ..Default::default()
        };
        let units = recording_options(&good).unwrap().units;
        assert_eq!(
            units
                .iter()
                .map(|o| (o.column.as_str(), o.unit_text.as_str(), o.unit))
                .collect::<Vec<_>>(),
            [("gyro_x", "deg/s", parse_unit("deg/s").unwrap())]
        );
    }

    #[test]
    fn only_an_assumed_unit_of_a_known_quantity_is_marked() {
        assert_eq!(unit_text("rad/s", "assumed", "angular_rate"), "rad/s (assumed)");
        assert_eq!(unit_text("", "assumed", "other"), "-");
        assert_eq!(unit_text("rad/s", "header", "angular_rate"), "rad/s");
    }
}
