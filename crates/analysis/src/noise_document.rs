//! The `imutherm.noise/1` JSON document of `imutherm noise --json`, as
//! types. The schema only gains fields: those of the former slope method
//! and fit (`slope`, `fit`, `chosen`, `fit_chi2_reduced`, `fit_points`,
//! `fit_left_out_taus`, `disagreements`) are kept and filled from the one
//! selected noise model; `model`, `filters` and `state_space` are new, and
//! `over_temperature` (the terms' law over the files' temperatures).

use std::path::PathBuf;

use allan::noise_model::NoiseModel;
use allan::noise_terms::{Chosen, Minimum, NoiseTerms, Term, TermEstimate, TermValue};
use serde::Serialize;

use crate::filters::{FilterParams, StateSpaceTerm, filter_params, gauss_markov_state_space};
use crate::selection::SelectedChannel;
use crate::term_law::LawEntry;
use crate::thesis::ThesisTables;
use crate::units::{Units, density_of, unit_of};

/// The schema's name and version.
pub const SCHEMA: &str = "imutherm.noise/1";

/// The whole document.
#[derive(Debug, Serialize)]
pub struct NoiseDocument {
    /// [`SCHEMA`].
    pub schema: &'static str,
    /// The writing imutherm's version.
    pub imutherm_version: &'static str,
    /// Confidence of every interval.
    pub confidence: f64,
    /// "si" or "datasheet": the units of the text output (the JSON gives
    /// both).
    pub units: &'static str,
    /// One entry per input file.
    pub files: Vec<FileEntry>,
    /// With two or more files at known temperatures: each axis's N, B
    /// and K over the files' temperatures, its law and every pair of
    /// files compared ([`crate::term_law`]); empty otherwise.
    pub over_temperature: Vec<LawEntry>,
}

/// One input file.
#[derive(Debug, Serialize)]
pub struct FileEntry {
    /// Its path.
    pub file: String,
    /// Its temperature column's mean, °C; where it has no such column,
    /// the temperature its metadata states (`temperature_c`).
    pub mean_temperature_c: Option<f64>,
    /// Its sample rate, Hz.
    pub rate_hz: f64,
    /// Its analysed channels.
    pub channels: Vec<ChannelEntry>,
    /// What reading it found and said (an override against the file, a
    /// clock, problems), as the text output prints them.
    pub notes: Vec<String>,
}

/// A value with its interval and unit.
#[derive(Debug, Clone, Serialize)]
pub struct JsonValue {
    /// The value.
    pub value: f64,
    /// Lower end.
    pub lo: f64,
    /// Upper end.
    pub hi: f64,
    /// Unit.
    pub unit: String,
}

/// One term as the former per-method lists gave it.
#[derive(Debug, Serialize)]
pub struct JsonTerm {
    /// Q, N, B, K or R.
    pub term: &'static str,
    /// Its snake-case name.
    pub name: &'static str,
    /// The list it is in ("slope" or "fit"; both now hold the model's).
    pub method: &'static str,
    /// Whether the model holds it.
    pub identified: bool,
    /// In SI.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub si: Option<JsonValue>,
    /// In the datasheets' units.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub datasheet: Option<JsonValue>,
    /// White noise as the datasheets quote it: a density per √Hz.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub density: Option<JsonValue>,
    /// τ it was read at (none for a fitted model).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tau: Option<f64>,
    /// Why it is not a value.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub reason: Option<String>,
}

/// The one answer for a term.
#[derive(Debug, Serialize)]
pub struct ChosenEntry {
    /// Q, N, B, K or R.
    pub term: &'static str,
    /// "fit" (the model's value), "upper_bound" or "none".
    pub method: &'static str,
    /// In SI.
    pub si: Option<JsonValue>,
    /// Always false: one estimator cannot disagree with itself.
    pub disagree: bool,
    /// Why the term is only bounded.
    pub note: Option<String>,
}

