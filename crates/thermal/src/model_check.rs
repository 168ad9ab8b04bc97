//! What a compensation model must hold before it touches data: a model file
//! is edited by hand, truncated or produced by another version, and a NaN
//! coefficient, a reversed range or a duplicated channel would otherwise
//! write NaN, panic, or compensate one axis twice.

use thiserror::Error;

use imu::Quantity;
use imu::log_file::classify_header;
use imu::recording::standard_name;

use crate::tcal::{Model, SCHEMA};

/// Why a model cannot be used, naming the field at fault
/// (`channels[2].coefficients[1] is not finite`).
/// A model file that cannot be used: unreadable, or not a valid model.
#[derive(Debug, thiserror::Error)]
pub enum ModelFileError {
    /// The file cannot be read.
    #[error("reading {}: {cause}", path.display())]
    Read {
        /// The file.
        path: std::path::PathBuf,
        /// Why.
        cause: std::io::Error,
    },
    /// The file is not a valid model.
    #[error("{}: {cause}", path.display())]
    Invalid {
        /// The file.
        path: std::path::PathBuf,
        /// The field at fault.
        cause: ModelError,
    },
}

#[derive(Debug, Clone, PartialEq, Error)]
pub enum ModelError {
    /// Not JSON, or not the model's shape.
    #[error("not an imutherm compensation model: {0}")]
    Json(String),
    /// Another schema.
    #[error("schema is '{found}', expected '{SCHEMA}'")]
    Schema {
        /// The file's schema.
        found: String,
    },
    /// NaN or infinite.
    #[error("{field} is not finite")]
    NotFinite {
        /// The field (`t_ref_c`, `channels[0].coefficients[2]`).
        field: String,
    },
    /// t_min_c ≥ t_max_c.
    #[error("t_min_c ({t_min_c}) is not below t_max_c ({t_max_c})")]
    EmptyRange {
        /// Lower end, °C.
        t_min_c: f64,
        /// Upper end, °C.
        t_max_c: f64,
    },
    /// A scale or bin width that is zero or negative.
    #[error("{field} ({value}) is not positive")]
    NotPositive {
        /// `scale_c` or `bin_width_c`.
        field: &'static str,
        /// Its value.
        value: f64,
    },
    /// The reference outside the fitted range.
    #[error("t_ref_c ({t_ref_c}) is outside the fitted range t_min_c..t_max_c ({t_min_c} to {t_max_c})")]
    TrefOutsideRange {
        /// Reference, °C.
        t_ref_c: f64,
        /// Lower end, °C.
        t_min_c: f64,
        /// Upper end, °C.
        t_max_c: f64,
    },
    /// No channel at all.
    #[error("channels is empty")]
    NoChannels,
    /// The temperature channel, which the compensation is a function of.
    #[error("{field} '{name}' is the temperature channel, which is never compensated")]
    TemperatureChannel {
        /// `channels[i].name`.
        field: String,
        /// The name.
        name: String,
    },
    /// Not an inertial axis.
    #[error("{field} '{name}' is not an inertial channel (gyro_x … gyro_z, accel_x … accel_z)")]
    UnknownChannel {
        /// `channels[i].name`.
        field: String,
        /// The name.
        name: String,
    },
    /// The same channel twice: it would be compensated twice.
    #[error("{field} '{name}' repeats channels[{first}]")]
    DuplicateChannel {
        /// `channels[i].name`.
        field: String,
        /// The name.
        name: String,
        /// Index of its first occurrence.
        first: usize,
    },
    /// A unit that is not the one the channel's data are compensated in:
    /// the recording is read in SI, so a model in any other unit (or in
    /// none imutherm knows) would correct by the wrong amount.
    #[error("{field} is '{unit}', not {expected}, the unit {name} is read and compensated in")]
    Unit {
        /// `channels[i].unit`.
        field: String,
        /// The unit given.
        unit: String,
        /// The channel.
        name: String,
        /// The SI unit expected.
        expected: &'static str,
    },
    /// Coefficients that do not match the order.
    #[error("{field} has {len} coefficients, order {order} needs {}", order + 1)]
    CoefficientCount {
        /// `channels[i].coefficients`.
        field: String,
        /// Coefficients given.
        len: usize,
        /// The channel's order.
        order: usize,
    },
    /// Finite coefficients whose polynomial overflows within the range.
    #[error("{field} overflow over the fitted range: the compensation would be infinite or NaN")]
    Overflow {
        /// `channels[i].coefficients` or `channels[i].rate_coefficient`.
        field: String,
    },
    /// An instance of a multi-instance model without its number, or with
    /// instances of its own.
    #[error("instances[{index}] {what}")]
    Instance {
        /// Its index in `instances`.
        index: usize,
        /// What is wrong with it.
        what: &'static str,
    },
    /// Two instances of one number: which set goes to which sensor would
    /// be a guess.
    #[error("instances[{index}] repeats instance {instance}")]
    DuplicateInstance {
        /// Its index in `instances`.
        index: usize,
        /// The repeated instance number.
        instance: u32,
    },
    /// A rate term without the dT/dt range to clamp it to.
    #[error("{field} is set but dtdt_range_c_per_s is missing: refit the model to store the dT/dt range")]
    MissingRateRange {
        /// `channels[i].rate_coefficient`.
        field: String,
    },
    /// A dT/dt range whose ends are reversed.
    #[error("dtdt_range_c_per_s [{lo}, {hi}] has its lower end above its upper end")]
    ReversedRateRange {
        /// Lower end, °C/s.
        lo: f64,
        /// Upper end, °C/s.
        hi: f64,
    },
}

