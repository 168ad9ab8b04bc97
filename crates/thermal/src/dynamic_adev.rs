//! Dynamic Allan deviation: the OADEV of sliding time windows, each
//! labelled by its mean temperature — the thesis's "3D ADEV" method
//! (dyx1994/Temperature-dependency-of-a-low-cost-IMU,
//! `DataAnalysisCode/cooling_main.m` and `DAVAR.m`: at Fs = 20 Hz windows of
//! 36 001 samples, 30 min, whose centres step by 1800 samples, 90 s, each
//! labelled by the mean of the temperature over it; drawn with `meshz` on
//! log τ and σ axes). The thesis's windows are odd in length, to have a
//! centre sample; these start on a sample and hold round(window × rate)
//! samples, and their τ grid is the octave one. On a cooling run the
//! windows follow the temperature down, so the surface σ(τ, T) is dense in
//! temperature where temperature bins give a dozen coarse steps.
//!
//! This is the one implementation of time windows: the report's dynamic
//! ADEV views use it directly and [`crate::surface`]'s
//! [`Slicing::Time`](crate::surface::Slicing::Time) adds each window's noise
//! terms to it.
//!
//! The statistic is `allan`'s own, computed on a slice of the recording per
//! window: nothing is copied up front, and at most one window per worker
//! thread is held, as the phase the statistic builds, at a time. Windows run
//! in parallel and come back in time order. A window with gaps is analysed
//! (OADEV skips the terms that cross them) and says how many samples it
//! lacked; a sample whose temperature is missing cannot be labelled and is a
//! gap too (as it is in no temperature bin); a window with too few samples,
//! or that the statistic refuses, is listed with its reason.

use rayon::prelude::*;
use thiserror::Error;

use allan::{AllanError, Options, Point, Stat, TauSpec};

/// The thesis's window length, s (30 min).
pub const DEFAULT_WINDOW_S: f64 = 1800.0;
/// The thesis's step between windows, s.
pub const DEFAULT_STEP_S: f64 = 90.0;
/// Fewest valid samples a window must hold to be analysed: below this the
/// octave grid has only a few τ on too few terms.
pub const MIN_WINDOW_SAMPLES: usize = 64;
/// Most windows a run is cut into; each is one OADEV curve.
pub const MAX_WINDOWS: usize = 10_000;

/// How the run is cut.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DynamicOptions {
    /// Window length, s.
    pub window_s: f64,
    /// Step between the starts of two windows, s.
    pub step_s: f64,
    /// Confidence level of each point's interval, in (0, 1).
    pub confidence: f64,
}

impl Default for DynamicOptions {
    fn default() -> Self {
        DynamicOptions {
            window_s: DEFAULT_WINDOW_S,
            step_s: DEFAULT_STEP_S,
            confidence: allan::DEFAULT_CONFIDENCE,
        }
    }
}

/// A run that cannot be cut as asked.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum DynamicAdevError {
    /// Samples and temperatures of different lengths.
    #[error("{samples} samples but {temperatures} temperatures")]
    LengthMismatch {
        /// Samples.
        samples: usize,
        /// Temperatures.
        temperatures: usize,
    },
    /// A window, step or rate that is not a positive finite number.
    #[error("the {what} must be a positive number, not {value}")]
    NotPositive {
        /// "window", "step" or "sample rate".
        what: &'static str,
        /// What was given.
        value: f64,
    },
    /// A window longer than the recording.
    #[error("a window of {window_s} s is longer than the run ({run_s:.1} s): give a shorter window")]
    WindowLongerThanRun {
        /// The window, s.
        window_s: f64,
        /// The run's length, s.
        run_s: f64,
    },
    /// A window too short for an Allan deviation.
    #[error(
        "a window of {window_s} s holds {samples} samples at {rate_hz} Hz; at least {MIN_WINDOW_SAMPLES} are needed"
    )]
    WindowTooShort {
        /// The window, s.
        window_s: f64,
        /// Samples in it.
        samples: usize,
        /// The rate, Hz.
        rate_hz: f64,
    },
    /// A step shorter than a sample.
    #[error("a step of {step_s} s is shorter than one sample ({tau0_s:.3e} s)")]
    StepShorterThanSample {
        /// The step, s.
        step_s: f64,
        /// The sample interval, s.
        tau0_s: f64,
    },
    /// More windows than are analysed.
    #[error(
        "a step of {step_s} s cuts {windows} windows; at most {MAX_WINDOWS} are analysed: give a longer step"
    )]
    TooManyWindows {
        /// The step, s.
        step_s: f64,
        /// Windows it would cut.
        windows: usize,
    },
    /// A confidence level outside (0, 1).
    #[error("the confidence level must lie strictly between 0 and 1, not {0}")]
    Confidence(f64),
}

