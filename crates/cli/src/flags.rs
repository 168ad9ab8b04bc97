//! Value parsers of the flags: a value outside what a flag takes is a usage
//! error (exit status 2) when the command line is parsed, before any file is
//! read, with a message naming the flag (clap's `invalid value 'V' for
//! '--FLAG'`) and what it takes.

#![cfg_attr(not(all(feature = "analysis", feature = "record")), allow(dead_code))]

use std::fmt;

use clap::builder::{PossibleValue, StringValueParser, TypedValueParser};

#[cfg(feature = "analysis")]
use allan::{DataType, Stat, TauSpec};
use imu::Quantity;
use imu::units::parse_unit;
use mpu9250::config::{AccelRange, Config, DLPF_BANDWIDTHS, GyroRange};
#[cfg(feature = "analysis")]
use thermal::tcal::Order;

/// A request the flags make impossible or absurd, found once they are
/// combined (after parsing): a usage error, exit status 2, like clap's.
#[derive(Debug)]
pub struct UsageError(pub String);

impl fmt::Display for UsageError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for UsageError {}

/// A parser whose accepted values are also listed in `--help` (clap prints
/// `[possible values: …]` for them).
#[derive(Clone)]
pub struct Listed<P> {
    inner: P,
    values: &'static [&'static str],
}

impl<P: TypedValueParser> TypedValueParser for Listed<P> {
    type Value = P::Value;

    fn parse_ref(
        &self,
        cmd: &clap::Command,
        arg: Option<&clap::Arg>,
        value: &std::ffi::OsStr,
    ) -> Result<Self::Value, clap::Error> {
        self.inner.parse_ref(cmd, arg, value)
    }

    fn possible_values(&self) -> Option<Box<dyn Iterator<Item = PossibleValue> + '_>> {
        Some(Box::new(self.values.iter().map(|v| PossibleValue::new(*v))))
    }
}

fn listed<T, E>(
    values: &'static [&'static str],
    parse: fn(&str) -> Result<T, E>,
) -> Listed<impl TypedValueParser<Value = T>>
where
    T: Clone + Send + Sync + 'static,
    E: Into<Box<dyn std::error::Error + Send + Sync + 'static>> + 'static,
{
    Listed {
        inner: StringValueParser::new().try_map(move |s| parse(&s)),
        values,
    }
}

fn number(text: &str) -> Result<f64, String> {
    text.trim()
        .parse::<f64>()
        .map_err(|_| format!("'{text}' is not a number"))
}

/// A number that `holds`, or the usage error `expected` says why not.
fn number_where(text: &str, holds: impl Fn(f64) -> bool, expected: &str) -> Result<f64, String> {
    let v = number(text)?;
    if holds(v) {
        Ok(v)
    } else {
        Err(expected.to_string())
    }
}

/// A positive, finite number (a rate, a width, a length of time).
pub fn positive(text: &str) -> Result<f64, String> {
    number_where(text, |v| v.is_finite() && v > 0.0, "expected a positive number")
}

/// A temperature in °C: finite, not below absolute zero, and below 1000 °C
/// (far beyond any IMU's survival), so that a typo is a usage error.
pub fn temperature(text: &str) -> Result<f64, String> {
    number_where(
        text,
        |v| v.is_finite() && (-273.15..=1000.0).contains(&v),
        "expected a finite number of °C between absolute zero (-273.15) and 1000",
    )
}

/// A confidence level, returned as a fraction: a fraction strictly between
/// 0 and 1 (0.683) or a percentage strictly between 1 and 100 (68.3, 95).
/// Exactly 1 is refused: it could mean 100 % or 1 %, and neither is a
/// usable level.
pub fn confidence(text: &str) -> Result<f64, String> {
    let v = number(text)?;
    if v > 0.0 && v < 1.0 {
        Ok(v)
    } else if v > 1.0 && v < 100.0 {
        Ok(v / 100.0)
    } else {
        Err(
            "expected a fraction between 0 and 1 (0.683) or a percentage between 1 and 100 (68.3), \
             both exclusive"
                .to_string(),
        )
    }
}

#[cfg(feature = "analysis")]
/// `--stat`: one of the statistics of [`Stat::ALL`].
pub fn stat() -> Listed<impl TypedValueParser<Value = Stat>> {
    listed(
        &[
            "adev", "oadev", "mdev", "tdev", "hdev", "ohdev", "totdev", "mtotdev", "ttotdev", "htotdev",
            "theo1",
        ],
        str::parse::<Stat>,
    )
}