impl Model {
    /// Reads a model from its JSON text and validates it.
    pub fn from_json(text: &str) -> Result<Model, ModelError> {
        let model: Model = serde_json::from_str(text).map_err(|e| ModelError::Json(e.to_string()))?;
        model.validate()?;
        Ok(model)
    }

    /// Reads and checks the model in `path`; every error names the file
    /// and the field.
    pub fn read(path: &std::path::Path) -> Result<Model, ModelFileError> {
        let text = std::fs::read_to_string(path).map_err(|cause| ModelFileError::Read {
            path: path.to_path_buf(),
            cause,
        })?;
        Model::from_json(&text).map_err(|cause| ModelFileError::Invalid {
            path: path.to_path_buf(),
            cause,
        })
    }

    /// Checks that the model can be applied: finite numbers, a range with
    /// t_min_c < t_max_c holding t_ref_c, a positive scale, distinct
    /// inertial channels (never the temperature), coefficients matching
    /// each order, and a dT/dt range wherever a rate term is.
    pub fn validate(&self) -> Result<(), ModelError> {
        for (index, m) in self.instances.iter().enumerate() {
            let Some(instance) = m.instance else {
                return Err(ModelError::Instance {
                    index,
                    what: "has no instance number",
                });
            };
            if !m.instances.is_empty() {
                return Err(ModelError::Instance {
                    index,
                    what: "holds instances of its own",
                });
            }
            if self.instances[..index]
                .iter()
                .any(|o| o.instance == Some(instance))
            {
                return Err(ModelError::DuplicateInstance { index, instance });
            }
            m.validate().map_err(|e| match e {
                ModelError::NotFinite { field } => ModelError::NotFinite {
                    field: format!("instances[{index}].{field}"),
                },
                e => e,
            })?;
        }
        self.validate_one()
    }

