//! Each noise term's law over temperature, and whether it is real: from
//! the terms of several constant-temperature runs (or of a sweep's
//! temperature bins), the slope of ln(term) against temperature by
//! weighted least squares, its interval and its test against zero, and
//! every pair of temperatures compared by a two-sample z test on ln(term).
//!
//! **The weights are the noise model's own intervals.** `allan::noise_model`
//! gives a term as `exp(θ/2)` with the interval `exp((θ ± q·sd)/2)`: it is
//! symmetric in ln(term), and only its upper end may be cut by the measured
//! ceiling. q is the normal quantile of its confidence where the spread
//! rests on the points' covariance alone, and Student's t on the fit's
//! degrees of freedom where the fit's own scatter exceeds it (χ² above its
//! expectation) and scales it. The standard deviation of ln(term) is
//! therefore read from the lower half, ln(value/lo)/q, with q taken as the
//! model took it: Student's t where χ²/dof exceeds 1 ([`model_quantile`]).
//!
//! **A bound is not a value.** A term the model holds only as an upper
//! bound at some temperature is left out of the fit and of the comparisons,
//! and said so ([`Law::left_out`]); with fewer than two temperatures of
//! value there is no law.
//!
//! **A dependence is called at p < [`SIGNIFICANCE`]**, not at 5 %: one
//! document tests the law of every term of every axis (18 for six axes and
//! N, B, K) and every pair of its temperatures, and at 5 % it would report
//! a spurious dependence nearly every time. The intervals keep the
//! confidence asked for.

use allan::noise_model::NoiseModel;
use allan::noise_terms::{Chosen, NoiseTerms, Term};
use serde::Serialize;
use statrs::distribution::{ChiSquared, ContinuousCDF, Normal, StudentsT};
use thermal::surface::{Slicing, Surface};

/// The p-value below which a slope or a difference is called real.
pub const SIGNIFICANCE: f64 = 0.01;

/// A log-linear law whose χ² has a p-value below this does not describe
/// the points within their intervals: its slope's interval is widened by
/// √(χ²/dof) and taken on Student's t.
pub const LAW_FIT_P: f64 = 0.01;

/// A term at one temperature, as a run's noise model gives it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Reading {
    /// A value, with the standard deviation of its natural logarithm.
    Value {
        /// The term.
        value: f64,
        /// Standard deviation of ln(value).
        sd_ln: f64,
    },
    /// Only an upper bound: the model does not hold the term.
    Bound(f64),
    /// Nothing can be said (no model, or a value without an interval).
    Missing,
}

impl Reading {
    /// `term` of a run's noise terms, its interval read at `confidence`
    /// (the model's, [`allan::noise_model::NoiseModel::confidence`]).
    pub fn of(terms: &NoiseTerms, term: Term) -> Reading {
        let z = model_quantile(&terms.model);
        match terms.choose(term).chosen {
            Chosen::Model(v) => {
                let sd_ln = (v.value / v.lo).ln() / z;
                if v.value > 0.0 && sd_ln.is_finite() && sd_ln > 0.0 {
                    Reading::Value {
                        value: v.value,
                        sd_ln,
                    }
                } else {
                    Reading::Missing
                }
            }
            Chosen::Bound(b) => Reading::Bound(b),
            Chosen::Nothing => Reading::Missing,
        }
    }
}

/// A term's reading at one temperature.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct At {
    /// The run's (or the bin's) mean temperature, °C.
    pub t_c: f64,
    /// The term there.
    pub reading: Reading,
}

/// A temperature left out of a law, and why.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct LeftOut {
    /// Its temperature, °C.
    pub t_c: f64,
    /// "upper_bound" (the model holds the term only as a bound) or
    /// "no_value".
    pub why: &'static str,
}

/// A value with its interval.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Interval {
    /// Upper end.
    pub hi: f64,
    /// Lower end.
    pub lo: f64,
    /// The estimate.
    pub value: f64,
}

