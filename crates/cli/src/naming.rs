//! The libraries' settings named as this program's flags: their messages
//! hold an [`imu::Setting`], and read `--rate 200` once [`install`] ran.

use imu::setting::{Given, Naming, Setting, Value};

/// The flags, as [`crate::args`] defines them.
struct Flags;

impl Naming for Flags {
    fn name(&self, setting: Setting) -> String {
        flag(setting).to_string()
    }

    fn given(&self, setting: Setting, value: &Value) -> String {
        format!("{} {}", flag(setting), self.value(value))
    }

    fn fit_call(&self, given: &Given) -> String {
        format!("`imutherm tcal fit {}`", self.given(given.setting, &given.value))
    }
}

fn flag(setting: Setting) -> &'static str {
    match setting {
        Setting::SampleRate => "--rate",
        Setting::TimeUnit => "--time-unit",
        Setting::TimeColumn => "--time-column",
        Setting::MaxGridFactor => "--max-grid-factor",
        Setting::UnitOverride => "--unit",
        Setting::ColumnScale => "--scale",
        Setting::Channels => "--channels",
        Setting::Topic => "--topic",
        Setting::Instance => "--instance",
        Setting::TempTopic => "--temp-topic",
        Setting::AllowPartial => "--allow-partial",
        Setting::Overwrite => "--overwrite",
        Setting::FitOrder => "--order",
        Setting::FitFirmware => "--for",
        Setting::RateTerm => "--rate-term",
        Setting::BinWidth => "--bin-width",
        Setting::ExportFirmware => "--export",
        Setting::DeviceId => "--device-id",
        Setting::CalibrationSlot => "--slot",
        Setting::KalibrFile => "--kalibr",
        Setting::NavigationModel => "--model",
    }
}

/// Names the settings as flags in every message from now on.
pub fn install() {
    imu::setting::name_settings(&Flags);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn settings_render_as_flags_with_their_values() {
        let f = Flags;
        assert_eq!(f.given(Setting::SampleRate, &Value::number(-1.0)), "--rate -1");
        assert_eq!(
            f.given(Setting::Channels, &Value::Spaced("gyro_x [rad/s]".into())),
            "--channels 'gyro_x [rad/s]'"
        );
        assert_eq!(f.value(&Value::text("auto")), "auto");
        assert_eq!(
            f.without(&[Setting::Instance, Setting::DeviceId]),
            "without --instance and --device-id"
        );
        assert_eq!(
            f.fit_call(&Setting::FitFirmware.given(Value::text("px4"))),
            "`imutherm tcal fit --for px4`"
        );
    }

    /// A flag renamed in `args` and not here would name a flag that does
    /// not exist.
    #[cfg(feature = "analysis")]
    #[test]
    fn every_setting_names_a_flag_the_program_has() {
        use clap::CommandFactory;
        fn longs(c: &clap::Command, out: &mut Vec<String>) {
            out.extend(
                c.get_arguments()
                    .filter_map(|a| a.get_long())
                    .map(|l| format!("--{l}")),
            );
            for sub in c.get_subcommands() {
                longs(sub, out);
            }
        }
        let mut all = Vec::new();
        longs(&crate::args::Cli::command(), &mut all);
        for s in Setting::ALL {
            assert!(all.iter().any(|l| l == flag(s)), "{s:?}: {} is no flag", flag(s));
        }
    }
}
