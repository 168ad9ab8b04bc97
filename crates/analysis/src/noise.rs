//! Each run's noise terms: every inertial channel's overlapping ADEV and
//! the noise model selected on it (`allan::noise_model`).

use std::path::Path;

use rayon::prelude::*;

use allan::Point;
use allan::noise_terms::{Chosen, NoiseTerms, Term, analyze_terms_vec};
use imu::{Quantity, RecordingOptions};

use crate::AnalysisError;
use crate::selection::{SelectedChannel, Selection, read_channels};
use crate::units::deg;

/// Confidence of the ADEV bands and term intervals in an experiment's
/// figures and tables.
pub const FIGURE_CONFIDENCE: f64 = 0.95;

/// One channel of one run, analysed.
pub struct ChannelNoise {
    /// The channel, its samples gone into the analysis (`data` is empty:
    /// several recordings' channels are held at once, and each is read
    /// again where its samples are wanted).
    pub channel: SelectedChannel,
    /// Number of samples the analysis took, gaps included.
    pub samples: usize,
    /// Mean of its finite samples (none without one), taken before they
    /// went into the analysis: the summary's bias slope across runs.
    pub mean: Option<f64>,
    /// Its OADEV at octave taus, [`FIGURE_CONFIDENCE`] intervals.
    pub points: Vec<Point>,
    /// Its noise terms.
    pub terms: NoiseTerms,
}

/// One run's channels, analysed.
pub struct RunNoise {
    /// The inertial channels, in the file's order.
    pub channels: Vec<ChannelNoise>,
    /// The run's mean temperature, °C.
    pub temperature_mean_c: Option<f64>,
    /// What the reader found ([`crate::selection::Selection::notes`]).
    pub notes: Vec<String>,
}

/// Reads the inertial channels of a run and identifies their noise terms.
pub fn analyse_run(path: &Path, read: &RecordingOptions) -> Result<RunNoise, AnalysisError> {
    analyse_selection(path, read_channels(path, &[], read)?)
}

/// [`analyse_run`] of the channels already read from `path`.
pub fn analyse_selection(path: &Path, sel: Selection) -> Result<RunNoise, AnalysisError> {
    let rate = sel.rate_hz;
    let channels = sel
        .channels
        .into_par_iter()
        .map(|mut channel| {
            let data = std::mem::take(&mut channel.data);
            let samples = data.len();
            let (n, sum) = data
                .iter()
                .filter(|x| x.is_finite())
                .fold((0usize, 0.0), |(n, s), x| (n + 1, s + x));
            let mean = (n > 0).then(|| sum / n as f64);
            let (points, terms) = analyze_terms_vec(data, rate, FIGURE_CONFIDENCE).map_err(
                AnalysisError::allan(format!("{}: {}", path.display(), channel.name)),
            )?;
            Ok(ChannelNoise {
                channel,
                samples,
                mean,
                points,
                terms,
            })
        })
        .collect::<Result<Vec<_>, AnalysisError>>()?;
    Ok(RunNoise {
        channels,
        temperature_mean_c: sel.temperature_mean_c,
        notes: sel.notes,
    })
}

/// The one answer for `term` ([`NoiseTerms::choose`]) in the thesis's
/// units, to four decimals: the selected model's value, or its upper bound
/// as "≤ …" where the model does not hold the term.
pub fn held_value(quantity: Quantity, terms: &NoiseTerms, term: Term) -> String {
    let f = deg(quantity);
    match terms.choose(term).chosen {
        Chosen::Model(v) => format!("{:.4}", v.value * f),
        Chosen::Bound(b) => format!("≤ {:.4}", b * f),
        Chosen::Nothing => "—".to_string(),
    }
}