/// The fitted line ln(term) = a + b·T.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LawFit {
    /// b, per °C, with its interval.
    pub slope_per_c: Interval,
    /// The standard deviation of b, per °C.
    pub slope_sd: f64,
    /// The coldest and hottest temperature fitted, °C.
    pub from_c: f64,
    /// See `from_c`.
    pub to_c: f64,
    /// The relative change from `from_c` to `to_c`, exp(b·ΔT) − 1, with
    /// its interval.
    pub change: Interval,
    /// P(|b̂| this large | b = 0), two-sided.
    pub p_value: f64,
    /// χ² of the points about the line, on `dof` = points − 2.
    pub chi2: f64,
    /// Points − 2.
    pub dof: usize,
    /// P(χ²_dof ≥ χ²); `None` with two points (the line passes through both).
    pub fit_p_value: Option<f64>,
    /// Whether the line misses the points (fit p below [`LAW_FIT_P`]) and
    /// the interval was widened by the misfit.
    pub widened: bool,
    /// χ² of the points about their weighted mean (no dependence at
    /// all), on points − 1 degrees of freedom.
    pub constant_chi2: f64,
    /// P(χ²_{points−1} ≥ `constant_chi2`): whether the runs differ at all.
    pub constant_p_value: f64,
}

/// What a law says.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Verdict {
    /// The term grows with temperature (p < [`SIGNIFICANCE`]).
    Rises,
    /// It shrinks with temperature.
    Falls,
    /// The runs differ (their χ² about a constant has p < [`SIGNIFICANCE`])
    /// but leave the log-linear law too (fit p below [`LAW_FIT_P`]): a
    /// dependence, of another shape.
    NotLogLinear,
    /// No dependence shown.
    NoDependence,
    /// Fewer than two temperatures with a value.
    TooFew,
}

impl Verdict {
    /// Its JSON name.
    pub fn name(self) -> &'static str {
        match self {
            Verdict::Rises => "rises",
            Verdict::Falls => "falls",
            Verdict::NoDependence => "no_dependence",
            Verdict::NotLogLinear => "not_log_linear",
            Verdict::TooFew => "too_few",
        }
    }
}

/// Two temperatures compared.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Difference {
    /// The colder temperature, °C.
    pub a_c: f64,
    /// The warmer, °C.
    pub b_c: f64,
    /// The term at `b_c` over the term at `a_c`, with its interval.
    pub ratio: Interval,
    /// The two-sample z test of ln(b) − ln(a) = 0, two-sided.
    pub p_value: f64,
}

impl Difference {
    /// Whether the two differ (p < [`SIGNIFICANCE`]).
    pub fn significant(&self) -> bool {
        self.p_value < SIGNIFICANCE
    }

    /// One sentence: "34 °C and 43 °C do not differ in N (p = 0.41)".
    pub fn describe(&self, symbol: &str) -> String {
        let (a, b) = (temp_text(self.a_c), temp_text(self.b_c));
        if self.significant() {
            format!(
                "{a} and {b} differ in {symbol}: ×{:.3} [{:.3}, {:.3}] ({})",
                self.ratio.value,
                self.ratio.lo,
                self.ratio.hi,
                p_text(self.p_value)
            )
        } else {
            format!("{a} and {b} do not differ in {symbol} ({})", p_text(self.p_value))
        }
    }
}

/// A term over temperature: its law and every pair compared.
#[derive(Debug, Clone, PartialEq)]
pub struct Law {
    /// The term.
    pub term: Term,
    /// Confidence of the intervals.
    pub confidence: f64,
    /// Temperatures whose value entered the fit, coldest first, °C.
    pub used_c: Vec<f64>,
    /// Temperatures left out, coldest first.
    pub left_out: Vec<LeftOut>,
    /// The fitted line; `None` with fewer than two temperatures of value.
    pub fit: Option<LawFit>,
    /// Every pair of temperatures of value, colder first.
    pub differences: Vec<Difference>,
}

/// The quantile the noise model set its intervals with: Student's t on
/// its degrees of freedom where its spreads were scaled by the fit's own
/// scatter (χ² above its expectation, which is the degrees of freedom for
/// independent points and near them for the correlated octave points),
/// the normal quantile otherwise.
pub fn model_quantile(m: &NoiseModel) -> f64 {
    let p = 0.5 + m.confidence / 2.0;
    match m.quality {
        Some(q) if q.chi2_reduced > 1.0 && q.dof > 0 => {
            StudentsT::new(0.0, 1.0, q.dof as f64).map_or(f64::INFINITY, |t| t.inverse_cdf(p))
        }
        _ => quantile(m.confidence),
    }
}

/// The normal quantile of a two-sided `confidence`.
fn quantile(confidence: f64) -> f64 {
    Normal::standard().inverse_cdf(0.5 + confidence / 2.0)
}