/// A slope stretch of the IEEE 952 reading (kept for σ_min's context).
#[derive(Debug, Serialize)]
pub struct Stretch {
    /// The term whose slope held.
    pub term: &'static str,
    /// From τ, s.
    pub tau_from: f64,
    /// To τ, s.
    pub tau_to: f64,
}

/// σ_min with its interval.
#[derive(Debug, Serialize)]
pub struct SigmaMin {
    /// In SI.
    pub si: JsonValue,
    /// In the datasheets' units.
    pub datasheet: JsonValue,
    /// Its τ, s.
    pub tau: Option<f64>,
}

/// A reading of the thesis's script.
#[derive(Debug, Serialize)]
pub struct ThesisValue {
    /// In SI.
    pub si: JsonValue,
    /// Its τ, s.
    pub tau: Option<f64>,
}

/// The thesis's own reading, by name.
#[derive(Debug, Serialize)]
pub struct ThesisReadingEntry {
    /// What it does.
    pub method: &'static str,
    /// N.
    #[serde(rename = "N")]
    pub n: Option<ThesisValue>,
    /// B.
    #[serde(rename = "B")]
    pub b: Option<ThesisValue>,
}

/// A Gauss–Markov term of the model.
#[derive(Debug, Serialize)]
pub struct GaussMarkovEntry {
    /// σ in the unit of the data.
    pub sigma: JsonValue,
    /// T, s.
    pub tau_c: JsonValue,
}

/// A candidate model and its criterion.
#[derive(Debug, Serialize)]
pub struct CandidateEntry {
    /// Its processes.
    pub label: String,
    /// χ² + p·ln n.
    pub criterion: f64,
    /// χ² of its fit.
    pub chi2: f64,
    /// Its parameter count.
    pub parameters: usize,
}

/// Where the best candidate parts from the curve, when no candidate fits.
#[derive(Debug, Serialize)]
pub struct DefeatEntry {
    /// The candidate ("N + K").
    pub candidate: String,
    /// The process whose own line exceeds the measured deviation's 99 %
    /// upper end ("K"); null where the candidate's whole curve misses.
    pub process: Option<String>,
    /// τ of the point, s.
    pub tau: f64,
    /// The measured deviation over the candidate's (or the process's) there.
    pub ratio: f64,
    /// The miss in the point's standard deviations (a misfit only).
    pub sigmas: Option<f64>,
    /// The same in one sentence.
    pub text: String,
}

/// The selected noise model.
#[derive(Debug, Serialize)]
pub struct ModelEntry {
    /// Its processes ("N + K").
    pub label: String,
    /// Whether it describes the curve (p ≥ 0.01).
    pub fits: bool,
    /// χ² on ln σ̂².
    pub chi2: Option<f64>,
    /// Points − parameters.
    pub dof: Option<usize>,
    /// χ²/dof.
    pub chi2_reduced: Option<f64>,
    /// P(χ²_dof ≥ χ²).
    pub p_value: Option<f64>,
    /// Its information criterion.
    pub criterion: Option<f64>,
    /// Points fitted.
    pub points: usize,
    /// τ of the points left out, s.
    pub left_out_taus: Vec<f64>,
    /// τ where its curve leaves the measured interval, s.
    pub outside_taus: Vec<f64>,
    /// Per process: how much worse the criterion is without it.
    pub evidence: Vec<(String, f64)>,
    /// The best admissible candidates.
    pub candidates: Vec<CandidateEntry>,
    /// Its Gauss–Markov terms.
    pub gauss_markov: Vec<GaussMarkovEntry>,
    /// Each term's upper bound in SI (null: no point to set one).
    pub bounds: Vec<(String, Option<f64>)>,
    /// Where no candidate fits: where the best one parts from the curve
    /// (null where the model fits).
    pub defeat: Option<DefeatEntry>,
    /// Whether the model fits within the points' own noise (p ≥ 0.01);
    /// `fits` also holds where every point lies within 5 % of the model, the misfit widening the intervals.
    pub within_noise: bool,
    /// The τ range the model was fitted over (null without a model).
    pub fit_range: Option<FitRangeEntry>,
    /// The low-pass filter the white noise passes through, where the
    /// curve's shortest τ show one (null otherwise): N is the white noise
    /// before it.
    pub low_pass: Option<LowPassEntry>,
    /// A periodic disturbance fitted beside the noise processes, where the
    /// curve has a sinusoid's bump the family alone does not describe
    /// (null otherwise): named, never a noise term.
    pub periodic: Option<PeriodicEntry>,
}

