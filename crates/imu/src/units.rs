//! Units as they appear in IMU files, and their conversion to SI.
//!
//! imutherm works in SI inside (m/s², rad/s, °C, s). A file's unit text is
//! parsed into the quantity it measures and the affine map to SI, so that
//! `deg/s` columns become rad/s and `mg` columns m/s² on reading. The thesis
//! log's misprint `m/^2` is read as m/s².

use std::f64::consts::PI;
use std::fmt;

/// Standard gravity, m/s², taken from `earth` as every crate takes it.
pub use earth::STANDARD_GRAVITY;

/// What a channel measures.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Quantity {
    /// Specific force, m/s² (accelerometer).
    Acceleration,
    /// Angular rate, rad/s (gyroscope).
    AngularRate,
    /// Temperature, °C.
    Temperature,
    /// Time, s.
    Time,
    /// Anything else; kept in the file's own unit.
    Other,
}

impl Quantity {
    /// The SI (or °C) unit imutherm stores this quantity in.
    pub fn si_unit(self) -> &'static str {
        match self {
            Quantity::Acceleration => "m/s^2",
            Quantity::AngularRate => "rad/s",
            Quantity::Temperature => "degC",
            Quantity::Time => "s",
            Quantity::Other => "",
        }
    }

    /// A short lower-case name used in JSON.
    pub fn name(self) -> &'static str {
        match self {
            Quantity::Acceleration => "acceleration",
            Quantity::AngularRate => "angular_rate",
            Quantity::Temperature => "temperature",
            Quantity::Time => "time",
            Quantity::Other => "other",
        }
    }
}

impl fmt::Display for Quantity {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// Where a channel's unit came from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum UnitSource {
    /// Written in the header (`[deg/s]`, `(g)`, `_dps`).
    Header,
    /// Given on the command line (`--unit gyro_x=deg/s`).
    Flag,
    /// Written in the file's metadata (`# unit.gyro_x: deg/s`).
    Metadata,
    /// Nowhere: the channel's name says what it measures, and its values
    /// are taken as already in SI. Printed as "assumed".
    #[default]
    Assumed,
}

impl UnitSource {
    /// Snake-case name for JSON.
    pub fn name(self) -> &'static str {
        match self {
            UnitSource::Header => "header",
            UnitSource::Flag => "flag",
            UnitSource::Metadata => "metadata",
            UnitSource::Assumed => "assumed",
        }
    }
}

/// A parsed unit: SI value = raw · scale + offset.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Unit {
    /// The quantity measured.
    pub quantity: Quantity,
    /// Multiplier to SI.
    pub scale: f64,
    /// Offset added after scaling (kelvin → °C).
    pub offset: f64,
}

impl Unit {
    /// The identity for a quantity's SI unit.
    pub fn si(quantity: Quantity) -> Unit {
        Unit {
            quantity,
            scale: 1.0,
            offset: 0.0,
        }
    }

    /// Converts a raw value to SI.
    #[inline]
    pub fn to_si(self, raw: f64) -> f64 {
        raw * self.scale + self.offset
    }

    /// Whether conversion changes nothing.
    pub fn is_identity(self) -> bool {
        self.scale == 1.0 && self.offset == 0.0
    }
}