/// Two-sided p of a standard normal statistic.
fn normal_p(z: f64) -> f64 {
    2.0 * (1.0 - Normal::standard().cdf(z.abs()))
}

impl Law {
    /// The law of `term` over `points`, intervals at `confidence`.
    pub fn fit(term: Term, points: &[At], confidence: f64) -> Law {
        let mut sorted = points.to_vec();
        sorted.sort_by(|a, b| a.t_c.total_cmp(&b.t_c));
        let mut values = Vec::new();
        let mut left_out = Vec::new();
        for p in &sorted {
            match p.reading {
                Reading::Value { value, sd_ln } if p.t_c.is_finite() => {
                    values.push((p.t_c, value.ln(), sd_ln))
                }
                Reading::Bound(_) => left_out.push(LeftOut {
                    t_c: p.t_c,
                    why: "upper_bound",
                }),
                _ => left_out.push(LeftOut {
                    t_c: p.t_c,
                    why: "no_value",
                }),
            }
        }
        let z = quantile(confidence);
        let mut differences = Vec::new();
        for (i, a) in values.iter().enumerate() {
            for b in &values[i + 1..] {
                let d = b.1 - a.1;
                let sd = (a.2 * a.2 + b.2 * b.2).sqrt();
                differences.push(Difference {
                    a_c: a.0,
                    b_c: b.0,
                    ratio: Interval {
                        value: d.exp(),
                        lo: (d - z * sd).exp(),
                        hi: (d + z * sd).exp(),
                    },
                    p_value: normal_p(d / sd),
                });
            }
        }
        Law {
            term,
            confidence,
            used_c: values.iter().map(|v| v.0).collect(),
            left_out,
            fit: weighted_line(&values, confidence),
            differences,
        }
    }

    /// What the law says.
    pub fn verdict(&self) -> Verdict {
        match &self.fit {
            None => Verdict::TooFew,
            Some(f) if f.p_value < SIGNIFICANCE && f.slope_per_c.value > 0.0 => Verdict::Rises,
            Some(f) if f.p_value < SIGNIFICANCE => Verdict::Falls,
            Some(f) if f.widened && f.constant_p_value < SIGNIFICANCE => Verdict::NotLogLinear,
            Some(_) => Verdict::NoDependence,
        }
    }

    /// One sentence: "gyro_y N rises 13 % [9, 17] from 34 to 82 °C
    /// (p = 3.1e-4)", "gyro_y B shows no temperature dependence here: …",
    /// with the temperatures left out named.
    pub fn describe(&self, channel: &str) -> String {
        let symbol = self.term.symbol();
        let mut text = match &self.fit {
            None if self.used_c.is_empty() => {
                format!("{channel} {symbol}: no value at any temperature, no law over temperature")
            }
            None => format!(
                "{channel} {symbol}: a value at one temperature only ({}), no law over temperature",
                temp_text(self.used_c[0])
            ),
            Some(f) => {
                let change = format!(
                    "{} [{}, {}] from {} to {} °C",
                    pct(f.change.value),
                    pct(f.change.lo),
                    pct(f.change.hi),
                    number(f.from_c),
                    number(f.to_c)
                );
                match self.verdict() {
                    v @ (Verdict::Rises | Verdict::Falls) => {
                        // A fall is said as its size: −13 % [−17, −9] is
                        // "falls 13 % [9, 17]".
                        let (word, c) = if v == Verdict::Rises {
                            ("rises", f.change)
                        } else {
                            (
                                "falls",
                                Interval {
                                    value: -f.change.value,
                                    lo: -f.change.hi,
                                    hi: -f.change.lo,
                                },
                            )
                        };
                        format!(
                            "{channel} {symbol} {word} {} % [{}, {}] from {} to {} °C ({})",
                            size(c.value),
                            size(c.lo),
                            size(c.hi),
                            number(f.from_c),
                            number(f.to_c),
                            p_text(f.p_value)
                        )
                    }
                    Verdict::NotLogLinear => format!(
                        "{channel} {symbol} changes with temperature, though not as ln {symbol} linear in T: the runs \
                         leave a constant (χ² = {:.1} on {} degrees of freedom, {}) and the line (χ² = {:.1} on {}); \
                         the line's {change} ({}) is no summary, read the pairs",
                        f.constant_chi2,
                        f.dof + 1,
                        p_text(f.constant_p_value),
                        f.chi2,
                        f.dof,
                        p_text(f.p_value)
                    ),
                    _ => format!(
                        "{channel} {symbol} shows no temperature dependence here: {change} ({})",
                        p_text(f.p_value)
                    ),
                }
            }
        };
        if let Some(f) = self
            .fit
            .filter(|f| f.widened && self.verdict() != Verdict::NotLogLinear)
        {
            text.push_str(&format!(
                "; the log-linear law misses the points (χ² = {:.1} on {} degrees of freedom), the interval widened by it",
                f.chi2, f.dof
            ));
        }
        let bounds: Vec<String> = self
            .left_out
            .iter()
            .filter(|l| l.why == "upper_bound")
            .map(|l| temp_text(l.t_c))
            .collect();
        if !bounds.is_empty() {
            text.push_str(&format!(
                "; left out where {symbol} is only an upper bound: {}",
                bounds.join(", ")
            ));
        }
        let none: Vec<String> = self
            .left_out
            .iter()
            .filter(|l| l.why == "no_value")
            .map(|l| temp_text(l.t_c))
            .collect();
        if !none.is_empty() {
            text.push_str(&format!("; no {symbol} at {}", none.join(", ")));
        }
        text
    }

