//! `imutherm tcal export`: a model as a flight stack's parameter file.

use std::io::Write;

use anyhow::{Context, Result};
use clap::CommandFactory;
use clap::error::ErrorKind;

use thermal::firmware::{Firmware, Target, export as export_params};

use crate::args::{Cli, FirmwareArg, TcalExportArgs};
use crate::commands::run_identity::same_file;
use crate::commands::tcal::load;

impl From<FirmwareArg> for Firmware {
    fn from(f: FirmwareArg) -> Firmware {
        match f {
            FirmwareArg::Px4 => Firmware::Px4,
            FirmwareArg::ArduPilot => Firmware::ArduPilot,
        }
    }
}

/// Ends the program as a usage error (status 2), as clap does for a bad
/// flag: for what only becomes wrong in combination with another flag.
pub fn usage_error(message: impl std::fmt::Display) -> ! {
    Cli::command().error(ErrorKind::ValueValidation, message).exit()
}

/// Refuses a calibration slot the firmware does not have.
pub fn check_instance(firmware: Firmware, instance: Option<u8>) {
    if let Some(n) = instance {
        let range = firmware.instances();
        if !range.contains(&n) {
            usage_error(format!(
                "--instance {n}: {} has calibration instances {} to {}",
                firmware.name(),
                range.start(),
                range.end()
            ));
        }
    }
}

pub fn run(a: &TcalExportArgs) -> Result<()> {
    let firmware = Firmware::from(a.firmware);
    check_instance(firmware, a.instance);
    if let Some(out) = &a.output
        && same_file(out, &a.model)
    {
        usage_error(format!("-o {}: that is the model being exported", out.display()));
    }
    let model = load(&a.model)?;
    let target = Target {
        instance: a.instance,
        device_id: a.device_id,
    };
    let exported = export_params(&model, firmware, target)
        .with_context(|| format!("{}: cannot be written for {}", a.model.display(), firmware.name()))?;
    for w in &exported.warnings {
        eprintln!("warning: {w}");
    }
    match &a.output {
        Some(path) => {
            imu::output::write_file(
                path,
                exported.text.as_bytes(),
                &imu::output::OutputPolicy {
                    overwrite: a.overwrite,
                    inputs: std::slice::from_ref(&a.model),
                },
            )?;
            eprintln!("wrote {} ({} parameters)", path.display(), firmware.name());
        }
        None => {
            let mut out = std::io::stdout().lock();
            out.write_all(exported.text.as_bytes())?;
            out.flush()?;
        }
    }
    Ok(())
}
