//! Every IMU instance of a flight controller's log in one model: which
//! instances a fit covers, the fit of each into one model, the instance a
//! compensation takes, and the evaluation of each instance against its own
//! set of the parameter file. `imutherm tcal` and the Python package both
//! call these, so that a model of several instances and its evaluation are
//! the same bytes from either.
//!
//! Reading a run is left to the caller (`read_runs`, one read of a file for
//! every instance it is asked for): the command line
//! prints the reader's notes and checks the sensor is static, Python does
//! neither.

use std::path::{Path, PathBuf};

use imu::{InstancePick, RecordingOptions, Setting, Value};
use thermal::firmware::{self, Target};
use thermal::tcal::Model;
use thiserror::Error;

use crate::AnalysisError;
use crate::compensation::{self, AsLoaded, EvalDocument, FitRequest, Fitted, RunData};

/// The IMU instances asked for (`--instance N|all`, Python's
/// `instance=N|"all"`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Instances {
    /// One instance of the log.
    One(u32),
    /// Every instance of the log.
    All,
}

/// An instance asked for that the log or the model does not hold. A usage
/// error: the settings, not the data, are at fault.
#[derive(Debug, Error)]
pub enum InstanceError {
    /// Every instance asked of a file that has none.
    #[error(
        "{}: {} has no IMU instances (it is not a PX4 ULog or ArduPilot DataFlash log with several IMUs)",
        Setting::Instance.given(Value::text("all")),
        file.display()
    )]
    NoneInLog {
        /// The first run.
        file: PathBuf,
    },
    /// Every instance asked of a model of one sensor.
    #[error(
        "{}: {model} is the model of one sensor; give its instance number",
        Setting::Instance.given(Value::text("all"))
    )]
    OneSensor {
        /// The model, as named.
        model: String,
    },
    /// An instance the model does not hold.
    #[error("{}: {model} holds instances {held:?}", Setting::Instance.given(Value::number(instance)))]
    NotInModel {
        /// The instance asked for.
        instance: u32,
        /// The model, as named.
        model: String,
        /// The instances it holds.
        held: Vec<u32>,
    },
    /// A compensation of a model of several instances without saying which.
    #[error(
        "{model} holds instances {held:?}: give {} to compensate one",
        Setting::Instance.given(Value::Placeholder("N"))
    )]
    Unchosen {
        /// The model, as named.
        model: String,
        /// The instances it holds.
        held: Vec<u32>,
    },
}

/// The instance numbers a model holds, in its order.
pub fn held(model: &Model) -> Vec<u32> {
    model.instances.iter().filter_map(|m| m.instance).collect()
}

/// Each run read as `read_runs` reads it: with its instance, or with
/// `None` for a run read as one stream.
pub type EachRun = Vec<(Option<u32>, RunData)>;

/// The instances a fit's first run is read for: every one with
/// [`Instances::All`], and by default when fitting for a firmware (with no
/// topic named) on a log of several IMUs; otherwise the one stream asked.
fn pick_for_fit(asked: Option<Instances>, for_firmware: bool, topic_named: bool) -> InstancePick {
    match asked {
        Some(Instances::All) => InstancePick::All,
        None if for_firmware && !topic_named => InstancePick::Several,
        _ => InstancePick::AsChosen,
    }
}