    /// The pairs that differ (p < [`SIGNIFICANCE`]), one sentence; or that
    /// none does.
    pub fn describe_differences(&self) -> String {
        let symbol = self.term.symbol();
        if self.differences.is_empty() {
            return format!("no two temperatures with a value of {symbol} to compare");
        }
        let differ: Vec<String> = self
            .differences
            .iter()
            .filter(|d| d.significant())
            .map(|d| d.describe(symbol))
            .collect();
        if differ.is_empty() {
            let p = self
                .differences
                .iter()
                .map(|d| d.p_value)
                .fold(f64::INFINITY, f64::min);
            format!("no two temperatures differ in {symbol} (smallest {})", p_text(p))
        } else {
            differ.join("; ")
        }
    }
}

/// The weighted least-squares line through (T, ln v, sd of ln v) with the
/// variances taken as known; widened by the misfit where the points leave
/// it (χ² p below [`LAW_FIT_P`]).
fn weighted_line(values: &[(f64, f64, f64)], confidence: f64) -> Option<LawFit> {
    if values.len() < 2 {
        return None;
    }
    let w: Vec<f64> = values.iter().map(|v| 1.0 / (v.2 * v.2)).collect();
    let sw: f64 = w.iter().sum();
    let xm = values.iter().zip(&w).map(|(v, w)| w * v.0).sum::<f64>() / sw;
    let ym = values.iter().zip(&w).map(|(v, w)| w * v.1).sum::<f64>() / sw;
    let sxx: f64 = values.iter().zip(&w).map(|(v, w)| w * (v.0 - xm).powi(2)).sum();
    if !(sxx.is_finite() && sxx > 0.0) {
        return None;
    }
    let b = values
        .iter()
        .zip(&w)
        .map(|(v, w)| w * (v.0 - xm) * (v.1 - ym))
        .sum::<f64>()
        / sxx;
    let a = ym - b * xm;
    let chi2: f64 = values
        .iter()
        .zip(&w)
        .map(|(v, w)| w * (v.1 - a - b * v.0).powi(2))
        .sum();
    let dof = values.len() - 2;
    let constant_chi2: f64 = values.iter().zip(&w).map(|(v, w)| w * (v.1 - ym).powi(2)).sum();
    let constant_p_value = ChiSquared::new((dof + 1) as f64).map_or(f64::NAN, |d| 1.0 - d.cdf(constant_chi2));
    let fit_p_value = (dof > 0).then(|| ChiSquared::new(dof as f64).map_or(f64::NAN, |d| 1.0 - d.cdf(chi2)));
    let widened = fit_p_value.is_some_and(|p| p < LAW_FIT_P);
    let mut sd = (1.0 / sxx).sqrt();
    let (q, p_value) = if widened {
        sd *= (chi2 / dof as f64).sqrt();
        let t = StudentsT::new(0.0, 1.0, dof as f64).ok()?;
        (
            t.inverse_cdf(0.5 + confidence / 2.0),
            2.0 * (1.0 - t.cdf((b / sd).abs())),
        )
    } else {
        (quantile(confidence), normal_p(b / sd))
    };
    let from_c = values.iter().map(|v| v.0).fold(f64::INFINITY, f64::min);
    let to_c = values.iter().map(|v| v.0).fold(f64::NEG_INFINITY, f64::max);
    let span = to_c - from_c;
    let slope_per_c = Interval {
        value: b,
        lo: b - q * sd,
        hi: b + q * sd,
    };
    Some(LawFit {
        slope_per_c,
        slope_sd: sd,
        from_c,
        to_c,
        change: Interval {
            value: (b * span).exp_m1(),
            lo: (slope_per_c.lo * span).exp_m1(),
            hi: (slope_per_c.hi * span).exp_m1(),
        },
        p_value,
        chi2,
        dof,
        fit_p_value,
        widened,
        constant_chi2,
        constant_p_value,
    })
}

