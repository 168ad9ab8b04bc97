//! The Allan deviation over temperature — the thesis's "3D ADEV": one
//! overlapping ADEV curve per temperature bin or per sliding time window,
//! with the noise terms of each.
//!
//! A temperature bin keeps the samples taken while the temperature was in
//! it; everything else becomes a gap, so terms never join stretches from
//! different visits to the bin (the engine skips terms that cross a gap), and
//! a τ is kept only where enough contiguous data support it. Time windows
//! are [`crate::dynamic_adev`]'s. A slice with too few samples, or that the
//! statistic refuses, has no row: it is listed in [`Surface::skipped`] with
//! the reason.

use rayon::prelude::*;

use allan::Point;
use allan::noise_terms::{NoiseTerms, identify};

use crate::ThermalError;
use crate::dynamic_adev::{DynamicOptions, Label, Skip, dynamic_adev};

/// How the recording is cut.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Slicing {
    /// Bins of this width in °C.
    Temperature {
        /// Bin width, °C.
        bin_width_c: f64,
    },
    /// Sliding windows (dynamic Allan variance).
    Time {
        /// Window length, s.
        window_s: f64,
        /// Step between windows, s.
        step_s: f64,
    },
}

/// One slice of the surface.
#[derive(Debug, Clone)]
pub struct SurfaceRow {
    /// Lower edge of the bin (°C) or start of the window (s).
    pub start: f64,
    /// Upper edge of the bin (°C) or end of the window (s).
    pub end: f64,
    /// Mean temperature of the samples used, °C.
    pub t_mean_c: f64,
    /// Temperature change over the slice (last − first sample), °C.
    pub t_change_c: f64,
    /// Samples used.
    pub samples: usize,
    /// The OADEV curve.
    pub points: Vec<Point>,
    /// Its noise terms.
    pub terms: NoiseTerms,
}

/// A slice with samples but no row, and why.
#[derive(Debug, Clone, PartialEq)]
pub struct SkippedSlice {
    /// Lower edge of the bin (°C) or start of the window (s).
    pub start: f64,
    /// Upper edge of the bin (°C) or end of the window (s).
    pub end: f64,
    /// Why it has no curve.
    pub reason: Skip,
}

/// The surface: its rows and the slices left out, each in order (bins by
/// temperature, windows by time).
#[derive(Debug, Clone)]
pub struct Surface {
    /// The analysed slices.
    pub rows: Vec<SurfaceRow>,
    /// The slices without a curve.
    pub skipped: Vec<SkippedSlice>,
}

/// Fewest samples a slice must hold to be analysed.
pub const MIN_SLICE_SAMPLES: usize = crate::dynamic_adev::MIN_WINDOW_SAMPLES;

/// Most temperature bins a surface is cut into: 0.1 °C bins over 100 °C.
/// Each bin costs a pass over the whole recording, so a finer request is
/// refused before any work rather than left running for hours.
pub const MAX_BINS: usize = 1000;

/// Most time windows a surface is cut into; each is one OADEV curve.
pub const MAX_WINDOWS: usize = crate::dynamic_adev::MAX_WINDOWS;

/// The temperature's resolution: the smallest step between two distinct
/// finite values (the sensor's quantum, 1/333.87 °C for an MPU-9250,
/// PS-MPU-9250A-01 Table 3). None for fewer than two distinct values.
pub fn temperature_resolution(temp: &[f64]) -> Option<f64> {
    // The distinct values, chunk by chunk: a quantized sensor has a few
    // thousand, so a long recording is not copied whole to be sorted. The
    // smallest step between neighbours is the same with or without the
    // repeats.
    let distinct = |c: &[f64]| {
        let mut t: Vec<f64> = c.iter().copied().filter(|t| t.is_finite()).collect();
        t.sort_unstable_by(f64::total_cmp);
        t.dedup_by(|a, b| a.total_cmp(b).is_eq());
        t
    };
    let mut t: Vec<f64> = temp.par_chunks(1 << 16).flat_map_iter(distinct).collect();
    t.par_sort_unstable_by(f64::total_cmp);
    t.windows(2)
        .map(|w| w[1] - w[0])
        .filter(|&d| d > 0.0)
        .min_by(f64::total_cmp)
}