/// One window's OADEV.
#[derive(Debug, Clone, PartialEq)]
pub struct Window {
    /// Start of the window from the start of the run, s.
    pub start_s: f64,
    /// Its end, s.
    pub end_s: f64,
    /// Mean temperature of its valid samples, °C.
    pub t_mean_c: f64,
    /// Temperature change over it (last − first valid sample), °C.
    pub t_change_c: f64,
    /// Valid samples (neither the sample nor its temperature missing).
    pub samples: usize,
    /// Samples missing in it (gaps).
    pub gap_samples: usize,
    /// The OADEV on the octave grid, with intervals.
    pub points: Vec<Point>,
}

/// Why a window has no curve.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum Skip {
    /// Too few valid samples left by its gaps.
    #[error("{valid} valid samples, fewer than {MIN_WINDOW_SAMPLES}")]
    TooFewSamples {
        /// Valid samples.
        valid: usize,
    },
    /// The statistic refused it.
    #[error(transparent)]
    Statistic(#[from] AllanError),
}

/// A window left without a curve, and why.
#[derive(Debug, Clone, PartialEq)]
pub struct SkippedWindow {
    /// Start, s.
    pub start_s: f64,
    /// End, s.
    pub end_s: f64,
    /// Why.
    pub reason: Skip,
}

/// The dynamic ADEV of one channel.
#[derive(Debug, Clone, PartialEq)]
pub struct DynamicAdev {
    /// The options it was computed with.
    pub options: DynamicOptions,
    /// The rate of the samples, Hz.
    pub rate_hz: f64,
    /// Samples in a window.
    pub window_samples: usize,
    /// The analysed windows, by start time.
    pub windows: Vec<Window>,
    /// The windows without a curve, by start time.
    pub skipped: Vec<SkippedWindow>,
    /// The end of the run no window reaches, s (less than a step).
    pub uncovered_s: f64,
}

impl DynamicAdev {
    /// The window with the lowest and the one with the highest mean
    /// temperature, if any window was analysed.
    pub fn coldest_and_hottest(&self) -> Option<(&Window, &Window)> {
        let by_t = |a: &&Window, b: &&Window| a.t_mean_c.total_cmp(&b.t_mean_c);
        Some((
            self.windows.iter().min_by(by_t)?,
            self.windows.iter().max_by(by_t)?,
        ))
    }
}

/// What every slice of a run is analysed with, a time window here or a
/// temperature bin in [`crate::surface`]: OADEV of rate data on octave τ.
pub(crate) fn slice_options(rate_hz: f64, confidence: f64) -> Options {
    Options {
        stat: Stat::Oadev,
        data_type: allan::DataType::Freq,
        rate_hz,
        taus: TauSpec::Octave,
        confidence,
    }
}

/// The dynamic ADEV of `data` (rate samples at `rate_hz`, NaN for gaps)
/// against `temp` (°C, same length).
pub fn dynamic_adev(
    data: &[f64],
    temp: &[f64],
    rate_hz: f64,
    options: &DynamicOptions,
) -> Result<DynamicAdev, DynamicAdevError> {
    let DynamicOptions {
        window_s,
        step_s,
        confidence,
    } = *options;
    if data.len() != temp.len() {
        return Err(DynamicAdevError::LengthMismatch {
            samples: data.len(),
            temperatures: temp.len(),
        });
    }
    for (what, value) in [("window", window_s), ("step", step_s), ("sample rate", rate_hz)] {
        if !(value.is_finite() && value > 0.0) {
            return Err(DynamicAdevError::NotPositive { what, value });
        }
    }
    if !(confidence > 0.0 && confidence < 1.0) {
        return Err(DynamicAdevError::Confidence(confidence));
    }
    let run_s = data.len() as f64 / rate_hz;
    let w = (window_s * rate_hz).round() as usize;
    if w > data.len() {
        return Err(DynamicAdevError::WindowLongerThanRun { window_s, run_s });
    }
    if w < MIN_WINDOW_SAMPLES {
        return Err(DynamicAdevError::WindowTooShort {
            window_s,
            samples: w,
            rate_hz,
        });
    }
    if step_s * rate_hz < 1.0 {
        return Err(DynamicAdevError::StepShorterThanSample {
            step_s,
            tau0_s: 1.0 / rate_hz,
        });
    }
    let s = (step_s * rate_hz).round() as usize;
    let count = (data.len() - w) / s + 1;
    if count > MAX_WINDOWS {
        return Err(DynamicAdevError::TooManyWindows {
            step_s,
            windows: count,
        });
    }
    let opts = slice_options(rate_hz, confidence);
    let results: Vec<Result<Window, SkippedWindow>> = (0..count)
        .into_par_iter()
        .map(|k| {
            let i = k * s;
            window(&data[i..i + w], &temp[i..i + w], i, rate_hz, &opts)
        })
        .collect();
    let (mut windows, mut skipped) = (Vec::new(), Vec::new());
    for r in results {
        match r {
            Ok(win) => windows.push(win),
            Err(skip) => skipped.push(skip),
        }
    }
    let covered = (count - 1) * s + w;
    Ok(DynamicAdev {
        options: *options,
        rate_hz,
        window_samples: w,
        windows,
        skipped,
        uncovered_s: (data.len() - covered) as f64 / rate_hz,
    })
}

