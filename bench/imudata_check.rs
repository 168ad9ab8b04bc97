//! The selected noise model of real recordings held against their own
//! measured curves: the rules no output may break, checked from outside the
//! estimator.
//!
//! For each file and axis (read and analysed as `imutherm noise` and the
//! report do, by `analysis::noise::analyse_run`, octave τ, 95 %
//! intervals):
//! - each kept term's own curve (Q, N, B, K, R, each Gauss–Markov process)
//!   against the measured deviation's 95 % upper end at every point with
//!   at least `allan::noise_model::MIN_EDF` degrees of freedom: the
//!   largest ratio is printed and must not exceed 1;
//! - each bound (a term the model does not hold) against the measured
//!   99 % upper end (`allan::noise_model::CEILING_CONFIDENCE`, the level
//!   the bounds are defined at), with each point's own EDF, the one its
//!   printed interval has: likewise at most 1;
//! - the model's curve against the measured 95 % interval at each fitted
//!   point: the τ it leaves, and whether the model says so itself
//!   (`NoiseModel::outside`, or "no candidate fits").
//!
//! usage: cargo run --release -p analysis --example imudata_check -- RATE_HZ FILE...
//! Prints one Markdown row per axis; exits 1 when a rule is broken or the
//! model leaves the intervals without saying so.

use std::path::Path;

use allan::Point;
use allan::confidence::chi2_interval;
use allan::noise_model::{CEILING_CONFIDENCE, MIN_EDF, NoiseModel, lm::power_basis, process};
use allan::noise_terms::{Term, TermEstimate};
use analysis::noise::analyse_run;
use imu::RecordingOptions;

/// The measured deviation's upper end at `confidence`, with the point's own
/// EDF and by the interval every output prints
/// (`allan::confidence::chi2_interval`).
fn upper(p: &Point, confidence: f64) -> f64 {
    chi2_interval(p.dev, p.edf, confidence).1
}

/// The largest ratio of a term's own σ(τ) to the measured upper end, over
/// the points with enough degrees of freedom (all points when none has),
/// and the τ it is at.
fn worst(points: &[Point], sigma: impl Fn(f64) -> f64, ceiling: impl Fn(&Point) -> f64) -> (f64, f64) {
    let supported = points.iter().any(|p| p.edf >= MIN_EDF);
    points
        .iter()
        .filter(|p| !supported || p.edf >= MIN_EDF)
        .map(|p| (sigma(p.tau) / ceiling(p), p.tau))
        .fold((0.0, f64::NAN), |a, b| if b.0 > a.0 { b } else { a })
}

struct Verdict {
    row: String,
    broken: bool,
}

