//! Kalibr's IMU noise model (`imu.yaml`) from the identified terms.

use std::fmt::Write as _;
use std::path::PathBuf;

use allan::noise_terms::{Chosen, NoiseTerms, Term};
use imu::Quantity;

use crate::AnalysisError;
use crate::selection::SelectedChannel;

/// One analysed channel, as the Kalibr file reads it.
pub struct KalibrChannel<'a> {
    /// The channel.
    pub channel: &'a SelectedChannel,
    /// Its noise terms.
    pub terms: &'a NoiseTerms,
}

/// The value written for Kalibr and how it was had, from the selected
/// model: its N; the upper end of its interval for K (a filter copes with
/// a random walk overstated, not with one understated, and K is the least
/// certain term of a record of hours); the term's upper bound where the
/// model does not hold it.
fn kalibr_value(r: &KalibrChannel, term: Term) -> Option<(f64, String)> {
    let choice = r.terms.choose(term);
    match choice.chosen {
        Chosen::Model(v) if term == Term::RateRandomWalk => Some((
            v.hi,
            format!("upper end of the model's interval (model {:.6e})", v.value),
        )),
        Chosen::Model(v) => Some((v.value, format!("model {}", r.terms.model.label))),
        Chosen::Bound(b) => Some((
            b,
            format!(
                "upper bound: {}",
                choice.note.as_deref().unwrap_or("not in the selected model")
            ),
        )),
        Chosen::Nothing => None,
    }
}

/// Kalibr's `imu.yaml` (the IMU noise model of ethz-asl/kalibr's wiki,
/// "IMU Noise Model") from the analysed channels of `files`: N and K of the
/// worst axis of each sensor, and how each axis's value was had, as
/// comments. `rate_hz` is the first recording's, `confidence` that of the
/// intervals.
pub fn kalibr_yaml(
    channels: &[KalibrChannel],
    files: &[PathBuf],
    rate_hz: f64,
    confidence: f64,
) -> Result<String, AnalysisError> {
    let mut text = String::new();
    let _ = writeln!(
        text,
        "# Kalibr IMU noise model written by imutherm {} from {}.",
        env!("CARGO_PKG_VERSION"),
        files
            .iter()
            .map(|f| f.display().to_string())
            .collect::<Vec<_>>()
            .join(", ")
    );
    let _ = writeln!(
        text,
        "# Continuous-time values (the selected noise model of the overlapping ADEV): *_noise_density = N, \
         *_random_walk = K; the worst axis of each sensor is used. Intervals at {:.1} %; bounds at the upper end \
         of the measured {:.0} % interval.",
        100.0 * confidence,
        100.0 * allan::noise_model::CEILING_CONFIDENCE
    );
    let mut values = Vec::new();
    for (q, sensor, n_unit, k_unit) in [
        (
            Quantity::Acceleration,
            "accelerometer",
            "m/s^2/sqrt(Hz)",
            "m/s^3/sqrt(Hz)",
        ),
        (
            Quantity::AngularRate,
            "gyroscope",
            "rad/s/sqrt(Hz)",
            "rad/s^2/sqrt(Hz)",
        ),
    ] {
        let axes: Vec<&KalibrChannel> = channels.iter().filter(|r| r.channel.quantity == q).collect();
        if axes.is_empty() {
            return Err(AnalysisError::Kalibr(format!(
                "no {sensor} channels in the input"
            )));
        }
        for (term, key, unit) in [
            (Term::WhiteNoise, "noise_density", n_unit),
            (Term::RateRandomWalk, "random_walk", k_unit),
        ] {
            let per_axis: Vec<(String, Option<(f64, String)>)> = axes
                .iter()
                .map(|r| {
                    (
                        format!("{} ({})", r.channel.name, r.channel.file.display()),
                        kalibr_value(r, term),
                    )
                })
                .collect();
            let worst = per_axis
                .iter()
                .filter_map(|(_, v)| v.as_ref().map(|v| v.0))
                .fold(f64::NAN, f64::max);
            if !(worst.is_finite() && worst > 0.0) {
                return Err(AnalysisError::Kalibr(format!(
                    "{sensor} {}: no axis has a curve to read it from, not even an upper bound",
                    term.symbol()
                )));
            }
            for (n, v) in &per_axis {
                let _ = writeln!(
                    text,
                    "# {sensor}_{key} {n}: {}",
                    v.as_ref().map_or_else(
                        || "nothing to read".to_string(),
                        |(v, how)| format!("{v:.6e} [{unit}], {how}")
                    )
                );
            }
            values.push((format!("{sensor}_{key}"), worst, unit));
        }
    }
    for (key, v, unit) in values {
        let _ = writeln!(text, "{key}: {v:.6e}  # {unit}");
    }
    let _ = writeln!(
        text,
        "rostopic: /imu0  # check: the topic your IMU publishes on\nupdate_rate: {}  # Hz, the recording's",
        imu::log_file::round_rate(rate_hz)
    );
    Ok(text)
}