    /// The checks of one sensor's model.
    fn validate_one(&self) -> Result<(), ModelError> {
        if self.schema != SCHEMA {
            return Err(ModelError::Schema {
                found: self.schema.clone(),
            });
        }
        for (field, v) in [
            ("t_ref_c", self.t_ref_c),
            ("t_min_c", self.t_min_c),
            ("t_max_c", self.t_max_c),
            ("centre_c", self.centre_c),
            ("scale_c", self.scale_c),
            ("bin_width_c", self.bin_width_c),
        ] {
            finite(field.to_string(), v)?;
        }
        if self.t_min_c >= self.t_max_c {
            return Err(ModelError::EmptyRange {
                t_min_c: self.t_min_c,
                t_max_c: self.t_max_c,
            });
        }
        for (field, value) in [("scale_c", self.scale_c), ("bin_width_c", self.bin_width_c)] {
            if value <= 0.0 {
                return Err(ModelError::NotPositive { field, value });
            }
        }
        if self.t_ref_c < self.t_min_c || self.t_ref_c > self.t_max_c {
            return Err(ModelError::TrefOutsideRange {
                t_ref_c: self.t_ref_c,
                t_min_c: self.t_min_c,
                t_max_c: self.t_max_c,
            });
        }
        if let Some([lo, hi]) = self.dtdt_range_c_per_s {
            finite("dtdt_range_c_per_s[0]".into(), lo)?;
            finite("dtdt_range_c_per_s[1]".into(), hi)?;
            if lo > hi {
                return Err(ModelError::ReversedRateRange { lo, hi });
            }
        }
        if self.channels.is_empty() {
            return Err(ModelError::NoChannels);
        }
        for (i, c) in self.channels.iter().enumerate() {
            let field = format!("channels[{i}].name");
            let kind = classify_header(&c.name, None);
            if kind.quantity == Quantity::Temperature {
                return Err(ModelError::TemperatureChannel {
                    field,
                    name: c.name.clone(),
                });
            }
            let inertial = matches!(kind.quantity, Quantity::Acceleration | Quantity::AngularRate)
                && kind.axis.is_some()
                && standard_name(kind.quantity, kind.axis) == c.name;
            if !inertial {
                return Err(ModelError::UnknownChannel {
                    field,
                    name: c.name.clone(),
                });
            }
            if let Some(first) = self.channels[..i].iter().position(|o| o.name == c.name) {
                return Err(ModelError::DuplicateChannel {
                    field,
                    name: c.name.clone(),
                    first,
                });
            }
            let in_si = imu::units::parse_unit(&c.unit)
                .is_some_and(|u| u.quantity == kind.quantity && u.is_identity());
            if !in_si {
                return Err(ModelError::Unit {
                    field: format!("channels[{i}].unit"),
                    unit: c.unit.clone(),
                    name: c.name.clone(),
                    expected: kind.quantity.si_unit(),
                });
            }
            if c.coefficients.len() != c.order + 1 {
                return Err(ModelError::CoefficientCount {
                    field: format!("channels[{i}].coefficients"),
                    len: c.coefficients.len(),
                    order: c.order,
                });
            }
            for (k, &v) in c.coefficients.iter().enumerate() {
                finite(format!("channels[{i}].coefficients[{k}]"), v)?;
            }
            finite(format!("channels[{i}].residual_rms"), c.residual_rms)?;
            finite(format!("channels[{i}].residual_max"), c.residual_max)?;
            // |p(u)| ≤ Σ|c_j|·m^j over the range; twice that bounds
            // p(T) − p(T_ref), the correction applied.
            let m = [self.t_min_c, self.t_max_c]
                .iter()
                .map(|t| ((t - self.centre_c) / self.scale_c).abs())
                .fold(1.0f64, f64::max);
            let bound: f64 = c
                .coefficients
                .iter()
                .enumerate()
                .map(|(j, c)| c.abs() * m.powi(j as i32))
                .sum();
            if !(2.0 * bound).is_finite() {
                return Err(ModelError::Overflow {
                    field: format!("channels[{i}].coefficients"),
                });
            }
            if let Some(k) = c.rate_coefficient {
                let field = format!("channels[{i}].rate_coefficient");
                finite(field.clone(), k)?;
                let Some([lo, hi]) = self.dtdt_range_c_per_s else {
                    return Err(ModelError::MissingRateRange { field });
                };
                if !(k * lo.abs().max(hi.abs()) + 2.0 * bound).is_finite() {
                    return Err(ModelError::Overflow { field });
                }
            }
        }
        Ok(())
    }
}

