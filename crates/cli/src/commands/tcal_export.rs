//! `imutherm tcal export`: a model as a flight stack's parameter file.

use std::io::Write;

use anyhow::{Context, Result};

use imu::output::same_file;
use thermal::firmware::{Firmware, Target, export as export_params};
use thermal::tcal::Model;

use crate::args::TcalExportArgs;
use crate::args::usage_error;

pub fn run(a: &TcalExportArgs) -> Result<()> {
    // The one check that the output is not the model: a usage error,
    // before anything is read (so it is not repeated when the file is
    // written).
    if let Some(out) = &a.output
        && same_file(out, &a.model)
    {
        usage_error(format!("-o {}: that is the model being exported", out.display()));
    }
    let Some(firmware) = a.firmware else {
        return header(a);
    };
    let firmware = Firmware::from(firmware);
    if let Err(e) = analysis::compensation::check_instance(firmware, a.slot) {
        usage_error(e);
    }
    let model = Model::read(&a.model)?;
    if !model.instances.is_empty() && (a.slot.is_some() || a.device_id.is_some()) {
        usage_error(format!(
            "{} holds instances {:?}, each written to its own slot with the ids its log gave: export it without --slot and --device-id",
            a.model.display(),
            model
                .instances
                .iter()
                .filter_map(|m| m.instance)
                .collect::<Vec<_>>()
        ));
    }
    let target = Target {
        instance: a.slot,
        device_id: a.device_id,
    };
    let exported = export_params(&model, firmware, target)
        .with_context(|| format!("{}: cannot be written for {}", a.model.display(), firmware.name()))?;
    for w in &exported.warnings {
        eprintln!("warning: {w}");
    }
    emit(a, &exported.text, &format!("{} parameters", firmware.name()))
}

/// Writes `text` to `-o FILE` (saying so) or to standard output.
fn emit(a: &TcalExportArgs, text: &str, what: &str) -> Result<()> {
    match &a.output {
        Some(path) => {
            imu::output::write_file(
                path,
                text.as_bytes(),
                &imu::output::OutputPolicy {
                    overwrite: a.overwrite,
                    inputs: &[],
                },
            )?;
            eprintln!("wrote {} ({what})", path.display());
        }
        None => {
            let mut out = std::io::stdout().lock();
            out.write_all(text.as_bytes())?;
            out.flush()?;
        }
    }
    Ok(())
}

/// `--format c`: the model as a C header.
fn header(a: &TcalExportArgs) -> Result<()> {
    let model = Model::read(&a.model)?;
    let text = thermal::c_header::render(&model)
        .with_context(|| format!("{}: cannot be written as a C header", a.model.display()))?;
    emit(a, &text, "C header")
}