#[cfg(feature = "analysis")]
/// `--data-type`: freq or phase (also frequency, rate, integrated).
pub fn data_type() -> Listed<impl TypedValueParser<Value = DataType>> {
    listed(&["freq", "phase"], str::parse::<DataType>)
}

#[cfg(feature = "analysis")]
/// `--taus`: a named grid or a comma list of positive finite taus.
pub fn taus(text: &str) -> Result<TauSpec, String> {
    text.parse::<TauSpec>().map_err(|e| e.to_string())
}

#[cfg(feature = "analysis")]
/// `--order`: auto, or a polynomial order from 0 to 9.
pub fn order(text: &str) -> Result<Order, String> {
    let t = text.trim();
    if t.eq_ignore_ascii_case("auto") {
        return Ok(Order::Auto);
    }
    t.parse::<usize>()
        .ok()
        .filter(|&o| o <= 9)
        .map(Order::Fixed)
        .ok_or_else(|| "expected auto or an order from 0 to 9".to_string())
}

/// `--instance`: one IMU instance of a log, or all of them.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Instance {
    /// Instance N.
    One(u32),
    /// Every instance the log has.
    All,
}

/// `--instance N|all`.
pub fn instance(text: &str) -> Result<Instance, String> {
    let t = text.trim();
    if t.eq_ignore_ascii_case("all") {
        return Ok(Instance::All);
    }
    t.parse::<u32>()
        .map(Instance::One)
        .map_err(|_| "expected an instance number (0, 1, …) or all".to_string())
}

/// A duration: plain seconds or a number with s, m, h or d (3600, 90m, 2h,
/// 1.5h), in seconds.
pub fn duration(text: &str) -> Result<f64, String> {
    let t = text.trim();
    let (num, unit) = match t.char_indices().find(|(_, c)| c.is_ascii_alphabetic()) {
        Some((i, _)) => (&t[..i], &t[i..]),
        None => (t, "s"),
    };
    let factor = match unit {
        "s" | "sec" => 1.0,
        "m" | "min" => 60.0,
        "h" => 3600.0,
        "d" => 86400.0,
        _ => return Err(format!("duration '{text}': unit '{unit}' is not s, m, h or d")),
    };
    let v: f64 = num
        .trim()
        .parse()
        .map_err(|_| format!("duration '{text}': '{num}' is not a number"))?;
    if !(v.is_finite() && v > 0.0) {
        return Err(format!("duration '{text}': must be positive"));
    }
    let seconds = v * factor;
    if !seconds.is_finite() {
        return Err(format!("duration '{text}': too long"));
    }
    Ok(seconds)
}

/// `--unit COL=UNIT`, with a unit imutherm converts, parsed once here and
/// passed on as it is to the reader.
pub fn unit_override(text: &str) -> Result<imu::units::UnitOverride, String> {
    text.parse::<imu::units::UnitOverride>()
        .map_err(|e| e.to_string())
}

/// `--scale`: `COLUMN=FACTOR`.
pub fn column_scale(text: &str) -> Result<imu::units::ColumnScale, String> {
    text.parse::<imu::units::ColumnScale>().map_err(|e| e.to_string())
}

/// `--time-unit`: a unit of time.
pub fn time_unit(text: &str) -> Result<String, String> {
    match parse_unit(text) {
        Some(u) if u.quantity == Quantity::Time => Ok(text.to_string()),
        _ => Err("expected s, ms, us or ns".to_string()),
    }
}

/// `record --rate`: a rate the MPU-9250 can be set to, 1000/(1 + n) Hz for
/// n = 0…255 (RM-MPU-9250A-00 §4.4, SMPLRT_DIV), once rounded.
pub fn chip_rate(text: &str) -> Result<f64, String> {
    let rate = number(text)?;
    let config = Config {
        rate_hz: rate,
        ..Config::default()
    };
    match config.divider() {
        Some(_) => Ok(rate),
        None => Err("the MPU-9250 makes 1000/(1 + n) Hz, n = 0…255: from 3.906 to 1000 Hz".to_string()),
    }
}

/// `--dlpf`: one of the chip's gyro bandwidths, Hz.
pub fn dlpf() -> Listed<impl TypedValueParser<Value = f64>> {
    listed(&["184", "92", "41", "20", "10", "5"], |text| {
        let hz = number(text)?;
        if DLPF_BANDWIDTHS.iter().any(|&(_, bw)| bw == hz) {
            Ok(hz)
        } else {
            Err("the MPU-9250's gyro low-pass bandwidths are 184, 92, 41, 20, 10 and 5 Hz".to_string())
        }
    })
}