/// One window starting at sample `first`.
fn window(
    data: &[f64],
    temp: &[f64],
    first: usize,
    rate_hz: f64,
    opts: &Options,
) -> Result<Window, SkippedWindow> {
    let start_s = first as f64 / rate_hz;
    let end_s = (first + data.len()) as f64 / rate_hz;
    let skip = |reason: Skip| SkippedWindow {
        start_s,
        end_s,
        reason,
    };
    let label = Label::of(data, temp);
    if label.samples < MIN_WINDOW_SAMPLES {
        return Err(skip(Skip::TooFewSamples { valid: label.samples }));
    }
    let unlabelled = temp.iter().any(|t| !t.is_finite());
    let points = if unlabelled {
        let mut masked = allan::buffer_for(data.len());
        masked.extend(
            data.iter()
                .zip(temp)
                .map(|(&v, t)| if t.is_finite() { v } else { f64::NAN }),
        );
        allan::analyze_vec(masked, opts)
    } else {
        allan::analyze(data, opts)
    }
    .map_err(|e| skip(Skip::Statistic(e)))?
    .points;
    Ok(Window {
        start_s,
        end_s,
        t_mean_c: label.t_mean_c(),
        t_change_c: label.t_change_c(),
        samples: label.samples,
        gap_samples: data.len() - label.samples,
        points,
    })
}

/// What labels a slice: its valid samples (neither the sample nor its
/// temperature missing) and their temperatures, summed in order without
/// being kept.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Label {
    /// Valid samples.
    pub samples: usize,
    sum: f64,
    first: f64,
    last: f64,
}

impl Label {
    /// The label of `data` against `temp` (same length).
    pub fn of(data: &[f64], temp: &[f64]) -> Label {
        // A sample without its temperature cannot be labelled: a gap too.
        data.iter()
            .zip(temp)
            .filter(|(v, t)| !v.is_nan() && t.is_finite())
            .fold(
                Label {
                    samples: 0,
                    sum: 0.0,
                    first: f64::NAN,
                    last: f64::NAN,
                },
                |l, (_, &t)| Label {
                    samples: l.samples + 1,
                    sum: l.sum + t,
                    first: if l.samples == 0 { t } else { l.first },
                    last: t,
                },
            )
    }

    /// Mean temperature of the valid samples, °C (NaN if none).
    pub fn t_mean_c(&self) -> f64 {
        self.sum / self.samples as f64
    }

