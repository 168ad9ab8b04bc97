//! The `imutherm.thermal/1` JSON document of `imutherm thermal --json`, as
//! types: each channel's deviation curves over temperature bins or time
//! windows, with the noise terms fitted to each slice.
//!
//! The document was first written from untyped maps, which serde_json
//! serialises with their keys sorted; its consumers read that order, so
//! every struct below declares its fields in the byte order of their JSON
//! names (capitals first: `B`, `K`, `N`, `sigma_min`). The schema only
//! gains fields (`over_temperature`, each term's law over the slices, is
//! new).

use allan::Point;
use allan::noise_terms::{Term, TermEstimate, TermValue};
use serde::Serialize;
use thermal::surface::{SkippedSlice, Slicing, Surface, SurfaceRow};

use crate::term_law::{LawEntry, surface_laws};

/// The schema's name and version.
pub const SCHEMA: &str = "imutherm.thermal/1";

/// One channel's slices, as [`thermal::surface::slices`] computed them.
#[derive(Debug, Clone, Copy)]
pub struct SlicedChannel<'a> {
    /// Its name.
    pub name: &'a str,
    /// The data's unit.
    pub unit: &'a str,
    /// Its curves per slice, and the slices without one.
    pub surface: &'a Surface,
}

/// The whole document.
#[derive(Debug, Serialize)]
pub struct ThermalDocument {
    /// How the recording was cut: `temperature` or `time`.
    pub by: &'static str,
    /// One entry per channel, in the order read.
    pub channels: Vec<ThermalChannel>,
    /// Confidence of every interval.
    pub confidence: f64,
    /// The file analysed, as the user named it.
    pub file: String,
    /// The writing imutherm's version.
    pub imutherm_version: &'static str,
    /// The recording's rate, Hz.
    pub rate_hz: f64,
    /// [`SCHEMA`].
    pub schema: &'static str,
}

/// One channel's slices.
#[derive(Debug, Serialize)]
pub struct ThermalChannel {
    /// Its name.
    pub name: String,
    /// N, B and K over the slices' mean temperatures: each term's law and
    /// every pair of slices compared ([`crate::term_law`]); empty where
    /// time windows overlap (their terms are not independent).
    pub over_temperature: Vec<LawEntry>,
    /// One row per slice with a curve, in order.
    pub rows: Vec<ThermalRow>,
    /// The slices with samples but no curve.
    pub skipped: Vec<ThermalSkipped>,
    /// The data's unit.
    pub unit: String,
}

/// One slice's curve and noise terms.
#[derive(Debug, Serialize)]
pub struct ThermalRow {
    /// The slice's end: °C (temperature bins) or s (time windows).
    pub end: f64,
    /// The slice's deviation curve.
    pub points: Vec<ThermalPoint>,
    /// Samples in the slice.
    pub samples: usize,
    /// The slice's start, in the unit of `end`.
    pub start: f64,
    /// Temperature change across the slice, °C.
    pub t_change_c: f64,
    /// Mean temperature of the slice, °C.
    pub t_mean_c: f64,
    /// The noise terms fitted to the curve.
    pub terms: ThermalTerms,
}

/// One τ of a slice's curve.
#[derive(Debug, Serialize)]
pub struct ThermalPoint {
    /// The deviation.
    pub dev: f64,
    /// Upper end of the interval.
    pub dev_hi: f64,
    /// Lower end of the interval.
    pub dev_lo: f64,
    /// Equivalent degrees of freedom.
    pub edf: f64,
    /// τ in samples.
    pub m: usize,
    /// Terms averaged.
    pub n: usize,
    /// τ, s.
    pub tau: f64,
}

/// The model's terms of a slice, and the curve's minimum.
#[derive(Debug, Serialize)]
pub struct ThermalTerms {
    /// Bias instability.
    #[serde(rename = "B")]
    pub bias_instability: ThermalTerm,
    /// Rate random walk.
    #[serde(rename = "K")]
    pub rate_random_walk: ThermalTerm,
    /// White noise.
    #[serde(rename = "N")]
    pub white_noise: ThermalTerm,
    /// The curve's lowest deviation (slope method), if it has one.
    pub sigma_min: Option<SigmaMin>,
}

/// A term with its interval, or why the data cannot show it.
#[derive(Debug, Serialize)]
#[serde(untagged)]
pub enum ThermalTerm {
    /// Identified.
    Value {
        /// Upper bound.
        hi: f64,
        /// Lower bound.
        lo: f64,
        /// The estimate.
        value: f64,
    },
    /// Not identifiable.
    NotIdentifiable {
        /// What the data lacks.
        reason: String,
    },
}

/// The curve's lowest deviation and where it lies.
#[derive(Debug, Serialize)]
pub struct SigmaMin {
    /// τ of the point, s (absent when the estimate carries none).
    pub tau: Option<f64>,
    /// The deviation.
    pub value: f64,
}

/// A slice with samples but no curve.
#[derive(Debug, Serialize)]
pub struct ThermalSkipped {
    /// The slice's end.
    pub end: f64,
    /// Why it has no curve.
    pub reason: String,
    /// The slice's start.
    pub start: f64,
}

/// The `by` field's name of a slicing.
pub fn slicing_name(slicing: Slicing) -> &'static str {
    match slicing {
        Slicing::Temperature { .. } => "temperature",
        Slicing::Time { .. } => "time",
    }
}

