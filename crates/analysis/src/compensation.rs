//! The temperature compensation of `imutherm tcal` as values: the runs a
//! fit reads, the checks before it, the model with its provenance, the
//! firmware's own view of an exported parameter file, and the evaluation
//! document (`imutherm.tcal-eval/1`). The command line and the Python
//! package both call these, so a model or an evaluation is the same bytes
//! from either.

use std::path::{Path, PathBuf};

use imu::{RecordingOptions, Setting, Value};

use serde::Serialize;
use thermal::evaluation::{BinMean, SliceMinimum, bin_means, level, spread, surface_minima};
use thermal::firmware::verdict::{self, RunFacts};
use thermal::firmware::{self, Calibration, Firmware, Sensor, Target, sensor_axis};
use thermal::tcal::{FitOptions, Model, Order, Run, TcalChannel};

use crate::AnalysisError;
use crate::selection::{Selection, read_channels_digested};

/// Most averaging bins a fit is asked for: 0.1 °C bins over 100 °C. Finer
/// bins hold a sample or two each, and the cross-validation over them would
/// run for hours; refused before the fit starts.
pub const MAX_FIT_BINS: f64 = 1000.0;

/// Width of the temperature slices whose ADEV minimum the evaluation
/// shows, °C.
pub const EVAL_SLICE_C: f64 = 5.0;

/// The channels of one run and its temperature, which is not compensated.
pub struct RunData {
    /// The channels to fit or evaluate (the temperature taken out).
    pub selection: Selection,
    /// The temperature, °C, one per sample.
    pub temp: Vec<f64>,
    /// The digest of the run's bytes ([`crate::file_identity::digest`]),
    /// which a model keeps to know its fitted runs by.
    pub digest: String,
}

impl RunData {
    /// Reads the `wanted` channels and the temperature of the run in
    /// `file`, its digest taken from the same read: the file is opened
    /// once, and may be a pipe.
    pub fn read(file: &Path, wanted: &[String], read: &RecordingOptions) -> Result<RunData, AnalysisError> {
        let (selection, digest) = read_channels_digested(file, wanted, read)?;
        RunData::new(file, selection, digest)
    }

    /// [`RunData::read`] of each IMU instance `pick` asks, from one open
    /// and one decode of the file
    /// ([`crate::selection::read_channels_digested_each`]).
    pub fn read_each(
        file: &Path,
        wanted: &[String],
        read: &RecordingOptions,
        pick: &imu::InstancePick,
    ) -> Result<Vec<(Option<u32>, RunData)>, AnalysisError> {
        let (each, digest) = crate::selection::read_channels_digested_each(file, wanted, read, pick)?;
        each.into_iter()
            .map(|(n, selection)| Ok((n, RunData::new(file, selection, digest.clone())?)))
            .collect()
    }

    /// Splits the temperature off channels read from `file`, whose bytes
    /// have `digest`.
    pub fn new(file: &Path, mut selection: Selection, digest: String) -> Result<RunData, AnalysisError> {
        let Some(temp) = selection.temperature.take() else {
            return Err(AnalysisError::MissingChannel {
                file: file.to_path_buf(),
                what: "no temperature channel to fit against".to_string(),
            });
        };
        selection
            .channels
            .retain(|c| c.quantity != imu::Quantity::Temperature);
        Ok(RunData {
            selection,
            temp,
            digest,
        })
    }
}

/// The fit's settings, as `tcal fit`'s flags give them.
#[derive(Debug, Clone, Copy)]
pub struct FitRequest {
    /// The polynomial order, or auto.
    pub order: Order,
    /// The reference temperature, °C; the runs' middle when `None`.
    pub t_ref_c: Option<f64>,
    /// The averaging bins' width, °C.
    pub bin_width_c: f64,
    /// Whether a dT/dt term is fitted.
    pub rate_term: bool,
    /// The firmware the model is for (`--for`): its cubic limits the order,
    /// and the model is exported once to check it can be.
    pub firmware: Option<Firmware>,
}

impl FitRequest {
    /// Refuses an order the firmware cannot evaluate, before anything is
    /// read.
    pub fn check(&self) -> Result<(), AnalysisError> {
        if let (Some(firmware), Order::Fixed(order)) = (self.firmware, self.order)
            && order > Firmware::MAX_ORDER
        {
            return Err(AnalysisError::OrderForFirmware { order, firmware });
        }
        Ok(())
    }
}