/// The ADEV surface of `data` (rate samples at `rate_hz`) against the
/// temperature `temp` (same length), sliced as asked: its rows only (see
/// [`slices`] for the slices left out).
pub fn surface(
    data: &[f64],
    temp: &[f64],
    rate_hz: f64,
    slicing: Slicing,
    confidence: f64,
) -> Result<Vec<SurfaceRow>, ThermalError> {
    slices(data, temp, rate_hz, slicing, confidence).map(|s| s.rows)
}

/// [`surface`], with the slices that have samples but no curve.
pub fn slices(
    data: &[f64],
    temp: &[f64],
    rate_hz: f64,
    slicing: Slicing,
    confidence: f64,
) -> Result<Surface, ThermalError> {
    same_length(data, temp)?;
    match slicing {
        Slicing::Temperature { bin_width_c } => bins(data, temp, rate_hz, bin_width_c, confidence),
        Slicing::Time { window_s, step_s } => {
            let options = DynamicOptions {
                window_s,
                step_s,
                confidence,
            };
            let d = dynamic_adev(data, temp, rate_hz, &options)?;
            let rows = d
                .windows
                .into_par_iter()
                .map(|w| SurfaceRow {
                    start: w.start_s,
                    end: w.end_s,
                    t_mean_c: w.t_mean_c,
                    t_change_c: w.t_change_c,
                    samples: w.samples,
                    terms: identify(&w.points, &w.points, confidence),
                    points: w.points,
                })
                .collect();
            let skipped = d
                .skipped
                .into_iter()
                .map(|s| SkippedSlice {
                    start: s.start_s,
                    end: s.end_s,
                    reason: s.reason,
                })
                .collect();
            Ok(Surface { rows, skipped })
        }
    }
}

/// Refuses data and temperatures of different lengths.
fn same_length(data: &[f64], temp: &[f64]) -> Result<(), ThermalError> {
    if data.len() != temp.len() {
        return Err(ThermalError::Invalid(format!(
            "{} samples but {} temperatures",
            data.len(),
            temp.len()
        )));
    }
    Ok(())
}

/// The surface over bins of `bin_width_c`.
fn bins(
    data: &[f64],
    temp: &[f64],
    rate_hz: f64,
    bin_width_c: f64,
    confidence: f64,
) -> Result<Surface, ThermalError> {
    let (rows, skipped) = bin_curves(
        data,
        temp,
        rate_hz,
        bin_width_c,
        confidence,
        |(a, b), label, points| SurfaceRow {
            start: a,
            end: b,
            t_mean_c: label.t_mean_c(),
            t_change_c: label.t_change_c(),
            samples: label.samples,
            terms: identify(&points, &points, confidence),
            points,
        },
    )?;
    Ok(Surface { rows, skipped })
}

/// One temperature bin's curve without the noise model a [`SurfaceRow`]
/// fits to it: what a heat map of the surface draws.
#[derive(Debug, Clone)]
pub struct BinCurve {
    /// Lower edge of the bin, °C.
    pub start: f64,
    /// Upper edge of the bin, °C.
    pub end: f64,
    /// Mean temperature of the samples used, °C.
    pub t_mean_c: f64,
    /// Samples used.
    pub samples: usize,
    /// The OADEV curve.
    pub points: Vec<Point>,
}

/// The OADEV curve of each bin of `bin_width_c`, the rows of [`surface`]
/// without their noise models: the fit is nearly all of a row's cost, and a
/// caller that draws the curves has no use for it.
pub fn bin_curves_only(
    data: &[f64],
    temp: &[f64],
    rate_hz: f64,
    bin_width_c: f64,
    confidence: f64,
) -> Result<Vec<BinCurve>, ThermalError> {
    let (rows, _) = bin_curves(
        data,
        temp,
        rate_hz,
        bin_width_c,
        confidence,
        |(a, b), label, points| BinCurve {
            start: a,
            end: b,
            t_mean_c: label.t_mean_c(),
            samples: label.samples,
            points,
        },
    )?;
    Ok(rows)
}