/// A relative change in percent, unsigned, to two significant figures
/// (whole percent from 10 %): 0.13 is "13".
fn size(x: f64) -> String {
    let v = 100.0 * x;
    if v.abs() >= 9.95 {
        format!("{v:.0}")
    } else {
        format!("{v:.1}")
    }
}

/// A relative change in percent, signed, to two significant figures
/// (whole percent from 10 %): "+13 %", "−4.2 %".
fn pct(x: f64) -> String {
    let v = 100.0 * x;
    let text = if v.abs() >= 9.95 {
        format!("{:.0}", v.abs())
    } else {
        format!("{:.1}", v.abs())
    };
    let sign = if v < 0.0 && !text.trim_start_matches(['0', '.']).is_empty() {
        "−"
    } else {
        "+"
    };
    format!("{sign}{text} %")
}

/// A temperature as the sentences print it: whole degrees, a decimal
/// where it is not one.
fn number(t: f64) -> String {
    if (t - t.round()).abs() < 0.05 {
        format!("{t:.0}")
    } else {
        format!("{t:.1}")
    }
}

fn temp_text(t: f64) -> String {
    format!("{} °C", number(t))
}

/// A p-value as the sentences give it: "p = 0.41" (two decimals from
/// 0.01, three from 0.001, scientific below), "p < 1e-12" below that, where
/// the normal tail no longer says anything of the data.
pub fn p_text(p: f64) -> String {
    if p >= 0.01 {
        format!("p = {p:.2}")
    } else if p >= 0.001 {
        format!("p = {p:.3}")
    } else if p >= 1e-12 {
        format!("p = {p:.1e}")
    } else {
        "p < 1e-12".to_string()
    }
}

/// A law as the JSON documents give it (`over_temperature`); fields in
/// the byte order of their names, as `imutherm.thermal/1` keeps them.
#[derive(Debug, Clone, Serialize)]
pub struct LawEntry {
    /// The relative change over the fitted range, exp(b·ΔT) − 1.
    pub change: Option<Interval>,
    /// The channel.
    pub channel: String,
    /// The law's χ² about the line (null without a fit).
    pub chi2: Option<f64>,
    /// Confidence of the intervals.
    pub confidence: f64,
    /// χ² of the values about their weighted mean (null without a fit).
    pub constant_chi2: Option<f64>,
    /// Its p: whether the temperatures differ at all, whatever the shape.
    pub constant_p_value: Option<f64>,
    /// Every pair of temperatures of value.
    pub differences: Vec<DifferenceEntry>,
    /// Its degrees of freedom: temperatures fitted − 2.
    pub dof: Option<usize>,
    /// P(χ²_dof ≥ χ²); null with two temperatures.
    pub fit_p_value: Option<f64>,
    /// The coldest temperature fitted, °C.
    pub from_c: Option<f64>,
    /// Temperatures left out, and why.
    pub left_out: Vec<LeftOut>,
    /// The two-sided p of the slope against zero.
    pub p_value: Option<f64>,
    /// The p-value below which a slope or a difference is called real.
    pub significance: f64,
    /// d ln(term)/dT, 1/°C.
    pub slope_per_c: Option<Interval>,
    /// Q, N, B, K or R.
    pub term: &'static str,
    /// The law in one sentence, and the differences in another.
    pub text: Vec<String>,
    /// The hottest temperature fitted, °C.
    pub to_c: Option<f64>,
    /// Temperatures whose value entered the fit, °C.
    pub used_c: Vec<f64>,
    /// "rises", "falls", "no_dependence", "not_log_linear" or "too_few".
    pub verdict: &'static str,
    /// Whether the line missed the points and its interval was widened.
    pub widened: bool,
}