/// A periodic disturbance: a sinusoid of the rate data.
#[derive(Debug, Serialize)]
pub struct PeriodicEntry {
    /// Its amplitude (peak), in the unit of the data.
    pub amplitude: f64,
    /// The unit of `amplitude`.
    pub unit: String,
    /// Its period, s.
    pub period_s: f64,
    /// Its frequency, Hz.
    pub frequency_hz: f64,
    /// The same in one sentence.
    pub text: String,
}

/// The τ range a model was fitted over.
#[derive(Debug, Serialize)]
pub struct FitRangeEntry {
    /// Shortest τ, s.
    pub lo: f64,
    /// Longest τ, s.
    pub hi: f64,
    /// Whether it is the whole curve.
    pub whole: bool,
    /// Each point beyond it: τ (s) and measured/model.
    pub misses: Vec<(f64, f64)>,
    /// The same in one sentence.
    pub text: String,
}

/// A first-order low-pass filter on the white noise.
#[derive(Debug, Serialize)]
pub struct LowPassEntry {
    /// Its time constant, s.
    pub tau_c: JsonValue,
    /// Its −3 dB frequency, Hz.
    pub cutoff_hz: f64,
}

/// One channel.
#[derive(Debug, Serialize)]
pub struct ChannelEntry {
    /// Its name.
    pub name: String,
    /// What it measures.
    pub quantity: &'static str,
    /// Its data unit.
    pub unit: String,
    /// Where the unit came from.
    pub unit_source: &'static str,
    /// Where the ADEV minimum lies.
    pub minimum: &'static str,
    /// EDF a point needs for σ_min.
    pub sigma_min_min_edf: f64,
    /// The IEEE 952 slope stretches found.
    pub slope_stretches: Vec<Stretch>,
    /// The model's left-out τ (as `model.left_out_taus`).
    pub fit_left_out_taus: Vec<f64>,
    /// The thesis's reading.
    pub thesis_reading: ThesisReadingEntry,
    /// One answer per term.
    pub chosen: Vec<ChosenEntry>,
    /// Samples analysed.
    pub samples: usize,
    /// σ_min.
    pub sigma_min: Option<SigmaMin>,
    /// The model's terms (the former slope list).
    pub slope: Vec<JsonTerm>,
    /// The model's terms (the former fit list).
    pub fit: Vec<JsonTerm>,
    /// The model's χ²/dof.
    pub fit_chi2_reduced: Option<f64>,
    /// Points fitted.
    pub fit_points: usize,
    /// Always empty: one estimator.
    pub disagreements: Vec<String>,
    /// The selected noise model.
    pub model: ModelEntry,
    /// PX4 EKF2 and ArduPilot EKF3 parameters (gyros and accelerometers).
    pub filters: Option<Vec<FilterParams>>,
    /// The model as a state-space form.
    pub state_space: Vec<StateSpaceTerm>,
}

/// One analysed channel, as the document reads it.
pub struct ChannelInput<'a> {
    /// Index of its file.
    pub file_index: usize,
    /// The channel.
    pub channel: &'a SelectedChannel,
    /// Samples analysed.
    pub samples: usize,
    /// Its noise terms.
    pub terms: &'a NoiseTerms,
}

fn json_value(v: &TermValue, term: Term, ch: &SelectedChannel, units: Units) -> JsonValue {
    let (f, unit) = unit_of(term, ch.quantity, &ch.unit, units);
    JsonValue {
        value: v.value * f,
        lo: v.lo * f,
        hi: v.hi * f,
        unit,
    }
}

fn interval(v: &TermValue, unit: &str) -> JsonValue {
    JsonValue {
        value: v.value,
        lo: v.lo,
        hi: v.hi,
        unit: unit.to_string(),
    }
}