/// Fits `files` as `req` asks: one model, or, where the instances asked
/// (see [`Instances`]) are several, one model holding a fit of each
/// instance (read as its own IMU), its warnings prefixed with the instance.
/// `read_runs` reads a file once for every instance `pick` names: the first
/// run decides the instances, the others are read for the same ones. A
/// model for a firmware is exported once whole, so that a fault of the file
/// the instances make together shows at the fit, not at the vehicle.
pub fn fit<E: From<AnalysisError>>(
    files: &[PathBuf],
    req: &FitRequest,
    read: &RecordingOptions,
    asked: Option<Instances>,
    topic_named: bool,
    mut read_runs: impl FnMut(&Path, &RecordingOptions, &InstancePick) -> Result<EachRun, E>,
) -> Result<Fitted, E> {
    let Some((first, rest)) = files.split_first() else {
        return Ok(compensation::fit(files, &[], req)?);
    };
    let pick = pick_for_fit(asked, req.firmware.is_some(), topic_named);
    let first_runs = read_runs(first, read, &pick)?;
    let numbers: Vec<u32> = first_runs.iter().filter_map(|(n, _)| *n).collect();
    let Some(&lead) = numbers.first() else {
        if pick == InstancePick::All {
            return Err(AnalysisError::from(InstanceError::NoneInLog {
                file: first.to_path_buf(),
            })
            .into());
        }
        let mut runs: Vec<RunData> = first_runs.into_iter().map(|(_, r)| r).collect();
        for f in rest {
            runs.extend(
                read_runs(f, read, &InstancePick::AsChosen)?
                    .into_iter()
                    .map(|(_, r)| r),
            );
        }
        return Ok(compensation::fit(files, &runs, req)?);
    };
    let mut by_instance: Vec<(u32, Vec<RunData>)> = first_runs
        .into_iter()
        .filter_map(|(n, r)| n.map(|n| (n, vec![r])))
        .collect();
    // The later runs are read for the first one's instances; naming one
    // makes a text log among them refused as a stream choice is.
    let mut each = read.clone();
    each.stream.instance = Some(lead);
    let these = InstancePick::These(numbers.clone());
    for f in rest {
        for (n, run) in read_runs(f, &each, &these)? {
            if let Some((_, runs)) = by_instance.iter_mut().find(|(k, _)| Some(*k) == n) {
                runs.push(run);
            }
        }
    }
    // Every instance of the first run must be read from every run: the
    // fit pairs each instance's runs with the files.
    if let Some((n, _)) = by_instance.iter().find(|(_, runs)| runs.len() != files.len()) {
        return Err(AnalysisError::MissingChannel {
            file: first.to_path_buf(),
            what: format!("IMU instance {n} was not read from every run"),
        }
        .into());
    }
    let mut models = Vec::with_capacity(by_instance.len());
    let mut export_warnings = Vec::new();
    for (n, runs) in by_instance {
        let fitted = compensation::fit(files, &runs, req)?;
        let mut model = fitted.model;
        model.instance = Some(n);
        export_warnings.extend(
            fitted
                .export_warnings
                .into_iter()
                .map(|w| format!("instance {n}: {w}")),
        );
        models.push(model);
    }
    let model = Model::of_instances(models).ok_or_else(|| {
        AnalysisError::from(InstanceError::NoneInLog {
            file: first.to_path_buf(),
        })
    })?;
    if let Some(fw) = req.firmware {
        firmware::export(&model, fw, Target::default()).map_err(|cause| AnalysisError::Firmware {
            context: format!("the instances together cannot be written for {}", fw.name()),
            cause,
        })?;
    }
    Ok(Fitted {
        model,
        export_warnings,
    })
}

/// The model that compensates a recording of instance `asked`: a model of
/// one sensor itself, else the instance's own model, which must be named.
pub fn to_apply(model: &Model, model_name: &str, asked: Option<u32>) -> Result<Model, InstanceError> {
    if model.instances.is_empty() {
        return Ok(model.clone());
    }
    let Some(n) = asked else {
        return Err(InstanceError::Unchosen {
            model: model_name.to_string(),
            held: held(model),
        });
    };
    model
        .instances
        .iter()
        .find(|m| m.instance == Some(n))
        .cloned()
        .ok_or_else(|| InstanceError::NotInModel {
            instance: n,
            model: model_name.to_string(),
            held: held(model),
        })
}

/// The sensors of `model` an evaluation judges: each of its instances (or
/// the one asked for), or the model itself for one sensor.
pub fn to_evaluate<'m>(
    model: &'m Model,
    model_name: &str,
    asked: Option<Instances>,
) -> Result<Vec<&'m Model>, InstanceError> {
    let many = !model.instances.is_empty();
    match (many, asked) {
        (false, Some(Instances::All)) => Err(InstanceError::OneSensor {
            model: model_name.to_string(),
        }),
        (true, Some(Instances::One(n))) => {
            let one: Vec<&Model> = model.instances.iter().filter(|m| m.instance == Some(n)).collect();
            if one.is_empty() {
                return Err(InstanceError::NotInModel {
                    instance: n,
                    model: model_name.to_string(),
                    held: held(model),
                });
            }
            Ok(one)
        }
        _ => Ok(model.sensors()),
    }
}

