//! `imutherm tcal export`: a model as a flight stack's parameter file.

use std::io::Write;

use anyhow::{Context, Result};

use imu::output::same_file;
use thermal::firmware::{Firmware, Target, export as export_params};
use thermal::tcal::Model;

use crate::args::TcalExportArgs;
use crate::args::usage_error;

pub fn run(a: &TcalExportArgs) -> Result<()> {
    let firmware = Firmware::from(a.firmware);
    if let Err(e) = analysis::compensation::check_instance(firmware, a.instance) {
        usage_error(e);
    }
    // The one check that the output is not the model: a usage error,
    // before anything is read (so it is not repeated when the file is
    // written).
    if let Some(out) = &a.output
        && same_file(out, &a.model)
    {
        usage_error(format!("-o {}: that is the model being exported", out.display()));
    }
    let model = Model::read(&a.model)?;
    if !model.instances.is_empty() && (a.instance.is_some() || a.device_id.is_some()) {
        usage_error(format!(
            "{} holds instances {:?}, each written to its own slot with the ids its log gave: export it without --instance and --device-id",
            a.model.display(),
            model
                .instances
                .iter()
                .filter_map(|m| m.instance)
                .collect::<Vec<_>>()
        ));
    }
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
                    inputs: &[],
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