/// A fitted model and what its export for the requested firmware warns of.
pub struct Fitted {
    /// The model, its fitted runs (names and digests) and device id set.
    pub model: Model,
    /// The export's warnings (range beyond the documented one, missing
    /// axes); the placeholder-id warning is left to `tcal export`.
    pub export_warnings: Vec<String>,
}

/// Fits a model on `runs`, read from `files` in the same order.
pub fn fit(files: &[PathBuf], runs: &[RunData], req: &FitRequest) -> Result<Fitted, AnalysisError> {
    req.check()?;
    let digests = distinct_runs(files, runs.iter().map(|r| r.digest.clone()).collect())?;
    check_bins(runs.iter().map(|r| r.temp.as_slice()), req.bin_width_c)?;
    let columns: Vec<Vec<TcalChannel>> = runs
        .iter()
        .map(|r| {
            r.selection
                .channels
                .iter()
                .map(|c| TcalChannel::new(c.name.clone(), c.unit.clone(), &c.data))
                .collect()
        })
        .collect();
    let fit_runs: Vec<Run> = runs
        .iter()
        .zip(&columns)
        .map(|(r, cols)| Run {
            channels: cols,
            temp: &r.temp,
            rate_hz: r.selection.rate_hz,
        })
        .collect();
    let opts = FitOptions {
        order: req.order,
        t_ref_c: req.t_ref_c,
        bin_width_c: req.bin_width_c,
        rate_term: req.rate_term,
        max_auto_order: match req.firmware {
            Some(_) => Firmware::MAX_ORDER,
            None => thermal::tcal::MAX_AUTO_ORDER,
        },
        dynamics: true,
        firmware_projection: req.firmware.is_some(),
    };
    let names: Vec<String> = files.iter().map(|f| f.display().to_string()).collect();
    let mut model = thermal::tcal::fit(&fit_runs, &opts).map_err(|cause| AnalysisError::Compensation {
        context: names.join(", "),
        cause,
    })?;
    model.fitted_on = names;
    model.fitted_on_digests = digests;
    // The ids every run agrees on: PX4 applies a set only to the sensor
    // whose device id it names.
    let agreed = |id: fn(&RunData) -> Option<u32>| {
        let first = runs.first().and_then(id)?;
        runs.iter().all(|r| id(r) == Some(first)).then_some(first)
    };
    // A text log's `# device_id:` is among them (`DeviceIds::of`).
    let gyro = agreed(|r| r.selection.device_ids.gyro);
    let accel = agreed(|r| r.selection.device_ids.accel);
    model.device_id = gyro;
    model.accel_device_id = accel.filter(|a| Some(*a) != gyro);
    // A model fitted for a firmware is checked against its export now: its
    // warnings come at the fit, not at the vehicle.
    let export_warnings = match req.firmware {
        Some(fw) => {
            firmware::export(&model, fw, Target::default())
                .map_err(|cause| AnalysisError::Firmware {
                    context: format!("the fit cannot be written for {}", fw.name()),
                    cause,
                })?
                .warnings
        }
        None => Vec::new(),
    };
    let export_warnings = export_warnings
        .into_iter()
        .filter(|w| !w.contains("placeholder"))
        .collect();
    Ok(Fitted {
        model,
        export_warnings,
    })
}

/// The digests of the runs in `files`, checked: one run given twice (by
/// two names, or as a copy) would count twice, and is refused.
pub fn distinct_runs(files: &[PathBuf], digests: Vec<String>) -> Result<Vec<String>, AnalysisError> {
    for (i, f) in files.iter().enumerate() {
        if let Some(j) = (0..i).find(|&j| digests[j] == digests[i] || imu::output::same_file(&files[j], f)) {
            return Err(AnalysisError::SameRecording {
                first: files[j].clone(),
                second: f.clone(),
            });
        }
    }
    Ok(digests)
}

/// Refuses a bin width that would make more than [`MAX_FIT_BINS`] bins over
/// the runs' temperatures.
pub fn check_bins<'a>(temps: impl Iterator<Item = &'a [f64]>, width: f64) -> Result<(), AnalysisError> {
    let (lo, hi) = temps
        .flatten()
        .filter(|t| t.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &t| {
            (a.min(t), b.max(t))
        });
    let bins = ((hi - lo) / width).floor() + 1.0;
    if bins > MAX_FIT_BINS {
        return Err(AnalysisError::TooManyBins { width, lo, hi, bins });
    }
    Ok(())
}