fn check(file: &str, axis: &str, unit: &str, all: &[Point], m: &NoiseModel) -> Verdict {
    // Kept terms and the model's curve are held to the points of the τ
    // range the model was fitted over; beyond it the output names the
    // misses itself (`FitRange::describe`). Bounds are held to every point.
    let fitted: Vec<Point> = all
        .iter()
        .filter(|p| {
            m.fit_range
                .as_ref()
                .is_none_or(|r| p.tau >= r.lo * (1.0 - 1e-9) && p.tau <= r.hi * (1.0 + 1e-9))
        })
        .copied()
        .collect();
    let points = &fitted[..];
    let mut kept = Vec::new();
    let mut bounds = Vec::new();
    let mut broken = false;
    for t in Term::ALL {
        match m.get(t) {
            TermEstimate::Value(v) => {
                // White noise through the sensor's filter has the filtered
                // process's curve, below N²/τ at the shortest τ.
                let own = |tau: f64| match (&m.low_pass, t) {
                    (Some(f), Term::WhiteNoise) => {
                        let tc = f.tau_c.value;
                        v.value * (process::gauss_markov(tau, tc) / (2.0 * tc)).sqrt()
                    }
                    _ => v.value * power_basis(t, tau).sqrt(),
                };
                let (r, at) = worst(points, own, |p| p.dev_hi);
                broken |= r > 1.0;
                kept.push(format!("{} {:.3e} ({r:.2} at {at:.3} s)", t.symbol(), v.value));
            }
            TermEstimate::NotIdentifiable(_) => {
                if let Some(b) = m.bound(t) {
                    let line = |tau: f64| b * power_basis(t, tau).sqrt();
                    let (r, at) = worst(all, line, |p| upper(p, CEILING_CONFIDENCE));
                    broken |= r > 1.0 + 1e-9;
                    bounds.push(if r > 1.0 + 1e-9 {
                        format!("{} ≤ {b:.3e} ({r:.2} at {at:.3} s)", t.symbol())
                    } else {
                        format!("{} ≤ {b:.3e} ({r:.2})", t.symbol())
                    });
                }
            }
        }
    }
    for g in &m.gauss_markov {
        let (s, tc) = (g.sigma.value, g.tau_c.value);
        let (r, at) = worst(
            points,
            |tau| s * process::gauss_markov(tau, tc).sqrt(),
            |p| p.dev_hi,
        );
        broken |= r > 1.0;
        kept.push(format!("GM σ {s:.3e}, T {tc:.3e} s ({r:.2} at {at:.3} s)"));
    }
    let (model, leaves) = if m.quality.is_some() {
        let fitted = points
            .iter()
            .filter(|p| !m.left_out.iter().any(|&t| (t - p.tau).abs() <= 1e-9 * t));
        let off: Vec<f64> = fitted
            .filter(|p| {
                let s = m.avar(p.tau).sqrt();
                s < p.dev_lo || s > p.dev_hi
            })
            .map(|p| p.tau)
            .collect();
        let unsaid = off
            .iter()
            .filter(|&&t| !m.outside.iter().any(|&o| (o - t).abs() <= 1e-9 * t))
            .count();
        broken |= unsaid > 0;
        let q = m.quality.map_or(f64::NAN, |q| q.p_value);
        let taus = off
            .iter()
            .map(|t| format!("{t:.3}"))
            .collect::<Vec<_>>()
            .join(", ");
        (
            format!(
                "{} (χ²/dof {:.2}, p {q:.2})",
                m.label,
                m.chi2_reduced.unwrap_or(f64::NAN)
            ),
            if off.is_empty() {
                "within".to_string()
            } else if unsaid == 0 {
                format!("leaves at τ = {taus} s; said")
            } else {
                format!("leaves at τ = {taus} s; {unsaid} NOT said")
            },
        )
    } else {
        ("none fits".to_string(), "no curve; said".to_string())
    };
    // Where no candidate fits, where the output says the best one fails;
    // where the range is narrowed, the range and the misses beyond it.
    let model = match &m.defeat {
        Some(d) => format!("{model}; {}", d.describe()),
        None => model,
    };
    let model = match m.fit_range.as_ref().filter(|r| !r.whole) {
        Some(r) => format!("{model}; {}", r.describe()),
        None => model,
    };
    let model = match &m.low_pass {
        Some(f) => format!(
            "{model}; low-pass Tc {:.3e} s ({:.2} Hz)",
            f.tau_c.value, f.cutoff_hz
        ),
        None => model,
    };
    let row = format!(
        "| {file} | {axis} [{unit}] | {model} | {} | {} | {leaves} |",
        if kept.is_empty() {
            "—".into()
        } else {
            kept.join("; ")
        },
        if bounds.is_empty() {
            "—".into()
        } else {
            bounds.join("; ")
        },
    );
    Verdict { row, broken }
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let Some((rate, files)) = args
        .split_first()
        .and_then(|(r, f)| Some((r.parse::<f64>().ok()?, f)))
    else {
        eprintln!("usage: imudata_check RATE_HZ FILE...");
        std::process::exit(2);
    };
    let read = RecordingOptions {
        rate_hz: Some(rate),
        ..RecordingOptions::default()
    };
    // IMUDATA_TERMS=FILE: one tab-separated line per axis with N and B in
    // SI (value, lo, hi; "bound" and the bound where not held), the model,
    // its τ range and filter, for `imudata/table.py`.
    let terms_out = std::env::var_os("IMUDATA_TERMS");
    let mut terms: Vec<String> = Vec::new();
    println!(
        "| file | axis | model | kept terms (largest σ_term/σ̂ 95 % upper) | bounds (largest σ_bound/σ̂ 99 % upper) | model curve vs 95 % intervals |"
    );
    println!("|---|---|---|---|---|---|");
    let mut broken = false;
    for f in files {
        let run = match analyse_run(Path::new(f), &read) {
            Ok(r) => r,
            Err(e) => {
                eprintln!("{f}: {e}");
                std::process::exit(1);
            }
        };
        let name = Path::new(f)
            .file_name()
            .map_or(f.clone(), |n| n.to_string_lossy().into_owned());
        for c in &run.channels {
            let v = check(&name, &c.channel.name, &c.channel.unit, &c.points, &c.terms.model);
            println!("{}", v.row);
            broken |= v.broken;
            if terms_out.is_some() {
                terms.push(terms_line(&name, c));
            }
        }
    }
    if let Some(out) = &terms_out
        && let Err(e) = std::fs::write(out, terms.join(""))
    {
        eprintln!("{}: {e}", Path::new(out).display());
        std::process::exit(1);
    }
    if broken {
        eprintln!("a rule is broken (a ratio above 1, or the model leaves the intervals unsaid)");
        std::process::exit(1);
    }
}

/// One axis's line of the IMUDATA_TERMS file.
fn terms_line(file: &str, c: &analysis::noise::ChannelNoise) -> String {
    let m = &c.terms.model;
    let term = |t: Term| match m.get(t) {
        TermEstimate::Value(v) => format!("value\t{:.6e}\t{:.6e}\t{:.6e}", v.value, v.lo, v.hi),
        TermEstimate::NotIdentifiable(_) => format!("bound\t{:.6e}\t\t", m.bound(t).unwrap_or(f64::NAN)),
    };
    let range = m
        .fit_range
        .as_ref()
        .map_or("—".to_string(), |r| format!("{}–{}", r.lo, r.hi));
    let filter = m.low_pass.map_or("—".to_string(), |f| {
        format!("{:.3e} s ({:.2} Hz)", f.tau_c.value, f.cutoff_hz)
    });
    format!(
        "{file}\t{}\t{}\t{}\t{}\t{}\t{range}\t{filter}\t{}\n",
        c.channel.name,
        term(Term::WhiteNoise),
        term(Term::BiasInstability),
        m.label,
        m.fits,
        m.within_noise
    )
}
