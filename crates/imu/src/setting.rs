//! The choices a user makes (the sample rate, a unit for a column, the
//! stream of a robot log, …), as the libraries' messages name them.
//!
//! An error or note about a choice holds its [`Setting`] (and the value
//! given, as a [`Given`]), never a front end's spelling of it: the command
//! line calls the sample rate `--rate 200`, Python `rate=200`. The front
//! end says how it names settings once, at start, with [`name_settings`];
//! every message rendered afterwards in the process names them its way.
//! Without a naming, a message names a setting by what it means ("the
//! sample rate 200").
//!
//! The naming is one per process rather than a parameter of each
//! rendering because messages are rendered where a front end cannot pass
//! one: through `thiserror` sources and `#[error(transparent)]` wrappers,
//! through the command line's `anyhow` contexts, and in reader notes built
//! on worker threads. A process has one front end.

use std::fmt;
use std::sync::OnceLock;

/// A choice the user makes, by what it means.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Setting {
    /// The sample rate, Hz.
    SampleRate,
    /// The time column's unit when its header has none.
    TimeUnit,
    /// The column that times the samples.
    TimeColumn,
    /// How far gaps may stretch the time grid, as a multiple of the
    /// samples.
    MaxGridFactor,
    /// A unit given for a column (`COLUMN=UNIT`).
    UnitOverride,
    /// A factor given for a column's values (`COLUMN=FACTOR`).
    ColumnScale,
    /// The channels to analyse.
    Channels,
    /// The IMU stream of a robot log, by topic.
    Topic,
    /// The IMU stream of a robot log (or the sensor of a model), by
    /// instance number.
    Instance,
    /// The temperature stream of a robot log, by topic.
    TempTopic,
    /// Reading a robot log that misses some of its storage files.
    AllowPartial,
    /// Replacing an output that exists.
    Overwrite,
    /// The polynomial order of a compensation fit.
    FitOrder,
    /// The firmware a compensation is fitted for.
    FitFirmware,
    /// A dT/dt term in a compensation fit.
    RateTerm,
    /// The width of a fit's temperature bins, °C.
    BinWidth,
    /// The firmware whose exported parameters a compensation is evaluated
    /// through.
    ExportFirmware,
    /// The sensor's device id written into a firmware's parameters.
    DeviceId,
    /// The firmware's calibration slot a compensation is exported to.
    CalibrationSlot,
    /// The Kalibr IMU file to write.
    KalibrFile,
    /// The compensation model a navigation predicts from.
    NavigationModel,
}

impl Setting {
    /// Every setting, for a front end to check that it names each.
    pub const ALL: [Setting; 21] = [
        Setting::SampleRate,
        Setting::TimeUnit,
        Setting::TimeColumn,
        Setting::MaxGridFactor,
        Setting::UnitOverride,
        Setting::ColumnScale,
        Setting::Channels,
        Setting::Topic,
        Setting::Instance,
        Setting::TempTopic,
        Setting::AllowPartial,
        Setting::Overwrite,
        Setting::FitOrder,
        Setting::FitFirmware,
        Setting::RateTerm,
        Setting::BinWidth,
        Setting::ExportFirmware,
        Setting::DeviceId,
        Setting::CalibrationSlot,
        Setting::KalibrFile,
        Setting::NavigationModel,
    ];

    /// What the setting is, in words.
    pub fn meaning(self) -> &'static str {
        match self {
            Setting::SampleRate => "the sample rate",
            Setting::TimeUnit => "the time unit",
            Setting::TimeColumn => "the time column",
            Setting::MaxGridFactor => "the grid's limit",
            Setting::UnitOverride => "the unit override",
            Setting::ColumnScale => "the column's factor",
            Setting::Channels => "the channel choice",
            Setting::Topic => "the IMU topic",
            Setting::Instance => "the IMU instance",
            Setting::TempTopic => "the temperature topic",
            Setting::AllowPartial => "the choice to read a partial log",
            Setting::Overwrite => "the choice to overwrite",
            Setting::FitOrder => "the fit's order",
            Setting::FitFirmware => "the fit's firmware",
            Setting::RateTerm => "the dT/dt term",
            Setting::BinWidth => "the bin width",
            Setting::ExportFirmware => "the export's firmware",
            Setting::DeviceId => "the device id",
            Setting::CalibrationSlot => "the calibration slot",
            Setting::KalibrFile => "the Kalibr file",
            Setting::NavigationModel => "the navigation's compensation model",
        }
    }

    /// The setting given `value`.
    pub fn given(self, value: Value) -> Given {
        Given { setting: self, value }
    }
}

/// A setting's value, by its kind: a front end quotes text and not numbers.
#[derive(Debug, Clone, PartialEq)]
pub enum Value {
    /// A number, as given.
    Number(String),
    /// A word or name (`all`, `auto`, `px4`, a topic, `COLUMN=UNIT`).
    Text(String),
    /// Text that may hold spaces or brackets (a column's full header),
    /// which a shell needs quoted.
    Spaced(String),
    /// A stand-in for the value the user is to give (`N`, `HZ`).
    Placeholder(&'static str),
}

impl Value {
    /// A number, written as `Display` writes it.
    pub fn number(n: impl fmt::Display) -> Value {
        Value::Number(n.to_string())
    }