fn finite(field: String, v: f64) -> Result<(), ModelError> {
    if v.is_finite() {
        Ok(())
    } else {
        Err(ModelError::NotFinite { field })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tcal::ChannelModel;

    fn model() -> Model {
        let ch = |name: &str, unit: &str| ChannelModel {
            name: name.to_string(),
            unit: unit.into(),
            order: 1,
            coefficients: vec![1e-3, 2e-4],
            rate_coefficient: None,
            residual_rms: 0.0,
            residual_max: 0.0,
            cross_validation: Vec::new(),
            hysteresis: None,
            lag_s: None,
            lag_interval_s: None,
            hysteresis_term: None,
            projection: None,
        };
        Model {
            schema: SCHEMA.into(),
            t_ref_c: 40.0,
            t_min_c: 20.0,
            t_max_c: 60.0,
            centre_c: 40.0,
            scale_c: 20.0,
            bin_width_c: 1.0,
            fitted_on: Vec::new(),
            fitted_on_digests: Vec::new(),
            dtdt_range_c_per_s: None,
            device_id: None,
            accel_device_id: None,
            instance: None,
            temperature_step_c: None,
            channels: vec![ch("gyro_x", "rad/s"), ch("accel_z", "m/s^2")],
            instances: Vec::new(),
        }
    }

    #[test]
    fn a_sound_model_passes_and_round_trips() {
        let m = model();
        m.validate().unwrap();
        let text = serde_json::to_string(&m).unwrap();
        assert_eq!(Model::from_json(&text).unwrap(), m);
    }

    #[test]
    fn a_multi_instance_model_round_trips_and_its_instances_are_checked() {
        let one = |n: u32| Model {
            instance: Some(n),
            device_id: Some(2_490_378 + n),
            ..model()
        };
        let m = Model::of_instances(vec![one(0), one(1)]).unwrap();
        m.validate().unwrap();
        let text = serde_json::to_string(&m).unwrap();
        let back = Model::from_json(&text).unwrap();
        assert_eq!(back, m);
        // The top level is instance 0's, so a reader of one-instance models
        // finds a whole model.
        assert_eq!(back.instance, Some(0));
        assert_eq!(back.sensors().len(), 2);
        // A one-instance model is its own single sensor.
        assert_eq!(model().sensors(), vec![&model()]);
        let mut bad = m.clone();
        bad.instances[1].instance = None;
        assert!(
            bad.validate()
                .unwrap_err()
                .to_string()
                .contains("instances[1] has no instance")
        );
        let mut bad = m.clone();
        bad.instances[1].instance = Some(0);
        assert!(
            bad.validate()
                .unwrap_err()
                .to_string()
                .contains("instances[1] repeats instance 0")
        );
        let mut bad = m.clone();
        bad.instances[0].t_ref_c = f64::NAN;
        assert!(
            bad.validate()
                .unwrap_err()
                .to_string()
                .contains("instances[0].t_ref_c is not finite")
        );
        let mut bad = m;
        bad.instances[1].instances = vec![one(2)];
        assert!(
            bad.validate()
                .unwrap_err()
                .to_string()
                .contains("instances[1] holds instances")
        );
    }

    #[test]
    fn each_fault_names_its_field() {
        type Spoil = fn(&mut Model);
        let cases: Vec<(Spoil, &str)> = vec![
            (
                |m| m.channels[1].coefficients[1] = f64::NAN,
                "channels[1].coefficients[1] is not finite",
            ),
            (
                |m| m.channels[0].coefficients[0] = f64::INFINITY,
                "channels[0].coefficients[0] is not finite",
            ),
            (|m| m.t_ref_c = f64::NAN, "t_ref_c is not finite"),
            (|m| m.scale_c = 0.0, "scale_c (0) is not positive"),
            (|m| m.scale_c = -2.0, "scale_c (-2) is not positive"),
            (|m| m.bin_width_c = 0.0, "bin_width_c (0) is not positive"),
            (
                |m| std::mem::swap(&mut m.t_min_c, &mut m.t_max_c),
                "t_min_c (60) is not below t_max_c (20)",
            ),
            (|m| m.t_ref_c = 500.0, "t_ref_c (500) is outside the fitted range"),
            (|m| m.channels.clear(), "channels is empty"),
            (
                |m| m.channels[1].name = "temp".into(),
                "channels[1].name 'temp' is the temperature channel",
            ),
            (
                |m| m.channels[1].name = "pressure".into(),
                "channels[1].name 'pressure' is not an inertial channel",
            ),
            (
                |m| m.channels[1].name = "gyro_x".into(),
                "channels[1].name 'gyro_x' repeats channels[0]",
            ),
            (
                |m| m.channels[0].coefficients.clear(),
                "channels[0].coefficients has 0 coefficients, order 1 needs 2",
            ),
            (
                |m| m.channels[0].rate_coefficient = Some(1.0),
                "channels[0].rate_coefficient is set but dtdt_range_c_per_s is missing",
            ),
            (
                |m| m.dtdt_range_c_per_s = Some([0.1, -0.1]),
                "dtdt_range_c_per_s [0.1, -0.1] has its lower end above its upper end",
            ),
            (|m| m.schema = "other/1".into(), "schema is 'other/1'"),
            (
                |m| m.channels[0].unit = "furlong".into(),
                "channels[0].unit is 'furlong', not rad/s, the unit gyro_x is read and compensated in",
            ),
            (
                |m| m.channels[0].unit = "deg/s".into(),
                "channels[0].unit is 'deg/s', not rad/s",
            ),
            (
                |m| m.channels[1].unit = "rad/s".into(),
                "channels[1].unit is 'rad/s', not m/s^2",
            ),
        ];
        for (spoil, expected) in cases {
            let mut m = model();
            spoil(&mut m);
            let e = m.validate().unwrap_err().to_string();
            assert!(e.starts_with(expected), "{e:?} should start with {expected:?}");
        }
    }

    #[test]
    fn huge_finite_coefficients_or_a_tiny_scale_overflow() {
        let mut m = model();
        m.channels[1].coefficients[1] = 1e308;
        assert_eq!(
            m.validate().unwrap_err().to_string(),
            "channels[1].coefficients overflow over the fitted range: the compensation would be infinite or NaN"
        );
        let mut m = model();
        m.scale_c = 1e-320;
        assert!(matches!(m.validate(), Err(ModelError::Overflow { .. })));
    }

    #[test]
    fn json_that_is_not_a_model_is_refused_without_panic() {
        for text in ["", "{", "[]", r#"{"schema":"imutherm.tcal/1"}"#, "null"] {
            assert!(
                matches!(Model::from_json(text), Err(ModelError::Json(_))),
                "{text}"
            );
        }
        // JSON has no NaN: an out-of-range literal is how one gets written.
        let text = serde_json::to_string(&model())
            .unwrap()
            .replace("0.0002", "1e999");
        assert!(text.contains("1e999"));
        assert!(matches!(Model::from_json(&text), Err(ModelError::Json(_))));
    }
}
