//! Cross-check against AllanTools 2024.6 on six 2048-sample data sets (white,
//! flicker PM; white, flicker, random-walk FM as frequency data; a mixed clock
//! as phase data), every statistic, octave taus.
//!
//! The reference is `tests/fixtures/allantools_reference.json`, written by
//! `tests/fixtures/make_allantools_reference.py` (see its docstring to
//! regenerate it). It holds the samples themselves, so nothing here depends on
//! a random generator.
//!
//! * Deviations agree to 1e-9 relative at every tau imutherm reports, with the
//!   same number of terms; every reported tau must be one AllanTools reports
//!   too, and there must be at least three per statistic.
//! * For ADEV, OADEV, MDEV, TDEV, HDEV and OHDEV, wherever imutherm identifies
//!   the same power-law noise as AllanTools' `confidence_interval_noiseID`,
//!   the EDF and the confidence bounds at 0.683 agree to 1e-6 relative.
//!
//! AllanTools labels Theo1 at τ = m·τ0 although its variance is normalised
//! for τ = 0.75·m·τ0 (SP 1065 eq. 30), which is what imutherm reports; Theo1
//! points are therefore matched by averaging factor.

use std::fs;
use std::path::Path;

use allan::{Curve, DataType, Options, Point, Stat, TauSpec, analyze};
use serde_json::Value;

/// Deviations: both tools compute the same sums, only the summation order
/// (and so the rounding) may differ.
const DEV_RTOL: f64 = 1e-9;
/// EDF and bounds: Greenhall's sums and the chi-squared quantiles are
/// computed by different numerical routines.
const EDF_RTOL: f64 = 1e-6;
/// Taus are exact multiples of τ0 = 1 s in both tools.
const TAU_RTOL: f64 = 1e-12;
/// Fewest taus each statistic must report on 2048 samples.
const MIN_TAUS: usize = 3;

const STATS: [&str; 11] = [
    "adev", "oadev", "mdev", "tdev", "hdev", "ohdev", "totdev", "mtotdev", "ttotdev", "htotdev", "theo1",
];

/// The statistics whose fixture carries AllanTools' noise-identified
/// confidence interval.
const CI_STATS: [&str; 6] = ["adev", "oadev", "mdev", "tdev", "hdev", "ohdev"];

fn fixture() -> Value {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/allantools_reference.json");
    let text = fs::read_to_string(&path).unwrap_or_else(|e| panic!("reading {}: {e}", path.display()));
    serde_json::from_str(&text).unwrap_or_else(|e| panic!("parsing {}: {e}", path.display()))
}

fn rate_hz(fx: &Value) -> f64 {
    fx["rate_hz"].as_f64().expect("fixture has no rate_hz")
}

fn datasets(fx: &Value) -> &[Value] {
    let sets = fx["datasets"].as_array().expect("fixture has no datasets array");
    assert_eq!(sets.len(), 6, "fixture should hold six data sets");
    sets
}

fn str_of<'a>(v: &'a Value, key: &str) -> &'a str {
    v[key]
        .as_str()
        .unwrap_or_else(|| panic!("missing string {key:?}"))
}

fn f64s(v: &Value) -> Vec<f64> {
    v.as_array()
        .expect("expected an array of numbers")
        .iter()
        .map(|x| x.as_f64().expect("expected a number"))
        .collect()
}

/// An array whose entries may be null (no AllanTools value at that tau).
fn opt_f64s(v: &Value) -> Vec<Option<f64>> {
    v.as_array()
        .expect("expected an array")
        .iter()
        .map(Value::as_f64)
        .collect()
}

fn usizes(v: &Value) -> Vec<usize> {
    v.as_array()
        .expect("expected an array of integers")
        .iter()
        .map(|x| x.as_u64().expect("expected a non-negative integer") as usize)
        .collect()
}

fn rel_diff(got: f64, want: f64) -> f64 {
    if got == want {
        0.0
    } else {
        ((got - want) / want).abs()
    }
}

/// Whether a relative difference is within tolerance; false for NaN, so a
/// NaN result never passes.
fn within(rel: f64, tol: f64) -> bool {
    rel <= tol
}

/// AllanTools' reference for one data set and statistic.
struct Reference {
    taus: Vec<f64>,
    ms: Vec<usize>,
    devs: Vec<f64>,
    ns: Vec<usize>,
}

impl Reference {
    fn new(v: &Value) -> Self {
        let r = Reference {
            taus: f64s(&v["taus"]),
            ms: usizes(&v["ms"]),
            devs: f64s(&v["devs"]),
            ns: usizes(&v["ns"]),
        };
        assert!(r.ms.len() == r.taus.len() && r.devs.len() == r.taus.len() && r.ns.len() == r.taus.len());
        r
    }

    /// Index of the reference point at the same averaging factor as `p`.
    fn index_of(&self, p: &Point) -> Option<usize> {
        self.ms.iter().position(|&m| m == p.m)
    }
}

