//! From the parsed command line to the libraries' options: the step from
//! the flags as typed ([`crate::args`], each value checked by
//! [`crate::flags`]) to what the readers and analyses take. It depends on
//! both; neither depends on it.

use crate::args::{DynamicArgs, FirmwareArg, ReadArgs};
use crate::flags::{Instance, UsageError};

impl ReadArgs {
    /// The shared read flags as the reader's options, checked.
    pub fn recording_options(&self) -> anyhow::Result<imu::RecordingOptions> {
        self.options(false)
    }

    /// The read flags of a command that takes `--instance all` (tcal fit
    /// and eval): with it, no instance is chosen here; the caller sets each.
    pub fn recording_options_any_instance(&self) -> anyhow::Result<imu::RecordingOptions> {
        self.options(true)
    }

    fn options(&self, all_allowed: bool) -> anyhow::Result<imu::RecordingOptions> {
        let checked = analysis::reading::recording_options(&analysis::reading::ReadingChoices {
            rate_hz: self.rate,
            // Parsed by the flag's value parser: passed on below as they are.
            units: Vec::new(),
            time_column: self.time_column.clone(),
            time_unit: self.time_unit.clone(),
            skip_bad_lines: self.skip_bad_lines,
            stream: imu::StreamChoice {
                topic: self.topic.clone(),
                instance: match self.instance {
                    None => None,
                    Some(Instance::One(n)) => Some(n),
                    Some(Instance::All) if all_allowed => None,
                    Some(Instance::All) => {
                        return Err(anyhow::Error::new(UsageError(
                                "--instance all: only tcal fit and tcal eval take every instance at once; give one number"
                                    .to_string(),
                            )));
                    }
                },
                temp_topic: self.temp_topic.clone(),
                first_if_several: false,
                allow_partial: self.allow_partial,
            },
            max_grid_factor: self.max_grid_factor.map(|f| f as usize),
        })?;
        Ok(imu::RecordingOptions {
            units: self.unit.clone(),
            scales: self.scale.clone(),
            ..checked
        })
    }
}

/// The firmware a `--firmware`, `--for` or `--export` flag names.
#[cfg(feature = "analysis")]
impl crate::args::PageUnitsArgs {
    /// The unit system the report crate draws in. Here, not beside the
    /// flag: the flags' definitions are also compiled into the command-line
    /// fuzz target, which does not link the report crate.
    pub fn units(&self) -> report::page_units::Units {
        use crate::args::PageUnits;
        use report::page_units::Units;
        match self.units {
            PageUnits::Si => Units::Si,
            PageUnits::Datasheet => Units::Datasheet,
            PageUnits::Thesis => Units::Thesis,
        }
    }
}

impl From<FirmwareArg> for thermal::firmware::Firmware {
    fn from(f: FirmwareArg) -> thermal::firmware::Firmware {
        match f {
            FirmwareArg::Px4 => thermal::firmware::Firmware::Px4,
            FirmwareArg::ArduPilot => thermal::firmware::Firmware::ArduPilot,
        }
    }
}

impl DynamicArgs {
    /// The dynamic ADEV's windows from `--dyn-window` and `--dyn-step`, the
    /// thesis's where not given.
    pub fn dynamic_options(&self) -> analysis::dynamic_adev::DynamicOptions {
        use analysis::dynamic_adev::{DEFAULT_STEP_S, DEFAULT_WINDOW_S, DynamicOptions};
        DynamicOptions {
            window_s: self.dyn_window.unwrap_or(DEFAULT_WINDOW_S),
            step_s: self.dyn_step.unwrap_or(DEFAULT_STEP_S),
            ..DynamicOptions::default()
        }
    }
}
