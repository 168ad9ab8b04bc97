//! Parameter files as ground stations read them.
//!
//! QGroundControl (`src/QmlControls/ParameterEditorController.cc`,
//! `buildDiffFromFile`): a line starting with `#` is a comment; any other
//! line is split on tabs into exactly five fields, vehicle id, component
//! id, name, value and MAVLink type (`MAV_PARAM_TYPE`: 6 int32, 9 float32).
//! ArduPilot's `.parm` (MAVProxy's `param load`, Mission Planner): one
//! `NAME VALUE` (or `NAME,VALUE`) per line, `#` comments. Values are held
//! as the firmware holds them: float32 or int32.

use super::FirmwareError;

/// MAVLink's `MAV_PARAM_TYPE_INT32`.
pub const TYPE_INT32: u8 = 6;
/// MAVLink's `MAV_PARAM_TYPE_REAL32`.
pub const TYPE_REAL32: u8 = 9;

/// A parameter's value as the firmware stores it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ParamValue {
    /// int32.
    Int(i32),
    /// float32.
    Float(f32),
}

impl ParamValue {
    /// The value as a float32, as the firmware reads a float parameter.
    pub fn as_f32(self) -> f32 {
        match self {
            ParamValue::Int(i) => i as f32,
            ParamValue::Float(f) => f,
        }
    }
}

/// The parameters of one file, in file order; a later line for the same
/// name overrides an earlier one, as loading sets them in turn.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ParamFile {
    /// (name, value).
    pub values: Vec<(String, ParamValue)>,
}

impl ParamFile {
    /// The value of `name`, the last one set.
    pub fn get(&self, name: &str) -> Option<ParamValue> {
        self.values.iter().rev().find(|(n, _)| n == name).map(|(_, v)| *v)
    }

    /// A float parameter, or an error naming it.
    pub fn float(&self, name: &str) -> Result<f32, FirmwareError> {
        self.get(name)
            .map(ParamValue::as_f32)
            .ok_or_else(|| FirmwareError::Missing(name.to_string()))
    }

    /// Reads QGroundControl's tab-separated parameter file.
    pub fn parse_qgc(text: &str) -> Result<ParamFile, FirmwareError> {
        let mut out = ParamFile::default();
        for (i, line) in text.lines().enumerate() {
            let bad = |message: String| FirmwareError::Parse { line: i + 1, message };
            if line.starts_with('#') || line.trim().is_empty() {
                continue;
            }
            let fields: Vec<&str> = line.split('\t').collect();
            let [vehicle, component, name, value, kind] = fields[..] else {
                return Err(bad(format!(
                    "{} tab-separated fields, QGroundControl's parameter file has 5 (vehicle id, component id, name, value, type)",
                    fields.len()
                )));
            };
            for (what, v) in [("vehicle id", vehicle), ("component id", component)] {
                v.parse::<u8>()
                    .map_err(|_| bad(format!("{what} '{v}' is not a number from 0 to 255")))?;
            }
            let value = match kind.parse::<u8>() {
                Ok(TYPE_INT32) => ParamValue::Int(
                    value
                        .parse::<i32>()
                        .map_err(|_| bad(format!("{name}: '{value}' is not an int32")))?,
                ),
                Ok(TYPE_REAL32) => ParamValue::Float(
                    float(value).ok_or_else(|| bad(format!("{name}: '{value}' is not a float32")))?,
                ),
                _ => {
                    return Err(bad(format!(
                        "{name}: type '{kind}' is neither 6 (int32) nor 9 (float32)"
                    )));
                }
            };
            out.values.push((name.to_string(), value));
        }
        Ok(out)
    }

    /// Reads a `NAME VALUE` (or `NAME,VALUE`) parameter file; every value
    /// is held as a float32, as ArduPilot's `AP_Param` sets it.
    pub fn parse_name_value(text: &str) -> Result<ParamFile, FirmwareError> {
        let mut out = ParamFile::default();
        for (i, line) in text.lines().enumerate() {
            let bad = |message: String| FirmwareError::Parse { line: i + 1, message };
            let line = line.trim();
            if line.starts_with('#') || line.is_empty() {
                continue;
            }
            let fields: Vec<&str> = line
                .split(|c: char| c == ',' || c.is_whitespace())
                .filter(|f| !f.is_empty())
                .collect();
            let [name, value] = fields[..] else {
                return Err(bad(format!("{} fields, expected NAME VALUE", fields.len())));
            };
            let v = float(value).ok_or_else(|| bad(format!("{name}: '{value}' is not a number")))?;
            out.values.push((name.to_string(), ParamValue::Float(v)));
        }
        Ok(out)
    }
}

/// A finite float32 from its text.
fn float(text: &str) -> Option<f32> {
    text.parse::<f32>().ok().filter(|v| v.is_finite())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn qgc_lines_need_five_tab_separated_fields() {
        let ok = "# header\n1\t1\tTC_G_ENABLE\t1\t6\n1\t1\tTC_G0_X0_0\t0.0125\t9\n";
        let f = ParamFile::parse_qgc(ok).unwrap();
        assert_eq!(f.get("TC_G_ENABLE"), Some(ParamValue::Int(1)));
        assert_eq!(f.float("TC_G0_X0_0").unwrap(), 0.0125f32);
        for bad in [
            "1 1 TC_G_ENABLE 1 6",
            "1\t1\tTC_G_ENABLE\t1",
            "1\t1\tTC_G_ENABLE\t1.5\t6",
            "1\t1\tTC_G0_X0_0\tnan\t9",
            "1\t1\tTC_G0_X0_0\t1\t4",
            " # indented comment is not a comment to QGroundControl",
        ] {
            assert!(ParamFile::parse_qgc(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn name_value_lines_and_last_one_wins() {
        let f = ParamFile::parse_name_value("# c\nINS_TCAL1_TMIN 20.5\nINS_TCAL1_TMIN,21\n").unwrap();
        assert_eq!(f.float("INS_TCAL1_TMIN").unwrap(), 21.0);
        assert!(ParamFile::parse_name_value("INS_TCAL1_TMIN").is_err());
        assert!(ParamFile::parse_name_value("A 1 2").is_err());
        assert!(matches!(
            f.float("INS_TCAL1_TMAX"),
            Err(FirmwareError::Missing(_))
        ));
    }
}