/// A full scale of the chip that `lookup` knows. The lookups truncate:
/// only the exact, whole values are full scales.
fn full_scale<R>(text: &str, lookup: fn(f64) -> Option<R>, expected: &str) -> Result<f64, String> {
    number_where(text, |v| lookup(v).is_some() && v.fract() == 0.0, expected)
}

/// `--accel-range`: a full scale of the chip, g.
pub fn accel_range() -> Listed<impl TypedValueParser<Value = f64>> {
    listed(&["2", "4", "8", "16"], |text| {
        full_scale(text, AccelRange::from_g, "expected 2, 4, 8 or 16")
    })
}

/// `--gyro-range`: a full scale of the chip, °/s.
pub fn gyro_range() -> Listed<impl TypedValueParser<Value = f64>> {
    listed(&["250", "500", "1000", "2000"], |text| {
        full_scale(text, GyroRange::from_dps, "expected 250, 500, 1000 or 2000")
    })
}

/// `--sim-bus-errors`: a fraction of transfers, from 0 up to (not
/// including) 1: a bus on which every transfer fails delivers nothing.
pub fn error_fraction(text: &str) -> Result<f64, String> {
    number_where(
        text,
        |v| (0.0..1.0).contains(&v),
        "expected a fraction from 0 to below 1 (0.01 = 1 %)",
    )
}

/// `--sim-brownout-at`: seconds into the run.
pub fn brownout_at(text: &str) -> Result<f64, String> {
    number_where(
        text,
        |v| (0.0..1e9).contains(&v),
        "expected seconds from 0 to 1e9",
    )
}

/// `--sim-clock-ppm`: a clock error that leaves the clock running forwards.
pub fn clock_ppm(text: &str) -> Result<f64, String> {
    number_where(
        text,
        |v| v.is_finite() && v >= -1e6,
        "a clock cannot run backwards (−1000000 stops it)",
    )
}

/// Where `record` reads from.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum DeviceKind {
    /// The simulated chip fed by a preset (or `counter`).
    Sim { preset: String },
    /// An I2C bus device and the chip's address.
    I2c { path: String, address: u8 },
    /// A spidev device.
    Spi { path: String },
}

/// `--device`, as given and as understood.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Device {
    /// The text given, for the log's metadata.
    pub text: String,
    pub kind: DeviceKind,
}

impl fmt::Display for Device {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.text)
    }
}

/// The presets of the simulated chip: the simulator's, and `counter`.
pub const SIM_PRESETS: [&str; 3] = ["mpu9250-thesis", "white", "counter"];

/// `--device`: sim[:PRESET], i2c[:/dev/i2c-N][@0x68|@0x69], spi[:/dev/spidevB.C].
pub fn device(text: &str) -> Result<Device, String> {
    let (kind, rest) = text.split_once(':').unwrap_or((text, ""));
    let kind = match kind {
        "sim" => {
            let preset = if rest.is_empty() { "mpu9250-thesis" } else { rest };
            if !SIM_PRESETS.contains(&preset) {
                return Err(format!(
                    "sim:{preset}: presets are mpu9250-thesis, white and counter"
                ));
            }
            DeviceKind::Sim {
                preset: preset.to_string(),
            }
        }
        "i2c" => {
            let (path, address) = match rest.split_once('@') {
                Some((p, addr)) => {
                    let address = u8::from_str_radix(addr.trim_start_matches("0x"), 16)
                        .map_err(|_| format!("'{addr}' is not an address like 0x68"))?;
                    if !matches!(address, 0x68 | 0x69) {
                        return Err(format!(
                            "the MPU-9250 answers at 0x68 (AD0 low) or 0x69 (AD0 high), not 0x{address:02x}"
                        ));
                    }
                    (p, address)
                }
                None => (rest, 0x68),
            };
            DeviceKind::I2c {
                path: if path.is_empty() { "/dev/i2c-1" } else { path }.to_string(),
                address,
            }
        }
        "spi" => DeviceKind::Spi {
            path: if rest.is_empty() { "/dev/spidev0.0" } else { rest }.to_string(),
        },
        _ => {
            return Err("expected sim[:PRESET], i2c:/dev/i2c-N[@0x68] or spi:/dev/spidevB.C".to_string());
        }
    };
    Ok(Device {
        text: text.to_string(),
        kind,
    })
}

