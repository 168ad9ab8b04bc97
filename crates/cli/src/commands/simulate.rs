//! `imutherm simulate`: a recording whose truth is known.

use std::io::Write;
use std::path::PathBuf;

use anyhow::{Context, Result, bail};
use indicatif::{ProgressBar, ProgressStyle};

use imu::output::{AtomicFile, OutputPolicy};
use imusim::population::{self, Defect, Scatter};
use imusim::thermal::Profile;
use imusim::{SimConfig, Simulator, presets};

use crate::args::SimulateArgs;
use crate::flags::UsageError;

/// Values a simulated recording may hold without `--allow-large`: at about
/// 19 bytes a value, 2 GB of text (24 h at 100 Hz is 60 million). More is
/// far more often a slip (`--rate 1e9`) than a wish, and would fill a disk.
const MAX_VALUES: f64 = 1e8;
/// Columns of a simulated log: ax, ay, az, gx, gy, gz, temperature.
const LOG_COLUMNS: f64 = 7.0;

fn configuration(a: &SimulateArgs) -> Result<(SimConfig, String)> {
    let (mut cfg, source) = match (&a.config, &a.preset) {
        (Some(path), _) => {
            let text =
                std::fs::read_to_string(path).with_context(|| format!("reading {}", path.display()))?;
            let mut cfg = SimConfig::from_toml(&text).with_context(|| path.display().to_string())?;
            // A profile file named in a configuration is found beside it,
            // wherever imutherm runs from.
            if let Profile::File { path: profile } = &mut cfg.profile
                && profile.is_relative()
                && let Some(dir) = path.parent()
            {
                *profile = dir.join(&*profile);
            }
            (cfg, format!("config {}", path.display()))
        }
        (None, p) => {
            let name = p.as_deref().unwrap_or("mpu9250-thesis");
            (presets::preset(name)?, name.to_string())
        }
    };
    if let Some(p) = &a.profile {
        // A profile on the command line is a flag: a bad one is a usage error.
        cfg.profile = Profile::parse(p).map_err(|e| UsageError(format!("--profile: {e}")))?;
    }
    if let Some(d) = a.duration {
        cfg.duration_s = d;
    }
    if let Some(r) = a.rate {
        cfg.rate_hz = r;
    }
    if let Some(s) = a.seed {
        cfg.seed = s;
    }
    cfg.validate()?;
    if let Some(id) = &a.unit_id {
        let (scatter, defect) = population_flags(a)?;
        cfg = population::draw(&cfg, id, scatter, defect.as_ref())
            .map_err(|e| UsageError(format!("--unit-id: {e}")))?;
    }
    Ok((cfg, source))
}

/// --scatter and --defect, read as flags: a bad one is a usage error.
fn population_flags(a: &SimulateArgs) -> Result<(Scatter, Option<Defect>)> {
    let scatter = Scatter::parse(&a.scatter).map_err(|e| UsageError(format!("--scatter: {e}")))?;
    let defect = a
        .defect
        .as_deref()
        .map(Defect::parse)
        .transpose()
        .map_err(|e| UsageError(format!("--defect: {e}")))?;
    Ok((scatter, defect))
}

pub fn run(a: &SimulateArgs) -> Result<()> {
    let (cfg, source) = configuration(a)?;
    if a.print_config {
        let text = toml::to_string(&cfg).context("writing the configuration")?;
        let mut out = std::io::stdout().lock();
        out.write_all(text.as_bytes())
            .and_then(|()| out.flush())
            .context("writing the configuration to standard output")?;
        return Ok(());
    }
    let Some(out) = &a.output else {
        bail!("give an output file with -o FILE");
    };
    // A log of no samples is a file no command can read: the duration or
    // rate asked for is the mistake, said before anything is written.
    if cfg.samples() == 0 {
        return Err(UsageError(format!(
            "{} s at {} Hz is less than one sample: give a longer --duration or a higher --rate",
            cfg.duration_s, cfg.rate_hz
        ))
        .into());
    }
    let values = cfg.duration_s * cfg.rate_hz * LOG_COLUMNS;
    if values > MAX_VALUES && !a.allow_large {
        return Err(UsageError(format!(
            "{} s at {} Hz is {:.3e} samples × {LOG_COLUMNS} columns = {values:.3e} values (about {:.0} GB); \
             more than {MAX_VALUES:.0e} is refused as a likely mistake: pass --allow-large to write it",
            cfg.duration_s,
            cfg.rate_hz,
            cfg.duration_s * cfg.rate_hz,
            values * 19e-9,
        ))
        .into());
    }
    let sim = Simulator::new(cfg)?;
    let total = sim.config().samples();
    let bar = ProgressBar::new(total).with_style(
        ProgressStyle::with_template("{spinner} simulating [{bar:40}] {pos}/{len} samples, {eta} left")
            .unwrap_or_else(|_| ProgressStyle::default_bar())
            .progress_chars("=> "),
    );
    let started = std::time::Instant::now();
    // The configuration file and a profile file are the inputs.
    let mut inputs: Vec<PathBuf> = a.config.iter().cloned().collect();
    if let Profile::File { path } = &sim.config().profile {
        inputs.push(path.clone());
    }
    // Written to a scratch file of its own and renamed at the end, so that an
    // interrupted run never leaves a log that looks complete.
    let mut file = AtomicFile::create(
        out,
        &OutputPolicy {
            overwrite: a.overwrite,
            inputs: &inputs,
        },
    )?;
    let mut meta = sim.metadata(Some(&source));
    if let Some(id) = &a.unit_id {
        let (scatter, defect) = population_flags(a)?;
        for (k, v) in population::describe(id, scatter, defect.as_ref()) {
            meta.set(k, v);
        }
    }
    let written = sim
        .write_log(&mut file, &meta, |done, _| bar.set_position(done))
        .with_context(|| format!("writing {}", out.display()));
    bar.finish_and_clear();
    let rows = written?;
    file.commit()?;
    let c = sim.config();
    eprintln!(
        "wrote {}: {rows} samples, {} s at {} Hz, {} ({}), in {:.2} s",
        out.display(),
        c.duration_s,
        c.rate_hz,
        c.profile.describe(),
        source,
        started.elapsed().as_secs_f64()
    );
    Ok(())
}