/// Whether the run read from `file`, whose bytes have `digest`, is one the
/// model was fitted on: the same bytes (the model keeps a digest of each
/// fitted run), whatever its name. A model from before digests were kept
/// falls back to the file itself (device and inode) or, failing that, its
/// name.
pub fn was_fitted_on(model: &Model, file: &Path, digest: &str) -> bool {
    if !model.fitted_on_digests.is_empty() {
        return model.fitted_on_digests.iter().any(|d| d == digest);
    }
    model
        .fitted_on
        .iter()
        .any(|f| Path::new(f) == file || imu::output::same_file(Path::new(f), file))
}

/// An exported parameter file and the firmware's view of it.
pub struct AsLoaded {
    /// The firmware.
    pub firmware: Firmware,
    /// The parameter file's text.
    pub text: String,
    /// The export's warnings (none for a file given).
    pub warnings: Vec<String>,
    /// The file as the firmware loads it.
    pub calibration: Calibration,
    /// ArduPilot's INS_ACCn_CALTEMP / INS_GYRn_CALTEMP for the evaluation.
    pub cal_temp_c: f64,
    /// The slot `calibration` holds; the firmware's first when `None`.
    pub slot: Option<u8>,
}

/// The parameter file at `params`, or the model exported for `firmware`,
/// read back as the ground station loads it, so that what is evaluated is
/// the file, float32 rounding included, not the model.
pub fn as_loaded(
    model: &Model,
    firmware: Firmware,
    params: Option<&Path>,
) -> Result<AsLoaded, AnalysisError> {
    let (text, warnings) = match params {
        Some(path) => (
            std::fs::read_to_string(path).map_err(|cause| AnalysisError::File {
                path: path.to_path_buf(),
                cause,
            })?,
            Vec::new(),
        ),
        None => {
            let exported = firmware::export(model, firmware, Target::default()).map_err(|cause| {
                AnalysisError::Firmware {
                    context: format!(
                        "{}: the model cannot be written for it",
                        Setting::ExportFirmware.given(Value::text(firmware.key()))
                    ),
                    cause,
                }
            })?;
            (exported.text, exported.warnings)
        }
    };
    let calibration = firmware::load(firmware, &text, None).map_err(|cause| AnalysisError::Firmware {
        context: match params {
            Some(p) => format!(
                "{}: not a {} parameter file imutherm can apply",
                p.display(),
                firmware.name()
            ),
            None => format!(
                "{}: the written file does not load",
                Setting::ExportFirmware.given(Value::text(firmware.key()))
            ),
        },
        cause,
    })?;
    Ok(AsLoaded {
        firmware,
        text,
        warnings,
        calibration,
        cal_temp_c: model.t_ref_c,
        slot: None,
    })
}

/// What the firmware does with the parameter file on one run, in words.
#[derive(Debug, Clone, Serialize)]
pub struct FileVerdict {
    /// Whether any sensor of the run gets a correction.
    pub applies: bool,
    /// The run, as named.
    pub file: String,
    /// The log's IMU instance judged, for a model of several.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub instance: Option<u32>,
    /// One sentence per sensor type, and notes.
    pub says: Vec<String>,
}

/// Judges the parameter file of `loaded` on the run read from `file` as
/// the firmware would: its ENABLE flags, its ids against the recording's,
/// its TMIN/TMAX against the run's temperatures.
pub fn judge(loaded: &AsLoaded, file: &Path, run: &RunData) -> Result<FileVerdict, AnalysisError> {
    let sensors: Vec<Sensor> = run
        .selection
        .channels
        .iter()
        .filter_map(|c| sensor_axis(&c.name).map(|(s, _)| s))
        .collect();
    let (lo, hi) = run
        .temp
        .iter()
        .filter(|t| t.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &t| {
            (a.min(t), b.max(t))
        });
    let facts = RunFacts {
        gyro_id: run.selection.device_ids.gyro,
        accel_id: run.selection.device_ids.accel,
        has_gyro: sensors.contains(&Sensor::Gyro),
        has_accel: sensors.contains(&Sensor::Accel),
        t_range_c: [lo, hi],
    };
    let v = verdict::judge(loaded.firmware, &loaded.text, loaded.slot, &facts).map_err(|cause| {
        AnalysisError::Firmware {
            context: format!("judging the {} parameter file", loaded.firmware.name()),
            cause,
        }
    })?;
    Ok(FileVerdict {
        applies: v.applies,
        file: file.display().to_string(),
        instance: None,
        says: v.says,
    })
}

