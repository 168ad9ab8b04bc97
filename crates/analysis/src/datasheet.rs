//! A datasheet's figures for the summary's comparison: built in for a few
//! parts (`datasheets/*.toml`), or read from a TOML file in the same form.
//! Every figure carries its source (document, revision, table or section);
//! a figure the file does not hold is "not given", never guessed.

use std::path::{Path, PathBuf};

use allan::noise_terms::Term;
use imu::Quantity;
use serde::{Deserialize, Serialize};

/// The built-in datasheets, by the name `--datasheet` takes.
const BUILT_IN: [(&str, &str); 5] = [
    ("MPU-9250", include_str!("../datasheets/mpu-9250.toml")),
    ("MPU-6050", include_str!("../datasheets/mpu-6050.toml")),
    ("ICM-20948", include_str!("../datasheets/icm-20948.toml")),
    ("BMI088", include_str!("../datasheets/bmi088.toml")),
    ("ADIS16405", include_str!("../datasheets/adis16405.toml")),
];

/// The names of the built-in datasheets.
pub fn built_in_names() -> Vec<&'static str> {
    BUILT_IN.iter().map(|(n, _)| *n).collect()
}

/// A datasheet that cannot be had.
#[derive(Debug, thiserror::Error)]
pub enum DatasheetError {
    /// Neither a built-in name nor a readable file.
    #[error("no built-in datasheet '{name}' (built in: {}) and no such file", built_in_names().join(", "))]
    Unknown {
        /// What was asked for.
        name: String,
    },
    /// The file could not be read.
    #[error("{}: {cause}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// Why.
        cause: std::io::Error,
    },
    /// The file is not a datasheet in imutherm's form.
    #[error("{what}: {message}")]
    Format {
        /// The file, or the built-in name.
        what: String,
        /// What is wrong.
        message: String,
    },
}

/// One figure of a datasheet.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Figure {
    /// The typical value, in `unit`; none when the datasheet gives only a
    /// range or a sentence (`text`).
    #[serde(default)]
    pub value: Option<f64>,
    /// The unit of `value`.
    #[serde(default)]
    pub unit: Option<String>,
    /// The figure as the datasheet words it, when not a plain value.
    #[serde(default)]
    pub text: Option<String>,
    /// Table or section of the document it is read from.
    pub source: String,
}

/// One sensor's figures (gyroscope or accelerometer).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SensorFigures {
    /// N as a noise density.
    #[serde(default)]
    pub white_noise: Option<Figure>,
    /// B.
    #[serde(default)]
    pub bias_instability: Option<Figure>,
    /// K.
    #[serde(default)]
    pub rate_random_walk: Option<Figure>,
    /// How the bias moves with temperature.
    #[serde(default)]
    pub bias_over_temperature: Option<Figure>,
}

/// A datasheet's figures.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Datasheet {
    /// The part.
    pub name: String,
    /// The document (maker and number).
    pub document: String,
    /// Its revision.
    pub revision: String,
    /// Sensors whose figures the file leaves out although the document has
    /// them ("gyro", "accel"): shown as "not carried", not "not given".
    #[serde(default)]
    pub omitted: Vec<String>,
    /// Gyroscope figures.
    #[serde(default)]
    pub gyro: SensorFigures,
    /// Accelerometer figures.
    #[serde(default)]
    pub accel: SensorFigures,
}

/// The unit the summary prints a term in, and so the unit a datasheet file
/// must give it in: N as a density (PS-MPU-9250A-01 quotes °/s/√Hz and
/// µg/√Hz), B and K in the datasheet units of [`crate::units::Units::Datasheet`].
pub fn summary_unit(quantity: Quantity, term: Term) -> Option<&'static str> {
    Some(match (quantity, term) {
        (Quantity::AngularRate, Term::WhiteNoise) => "°/s/√Hz",
        (Quantity::AngularRate, Term::BiasInstability) => "°/h",
        (Quantity::AngularRate, Term::RateRandomWalk) => "°/h/√h",
        (Quantity::Acceleration, Term::WhiteNoise) => "µg/√Hz",
        (Quantity::Acceleration, Term::BiasInstability) => "µg",
        (Quantity::Acceleration, Term::RateRandomWalk) => "µg/√s",
        _ => return None,
    })
}