/// A pair of temperatures compared, in the JSON documents.
#[derive(Debug, Clone, Serialize)]
pub struct DifferenceEntry {
    /// The colder, °C.
    pub a_c: f64,
    /// The warmer, °C.
    pub b_c: f64,
    /// Two-sided p of the two-sample z test on ln(term).
    pub p_value: f64,
    /// The term at `b_c` over the term at `a_c`.
    pub ratio: Interval,
    /// Whether p < [`SIGNIFICANCE`].
    pub significant: bool,
}

impl LawEntry {
    /// The entry of `law` for `channel`.
    pub fn new(channel: &str, law: &Law) -> LawEntry {
        let f = law.fit.as_ref();
        LawEntry {
            change: f.map(|f| f.change),
            channel: channel.to_string(),
            chi2: f.map(|f| f.chi2),
            confidence: law.confidence,
            constant_chi2: f.map(|f| f.constant_chi2),
            constant_p_value: f.map(|f| f.constant_p_value),
            differences: law
                .differences
                .iter()
                .map(|d| DifferenceEntry {
                    a_c: d.a_c,
                    b_c: d.b_c,
                    p_value: d.p_value,
                    ratio: d.ratio,
                    significant: d.significant(),
                })
                .collect(),
            dof: f.map(|f| f.dof),
            fit_p_value: f.and_then(|f| f.fit_p_value),
            from_c: f.map(|f| f.from_c),
            left_out: law.left_out.clone(),
            p_value: f.map(|f| f.p_value),
            significance: SIGNIFICANCE,
            slope_per_c: f.map(|f| f.slope_per_c),
            term: law.term.symbol(),
            text: vec![law.describe(channel), law.describe_differences()],
            to_c: f.map(|f| f.to_c),
            used_c: law.used_c.clone(),
            verdict: law.verdict().name(),
            widened: f.is_some_and(|f| f.widened),
        }
    }
}

/// The laws of [`LAW_TERMS`] over a surface's slices (`thermal`'s bins),
/// each slice at its mean temperature; `None` where the slices share
/// samples (time windows stepped by less than their length): their terms
/// are not independent, and a law weighing them as if they were would
/// claim more than the data hold.
pub fn surface_laws(surface: &Surface, slicing: Slicing, confidence: f64) -> Option<Vec<Law>> {
    if let Slicing::Time { window_s, step_s } = slicing
        && step_s < window_s
    {
        return None;
    }
    Some(
        LAW_TERMS
            .iter()
            .map(|&term| {
                let at: Vec<At> = surface
                    .rows
                    .iter()
                    .map(|r| At {
                        t_c: r.t_mean_c,
                        reading: Reading::of(&r.terms, term),
                    })
                    .collect();
                Law::fit(term, &at, confidence)
            })
            .collect(),
    )
}

/// One sentence naming the channels' terms of `laws` that have no law
/// (a value at fewer than two temperatures; bounds are left out), for a
/// table that lists only the laws there are; `None` where every term has
/// one.
pub fn without_law(laws: &[(&str, Law)]) -> Option<String> {
    let names: Vec<String> = laws
        .iter()
        .filter(|(_, l)| l.fit.is_none())
        .map(|(c, l)| format!("{c} {}", l.term.symbol()))
        .collect();
    (!names.is_empty()).then(|| {
        format!(
            "no law over temperature (a value at fewer than two temperatures; an upper bound is left out, \
             never taken for a value): {}",
            names.join(", ")
        )
    })
}

/// The terms whose laws the outputs give: white noise, bias instability
/// and rate random walk, the three every model is asked about.
pub const LAW_TERMS: [Term; 3] = [Term::WhiteNoise, Term::BiasInstability, Term::RateRandomWalk];

#[cfg(test)]
mod tests {
    use super::*;

    fn value(t_c: f64, value: f64, sd_ln: f64) -> At {
        At {
            t_c,
            reading: Reading::Value { value, sd_ln },
        }
    }