impl AsLoaded {
    /// The same file as the firmware applies it to the run read from
    /// `file`: on PX4, the set whose id is the run's gyro's, where one is
    /// (`set_sensor_id`); else the slot already loaded.
    pub fn for_run(&self, file: &Path, run: &RunData) -> Result<Option<AsLoaded>, AnalysisError> {
        let (Firmware::Px4, Some(id)) = (self.firmware, run.selection.device_ids.gyro) else {
            return Ok(None);
        };
        let context = || format!("{}: the PX4 set for its gyro", file.display());
        let firmware_error = |cause| AnalysisError::Firmware {
            context: context(),
            cause,
        };
        let Some(slot) = verdict::px4_gyro_slot(&self.text, id).map_err(firmware_error)? else {
            return Ok(None);
        };
        let calibration = firmware::load(self.firmware, &self.text, Some(slot)).map_err(firmware_error)?;
        Ok(Some(AsLoaded {
            firmware: self.firmware,
            text: self.text.clone(),
            warnings: self.warnings.clone(),
            calibration,
            cal_temp_c: self.cal_temp_c,
            slot: Some(slot),
        }))
    }

    /// The same file for the log's IMU instance `instance` of a model of
    /// several: the slot the export gives it (PX4 `TC_x{n}`, ArduPilot
    /// `INS_TCAL{n+1}`, the firmware's IMU order), with the instance's own
    /// calibration temperature.
    pub fn for_instance(&self, model: &Model) -> Result<AsLoaded, AnalysisError> {
        let number = model.instance.unwrap_or(0);
        let slot = match self.firmware {
            Firmware::Px4 => number,
            Firmware::ArduPilot => number.saturating_add(1),
        };
        let slot = u8::try_from(slot).unwrap_or(u8::MAX);
        let calibration = firmware::load(self.firmware, &self.text, Some(slot)).map_err(|cause| {
            AnalysisError::Firmware {
                context: format!("instance {number}: its {} set", self.firmware.name()),
                cause,
            }
        })?;
        Ok(AsLoaded {
            firmware: self.firmware,
            text: self.text.clone(),
            warnings: Vec::new(),
            calibration,
            cal_temp_c: model.t_ref_c,
            slot: Some(slot),
        })
    }
}

/// Refuses a calibration slot the firmware does not have.
pub fn check_instance(firmware: Firmware, instance: Option<u8>) -> Result<(), AnalysisError> {
    match instance {
        Some(instance) if !firmware.instances().contains(&instance) => {
            Err(AnalysisError::Instance { instance, firmware })
        }
        _ => Ok(()),
    }
}

/// `tcal eval --json`'s document, `imutherm.tcal-eval/1`. The fields are in
/// the order of their names, as the document has always been written.
#[derive(Debug, Clone, Serialize)]
pub struct EvalDocument {
    /// The firmware's view, with `--export`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub firmware: Option<FirmwareView>,
    /// The model file, as named.
    pub model: String,
    /// One row per file and channel.
    pub rows: Vec<EvalRow>,
    /// `imutherm.tcal-eval/1`.
    pub schema: &'static str,
}

/// The parameter file evaluated and what its export warned of.
#[derive(Debug, Clone, Serialize)]
pub struct FirmwareView {
    /// The CALTEMP the evaluation used (ArduPilot only, else null).
    pub cal_temp_c: Option<f64>,
    /// `px4` or `ardupilot`.
    pub name: &'static str,
    /// The parameter file's text.
    pub parameters: String,
    /// What the firmware does with the file on each run.
    pub verdicts: Vec<FileVerdict>,
    /// The export's warnings.
    pub warnings: Vec<String>,
}

