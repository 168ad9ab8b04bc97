//! The thesis's experiment as a value: constant-temperature runs for the
//! noise terms, a cooling run for the ADEV over temperature and the
//! compensation fit, a heating run the compensation never saw for its
//! evaluation, and the navigation that says what it all costs in metres.

use std::path::{Path, PathBuf};

use rayon::prelude::*;

use imu::{Quantity, RecordingOptions};
use ins::drift::report_times;
use ins::strapdown::NavOptions;
use thermal::evaluation::{BinMean, bin_means, slice_minima};
use thermal::surface::{BinCurve, bin_curves_only};
use thermal::tcal::{FitOptions, Model, Run, TcalChannel, fit};

use crate::AnalysisError;
use crate::dynamic_adev::{DynamicAdev, DynamicOptions, dynamic_adev};
use crate::navigation::{
    Navigated, Plan, compensated_channels, horizontal_rms_at, navigate_pair, six_channels,
};
use crate::noise::{RunNoise, analyse_run};
use crate::selection::{Selection, read_channels};

/// Width of the cooling run's temperature slices for the ADEV surface, °C.
pub const SURFACE_BIN_C: f64 = 5.0;
/// Width of the heating run's slices for the ADEV minimum before and after
/// compensation, °C: wide enough for long τ.
pub const CHANGE_BIN_C: f64 = 10.0;
/// Alignment windows compared at 60 s without GNSS, s.
pub const ALIGNMENT_WINDOWS_S: [f64; 3] = [10.0, 30.0, 60.0];
/// The time since alignment the comparisons read, s.
pub const COMPARED_AT_S: f64 = 60.0;

/// The recordings of an experiment.
#[derive(Debug, Clone)]
pub struct Inputs {
    /// The constant-temperature runs, coldest first.
    pub constant: Vec<PathBuf>,
    /// The run the compensation is fitted on.
    pub cooling: PathBuf,
    /// The held-out run it is evaluated on.
    pub heating: PathBuf,
}

/// One channel's bias over temperature on the held-out run.
pub struct ChannelCompensation {
    /// Channel name.
    pub name: String,
    /// Unit of its samples.
    pub unit: String,
    /// What it measures.
    pub quantity: Quantity,
    /// 1 °C bin means, raw.
    pub before: Vec<BinMean>,
    /// 1 °C bin means, compensated.
    pub after: Vec<BinMean>,
    /// σ_min per [`CHANGE_BIN_C`] slice, raw: (mean T, σ_min).
    pub adev_before: Vec<(f64, f64)>,
    /// The same, compensated.
    pub adev_after: Vec<(f64, f64)>,
}

/// The cooling run navigated raw and compensated.
pub struct Navigation {
    /// How it was navigated.
    pub plan: Plan,
    /// Raw.
    pub raw: Navigated,
    /// Compensated with the experiment's model.
    pub compensated: Navigated,
    /// Horizontal position RMS at [`COMPARED_AT_S`] for each of
    /// [`ALIGNMENT_WINDOWS_S`]: (window, raw, compensated), m.
    pub by_alignment: Vec<(f64, f64, f64)>,
}

/// One channel's dynamic ADEV, raw and compensated.
pub struct DynamicPair {
    /// The raw samples'.
    pub raw: DynamicAdev,
    /// The compensated samples', over the same windows.
    pub compensated: DynamicAdev,
}

/// Everything the experiment found.
pub struct Experiment {
    /// The constant runs' noise terms, in the order of [`Inputs::constant`].
    pub runs: Vec<RunNoise>,
    /// The cooling run's channels.
    pub cooling: Selection,
    /// Its ADEV over temperature, one surface per channel: the curves of
    /// its temperature bins (the report draws them; no noise model is
    /// fitted to them).
    pub surfaces: Vec<Vec<BinCurve>>,
    /// Its dynamic ADEV (sliding windows), per channel: raw, and
    /// compensated with [`Experiment::model`] over the same windows.
    pub dynamic: Vec<DynamicPair>,
    /// The compensation fitted on it.
    pub model: Model,
    /// Its evaluation on the heating run, per channel.
    pub compensation: Vec<ChannelCompensation>,
    /// What it costs in metres.
    pub navigation: Navigation,
    /// What the readers and the compensation noted, one line each.
    pub notes: Vec<String>,
}