fn json_term(term: Term, est: &TermEstimate, method: &'static str, ch: &SelectedChannel) -> JsonTerm {
    match est {
        TermEstimate::Value(v) => JsonTerm {
            term: term.symbol(),
            name: term.name(),
            method,
            identified: true,
            si: Some(json_value(v, term, ch, Units::Si)),
            datasheet: Some(json_value(v, term, ch, Units::Datasheet)),
            density: density_of(ch.quantity)
                .filter(|_| term == Term::WhiteNoise)
                .map(|(f, u)| JsonValue {
                    value: v.value * f,
                    lo: v.lo * f,
                    hi: v.hi * f,
                    unit: u.to_string(),
                }),
            tau: v.tau,
            reason: None,
        },
        TermEstimate::NotIdentifiable(why) => JsonTerm {
            term: term.symbol(),
            name: term.name(),
            method,
            identified: false,
            si: None,
            datasheet: None,
            density: None,
            tau: None,
            reason: Some(why.clone()),
        },
    }
}

/// The document's entry for a selected model of data in `unit` (the
/// Gauss–Markov σ's unit).
pub fn model_entry(m: &NoiseModel, unit: &str) -> ModelEntry {
    ModelEntry {
        label: m.label.clone(),
        fits: m.fits,
        chi2: m.quality.map(|q| q.chi2),
        dof: m.quality.map(|q| q.dof),
        chi2_reduced: m.chi2_reduced,
        p_value: m.quality.map(|q| q.p_value),
        criterion: m.quality.map(|q| q.criterion),
        points: m.points,
        left_out_taus: m.left_out.clone(),
        outside_taus: m.outside.clone(),
        evidence: m.evidence.clone(),
        candidates: m
            .candidates
            .iter()
            .map(|c| CandidateEntry {
                label: c.label.clone(),
                criterion: c.criterion,
                chi2: c.chi2,
                parameters: c.parameters,
            })
            .collect(),
        gauss_markov: m
            .gauss_markov
            .iter()
            .map(|g| GaussMarkovEntry {
                sigma: interval(&g.sigma, unit),
                tau_c: interval(&g.tau_c, "s"),
            })
            .collect(),
        bounds: Term::ALL
            .iter()
            .map(|&t| (t.symbol().to_string(), m.bound(t)))
            .collect(),
        defeat: m.defeat.as_ref().map(|d| DefeatEntry {
            candidate: d.candidate.clone(),
            process: d.process.clone(),
            tau: d.tau,
            ratio: d.ratio,
            sigmas: d.sigmas,
            text: d.describe(),
        }),
        within_noise: m.within_noise,
        fit_range: m.fit_range.as_ref().map(|r| FitRangeEntry {
            lo: r.lo,
            hi: r.hi,
            whole: r.whole,
            misses: r.misses.iter().map(|x| (x.tau, x.ratio)).collect(),
            text: r.describe(),
        }),
        low_pass: m.low_pass.map(|f| LowPassEntry {
            tau_c: interval(&f.tau_c, "s"),
            cutoff_hz: f.cutoff_hz,
        }),
        periodic: m.periodic.map(|t| PeriodicEntry {
            amplitude: t.amplitude,
            unit: unit.to_string(),
            period_s: t.period,
            frequency_hz: t.frequency_hz,
            text: t.describe(unit),
        }),
    }
}