/// One channel of one file, before and after the compensation.
#[derive(Debug, Clone, Serialize)]
pub struct EvalRow {
    /// σ_min per [`EVAL_SLICE_C`] slice, compensated.
    pub adev_minimum_over_temperature_after: Vec<Minimum>,
    /// σ_min per slice, as recorded.
    pub adev_minimum_over_temperature_before: Vec<Minimum>,
    /// Largest deviation of the 1 °C bin means, compensated.
    pub bias_max_after: f64,
    /// The same, as the firmware applies the parameter file.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub bias_max_as_loaded: Option<f64>,
    /// The same, as recorded.
    pub bias_max_before: f64,
    /// RMS deviation of the bin means, compensated.
    pub bias_rms_after: f64,
    /// The same, as the firmware applies the parameter file.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub bias_rms_as_loaded: Option<f64>,
    /// The same, as recorded.
    pub bias_rms_before: f64,
    /// The bin means, compensated.
    pub bins_after: Vec<Bin>,
    /// The bin means as the firmware applies the parameter file.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub bins_as_loaded: Option<Vec<Bin>>,
    /// The bin means, as recorded.
    pub bins_before: Vec<Bin>,
    /// The channel.
    pub channel: String,
    /// The file, as named.
    pub file: String,
    /// Whether the model was fitted on other runs than this.
    pub held_out: bool,
    /// The log's IMU instance, for a model of several.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub instance: Option<u32>,
    /// Mean of the bin means as the firmware applies the parameter file.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub level_as_loaded: Option<f64>,
    /// Mean of the bin means as recorded (with the firmware's view only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub level_before: Option<f64>,
    /// Samples outside the fitted range, compensated at its edge.
    pub samples_out_of_range: usize,
    /// The channel's unit.
    pub unit: String,
}

/// A bin's mean temperature and mean with its 95 % interval.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct Bin {
    /// Upper end of the 95 % interval.
    pub hi: f64,
    /// Lower end.
    pub lo: f64,
    /// Mean of the bin's samples.
    pub mean: f64,
    /// Mean temperature of the bin's samples, °C.
    pub t_c: f64,
}

/// A slice's ADEV minimum.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct Minimum {
    /// σ_min.
    pub sigma_min: f64,
    /// Mean temperature of the slice, °C.
    pub t_c: f64,
    /// Its τ, s (null where the slice has none).
    pub tau: f64,
}

fn bins(b: &[BinMean]) -> Vec<Bin> {
    b.iter()
        .map(|b| Bin {
            hi: b.mean + 1.96 * b.se,
            lo: b.mean - 1.96 * b.se,
            mean: b.mean,
            t_c: b.t,
        })
        .collect()
}

fn minima(m: &[SliceMinimum]) -> Vec<Minimum> {
    m.iter()
        .map(|m| Minimum {
            sigma_min: m.sigma_min,
            t_c: m.t_c,
            tau: m.tau,
        })
        .collect()
}

/// The evaluation's rows for one run read from `file`.
pub fn eval_rows(
    model: &Model,
    file: &Path,
    run: RunData,
    loaded: Option<&AsLoaded>,
) -> Result<Vec<EvalRow>, AnalysisError> {
    let held_out = !was_fitted_on(model, file, &run.digest);
    let RunData { selection, temp, .. } = run;
    let mut rows = Vec::with_capacity(selection.channels.len());
    for ch in selection.channels {
        let mut comp = ch.data.clone();
        let report = model
            .apply(&ch.name, &mut comp, &temp, selection.rate_hz)
            .map_err(AnalysisError::Model)?;
        let before = bin_means(&ch.data, &temp, 2);
        let after = bin_means(&comp, &temp, 2);
        let as_loaded = match (loaded, sensor_axis(&ch.name)) {
            (Some(l), Some((sensor, axis))) => {
                let corrected: Vec<f64> = ch
                    .data
                    .iter()
                    .zip(&temp)
                    .map(|(&x, &t)| l.calibration.correct(sensor, axis, x, t, l.cal_temp_c))
                    .collect();
                Some(bin_means(&corrected, &temp, 2))
            }
            _ => None,
        };
        let (sb, sa) = (spread(&before), spread(&after));
        let sl = as_loaded.as_deref().map(spread);
        rows.push(EvalRow {
            adev_minimum_over_temperature_after: minima(&surface_minima(
                &comp,
                &temp,
                selection.rate_hz,
                EVAL_SLICE_C,
            )),
            adev_minimum_over_temperature_before: minima(&surface_minima(
                &ch.data,
                &temp,
                selection.rate_hz,
                EVAL_SLICE_C,
            )),
            bias_max_after: sa.max,
            bias_max_as_loaded: sl.map(|s| s.max),
            bias_max_before: sb.max,
            bias_rms_after: sa.rms,
            bias_rms_as_loaded: sl.map(|s| s.rms),
            bias_rms_before: sb.rms,
            bins_after: bins(&after),
            bins_as_loaded: as_loaded.as_deref().map(bins),
            bins_before: bins(&before),
            channel: ch.name,
            file: file.display().to_string(),
            held_out,
            instance: model.instance,
            level_as_loaded: as_loaded.as_deref().map(level),
            level_before: as_loaded.is_some().then(|| level(&before)),
            samples_out_of_range: report.out_of_range,
            unit: ch.unit,
        });
    }
    Ok(rows)
}