    /// A word or name.
    pub fn text(t: impl Into<String>) -> Value {
        Value::Text(t.into())
    }
}

impl fmt::Display for Value {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&naming().value(self))
    }
}

/// A setting with the value the user gave it (or is to give it).
#[derive(Debug, Clone, PartialEq)]
pub struct Given {
    /// The setting.
    pub setting: Setting,
    /// Its value.
    pub value: Value,
}

impl fmt::Display for Given {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&naming().given(self.setting, &self.value))
    }
}

impl fmt::Display for Setting {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&naming().name(*self))
    }
}

/// Settings left unset (`refit without the dT/dt term`), as a front end
/// says it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Without(pub &'static [Setting]);

impl fmt::Display for Without {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&naming().without(self.0))
    }
}

/// A new compensation fit with `given`, as the user would run it.
#[derive(Debug, Clone, PartialEq)]
pub struct FitCall(pub Given);

impl fmt::Display for FitCall {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&naming().fit_call(&self.0))
    }
}

/// How a front end names settings.
pub trait Naming: Sync + Send {
    /// The setting alone (`--rate`).
    fn name(&self, setting: Setting) -> String;

    /// A value alone, as it would be given (`auto`): by default as a
    /// shell takes it, text with spaces quoted.
    fn value(&self, value: &Value) -> String {
        match value {
            Value::Number(v) | Value::Text(v) => v.clone(),
            Value::Spaced(v) => format!("'{v}'"),
            Value::Placeholder(v) => (*v).to_string(),
        }
    }

    /// The setting given a value (`--rate 200`).
    fn given(&self, setting: Setting, value: &Value) -> String;

    /// The settings left unset (`without --instance and --device-id`).
    fn without(&self, settings: &[Setting]) -> String {
        let names: Vec<String> = settings.iter().map(|&s| self.name(s)).collect();
        format!("without {}", and_list(&names))
    }

    /// A compensation fit given one setting, as it is run
    /// (`` `imutherm tcal fit --for px4` ``).
    fn fit_call(&self, given: &Given) -> String;
}

/// `a`, `a and b`, `a, b and c`.
pub fn and_list(items: &[String]) -> String {
    match items {
        [] => String::new(),
        [one] => one.clone(),
        [init @ .., last] => format!("{} and {last}", init.join(", ")),
    }
}

/// Settings named by what they mean, for a program that installs no
/// naming of its own.
#[derive(Debug, Clone, Copy, Default)]
pub struct Meanings;

impl Naming for Meanings {
    fn name(&self, setting: Setting) -> String {
        setting.meaning().to_string()
    }

    fn given(&self, setting: Setting, value: &Value) -> String {
        format!("{} {}", setting.meaning(), self.value(value))
    }

    fn fit_call(&self, given: &Given) -> String {
        format!(
            "a compensation fit with {}",
            self.given(given.setting, &given.value)
        )
    }
}

static NAMING: OnceLock<&'static dyn Naming> = OnceLock::new();

/// Names settings `naming`'s way in every message rendered from now on in
/// this process. The first naming installed stays: a second call returns
/// false and changes nothing.
pub fn name_settings(naming: &'static dyn Naming) -> bool {
    NAMING.set(naming).is_ok()
}

/// The naming in effect: the front end's, or [`Meanings`].
pub fn naming() -> &'static dyn Naming {
    NAMING.get().copied().unwrap_or(&Meanings)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn without_a_front_end_a_setting_is_named_by_its_meaning() {
        // Library tests install no naming (one installed would hold for
        // every test of the process).
        assert_eq!(
            Setting::SampleRate.given(Value::number(-1.0)).to_string(),
            "the sample rate -1"
        );
        assert_eq!(Setting::Topic.to_string(), "the IMU topic");
        assert_eq!(
            Without(&[Setting::Instance, Setting::DeviceId]).to_string(),
            "without the IMU instance and the device id"
        );
        assert_eq!(
            FitCall(Setting::FitFirmware.given(Value::text("px4"))).to_string(),
            "a compensation fit with the fit's firmware px4"
        );
        assert_eq!(
            Setting::Channels.given(Value::Spaced("g x".into())).to_string(),
            "the channel choice 'g x'"
        );
    }

    #[test]
    fn every_setting_has_a_distinct_meaning() {
        let mut seen: Vec<&str> = Setting::ALL.iter().map(|s| s.meaning()).collect();
        seen.sort_unstable();
        seen.dedup();
        assert_eq!(seen.len(), Setting::ALL.len());
    }

    #[test]
    fn lists_read_as_prose() {
        let s = |v: &[&str]| and_list(&v.iter().map(|x| x.to_string()).collect::<Vec<_>>());
        assert_eq!(s(&[]), "");
        assert_eq!(s(&["a"]), "a");
        assert_eq!(s(&["a", "b"]), "a and b");
        assert_eq!(s(&["a", "b", "c"]), "a, b and c");
    }
}