    /// Last − first valid temperature, °C (NaN if none).
    pub fn t_change_c(&self) -> f64 {
        self.last - self.first
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// White-ish data (a fixed pseudo-random sequence) and a linear cooling
    /// from 80 °C, at 10 Hz.
    fn run(n: usize) -> (Vec<f64>, Vec<f64>) {
        let data = allan::work::uniform(0x2545_F491_4F6C_DD1D)
            .take(n)
            .map(|u| u - 0.5)
            .collect();
        let temp = (0..n).map(|i| 80.0 - 0.01 * i as f64).collect();
        (data, temp)
    }

    fn opts(window_s: f64, step_s: f64) -> DynamicOptions {
        DynamicOptions {
            window_s,
            step_s,
            ..DynamicOptions::default()
        }
    }

    #[test]
    fn windows_come_in_time_order_labelled_by_their_mean_temperature() {
        let (data, temp) = run(3000);
        let d = dynamic_adev(&data, &temp, 10.0, &opts(60.0, 25.0)).unwrap();
        // (3000 − 600) / 250 + 1 = 10 windows; the last ends at 2850.
        assert_eq!(d.window_samples, 600);
        assert_eq!(d.windows.len(), 10);
        assert!(d.skipped.is_empty());
        assert!((d.uncovered_s - 15.0).abs() < 1e-9, "{}", d.uncovered_s);
        for (k, w) in d.windows.iter().enumerate() {
            let first = k * 250;
            assert_eq!(w.start_s, first as f64 / 10.0);
            assert_eq!(w.end_s, (first + 600) as f64 / 10.0);
            // Mean of 80 − 0.01·i over i in [first, first + 600).
            let expect = 80.0 - 0.01 * (first as f64 + 299.5);
            assert!((w.t_mean_c - expect).abs() < 1e-9, "{} {expect}", w.t_mean_c);
            assert!((w.t_change_c + 5.99).abs() < 1e-9);
            assert_eq!((w.samples, w.gap_samples), (600, 0));
        }
        let (cold, hot) = d.coldest_and_hottest().unwrap();
        assert_eq!((cold.start_s, hot.start_s), (225.0, 0.0));
    }

    #[test]
    fn each_window_is_allans_own_oadev_of_its_samples() {
        let (data, temp) = run(2000);
        let d = dynamic_adev(&data, &temp, 10.0, &opts(50.0, 30.0)).unwrap();
        let w = &d.windows[3];
        let own = allan::analyze(
            &data[900..1400],
            &Options {
                rate_hz: 10.0,
                ..Options::default()
            },
        )
        .unwrap();
        assert_eq!(w.points, own.points);
        assert!(w.points.iter().all(|p| p.dev_lo < p.dev && p.dev < p.dev_hi));
    }

    #[test]
    fn gaps_are_counted_and_a_window_they_empty_is_listed_not_dropped() {
        let (mut data, mut temp) = run(2000);
        data[130] = f64::NAN;
        // Samples 1000..1580 lost: the window 1000..1500 has no sample
        // left, 1500..2000 keeps 420.
        for v in &mut data[1000..1580] {
            *v = f64::NAN;
        }
        temp[1700] = f64::NAN;
        let d = dynamic_adev(&data, &temp, 10.0, &opts(50.0, 50.0)).unwrap();
        assert_eq!(d.windows.len() + d.skipped.len(), 4);
        assert_eq!(d.windows[0].gap_samples, 1);
        assert_eq!(d.skipped.len(), 1);
        assert_eq!(d.skipped[0].start_s, 100.0);
        assert_eq!(d.skipped[0].reason, Skip::TooFewSamples { valid: 0 });
        let last = d.windows.last().unwrap();
        assert_eq!((last.start_s, last.samples, last.gap_samples), (150.0, 419, 81));
    }

    #[test]
    fn a_run_that_cannot_be_cut_as_asked_is_refused_with_the_reason() {
        let (data, temp) = run(1000);
        let err = |o: DynamicOptions, rate: f64| dynamic_adev(&data, &temp, rate, &o).unwrap_err();
        assert_eq!(
            err(opts(1800.0, 90.0), 10.0),
            DynamicAdevError::WindowLongerThanRun {
                window_s: 1800.0,
                run_s: 100.0
            }
        );
        assert!(
            err(opts(1800.0, 90.0), 10.0)
                .to_string()
                .contains("longer than the run (100.0 s)")
        );
        assert!(matches!(
            err(opts(5.0, 1.0), 10.0),
            DynamicAdevError::WindowTooShort { samples: 50, .. }
        ));
        assert!(matches!(
            err(opts(50.0, 0.01), 10.0),
            DynamicAdevError::StepShorterThanSample { .. }
        ));
        assert!(matches!(
            err(opts(f64::NAN, 1.0), 10.0),
            DynamicAdevError::NotPositive { what: "window", .. }
        ));
        let long = vec![0.0; 200_000];
        assert!(matches!(
            dynamic_adev(&long, &long, 100.0, &opts(1.0, 0.01)),
            Err(DynamicAdevError::TooManyWindows { windows: 199_901, .. })
        ));
        assert!(matches!(
            dynamic_adev(&data, &temp[1..], 10.0, &opts(50.0, 10.0)),
            Err(DynamicAdevError::LengthMismatch { .. })
        ));
    }
}