impl EvalDocument {
    /// The document of `rows` for the model named `model`.
    pub fn new(
        model: &str,
        rows: Vec<EvalRow>,
        loaded: Option<&AsLoaded>,
        verdicts: Vec<FileVerdict>,
    ) -> EvalDocument {
        EvalDocument {
            firmware: loaded.map(|l| FirmwareView {
                cal_temp_c: matches!(l.firmware, Firmware::ArduPilot).then_some(l.cal_temp_c),
                name: l.firmware.key(),
                parameters: l.text.clone(),
                verdicts,
                warnings: l.warnings.clone(),
            }),
            model: model.to_string(),
            rows,
            schema: "imutherm.tcal-eval/1",
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bins_beyond_the_limit_are_refused_with_their_count() {
        // 0 to 999.5 °C in 1 °C bins: floor(999.5) + 1 = 1000, the limit.
        check_bins([&[0.0, 999.5][..]].into_iter(), 1.0).unwrap();
        let err = check_bins([&[0.0][..], &[1000.5][..]].into_iter(), 1.0).unwrap_err();
        assert!(
            matches!(err, AnalysisError::TooManyBins { bins, .. } if bins == 1001.0),
            "{err}"
        );
        // NaN temperatures (gaps) do not widen the range.
        check_bins([&[0.0, f64::NAN, 999.5][..]].into_iter(), 1.0).unwrap();
    }

    #[test]
    fn an_order_above_the_firmware_cubic_is_refused_before_reading() {
        let req = FitRequest {
            order: Order::Fixed(4),
            t_ref_c: None,
            bin_width_c: 1.0,
            rate_term: false,
            firmware: Some(Firmware::Px4),
        };
        let err = req.check().unwrap_err().to_string();
        assert_eq!(
            err,
            "the fit's order 4 the fit's firmware px4: PX4 evaluates a cubic at most (the fit's order 3 or auto)"
        );
        assert!(
            FitRequest {
                firmware: None,
                ..req
            }
            .check()
            .is_ok()
        );
    }

    #[test]
    fn a_copy_of_a_run_is_the_same_recording() {
        let dir = tempfile::tempdir().unwrap();
        let (a, b, c) = (dir.path().join("a"), dir.path().join("b"), dir.path().join("c"));
        std::fs::write(&a, "gyro_x,temperature\n1,20\n").unwrap();
        std::fs::write(&b, "gyro_x,temperature\n1,21\n").unwrap();
        std::fs::copy(&a, &c).unwrap();
        let digests = |files: &[PathBuf]| -> Vec<String> {
            files
                .iter()
                .map(|f| crate::file_identity::digest(f).unwrap())
                .collect()
        };
        let two = [a.clone(), b.clone()];
        assert_eq!(distinct_runs(&two, digests(&two)).unwrap().len(), 2);
        let three = [a.clone(), b, c.clone()];
        let err = distinct_runs(&three, digests(&three)).unwrap_err();
        assert!(
            matches!(&err, AnalysisError::SameRecording { first, second } if *first == a && *second == c)
        );
    }

    #[test]
    fn a_text_log_gives_its_device_id_and_its_digest_from_one_read() {
        let dir = tempfile::tempdir().unwrap();
        let write = |name: &str, id: &str| {
            let p = dir.path().join(name);
            std::fs::write(&p, format!("# device_id: {id}\ngyro_x,temperature\n1,20\n2,21\n")).unwrap();
            p
        };
        let (hex, dec) = (write("a", "0x2f0009"), write("b", "3080201"));
        let read = RecordingOptions::default();
        let a = RunData::read(&hex, &[], &read).unwrap();
        let b = RunData::read(&dec, &[], &read).unwrap();
        // 0x2f0009 = 3080201: the ids agree, written either way.
        assert_eq!(a.selection.device_ids.gyro, Some(0x2f0009));
        assert_eq!(a.selection.device_ids.gyro, b.selection.device_ids.gyro);
        assert_eq!(a.digest, crate::file_identity::digest(&hex).unwrap());
        assert_ne!(a.digest, b.digest);
    }
}