/// Each bin's curve, turned by `read` (given the bin's edges in °C, what
/// its samples hold, and the curve) into what the caller needs: the
/// noise model's fit is by far the dearest part of a slice, and a caller
/// that needs only the curve's minimum should not pay for it.
pub(crate) fn bin_curves<R: Send>(
    data: &[f64],
    temp: &[f64],
    rate_hz: f64,
    bin_width_c: f64,
    confidence: f64,
    read: impl Fn((f64, f64), &Label, Vec<Point>) -> R + Sync,
) -> Result<(Vec<R>, Vec<SkippedSlice>), ThermalError> {
    same_length(data, temp)?;
    if !(bin_width_c.is_finite() && bin_width_c > 0.0) {
        return Err(ThermalError::Invalid(format!(
            "bin width {bin_width_c} °C must be positive"
        )));
    }
    let (lo, hi) = temp
        .iter()
        .filter(|t| t.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &t| {
            (a.min(t), b.max(t))
        });
    if !lo.is_finite() {
        return Err(ThermalError::NoTemperature);
    }
    let bins = ((hi / bin_width_c).floor() - (lo / bin_width_c).floor()) + 1.0;
    if bins > MAX_BINS as f64 {
        return Err(ThermalError::Invalid(format!(
            "bins of {bin_width_c} °C over {lo:.2} to {hi:.2} °C would be {bins:.0} bins; \
             at most {MAX_BINS} are analysed: give a wider bin"
        )));
    }
    if let Some(q) = temperature_resolution(temp)
        && bin_width_c < q
    {
        return Err(ThermalError::Invalid(format!(
            "bins of {bin_width_c} °C are finer than the temperature's resolution, {q:.3e} °C"
        )));
    }
    let opts = crate::dynamic_adev::slice_options(rate_hz, confidence);
    let first = (lo / bin_width_c).floor() as i64;
    let last = (hi / bin_width_c).floor() as i64;
    let results: Vec<Result<R, SkippedSlice>> = (first..=last)
        .into_par_iter()
        .filter_map(|k| {
            let (a, b) = (k as f64 * bin_width_c, (k + 1) as f64 * bin_width_c);
            let inside = |t: f64| t >= a && t < b;
            // From the bin's first sample to its last: the NaN edges
            // outside would be trimmed as missing edges anyway
            // (`PhaseSeries`), and a bin of a cooling run is a short
            // stretch of it, not a copy of the whole channel. A bin the
            // temperature never visits is no slice at all.
            let first = temp.iter().position(|&t| inside(t))?;
            let last = temp.iter().rposition(|&t| inside(t))?;
            let mut series = allan::buffer_for(last + 1 - first);
            series.extend(
                data[first..=last]
                    .iter()
                    .zip(&temp[first..=last])
                    .map(|(&v, &t)| if inside(t) { v } else { f64::NAN }),
            );
            let skip = |reason: Skip| SkippedSlice {
                start: a,
                end: b,
                reason,
            };
            let label = Label::of(&series, &temp[first..=last]);
            if label.samples < MIN_SLICE_SAMPLES {
                return Some(Err(skip(Skip::TooFewSamples { valid: label.samples })));
            }
            Some(match allan::analyze_vec(series, &opts) {
                Ok(curve) => Ok(read((a, b), &label, curve.points)),
                Err(e) => Err(skip(Skip::Statistic(e))),
            })
        })
        .collect();
    let (mut rows, mut skipped) = (Vec::new(), Vec::new());
    for r in results {
        match r {
            Ok(row) => rows.push(row),
            Err(s) => skipped.push(s),
        }
    }
    Ok((rows, skipped))
}

#[cfg(test)]
mod tests {
    use super::*;
    use allan::{Options, TauSpec};

    /// A ramp from 20 to 80 °C quantized to the MPU-9250's 1/333.87 °C,
    /// with white data.
    fn ramp(n: usize) -> (Vec<f64>, Vec<f64>) {
        let q = 1.0 / 333.87;
        let temp = (0..n)
            .map(|i| ((20.0 + 60.0 * i as f64 / n as f64) / q).round() * q)
            .collect();
        let data = (0..n).map(|i| ((i * 7919) % 101) as f64 - 50.0).collect();
        (data, temp)
    }

    /// Back-to-back 100 s time slices of a 10 Hz channel.
    fn hundred_second_slices(data: &[f64], temp: &[f64]) -> Surface {
        let slicing = Slicing::Time {
            window_s: 100.0,
            step_s: 100.0,
        };
        slices(data, temp, 10.0, slicing, allan::DEFAULT_CONFIDENCE).unwrap()
    }