fn channel_entry(c: &ChannelInput) -> ChannelEntry {
    let (ch, terms) = (c.channel, c.terms);
    let model_list = |method| {
        Term::ALL
            .iter()
            .map(|&t| json_term(t, terms.model.get(t), method, ch))
            .collect()
    };
    let chosen = Term::ALL
        .iter()
        .map(|&t| {
            let choice = terms.choose(t);
            let (method, si) = match choice.chosen {
                Chosen::Model(v) => ("fit", Some(json_value(&v, t, ch, Units::Si))),
                Chosen::Bound(b) => {
                    let (f, unit) = unit_of(t, ch.quantity, &ch.unit, Units::Si);
                    (
                        "upper_bound",
                        Some(JsonValue {
                            value: b * f,
                            lo: 0.0,
                            hi: b * f,
                            unit,
                        }),
                    )
                }
                Chosen::Nothing => ("none", None),
            };
            ChosenEntry {
                term: t.symbol(),
                method,
                si,
                disagree: false,
                note: choice.note,
            }
        })
        .collect();
    let thesis = &terms.slope.thesis;
    let reading = |v: Option<TermValue>, t: Term| {
        v.map(|v| ThesisValue {
            si: json_value(&v, t, ch, Units::Si),
            tau: v.tau,
        })
    };
    ChannelEntry {
        name: ch.name.clone(),
        quantity: ch.quantity.name(),
        unit: ch.unit.clone(),
        unit_source: ch.unit_source.name(),
        minimum: match terms.slope.minimum {
            Minimum::Found => "found",
            Minimum::StillFalling => "still_falling",
            Minimum::RisesFromStart => "rises_from_start",
            Minimum::Unknown => "unknown",
        },
        sigma_min_min_edf: allan::noise_terms::MIN_EDF,
        slope_stretches: terms
            .slope
            .stretches
            .iter()
            .map(|&(t, a, b)| Stretch {
                term: t.symbol(),
                tau_from: a,
                tau_to: b,
            })
            .collect(),
        fit_left_out_taus: terms.model.left_out.clone(),
        thesis_reading: ThesisReadingEntry {
            method: "analyzeAllan.m: N on the -1/2 line through the slope nearest -1/2; B = sigma at the first \
                     positive slope / 0.664",
            n: reading(thesis.n, Term::WhiteNoise),
            b: reading(thesis.b, Term::BiasInstability),
        },
        chosen,
        samples: c.samples,
        sigma_min: terms.slope.sigma_min.map(|v| SigmaMin {
            si: json_value(&v, Term::BiasInstability, ch, Units::Si),
            datasheet: json_value(&v, Term::BiasInstability, ch, Units::Datasheet),
            tau: v.tau,
        }),
        slope: model_list("slope"),
        fit: model_list("fit"),
        fit_chi2_reduced: terms.model.chi2_reduced,
        fit_points: terms.model.points,
        disagreements: Vec::new(),
        model: model_entry(&terms.model, &ch.unit),
        filters: filter_params(ch.quantity, terms),
        state_space: gauss_markov_state_space(&terms.model),
    }
}

impl NoiseDocument {
    /// The document of `channels` read from `files`, with each file's mean
    /// temperature and rate; `units` names the text output's units.
    pub fn new(
        files: &[PathBuf],
        temps: &[Option<f64>],
        rates: &[f64],
        channels: &[ChannelInput],
        confidence: f64,
        units: Units,
    ) -> NoiseDocument {
        let tables = ThesisTables::new(
            temps.to_vec(),
            channels.iter().map(|c| (c.file_index, c.channel, c.terms)),
        );
        let over_temperature = if tables.over_temperature() {
            tables
                .laws(confidence)
                .iter()
                .map(|(name, law)| LawEntry::new(name, law))
                .collect()
        } else {
            Vec::new()
        };
        NoiseDocument {
            over_temperature,
            schema: SCHEMA,
            imutherm_version: env!("CARGO_PKG_VERSION"),
            confidence,
            units: match units {
                Units::Si => "si",
                _ => "datasheet",
            },
            files: files
                .iter()
                .enumerate()
                .map(|(i, f)| FileEntry {
                    file: f.display().to_string(),
                    mean_temperature_c: temps[i],
                    rate_hz: rates[i],
                    channels: channels
                        .iter()
                        .filter(|c| c.file_index == i)
                        .map(channel_entry)
                        .collect(),
                    notes: Vec::new(),
                })
                .collect(),
        }
    }

    /// The document with each file's reading notes, in the files' order.
    pub fn with_notes(mut self, notes: Vec<Vec<String>>) -> Self {
        for (f, n) in self.files.iter_mut().zip(notes) {
            f.notes = n;
        }
        self
    }
}