fn run(ds: &Value, stat_name: &str, rate_hz: f64) -> Result<Curve, String> {
    let stat: Stat = stat_name.parse().map_err(|e| format!("{stat_name}: {e}"))?;
    assert_eq!(stat.name(), stat_name);
    let data_type = match str_of(ds, "data_type") {
        "freq" => DataType::Freq,
        "phase" => DataType::Phase,
        other => panic!("unknown data_type {other:?}"),
    };
    let opts = Options {
        stat,
        data_type,
        rate_hz,
        taus: TauSpec::Octave,
        confidence: 0.683,
    };
    analyze(&f64s(&ds["data"]), &opts).map_err(|e| format!("analyze failed: {e}"))
}

#[test]
fn deviations_match_allantools() {
    let fx = fixture();
    let mut failures = Vec::new();
    let mut compared = 0usize;
    for ds in datasets(&fx) {
        let name = str_of(ds, "name");
        for stat_name in STATS {
            let ctx = format!("{name}/{stat_name}");
            let reference = Reference::new(&ds["stats"][stat_name]);
            let curve = match run(ds, stat_name, rate_hz(&fx)) {
                Ok(c) => c,
                Err(e) => {
                    failures.push(format!("{ctx}: {e}"));
                    continue;
                }
            };
            if curve.points.len() < MIN_TAUS {
                failures.push(format!(
                    "{ctx}: only {} taus reported, want at least {MIN_TAUS}",
                    curve.points.len()
                ));
            }
            for p in &curve.points {
                let Some(i) = reference.index_of(p) else {
                    failures.push(format!(
                        "{ctx}: tau {} (m = {}) is not among AllanTools' taus {:?}",
                        p.tau, p.m, reference.taus
                    ));
                    continue;
                };
                let want_tau = if stat_name == "theo1" {
                    0.75 * reference.taus[i]
                } else {
                    reference.taus[i]
                };
                if rel_diff(p.tau, want_tau) > TAU_RTOL {
                    failures.push(format!("{ctx} m={}: tau {} vs AllanTools {want_tau}", p.m, p.tau));
                }
                let (want, want_n) = (reference.devs[i], reference.ns[i]);
                let rd = rel_diff(p.dev, want);
                if !within(rd, DEV_RTOL) {
                    failures.push(format!(
                        "{ctx} tau={}: dev {:.17e} vs AllanTools {want:.17e} (rel diff {rd:.3e})",
                        p.tau, p.dev
                    ));
                }
                if p.n != want_n {
                    failures.push(format!("{ctx} tau={}: n {} vs AllanTools {want_n}", p.tau, p.n));
                }
                compared += 1;
            }
        }
    }
    println!("deviations compared with AllanTools: {compared} points");
    assert!(compared > 0, "no deviation was compared with AllanTools");
    assert!(
        failures.is_empty(),
        "{} disagreement(s) with AllanTools 2024.6:\n{}",
        failures.len(),
        failures.join("\n")
    );
}

#[test]
fn confidence_intervals_match_allantools() {
    let fx = fixture();
    let mut failures = Vec::new();
    let mut compared = 0usize;
    let mut other_alpha = Vec::new();
    for ds in datasets(&fx) {
        let name = str_of(ds, "name");
        for stat_name in CI_STATS {
            let ctx = format!("{name}/{stat_name}");
            let v = &ds["stats"][stat_name];
            let reference = Reference::new(v);
            let alphas: Vec<Option<i64>> = v["alpha"]
                .as_array()
                .expect("fixture lacks alpha")
                .iter()
                .map(Value::as_i64)
                .collect();
            let (edfs, los, his) = (
                opt_f64s(&v["edf"]),
                opt_f64s(&v["dev_lo"]),
                opt_f64s(&v["dev_hi"]),
            );
            let curve = match run(ds, stat_name, rate_hz(&fx)) {
                Ok(c) => c,
                Err(e) => {
                    failures.push(format!("{ctx}: {e}"));
                    continue;
                }
            };
            for p in &curve.points {
                // Missing taus are reported by deviations_match_allantools.
                let Some(i) = reference.index_of(p) else { continue };
                let (Some(alpha), Some(edf), Some(lo), Some(hi)) = (alphas[i], edfs[i], los[i], his[i])
                else {
                    continue;
                };
                if alpha != i64::from(p.alpha) {
                    other_alpha.push(format!(
                        "{ctx} tau={}: alpha {} vs AllanTools {alpha}",
                        p.tau, p.alpha
                    ));
                    continue;
                }
                for (what, got, want) in [
                    ("edf", p.edf, edf),
                    ("dev_lo", p.dev_lo, lo),
                    ("dev_hi", p.dev_hi, hi),
                ] {
                    let rd = rel_diff(got, want);
                    if !within(rd, EDF_RTOL) {
                        failures.push(format!(
                            "{ctx} tau={} alpha={alpha}: {what} {got:.12e} vs AllanTools {want:.12e} \
                             (rel diff {rd:.3e})",
                            p.tau
                        ));
                    }
                }
                compared += 1;
            }
        }
    }
    println!(
        "EDF and confidence bounds compared with AllanTools: {compared} points; \
         {} points skipped for a different noise identification",
        other_alpha.len()
    );
    for line in &other_alpha {
        println!("  {line}");
    }
    assert!(
        compared > 0,
        "no EDF was compared with AllanTools: imutherm never identified the same noise type"
    );
    assert!(
        failures.is_empty(),
        "{} EDF/interval disagreement(s) with AllanTools 2024.6:\n{}",
        failures.len(),
        failures.join("\n")
    );
}