    fn refused(slicing: Slicing, rate_hz: f64) -> String {
        let (data, temp) = ramp(20_000);
        match surface(&data, &temp, rate_hz, slicing, allan::DEFAULT_CONFIDENCE) {
            Err(e) => e.to_string(),
            Ok(rows) => panic!("{slicing:?}: {} rows, expected a refusal", rows.len()),
        }
    }

    /// A slice as the straightforward computations give it: start, end,
    /// mean and change of temperature, samples, curve.
    type Row = (f64, f64, f64, f64, usize, Vec<Point>);

    /// One slice as first written: `series` holds its samples (NaN where
    /// not in it), labelled by the temperatures `temp` beside them, and
    /// spans `(start, end)`.
    fn straightforward_slice(
        series: Vec<f64>,
        temp: &[f64],
        (start, end): (f64, f64),
        opts: &Options,
    ) -> Option<Row> {
        let used: Vec<f64> = series
            .iter()
            .zip(temp)
            .filter(|(v, _)| !v.is_nan())
            .map(|(_, &t)| t)
            .collect();
        if used.len() < MIN_SLICE_SAMPLES {
            return None;
        }
        let mean = used.iter().sum::<f64>() / used.len() as f64;
        let change = used[used.len() - 1] - used[0];
        let curve = allan::analyze_vec(series, opts).ok()?;
        Some((start, end, mean, change, used.len(), curve.points))
    }

