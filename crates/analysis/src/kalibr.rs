//! Kalibr's IMU noise model (`imu.yaml`) from the identified terms.

use std::fmt::Write as _;
use std::path::PathBuf;

use allan::noise_terms::{Chosen, NoiseTerms, Term};
use imu::Quantity;

use crate::AnalysisError;
use crate::filters::FilterParam;
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
fn kalibr_value(terms: &NoiseTerms, term: Term) -> Option<(f64, String)> {
    let choice = terms.choose(term);
    match choice.chosen {
        Chosen::Model(v) if term == Term::RateRandomWalk => Some((
            v.hi,
            format!("upper end of the model's interval (model {:.6e})", v.value),
        )),
        Chosen::Model(v) => Some((v.value, format!("model {}", terms.model.label))),
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

/// Kalibr's sensors: quantity, name, and the units of `*_noise_density`
/// and `*_random_walk` (ethz-asl/kalibr wiki, "IMU Noise Model").
const SENSORS: [(Quantity, &str, &str, &str); 2] = [
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
];

/// One axis's Kalibr values, as the file's per-axis comments give them:
/// `*_noise_density` = N and `*_random_walk` = K (continuous-time, so no
/// Δt), each with where it came from; `None` for a channel that is neither
/// gyro nor accelerometer.
pub fn kalibr_params(quantity: Quantity, terms: &NoiseTerms) -> Option<Vec<FilterParam>> {
    let (_, _, n_unit, k_unit) = SENSORS.into_iter().find(|s| s.0 == quantity)?;
    let names = if quantity == Quantity::AngularRate {
        ["gyroscope_noise_density", "gyroscope_random_walk"]
    } else {
        ["accelerometer_noise_density", "accelerometer_random_walk"]
    };
    Some(
        [
            (Term::WhiteNoise, names[0], n_unit, "N"),
            (Term::RateRandomWalk, names[1], k_unit, "K"),
        ]
        .into_iter()
        .filter_map(|(term, name, unit, sym)| {
            kalibr_value(terms, term).map(|(value, source)| FilterParam {
                name,
                value,
                unit,
                formula: format!("{sym}, a continuous-time density (no Δt)"),
                source,
            })
        })
        .collect(),
    )
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
    for (q, sensor, n_unit, k_unit) in SENSORS {
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
                        kalibr_value(r.terms, term),
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

#[cfg(test)]
mod tests {
    use super::*;
    use allan::noise_terms::analyze_terms;

    /// Gaussian white noise of density `n` at `rate` Hz (per-sample σ =
    /// n·√rate), from a fixed xorshift generator and Box–Muller.
    fn white(n: f64, rate: f64, len: usize) -> Vec<f64> {
        let mut s = 0x9e37_79b9_7f4a_7c15u64;
        let mut u = || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            ((s >> 11) as f64 + 0.5) / (1u64 << 53) as f64
        };
        (0..len)
            .map(|_| n * rate.sqrt() * (-2.0 * u().ln()).sqrt() * (std::f64::consts::TAU * u()).cos())
            .collect()
    }

    #[test]
    fn the_per_axis_values_are_the_models_n_and_ks_bound() {
        let (n, rate) = (2e-4, 100.0);
        let (_, terms) = analyze_terms(&white(n, rate, 200_000), rate, 0.95).unwrap();
        let p = kalibr_params(Quantity::AngularRate, &terms).unwrap();
        assert_eq!(p[0].name, "gyroscope_noise_density");
        assert_eq!(p[0].unit, "rad/s/sqrt(Hz)");
        let model_n = terms
            .model
            .get(Term::WhiteNoise)
            .value()
            .expect("N in the model")
            .value;
        assert_eq!(p[0].value, model_n);
        // White noise of density n: N within 5 % of it (2000 s, the
        // shortest τ holds ~10^5 degrees of freedom).
        assert!((model_n / n - 1.0).abs() < 0.05, "N = {model_n}");
        // No random walk in the data: K is its bound.
        assert_eq!(p[1].name, "gyroscope_random_walk");
        assert_eq!(p[1].unit, "rad/s^2/sqrt(Hz)");
        assert_eq!(Some(p[1].value), terms.model.bound(Term::RateRandomWalk));
        assert!(p[1].source.starts_with("upper bound"), "{}", p[1].source);
        let a = kalibr_params(Quantity::Acceleration, &terms).unwrap();
        assert_eq!(a[0].name, "accelerometer_noise_density");
        assert_eq!(a[1].unit, "m/s^3/sqrt(Hz)");
        assert!(kalibr_params(Quantity::Temperature, &terms).is_none());
    }
}