impl Experiment {
    /// Runs every analysis on `inputs`; `step` hears the name of each step
    /// as it starts. `fit_options` are the compensation's, `dynamic` the
    /// dynamic ADEV's windows.
    pub fn run(
        inputs: &Inputs,
        read: &RecordingOptions,
        fit_options: &FitOptions,
        dynamic: &DynamicOptions,
        mut step: impl FnMut(&str),
    ) -> Result<Experiment, AnalysisError> {
        step("noise terms of the constant-temperature runs");
        // The runs side by side as well as their channels: a run has fewer
        // channels than a pool has room for while its files are read.
        let runs: Vec<RunNoise> = inputs
            .constant
            .par_iter()
            .map(|p| analyse_run(p, read))
            .collect::<Result<_, _>>()?;
        let mut notes: Vec<String> = runs.iter().flat_map(|r| r.notes.iter().cloned()).collect();

        step("ADEV over temperature of the cooling run");
        let cooling = read_channels(&inputs.cooling, &[], read)?;
        notes.extend(cooling.notes.iter().cloned());
        let cool_temp = temperature(&inputs.cooling, &cooling)?;
        let surfaces: Vec<Vec<BinCurve>> = cooling
            .channels
            .par_iter()
            .map(|c| {
                bin_curves_only(
                    &c.data,
                    cool_temp,
                    cooling.rate_hz,
                    SURFACE_BIN_C,
                    allan::DEFAULT_CONFIDENCE,
                )
                .map_err(AnalysisError::thermal(format!(
                    "{}: {}",
                    inputs.cooling.display(),
                    c.name
                )))
            })
            .collect::<Result<_, _>>()?;

        step("compensation: fit on cooling, evaluation on heating");
        let cols: Vec<TcalChannel> = cooling
            .channels
            .iter()
            .map(|c| TcalChannel::new(c.name.clone(), c.unit.clone(), &c.data))
            .collect();
        let mut model = fit(
            &[Run {
                channels: &cols,
                temp: cool_temp,
                rate_hz: cooling.rate_hz,
            }],
            fit_options,
        )
        .map_err(AnalysisError::thermal(inputs.cooling.display().to_string()))?;
        model.fitted_on = vec![inputs.cooling.display().to_string()];
        let compensation = evaluate(&inputs.heating, &model, read, &mut notes)?;

        step("dynamic ADEV of the cooling run, raw and compensated");
        let dynamic = cooling
            .channels
            .par_iter()
            .map(|c| {
                let context = format!("{}: {}", inputs.cooling.display(), c.name);
                let mut comp = c.data.clone();
                model
                    .apply(&c.name, &mut comp, cool_temp, cooling.rate_hz)
                    .map_err(AnalysisError::thermal(context.clone()))?;
                let of = |x: &[f64]| {
                    dynamic_adev(x, cool_temp, cooling.rate_hz, dynamic)
                        .map_err(AnalysisError::dynamic_adev(context.clone()))
                };
                Ok(DynamicPair {
                    raw: of(&c.data)?,
                    compensated: of(&comp)?,
                })
            })
            .collect::<Result<_, AnalysisError>>()?;

        step("navigation of the cooling run, raw and compensated");
        let navigation = navigation(&inputs.cooling, &cooling, &model, &mut notes)?;
        Ok(Experiment {
            runs,
            cooling,
            surfaces,
            dynamic,
            model,
            compensation,
            navigation,
            notes,
        })
    }
}

fn temperature<'a>(file: &Path, sel: &'a Selection) -> Result<&'a [f64], AnalysisError> {
    sel.temperature
        .as_deref()
        .ok_or_else(|| AnalysisError::MissingChannel {
            file: file.to_path_buf(),
            what: "no temperature channel".to_string(),
        })
}

/// The model applied to the held-out run: bias over 1 °C bins and the ADEV
/// minimum per slice, before and after.
fn evaluate(
    heating: &Path,
    model: &Model,
    read: &RecordingOptions,
    notes: &mut Vec<String>,
) -> Result<Vec<ChannelCompensation>, AnalysisError> {
    let heat = read_channels(heating, &[], read)?;
    notes.extend(heat.notes.iter().cloned());
    let heat_temp = temperature(heating, &heat)?;
    let mut out = Vec::new();
    for c in &heat.channels {
        let mut comp = c.data.clone();
        model
            .apply(&c.name, &mut comp, heat_temp, heat.rate_hz)
            .map_err(AnalysisError::thermal(format!(
                "{}: {}",
                heating.display(),
                c.name
            )))?;
        // The ADEV over temperature before and after: its minimum per
        // slice, where a drifting bias shows as a rise at long τ.
        let minima = |x: &[f64]| -> Result<Vec<(f64, f64)>, AnalysisError> {
            Ok(slice_minima(x, heat_temp, heat.rate_hz, CHANGE_BIN_C)
                .map_err(AnalysisError::thermal(format!(
                    "{}: {}",
                    heating.display(),
                    c.name
                )))?
                .iter()
                .map(|m| (m.t_c, m.sigma_min))
                .collect())
        };
        out.push(ChannelCompensation {
            name: c.name.clone(),
            unit: c.unit.clone(),
            quantity: c.quantity,
            // Every 1 °C bin, a single sample's too.
            before: bin_means(&c.data, heat_temp, 1),
            after: bin_means(&comp, heat_temp, 1),
            adev_before: minima(&c.data)?,
            adev_after: minima(&comp)?,
        });
    }
    Ok(out)
}

/// The cooling run navigated without aiding from many start points, raw
/// and compensated; and the 60 s drift for longer alignment windows: a
/// longer window averages the noise out of the gyro bias it takes, but on
/// a cooling run that bias is older when the navigation starts. The same
/// times for all, so that the 10 s row has the same windows.
fn navigation(
    file: &Path,
    sel: &Selection,
    model: &Model,
    notes: &mut Vec<String>,
) -> Result<Navigation, AnalysisError> {
    let plan = Plan::standard(report_times(120.0));
    let six = six_channels(file, sel)?;
    let comp_six = compensated_channels(file, sel, model, &six, notes)?;
    let (raw, compensated) = navigate_pair(file, &six, &comp_six, sel.rate_hz, &plan)?;
    let at = |c: &[Vec<f64>], o: &NavOptions| -> Result<f64, AnalysisError> {
        horizontal_rms_at(c, sel.rate_hz, o, plan.every_s, &plan.times, COMPARED_AT_S)
            .map_err(AnalysisError::ins(file.display().to_string()))?
            .ok_or_else(|| AnalysisError::MissingChannel {
                file: file.to_path_buf(),
                what: format!("no navigation error at {COMPARED_AT_S} s"),
            })
    };
    let by_alignment = ALIGNMENT_WINDOWS_S
        .iter()
        .map(|&align_s| {
            let o = NavOptions {
                align_s,
                ..plan.options
            };
            Ok((align_s, at(&six, &o)?, at(&comp_six, &o)?))
        })
        .collect::<Result<_, AnalysisError>>()?;
    Ok(Navigation {
        plan,
        raw,
        compensated,
        by_alignment,
    })
}