/// The datasheet `--datasheet` names: a built-in part or a TOML file. A
/// name that is neither is a usage error; a file that is not a datasheet
/// is the file's.
#[cfg(feature = "analysis")]
pub fn datasheet(spec: &str) -> anyhow::Result<analysis::datasheet::Datasheet> {
    use analysis::datasheet::{Datasheet, DatasheetError};
    Datasheet::resolve(spec).map_err(|e| match e {
        DatasheetError::Unknown { .. } => anyhow::Error::new(UsageError(format!("--datasheet: {e}"))),
        e => anyhow::Error::new(e),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn durations() {
        for (text, s) in [
            ("2h", 7200.0),
            ("90m", 5400.0),
            ("3600s", 3600.0),
            ("3600", 3600.0),
            ("1.5h", 5400.0),
            (" 10 min", 600.0),
        ] {
            assert_eq!(duration(text).unwrap(), s, "{text}");
        }
        for bad in [
            "",
            "h",
            "ten minutes",
            "-5s",
            "0",
            "3 weeks",
            "nan",
            "inf",
            "1e308h",
        ] {
            assert!(duration(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn a_confidence_is_a_fraction_or_a_percentage_never_both() {
        for (text, level) in [
            ("0.683", 0.683),
            ("68.3", 0.683),
            ("95", 0.95),
            ("0.95", 0.95),
            ("99.9", 0.999),
        ] {
            assert!((confidence(text).unwrap() - level).abs() < 1e-12, "{text}");
        }
        for bad in ["1", "0", "100", "150", "-0.5", "nan", "inf", "", "1.0"] {
            assert!(confidence(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn chip_settings_are_the_chips() {
        assert_eq!(chip_rate("200").unwrap(), 200.0);
        assert_eq!(chip_rate("1000").unwrap(), 1000.0);
        for bad in ["0", "5000", "1", "nan", "-200"] {
            assert!(chip_rate(bad).is_err(), "{bad}");
        }
        let cmd = clap::Command::new("t");
        let dlpf = dlpf();
        for ok in ["184", "5", "41.0"] {
            assert!(dlpf.parse_ref(&cmd, None, ok.as_ref()).is_ok(), "{ok}");
        }
        for bad in ["0", "100", "nan", "-5"] {
            assert!(dlpf.parse_ref(&cmd, None, bad.as_ref()).is_err(), "{bad}");
        }
        let gyro = gyro_range();
        assert!(gyro.parse_ref(&cmd, None, "2000".as_ref()).is_ok());
        assert!(gyro.parse_ref(&cmd, None, "250.5".as_ref()).is_err());
        let accel = accel_range();
        assert!(accel.parse_ref(&cmd, None, "16".as_ref()).is_ok());
        assert!(accel.parse_ref(&cmd, None, "3".as_ref()).is_err());
    }

    #[test]
    fn devices() {
        assert_eq!(
            device("i2c").unwrap().kind,
            DeviceKind::I2c {
                path: "/dev/i2c-1".into(),
                address: 0x68
            }
        );
        assert_eq!(
            device("i2c:/dev/i2c-3@0x69").unwrap().kind,
            DeviceKind::I2c {
                path: "/dev/i2c-3".into(),
                address: 0x69
            }
        );
        assert_eq!(
            device("sim").unwrap().kind,
            DeviceKind::Sim {
                preset: "mpu9250-thesis".into()
            }
        );
        assert_eq!(
            device("spi:/dev/spidev1.0").unwrap().to_string(),
            "spi:/dev/spidev1.0"
        );
        for bad in ["usb:0", "i2c:/dev/i2c-1@0x70", "i2c@68h", "sim:nope", ""] {
            assert!(device(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn orders_and_fractions() {
        assert_eq!(order("AUTO").unwrap(), Order::Auto);
        assert_eq!(order("3").unwrap(), Order::Fixed(3));
        assert!(order("10").is_err() && order("-1").is_err() && order("x").is_err());
        assert_eq!(error_fraction("0").unwrap(), 0.0);
        assert!(error_fraction("1").is_err() && error_fraction("nan").is_err());
        assert!(positive("0").is_err() && positive("inf").is_err() && positive("1e-3").is_ok());
        assert!(unit_override("gyro_x=deg/s").is_ok());
        assert!(unit_override("gyro_x=furlong").is_err() && unit_override("=deg/s").is_err());
        assert!(time_unit("ms").is_ok() && time_unit("deg/s").is_err());
    }
}