/// `tcal eval`'s document: every run of `files` judged for each sensor of
/// `model` (read as its own IMU for a model of several instances, every
/// instance from one read of the file where the sensors take the same
/// channels), with `loaded`, where given, applied as the firmware applies
/// it (each instance against its own set) and its verdict on each run.
pub fn evaluate<E: From<AnalysisError>>(
    model: &Model,
    model_name: &str,
    files: &[PathBuf],
    loaded: Option<&AsLoaded>,
    asked: Option<Instances>,
    read: &RecordingOptions,
    mut read_runs: impl FnMut(&Path, &[String], &RecordingOptions, &InstancePick) -> Result<EachRun, E>,
) -> Result<EvalDocument, E> {
    let many = !model.instances.is_empty();
    let sensors = to_evaluate(model, model_name, asked).map_err(AnalysisError::from)?;
    let names_of = |m: &Model| -> Vec<String> { m.channels.iter().map(|c| c.name.clone()).collect() };
    let together = many && sensors.len() > 1 && sensors.iter().all(|m| names_of(m) == names_of(sensors[0]));
    let mut rows = Vec::new();
    let mut verdicts = Vec::new();
    for file in files {
        let mut runs: Vec<(&Model, RunData)> = Vec::with_capacity(sensors.len());
        if together {
            let numbers: Vec<u32> = sensors.iter().filter_map(|m| m.instance).collect();
            let mut each = read.clone();
            each.stream.instance = numbers.first().copied();
            let got = read_runs(file, &names_of(sensors[0]), &each, &InstancePick::These(numbers))?;
            for (n, run) in got {
                if let Some(m) = sensors.iter().find(|m| m.instance.is_some() && m.instance == n) {
                    runs.push((m, run));
                }
            }
        } else {
            for m in &sensors {
                let mut one = read.clone();
                if many {
                    one.stream.instance = m.instance;
                }
                for (_, run) in read_runs(file, &names_of(m), &one, &InstancePick::AsChosen)? {
                    runs.push((m, run));
                }
            }
        }
        for (m, run) in runs {
            let for_instance = match (many, loaded) {
                (true, Some(l)) => Some(l.for_instance(m)?),
                _ => None,
            };
            let loaded = for_instance.as_ref().or(loaded);
            if let Some(l) = loaded {
                let mut v = compensation::judge(l, file, &run)?;
                v.instance = m.instance.filter(|_| many);
                verdicts.push(v);
            }
            let for_run = match loaded {
                Some(l) => l.for_run(file, &run)?,
                None => None,
            };
            rows.extend(compensation::eval_rows(
                m,
                file,
                run,
                for_run.as_ref().or(loaded),
            )?);
        }
    }
    Ok(EvalDocument::new(model_name, rows, loaded, verdicts))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn model(instance: Option<u32>) -> Model {
        let text = r#"{"schema":"imutherm.tcal/1","t_ref_c":30.0,"t_min_c":20.0,"t_max_c":40.0,
            "centre_c":30.0,"scale_c":10.0,"bin_width_c":1.0,"channels":[]}"#;
        let mut m: Model = serde_json::from_str(text).unwrap();
        m.instance = instance;
        m
    }

    #[test]
    fn a_model_of_several_instances_compensates_only_the_one_named() {
        let many = Model::of_instances(vec![model(Some(0)), model(Some(2))]).unwrap();
        assert_eq!(to_apply(&many, "m.json", Some(2)).unwrap().instance, Some(2));
        let err = to_apply(&many, "m.json", Some(1)).unwrap_err().to_string();
        assert_eq!(err, "the IMU instance 1: m.json holds instances [0, 2]");
        let err = to_apply(&many, "m.json", None).unwrap_err().to_string();
        assert_eq!(
            err,
            "m.json holds instances [0, 2]: give the IMU instance N to compensate one"
        );
        // A model of one sensor compensates whatever instance was read.
        assert_eq!(to_apply(&model(None), "m.json", Some(3)).unwrap(), model(None));
    }

    #[test]
    fn an_evaluation_judges_each_instance_or_the_one_asked() {
        let many = Model::of_instances(vec![model(Some(0)), model(Some(1))]).unwrap();
        let each = |asked| -> Vec<Option<u32>> {
            to_evaluate(&many, "m", asked)
                .unwrap()
                .iter()
                .map(|m| m.instance)
                .collect()
        };
        assert_eq!(each(None), [Some(0), Some(1)]);
        assert_eq!(each(Some(Instances::All)), [Some(0), Some(1)]);
        assert_eq!(each(Some(Instances::One(1))), [Some(1)]);
        assert!(matches!(
            to_evaluate(&many, "m", Some(Instances::One(5))),
            Err(InstanceError::NotInModel { instance: 5, .. })
        ));
        let one = model(None);
        assert_eq!(to_evaluate(&one, "m", Some(Instances::One(4))).unwrap().len(), 1);
        assert!(matches!(
            to_evaluate(&one, "m", Some(Instances::All)),
            Err(InstanceError::OneSensor { .. })
        ));
    }

    #[test]
    fn instances_are_fitted_together_only_where_asked_or_a_firmware_wants_them() {
        assert_eq!(pick_for_fit(None, true, false), InstancePick::Several);
        assert_eq!(pick_for_fit(None, true, true), InstancePick::AsChosen);
        assert_eq!(pick_for_fit(None, false, false), InstancePick::AsChosen);
        assert_eq!(
            pick_for_fit(Some(Instances::One(1)), true, false),
            InstancePick::AsChosen
        );
        assert_eq!(pick_for_fit(Some(Instances::All), false, true), InstancePick::All);

        // Every instance of a text log, which has none: a usage error.
        let dir = tempfile::tempdir().unwrap();
        let text = dir.path().join("run.csv");
        std::fs::write(&text, "gyro_x,temperature\n1,20\n").unwrap();
        let req = FitRequest {
            order: thermal::tcal::Order::Auto,
            t_ref_c: None,
            bin_width_c: 1.0,
            rate_term: false,
            firmware: None,
        };
        let mut picks = Vec::new();
        let Err(err) = fit::<AnalysisError>(
            &[text],
            &req,
            &RecordingOptions::default(),
            Some(Instances::All),
            false,
            |f, read, pick| {
                picks.push(pick.clone());
                RunData::read_each(f, &[], read, pick)
            },
        ) else {
            panic!("a text log fitted for every instance");
        };
        assert_eq!(picks, [InstancePick::All]);
        assert!(err.is_usage(), "{err}");
        assert!(err.to_string().contains("has no IMU instances"), "{err}");
    }
}