    #[test]
    fn weighted_line_matches_the_hand_computed_one() {
        // ln v = 0, 1, 3 at T = 0, 1, 2 with sd 1, 1, 0.5 (weights 1, 1, 4):
        // Σw = 6, x̄ = 9/6 = 1.5, ȳ = 13/6, Sxx = 2.25 + 0.25 + 4·0.25 = 3.5,
        // Sxy = 1.5·13/6 + 0.5·7/6 + 4·0.5·5/6 = 5.5, b = 5.5/3.5 = 11/7,
        // var b = 1/Sxx = 1/3.5, a = ȳ − b·x̄ = 13/6 − 33/14.
        let pts = [
            value(0.0, 1.0, 1.0),
            value(1.0, 1f64.exp(), 1.0),
            value(2.0, 3f64.exp(), 0.5),
        ];
        let law = Law::fit(Term::WhiteNoise, &pts, 0.95);
        let f = law.fit.unwrap();
        assert!((f.slope_per_c.value - 11.0 / 7.0).abs() < 1e-12);
        assert!((f.slope_sd - (1.0f64 / 3.5).sqrt()).abs() < 1e-12);
        // Residuals y − a − b·x = (4, −8, 1)/21: χ² = (16 + 64 + 4)/441 = 4/21.
        assert!((f.chi2 - 4.0 / 21.0).abs() < 1e-12, "{}", f.chi2);
        assert_eq!(f.dof, 1);
        // χ² = 0.19 on one degree of freedom: the line holds, no widening.
        assert!(!f.widened);
        let z = 1.959_963_984_540_054;
        assert!((f.slope_per_c.lo - (11.0 / 7.0 - z * (1.0f64 / 3.5).sqrt())).abs() < 1e-9);
        // b/sd = (11/7)·√3.5 = 2.9399: p = 2(1 − Φ(2.9399)) = 0.003283.
        assert!((f.p_value - 0.003_283).abs() < 2e-6, "{}", f.p_value);
        assert!((f.change.value - (22.0f64 / 7.0).exp_m1()).abs() < 1e-9);
        assert_eq!(law.verdict(), Verdict::Rises);
    }

    #[test]
    fn a_constant_term_shows_no_dependence() {
        let pts = [
            value(34.0, 1.0, 0.03),
            value(43.0, 1.01, 0.03),
            value(62.0, 0.99, 0.03),
            value(82.0, 1.0, 0.03),
        ];
        let law = Law::fit(Term::BiasInstability, &pts, 0.95);
        assert_eq!(law.verdict(), Verdict::NoDependence);
        let text = law.describe("gyro_y");
        assert!(
            text.starts_with("gyro_y B shows no temperature dependence here"),
            "{text}"
        );
        assert!(law.differences.iter().all(|d| !d.significant()));
        assert_eq!(law.differences.len(), 6);
    }

    #[test]
    fn two_sample_z_test_of_two_temperatures() {
        // ln 1.1 − ln 1 = 0.09531 over √(0.04² + 0.03²) = 0.05: z = 1.906,
        // p = 2(1 − Φ(1.906)) = 0.0566.
        let law = Law::fit(
            Term::WhiteNoise,
            &[value(34.0, 1.0, 0.04), value(43.0, 1.1, 0.03)],
            0.95,
        );
        let d = law.differences[0];
        assert!((d.p_value - 0.056_6).abs() < 2e-4, "{}", d.p_value);
        assert!((d.ratio.value - 1.1).abs() < 1e-12);
        assert!((d.ratio.lo - (0.095_31 - 1.959_96 * 0.05f64).exp()).abs() < 1e-4);
        assert_eq!(
            d.describe("N"),
            format!("34 °C and 43 °C do not differ in N ({})", p_text(d.p_value))
        );
        // Two points fix the line: no χ² to test it by.
        assert_eq!(law.fit.unwrap().fit_p_value, None);
    }

    #[test]
    fn a_rise_is_said_in_percent_over_the_range() {
        // 13 % from 34 to 82 °C, each value known to 1 %.
        let b = 1.13f64.ln() / 48.0;
        let pts: Vec<At> = [34.0, 43.0, 62.0, 82.0]
            .iter()
            .map(|&t| value(t, (b * (t - 34.0)).exp(), 0.01))
            .collect();
        let law = Law::fit(Term::WhiteNoise, &pts, 0.95);
        let text = law.describe("gyro_y");
        assert!(text.starts_with("gyro_y N rises 13 % ["), "{text}");
        assert!(text.contains("from 34 to 82 °C"), "{text}");
        let f = law.fit.unwrap();
        assert!((f.change.value - 0.13).abs() < 1e-9);
        assert!(f.change.lo < 0.13 && 0.13 < f.change.hi);
    }

