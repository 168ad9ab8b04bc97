//! `imutherm tcal export`: a model as a flight stack's parameter file.

use std::io::Write;
use std::path::Path;

use anyhow::{Context, Result, bail};
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
            write_new_file(path, exported.text.as_bytes(), a.overwrite)?;
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

/// Writes `bytes` to `path` whole or not at all: into a temporary file
/// beside it, synced, then moved into place. An existing `path` is refused
/// unless `overwrite`; without it the final step is a hard link, which
/// fails rather than replace a file that appeared meanwhile.
fn write_new_file(path: &Path, bytes: &[u8], overwrite: bool) -> Result<()> {
    if !overwrite && path.exists() {
        bail!("{}: exists (--overwrite to replace it)", path.display());
    }
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    let name = path
        .file_name()
        .with_context(|| format!("{}: not a file name", path.display()))?;
    let tmp = dir.join(format!(
        ".{}.{}.partial",
        name.to_string_lossy(),
        std::process::id()
    ));
    let result = (|| -> std::io::Result<()> {
        let mut f = std::fs::OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(&tmp)?;
        f.write_all(bytes)?;
        f.sync_all()?;
        if overwrite {
            std::fs::rename(&tmp, path)
        } else {
            std::fs::hard_link(&tmp, path)?;
            std::fs::remove_file(&tmp)
        }
    })();
    if let Err(e) = result {
        let _ = std::fs::remove_file(&tmp);
        return Err(e).with_context(|| format!("writing {}", path.display()));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_existing_file_is_kept_unless_overwrite() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("x.params");
        write_new_file(&p, b"one\n", false).unwrap();
        let e = write_new_file(&p, b"two\n", false).unwrap_err();
        assert!(e.to_string().contains("exists"), "{e}");
        assert_eq!(std::fs::read_to_string(&p).unwrap(), "one\n");
        write_new_file(&p, b"two\n", true).unwrap();
        assert_eq!(std::fs::read_to_string(&p).unwrap(), "two\n");
        // No temporary file is left beside it.
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
    }

    #[test]
    fn a_failed_write_leaves_nothing() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("missing-dir").join("x.params");
        assert!(write_new_file(&p, b"one\n", false).is_err());
        assert!(!p.exists());
    }
}