/// Parses a unit text; `None` when it is not one imutherm knows (the
/// channel is then kept as [`Quantity::Other`] in its own unit).
///
/// ```
/// use imu::units::{parse_unit, Quantity};
/// let u = parse_unit("deg/s").unwrap();
/// assert_eq!(u.quantity, Quantity::AngularRate);
/// assert!((u.to_si(180.0) - std::f64::consts::PI).abs() < 1e-15);
/// assert_eq!(parse_unit("m/^2").unwrap().quantity, Quantity::Acceleration);
/// ```
pub fn parse_unit(text: &str) -> Option<Unit> {
    let t: String = text
        .trim()
        .chars()
        .filter(|c| !c.is_whitespace())
        .collect::<String>()
        .to_ascii_lowercase()
        .replace('²', "^2")
        .replace('°', "deg")
        .replace(['µ', 'μ'], "u");
    let u = |quantity, scale| {
        Some(Unit {
            quantity,
            scale,
            offset: 0.0,
        })
    };
    let deg = PI / 180.0;
    match t.as_str() {
        "m/s^2" | "m/s2" | "m/s/s" | "ms^-2" | "ms-2" | "mps2" | "m/^2" => u(Quantity::Acceleration, 1.0),
        "g" | "g0" | "gee" => u(Quantity::Acceleration, STANDARD_GRAVITY),
        "mg" => u(Quantity::Acceleration, STANDARD_GRAVITY * 1e-3),
        "ug" => u(Quantity::Acceleration, STANDARD_GRAVITY * 1e-6),
        "rad/s" | "rads^-1" | "rad/sec" | "rps" | "radps" => u(Quantity::AngularRate, 1.0),
        "mrad/s" => u(Quantity::AngularRate, 1e-3),
        "deg/s" | "dps" | "deg/sec" | "degs^-1" | "degps" => u(Quantity::AngularRate, deg),
        "deg/h" | "deg/hr" | "dph" => u(Quantity::AngularRate, deg / 3600.0),
        "degc" | "c" | "celsius" | "degreesc" => u(Quantity::Temperature, 1.0),
        // °F → °C: (F − 32)·5/9.
        "degf" | "f" | "fahrenheit" => Some(Unit {
            quantity: Quantity::Temperature,
            scale: 5.0 / 9.0,
            offset: -32.0 * 5.0 / 9.0,
        }),
        "k" | "kelvin" => Some(Unit {
            quantity: Quantity::Temperature,
            scale: 1.0,
            offset: -273.15,
        }),
        "s" | "sec" | "seconds" => u(Quantity::Time, 1.0),
        "ms" => u(Quantity::Time, 1e-3),
        "us" => u(Quantity::Time, 1e-6),
        "ns" => u(Quantity::Time, 1e-9),
        _ => None,
    }
}

/// The units imutherm converts, one spelling each, as messages list them;
/// [`parse_unit`] reads each (and the other spellings it knows).
pub const KNOWN_UNITS: [&str; 15] = [
    "m/s^2", "g", "mg", "ug", "rad/s", "mrad/s", "deg/s", "deg/h", "degC", "degF", "K", "s", "ms", "us", "ns",
];

/// A unit given for a column (`gyro_x=deg/s`), parsed once: the column's
/// name, the unit as given and what it converts to.
#[derive(Debug, Clone, PartialEq)]
pub struct UnitOverride {
    /// The column, by header or imutherm name.
    pub column: String,
    /// The unit as given, trimmed.
    pub unit_text: String,
    /// The unit.
    pub unit: Unit,
}

/// Why a `COLUMN=UNIT` pair is not one.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum UnitOverrideError {
    /// Not `COLUMN=UNIT`, or no column.
    #[error("expected COLUMN=UNIT, e.g. gyro_x=deg/s")]
    Malformed,
    /// A unit imutherm does not convert.
    #[error("unknown unit '{unit}' (known: {})", KNOWN_UNITS.join(" "))]
    UnknownUnit {
        /// The unit as given.
        unit: String,
    },
}

/// `COLUMN=VALUE`, both trimmed, with a column named: the form of
/// `--unit` and `--scale` alike.
fn column_pair(text: &str) -> Option<(&str, &str)> {
    text.split_once('=')
        .map(|(c, v)| (c.trim(), v.trim()))
        .filter(|(c, _)| !c.is_empty())
}

impl std::str::FromStr for UnitOverride {
    type Err = UnitOverrideError;

    fn from_str(text: &str) -> Result<Self, Self::Err> {
        let (column, unit_text) = column_pair(text).ok_or(UnitOverrideError::Malformed)?;
        let unit = parse_unit(unit_text).ok_or_else(|| UnitOverrideError::UnknownUnit {
            unit: unit_text.to_string(),
        })?;
        Ok(UnitOverride {
            column: column.to_string(),
            unit_text: unit_text.to_string(),
            unit,
        })
    }
}