    #[test]
    fn a_bound_is_left_out_and_said() {
        let pts = [
            value(34.0, 1.0, 0.05),
            value(43.0, 1.0, 0.05),
            At {
                t_c: 82.0,
                reading: Reading::Bound(5.0),
            },
        ];
        let law = Law::fit(Term::BiasInstability, &pts, 0.95);
        assert_eq!(law.used_c, vec![34.0, 43.0]);
        assert_eq!(
            law.left_out,
            vec![LeftOut {
                t_c: 82.0,
                why: "upper_bound"
            }]
        );
        // The fit spans the values alone, never the bound's temperature.
        assert_eq!(law.fit.unwrap().to_c, 43.0);
        assert!(
            law.describe("gyro_x")
                .contains("left out where B is only an upper bound: 82 °C")
        );
        let lone = Law::fit(Term::BiasInstability, &pts[1..], 0.95);
        assert_eq!(lone.verdict(), Verdict::TooFew);
        assert!(lone.differences.is_empty());
    }

    #[test]
    fn a_line_that_misses_its_points_is_widened() {
        // A zigzag far outside 1 % intervals.
        let pts = [
            value(30.0, 1.0, 0.01),
            value(40.0, 1.3, 0.01),
            value(50.0, 1.0, 0.01),
            value(60.0, 1.3, 0.01),
        ];
        let f = Law::fit(Term::WhiteNoise, &pts, 0.95).fit.unwrap();
        assert!(f.widened);
        assert!(f.fit_p_value.unwrap() < LAW_FIT_P);
        // ln 1.3 = 0.262 apart at 1 %: far from a constant, yet no line.
        let law = Law::fit(Term::WhiteNoise, &pts, 0.95);
        assert_eq!(law.verdict(), Verdict::NotLogLinear);
        assert!(
            law.describe("accel_x")
                .contains("changes with temperature, though not as ln N linear in T")
        );
        let known = (1.0 / (4.0 * 1e4 * 125.0f64)).sqrt();
        assert!((f.slope_sd - known * (f.chi2 / 2.0).sqrt()).abs() < 1e-12);
    }

    #[test]
    fn a_run_gives_its_value_with_the_models_spread_and_its_bounds() {
        // Uniform white noise: the model holds N and bounds K.
        let y: Vec<f64> = allan::work::uniform(0x9e37_79b9_7f4a_7c15)
            .take(20_000)
            .map(|u| u - 0.5)
            .collect();
        let (_, terms) = allan::noise_terms::analyze_terms(&y, 10.0, 0.95).unwrap();
        let v = *terms.model.get(Term::WhiteNoise).value().unwrap();
        let Reading::Value { value, sd_ln } = Reading::of(&terms, Term::WhiteNoise) else {
            panic!("N is a value of white noise's model")
        };
        assert_eq!(value, v.value);
        // The model's lower end, at the quantile it took.
        let q = model_quantile(&terms.model);
        assert!(((value.ln() - q * sd_ln).exp() - v.lo).abs() < 1e-12 * v.lo);
        assert!(matches!(
            Reading::of(&terms, Term::RateRandomWalk),
            Reading::Bound(_)
        ));
    }

    #[test]
    fn overlapping_windows_get_no_law() {
        let surface = Surface {
            rows: Vec::new(),
            skipped: Vec::new(),
        };
        let time = |step_s| Slicing::Time {
            window_s: 10.0,
            step_s,
        };
        assert!(surface_laws(&surface, time(5.0), 0.95).is_none());
        assert_eq!(surface_laws(&surface, time(10.0), 0.95).unwrap().len(), 3);
        let bins = Slicing::Temperature { bin_width_c: 5.0 };
        assert!(surface_laws(&surface, bins, 0.95).is_some());
    }

    #[test]
    fn percent_and_p_texts() {
        assert_eq!(pct(0.13), "+13 %");
        assert_eq!(pct(-0.042), "−4.2 %");
        assert_eq!(pct(-0.0001), "+0.0 %");
        assert_eq!(p_text(0.41), "p = 0.41");
        assert_eq!(p_text(0.0031), "p = 0.003");
        assert_eq!(p_text(3.1e-5), "p = 3.1e-5");
        assert_eq!(p_text(0.0), "p < 1e-12");
    }
}