impl ThermalDocument {
    /// The document of `channels`, sliced by `slicing` from `file` read at
    /// `rate_hz`, written by imutherm `version`.
    pub fn new(
        imutherm_version: &'static str,
        file: String,
        slicing: Slicing,
        rate_hz: f64,
        confidence: f64,
        channels: &[SlicedChannel<'_>],
    ) -> Self {
        ThermalDocument {
            by: slicing_name(slicing),
            channels: channels
                .iter()
                .map(|c| ThermalChannel::of(c, slicing, confidence))
                .collect(),
            confidence,
            file,
            imutherm_version,
            rate_hz,
            schema: SCHEMA,
        }
    }
}

impl ThermalChannel {
    fn of(ch: &SlicedChannel<'_>, slicing: Slicing, confidence: f64) -> Self {
        ThermalChannel {
            name: ch.name.to_owned(),
            over_temperature: surface_laws(ch.surface, slicing, confidence)
                .unwrap_or_default()
                .iter()
                .map(|law| LawEntry::new(ch.name, law))
                .collect(),
            rows: ch.surface.rows.iter().map(ThermalRow::of).collect(),
            skipped: ch.surface.skipped.iter().map(ThermalSkipped::of).collect(),
            unit: ch.unit.to_owned(),
        }
    }
}

impl ThermalRow {
    fn of(r: &SurfaceRow) -> Self {
        ThermalRow {
            end: r.end,
            points: r.points.iter().map(ThermalPoint::of).collect(),
            samples: r.samples,
            start: r.start,
            t_change_c: r.t_change_c,
            t_mean_c: r.t_mean_c,
            terms: ThermalTerms {
                bias_instability: ThermalTerm::of(r.terms.model.get(Term::BiasInstability)),
                rate_random_walk: ThermalTerm::of(r.terms.model.get(Term::RateRandomWalk)),
                white_noise: ThermalTerm::of(r.terms.model.get(Term::WhiteNoise)),
                sigma_min: r.terms.slope.sigma_min.as_ref().map(SigmaMin::of),
            },
        }
    }
}

impl ThermalPoint {
    fn of(p: &Point) -> Self {
        ThermalPoint {
            dev: p.dev,
            dev_hi: p.dev_hi,
            dev_lo: p.dev_lo,
            edf: p.edf,
            m: p.m,
            n: p.n,
            tau: p.tau,
        }
    }
}

impl ThermalTerm {
    fn of(e: &TermEstimate) -> Self {
        match e {
            TermEstimate::Value(v) => ThermalTerm::Value {
                hi: v.hi,
                lo: v.lo,
                value: v.value,
            },
            TermEstimate::NotIdentifiable(why) => ThermalTerm::NotIdentifiable { reason: why.clone() },
        }
    }
}

impl SigmaMin {
    fn of(m: &TermValue) -> Self {
        SigmaMin {
            tau: m.tau,
            value: m.value,
        }
    }
}

impl ThermalSkipped {
    fn of(k: &SkippedSlice) -> Self {
        ThermalSkipped {
            end: k.end,
            reason: k.reason.to_string(),
            start: k.start,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use thermal::surface::slices;

    /// A recording warming linearly over 20 °C with white noise, long
    /// enough for two 10 °C bins to carry a curve each.
    fn warming() -> (Vec<f64>, Vec<f64>) {
        let n = 8000;
        let data = allan::work::uniform(0x2545_f491_4f6c_dd1d)
            .take(n)
            .map(|u| u - 0.5)
            .collect();
        let temp = (0..n).map(|i| 20.0 + 20.0 * i as f64 / n as f64).collect();
        (data, temp)
    }

    #[test]
    fn keys_are_written_in_the_schemas_order() {
        let (data, temp) = warming();
        let slicing = Slicing::Temperature { bin_width_c: 10.0 };
        let surface = slices(&data, &temp, 100.0, slicing, 0.683).unwrap();
        assert!(!surface.rows.is_empty());
        let ch = SlicedChannel {
            name: "gyro_z",
            unit: "rad/s",
            surface: &surface,
        };
        let doc = ThermalDocument::new("V", "f.txt".into(), slicing, 100.0, 0.683, &[ch]);
        let text = serde_json::to_string(&doc).unwrap();
        // The untyped map the document was first written from sorted its
        // keys; a Value re-sorts them, so equal text means the same order.
        // (`to_value`, not a parse of the text, keeps every float exact.)
        let value = serde_json::to_value(&doc).unwrap();
        assert_eq!(serde_json::to_string(&value).unwrap(), text);
        assert_eq!(value["schema"], SCHEMA);
        assert_eq!(value["by"], "temperature");
        let row = &value["channels"][0]["rows"][0];
        assert_eq!(
            row["points"].as_array().unwrap().len(),
            surface.rows[0].points.len()
        );
        for key in ["B", "K", "N"] {
            let term = &row["terms"][key];
            assert!(
                term.get("value").is_some() != term.get("reason").is_some(),
                "{key}: {term}"
            );
        }
    }

    #[test]
    fn time_windows_are_named_time() {
        let slicing = Slicing::Time {
            window_s: 10.0,
            step_s: 5.0,
        };
        let doc = ThermalDocument::new("V", String::new(), slicing, 1.0, 0.683, &[]);
        assert_eq!(doc.by, "time");
        assert!(doc.channels.is_empty());
    }
}