/// A factor for a column's values (`accel_x=4`), applied before its unit
/// converts them: what a firmware that prints with the wrong sensitivity
/// needs.
#[derive(Debug, Clone, PartialEq)]
pub struct ColumnScale {
    /// The column, by header or imutherm name.
    pub column: String,
    /// The factor.
    pub factor: f64,
}

/// Why a `COLUMN=FACTOR` pair is not one.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum ColumnScaleError {
    /// Not `COLUMN=FACTOR`, or no column.
    #[error("expected COLUMN=FACTOR, e.g. accel_x=4")]
    Malformed,
    /// A factor that is not a finite number other than zero.
    #[error("the factor '{0}' is not a finite number other than 0")]
    Factor(String),
}

impl std::str::FromStr for ColumnScale {
    type Err = ColumnScaleError;

    fn from_str(text: &str) -> Result<Self, Self::Err> {
        let (column, factor) = column_pair(text).ok_or(ColumnScaleError::Malformed)?;
        let value = factor
            .parse::<f64>()
            .ok()
            .filter(|f| f.is_finite() && *f != 0.0)
            .ok_or_else(|| ColumnScaleError::Factor(factor.to_string()))?;
        Ok(ColumnScale {
            column: column.to_string(),
            factor: value,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn known_units_convert_to_si() {
        let cases = [
            ("m/s²", Quantity::Acceleration, 2.0, 2.0),
            ("g", Quantity::Acceleration, 1.0, 9.80665),
            ("mg", Quantity::Acceleration, 1000.0, 9.80665),
            ("°/s", Quantity::AngularRate, 1.0, PI / 180.0),
            ("rad/s", Quantity::AngularRate, 0.5, 0.5),
            ("K", Quantity::Temperature, 300.0, 26.85),
            ("degC", Quantity::Temperature, 21.0, 21.0),
            ("ns", Quantity::Time, 1e9, 1.0),
            ("degF", Quantity::Temperature, 212.0, 100.0),
            ("dps", Quantity::AngularRate, 180.0, PI),
        ];
        for (text, q, raw, si) in cases {
            let u = parse_unit(text).unwrap_or_else(|| panic!("{text}"));
            assert_eq!(u.quantity, q, "{text}");
            assert!((u.to_si(raw) - si).abs() < 1e-12, "{text}");
        }
        assert!(parse_unit("furlong/fortnight").is_none());
    }

    #[test]
    fn every_listed_unit_parses() {
        for u in KNOWN_UNITS {
            assert!(parse_unit(u).is_some(), "{u}");
        }
    }

    #[test]
    fn a_unit_override_is_parsed_once_with_its_reason() {
        let o: UnitOverride = " gyro_x = deg/s".parse().unwrap();
        assert_eq!((o.column.as_str(), o.unit_text.as_str()), ("gyro_x", "deg/s"));
        assert_eq!(o.unit.quantity, Quantity::AngularRate);
        let e = "gyro_x=furlong".parse::<UnitOverride>().unwrap_err();
        assert_eq!(
            e,
            UnitOverrideError::UnknownUnit {
                unit: "furlong".into()
            }
        );
        assert!(e.to_string().contains("degC degF K s ms us ns)"), "{e}");
        for bad in ["gyro_x", "=deg/s", " = furlong"] {
            assert_eq!(
                bad.parse::<UnitOverride>().unwrap_err(),
                UnitOverrideError::Malformed,
                "{bad}"
            );
        }
    }

    #[test]
    fn column_scales_parse_and_refuse() {
        let s: ColumnScale = " col2 = 4 ".parse().unwrap();
        assert_eq!((s.column.as_str(), s.factor), ("col2", 4.0));
        assert_eq!(
            "=4".parse::<ColumnScale>().unwrap_err(),
            ColumnScaleError::Malformed
        );
        assert_eq!(
            "a4".parse::<ColumnScale>().unwrap_err(),
            ColumnScaleError::Malformed
        );
        for bad in ["a=0", "a=x", "a=inf"] {
            assert!(
                matches!(bad.parse::<ColumnScale>(), Err(ColumnScaleError::Factor(_))),
                "{bad}"
            );
        }
    }
}