impl Datasheet {
    /// A built-in datasheet by name (case-insensitive), or else the TOML
    /// file at `spec`.
    pub fn resolve(spec: &str) -> Result<Datasheet, DatasheetError> {
        if let Some((name, text)) = BUILT_IN.iter().find(|(n, _)| n.eq_ignore_ascii_case(spec)) {
            return Datasheet::parse(text, name);
        }
        let path = Path::new(spec);
        if !path.is_file() {
            return Err(DatasheetError::Unknown {
                name: spec.to_string(),
            });
        }
        let text = std::fs::read_to_string(path).map_err(|cause| DatasheetError::Io {
            path: path.to_path_buf(),
            cause,
        })?;
        Datasheet::parse(&text, &path.display().to_string())
    }

    /// Parses a datasheet; `what` names it in errors. Refuses a figure in
    /// another unit than the summary prints, rather than convert it wrongly.
    pub fn parse(text: &str, what: &str) -> Result<Datasheet, DatasheetError> {
        let format = |message: String| DatasheetError::Format {
            what: what.to_string(),
            message,
        };
        let sheet: Datasheet = toml::from_str(text).map_err(|e| format(e.message().to_string()))?;
        for q in [Quantity::AngularRate, Quantity::Acceleration] {
            for term in [Term::WhiteNoise, Term::BiasInstability, Term::RateRandomWalk] {
                let Some(f) = sheet.figure(q, term) else { continue };
                let want = summary_unit(q, term).unwrap_or("");
                if f.value.is_some() && f.unit.as_deref() != Some(want) {
                    return Err(format(format!(
                        "{} {}: unit {:?}, expected \"{want}\"",
                        sensor_key(q),
                        term.symbol(),
                        f.unit.as_deref().unwrap_or("none")
                    )));
                }
            }
        }
        Ok(sheet)
    }

    /// The figures of the sensor measuring `quantity`.
    pub fn sensor(&self, quantity: Quantity) -> Option<&SensorFigures> {
        match quantity {
            Quantity::AngularRate => Some(&self.gyro),
            Quantity::Acceleration => Some(&self.accel),
            _ => None,
        }
    }

    /// The figure for `term` of the sensor measuring `quantity`.
    pub fn figure(&self, quantity: Quantity, term: Term) -> Option<&Figure> {
        let s = self.sensor(quantity)?;
        match term {
            Term::WhiteNoise => s.white_noise.as_ref(),
            Term::BiasInstability => s.bias_instability.as_ref(),
            Term::RateRandomWalk => s.rate_random_walk.as_ref(),
            _ => None,
        }
    }

    /// Whether the file leaves out the sensor measuring `quantity`.
    pub fn omits(&self, quantity: Quantity) -> bool {
        self.omitted.iter().any(|o| o == sensor_key(quantity))
    }
}

fn sensor_key(q: Quantity) -> &'static str {
    if q == Quantity::AngularRate {
        "gyro"
    } else {
        "accel"
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_built_in_parses_and_cites_its_document() {
        for name in built_in_names() {
            let d = Datasheet::resolve(&name.to_lowercase()).unwrap();
            assert_eq!(d.name, name);
            assert!(!d.document.is_empty() && !d.revision.is_empty());
        }
        // PS-MPU-9250A-01 rev 1.1 §3.1, §3.2.
        let d = Datasheet::resolve("MPU-9250").unwrap();
        let n = d.figure(Quantity::AngularRate, Term::WhiteNoise).unwrap();
        assert_eq!((n.value, n.unit.as_deref()), (Some(0.01), Some("°/s/√Hz")));
        assert!(d.figure(Quantity::AngularRate, Term::BiasInstability).is_none());
        // Parts whose accelerometer table is not carried say so, rather
        // than read as "not given".
        for name in ["BMI088", "ADIS16405"] {
            let d = Datasheet::resolve(name).unwrap();
            assert!(d.omits(Quantity::Acceleration) && !d.omits(Quantity::AngularRate));
            assert!(d.figure(Quantity::AngularRate, Term::WhiteNoise).is_some());
        }
    }

    #[test]
    fn a_figure_in_another_unit_is_refused() {
        let text = "name = \"X\"\ndocument = \"D\"\nrevision = \"1\"\n\
                    [gyro.white_noise]\nvalue = 0.3\nunit = \"°/√h\"\nsource = \"t1\"\n";
        let e = Datasheet::parse(text, "x.toml").unwrap_err().to_string();
        assert!(e.contains("expected \"°/s/√Hz\""), "{e}");
    }

    #[test]
    fn an_unknown_name_lists_the_built_ins() {
        let e = Datasheet::resolve("no-such-part").unwrap_err().to_string();
        assert!(e.contains("MPU-9250") && e.contains("ICM-20948"), "{e}");
    }
}