    /// The surface of temperature bins as first written: every bin a copy
    /// of the whole channel, NaN outside it, and the temperatures used
    /// collected. What the trimmed bins must reproduce.
    fn straightforward_bins(data: &[f64], temp: &[f64], width: f64) -> Vec<Row> {
        let (lo, hi) = temp
            .iter()
            .filter(|t| t.is_finite())
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &t| {
                (a.min(t), b.max(t))
            });
        let opts = Options {
            taus: TauSpec::Octave,
            ..Options::default()
        };
        ((lo / width).floor() as i64..=(hi / width).floor() as i64)
            .filter_map(|k| {
                let (a, b) = (k as f64 * width, (k + 1) as f64 * width);
                let series: Vec<f64> = data
                    .iter()
                    .zip(temp)
                    .map(|(&v, &t)| if t >= a && t < b { v } else { f64::NAN })
                    .collect();
                straightforward_slice(series, temp, (a, b), &opts)
            })
            .collect()
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(24))]
        #[test]
        fn trimmed_bins_give_what_whole_length_bins_gave(
            seed in proptest::prelude::any::<u64>(),
            n in 200usize..6000,
            gaps in 0usize..40,
            width in 0.05f64..2.0,
        ) {
            // A wandering, quantized temperature that leaves and re-enters
            // bins, and data with gaps of its own.
            let mut state = seed | 1;
            let mut next = || {
                state ^= state << 13;
                state ^= state >> 7;
                state ^= state << 17;
                (state >> 11) as f64 / (1u64 << 53) as f64
            };
            let q = 1.0 / 333.87;
            let mut t = 40.0;
            let temp: Vec<f64> = (0..n)
                .map(|_| {
                    t += (next() - 0.5) * 0.05;
                    (t / q).round() * q
                })
                .collect();
            let mut data: Vec<f64> = (0..n).map(|_| next() - 0.5).collect();
            for _ in 0..gaps {
                let at = (next() * n as f64) as usize % n;
                data[at] = f64::NAN;
            }
            let got = surface(&data, &temp, 1.0, Slicing::Temperature { bin_width_c: width }, allan::DEFAULT_CONFIDENCE)
                .unwrap();
            let want = straightforward_bins(&data, &temp, width);
            proptest::prop_assert_eq!(got.len(), want.len());
            for (g, w) in got.iter().zip(&want) {
                proptest::prop_assert_eq!((g.start, g.end, g.t_mean_c, g.t_change_c, g.samples), (w.0, w.1, w.2, w.3, w.4));
                proptest::prop_assert_eq!(&g.points, &w.5);
            }
            // The resolution from distinct values chunk by chunk is the one
            // of the whole channel sorted.
            let mut all: Vec<f64> = temp.iter().copied().filter(|t| t.is_finite()).collect();
            all.sort_unstable_by(f64::total_cmp);
            let whole = all.windows(2).map(|w| w[1] - w[0]).filter(|&d| d > 0.0).min_by(f64::total_cmp);
            proptest::prop_assert_eq!(temperature_resolution(&temp), whole);
        }
    }

    #[test]
    fn the_resolution_over_many_chunks_is_that_of_the_whole_channel() {
        // A random walk over several chunks of distinct-value collection,
        // its smallest step in one chunk only.
        let mut t = 30.0f64;
        let mut temp: Vec<f64> = (0..300_000u64)
            .map(|i| {
                t += if (i * 2_654_435_761) % 7 < 3 { 0.25 } else { -0.25 };
                t
            })
            .collect();
        temp[200_001] = temp[200_000] + 0.001;
        temp[5] = f64::NAN;
        let mut all: Vec<f64> = temp.iter().copied().filter(|t| t.is_finite()).collect();
        all.sort_unstable_by(f64::total_cmp);
        let whole = all
            .windows(2)
            .map(|w| w[1] - w[0])
            .filter(|&d| d > 0.0)
            .min_by(f64::total_cmp);
        assert_eq!(temperature_resolution(&temp), whole);
        assert!(whole.is_some_and(|q| q < 0.01));
    }

    #[test]
    fn the_curves_alone_are_the_surfaces_curves() {
        let (data, temp) = ramp(20_000);
        let conf = allan::DEFAULT_CONFIDENCE;
        let rows = surface(
            &data,
            &temp,
            10.0,
            Slicing::Temperature { bin_width_c: 5.0 },
            conf,
        )
        .unwrap();
        let curves = bin_curves_only(&data, &temp, 10.0, 5.0, conf).unwrap();
        assert_eq!(rows.len(), curves.len());
        assert!(rows.len() > 3);
        for (r, c) in rows.iter().zip(&curves) {
            assert_eq!(
                (r.start, r.end, r.t_mean_c, r.samples),
                (c.start, c.end, c.t_mean_c, c.samples)
            );
            assert_eq!(r.points, c.points);
        }
    }

    #[test]
    fn the_resolution_is_the_sensors_quantum() {
        let (_, temp) = ramp(20_000);
        let q = temperature_resolution(&temp).unwrap();
        assert!((q - 1.0 / 333.87).abs() < 1e-9, "{q}");
        assert_eq!(temperature_resolution(&[25.0, 25.0, f64::NAN]), None);
    }

    #[test]
    fn absurd_slicings_are_refused_before_any_work() {
        let bins = refused(Slicing::Temperature { bin_width_c: 0.01 }, 100.0);
        assert!(
            bins.contains("6001 bins") && bins.contains("at most 1000"),
            "{bins}"
        );
        // 0.06 °C bins over 60 °C are 1001; 0.061 °C fit the limit.
        let (data, temp) = ramp(20_000);
        let ok = surface(
            &data,
            &temp,
            100.0,
            Slicing::Temperature { bin_width_c: 0.061 },
            allan::DEFAULT_CONFIDENCE,
        );
        assert!(ok.is_ok());
        let step = refused(
            Slicing::Time {
                window_s: 10.0,
                step_s: 1e-6,
            },
            100.0,
        );
        assert!(step.contains("shorter than one sample"), "{step}");
        let windows = refused(
            Slicing::Time {
                window_s: 1.0,
                step_s: 0.01,
            },
            100.0,
        );
        assert!(windows.contains("19901 windows"), "{windows}");
    }

    /// The time windows as first written: each a copy of the window,
    /// labelled by the temperatures of its non-NaN samples, dropped when
    /// too short. What the shared windows must reproduce where the
    /// temperature has no gap.
    fn straightforward_windows(data: &[f64], temp: &[f64], rate_hz: f64, w: usize, s: usize) -> Vec<Row> {
        let opts = Options {
            rate_hz,
            taus: TauSpec::Octave,
            ..Options::default()
        };
        (0..=data.len() - w)
            .step_by(s)
            .filter_map(|i| {
                let mut window = allan::buffer_for(w);
                window.extend_from_slice(&data[i..i + w]);
                let span = (i as f64 / rate_hz, (i + w) as f64 / rate_hz);
                straightforward_slice(window, &temp[i..i + w], span, &opts)
            })
            .collect()
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(16))]
        #[test]
        fn time_windows_give_what_copied_windows_gave(
            seed in proptest::prelude::any::<u64>(),
            n in 300usize..4000,
            gaps in 0usize..3,
            w in 64usize..300,
            s in 1usize..200,
        ) {
            let (mut data, temp) = ramp(n);
            let mut state = seed | 1;
            for _ in 0..gaps {
                state ^= state << 13;
                state ^= state >> 7;
                state ^= state << 17;
                // A lost stretch that may empty a window.
                let at = (state % n as u64) as usize;
                let len = (state >> 32) as usize % 300;
                for v in &mut data[at..(at + len).min(n)] {
                    *v = f64::NAN;
                }
            }
            let rate = 10.0;
            let slicing = Slicing::Time { window_s: w as f64 / rate, step_s: s as f64 / rate };
            let got = slices(&data, &temp, rate, slicing, allan::DEFAULT_CONFIDENCE).unwrap();
            let want = straightforward_windows(&data, &temp, rate, w, s);
            proptest::prop_assert_eq!(got.rows.len(), want.len());
            for (g, w) in got.rows.iter().zip(&want) {
                proptest::prop_assert_eq!((g.start, g.end, g.t_mean_c, g.t_change_c, g.samples), (w.0, w.1, w.2, w.3, w.4));
                proptest::prop_assert_eq!(&g.points, &w.5);
            }
            // What the copied windows dropped is listed, not lost.
            proptest::prop_assert_eq!(got.rows.len() + got.skipped.len(), (n - w) / s + 1);
        }
    }

    #[test]
    fn a_window_without_temperatures_is_labelled_by_the_samples_that_have_one() {
        let (data, mut temp) = ramp(3000);
        // The sensor's temperature lost for a while in the second window.
        for t in &mut temp[1100..1150] {
            *t = f64::NAN;
        }
        let s = hundred_second_slices(&data, &temp);
        assert_eq!(s.rows.len(), 3);
        let row = &s.rows[1];
        assert_eq!(row.samples, 950);
        let labelled: Vec<f64> = temp[1000..2000]
            .iter()
            .copied()
            .filter(|t| t.is_finite())
            .collect();
        let mean = labelled.iter().sum::<f64>() / labelled.len() as f64;
        assert!((row.t_mean_c - mean).abs() < 1e-9, "{} {mean}", row.t_mean_c);
    }

    #[test]
    fn slices_without_enough_samples_are_listed_with_the_reason() {
        let (mut data, temp) = ramp(3000);
        for v in &mut data[1000..1990] {
            *v = f64::NAN;
        }
        let s = hundred_second_slices(&data, &temp);
        assert_eq!(s.rows.len(), 2);
        assert_eq!(
            s.skipped,
            vec![SkippedSlice {
                start: 100.0,
                end: 200.0,
                reason: Skip::TooFewSamples { valid: 10 }
            }]
        );
        // A bin the ramp crosses in fewer samples than a slice needs: 20
        // samples per °C here, so 1 °C bins are all too short.
        let (data, temp) = ramp(1200);
        let s = slices(
            &data,
            &temp,
            10.0,
            Slicing::Temperature { bin_width_c: 1.0 },
            allan::DEFAULT_CONFIDENCE,
        )
        .unwrap();
        assert!(s.rows.is_empty());
        let mut visited: Vec<i64> = temp.iter().map(|t| t.floor() as i64).collect();
        visited.dedup();
        assert_eq!(s.skipped.len(), visited.len());
        assert!(
            s.skipped
                .iter()
                .all(|k| matches!(k.reason, Skip::TooFewSamples { valid } if valid < MIN_SLICE_SAMPLES))
        );
    }

    #[test]
    fn bins_finer_than_the_resolution_are_refused() {
        // 0.1 °C of ramp: few bins, but narrower than the quantum.
        let q = 1.0 / 333.87;
        let temp: Vec<f64> = (0..2000)
            .map(|i| (25.0 / q + (i / 100) as f64).round() * q)
            .collect();
        let data = vec![0.0; temp.len()];
        let e = surface(
            &data,
            &temp,
            100.0,
            Slicing::Temperature { bin_width_c: 1e-4 },
            allan::DEFAULT_CONFIDENCE,
        )
        .unwrap_err()
        .to_string();
        assert!(e.contains("finer than the temperature's resolution"), "{e}");
    }
}
