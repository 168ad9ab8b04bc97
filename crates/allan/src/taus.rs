//! Tau grids: which averaging factors m (τ = m·τ0) a statistic is computed at.
//!
//! The largest averaging factor follows Stable32's stop ratio
//! ([`Stat::stop_ratio`]): beyond `N_phase / ratio` the estimates rest on so
//! few terms that they are noise themselves (AllanTools issue #68), so such
//! taus are dropped rather than returned.

use std::fmt;
use std::str::FromStr;

use crate::{AllanError, Stat};

/// Points per decade of the `many` grid: a few hundred points over the
/// decades an IMU recording spans, dense enough for slope reading.
pub const MANY_PER_DECADE: usize = 50;

/// Which taus to compute.
#[derive(Debug, Clone, PartialEq, Default)]
pub enum TauSpec {
    /// m = 1, 2, 4, 8, … (the default).
    #[default]
    Octave,
    /// m = 1, 2, 4, 10, 20, 40, 100, … (Stable32's decade spacing).
    Decade,
    /// Every m from 1 to the largest the data support. O(N) per tau, so
    /// O(N²) in all: meant for short series.
    All,
    /// Log-spaced, [`MANY_PER_DECADE`] per decade, de-duplicated.
    Many,
    /// Explicit taus in seconds; each is rounded to the nearest averaging
    /// factor, and duplicates after rounding are merged.
    List(Vec<f64>),
}

impl FromStr for TauSpec {
    type Err = AllanError;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s.trim().to_ascii_lowercase().as_str() {
            "octave" => Ok(TauSpec::Octave),
            "decade" => Ok(TauSpec::Decade),
            "all" => Ok(TauSpec::All),
            "many" => Ok(TauSpec::Many),
            other => {
                let taus = other
                    .split(',')
                    .map(|t| {
                        t.trim()
                            .parse::<f64>()
                            .ok()
                            .filter(|v| v.is_finite() && *v > 0.0)
                            .ok_or_else(|| AllanError::InvalidTaus(s.to_string()))
                    })
                    .collect::<Result<Vec<_>, _>>()?;
                if taus.is_empty() {
                    return Err(AllanError::InvalidTaus(s.to_string()));
                }
                Ok(TauSpec::List(taus))
            }
        }
    }
}

impl fmt::Display for TauSpec {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            TauSpec::Octave => f.write_str("octave"),
            TauSpec::Decade => f.write_str("decade"),
            TauSpec::All => f.write_str("all"),
            TauSpec::Many => f.write_str("many"),
            TauSpec::List(t) => {
                let parts: Vec<String> = t.iter().map(|v| v.to_string()).collect();
                f.write_str(&parts.join(","))
            }
        }
    }
}

/// The largest averaging factor `stat` is computed at on `n_phase` phase points.
pub fn max_factor(stat: Stat, n_phase: usize) -> usize {
    n_phase / stat.stop_ratio()
}

/// The τ a statistic reports at averaging factor m. Theo1 spans 0.75·m·τ0
/// (SP 1065 eq. 30); every other statistic m·τ0.
pub fn tau_of(stat: Stat, m: usize, tau0: f64) -> f64 {
    match stat {
        Stat::Theo1 => 0.75 * m as f64 * tau0,
        _ => m as f64 * tau0,
    }
}

/// What `stat` asks of the taus of a list, with the nearest ones it takes
/// to those asked for, for a message when none could be computed; empty
/// for a statistic that takes every multiple of τ0.
pub fn constraint(stat: Stat, spec: &TauSpec, tau0: f64, max_m: usize) -> String {
    let TauSpec::List(asked) = spec else {
        return String::new();
    };
    if stat != Stat::Theo1 || max_m < 2 {
        return String::new();
    }
    let largest_even = max_m - max_m % 2;
    let nearest: Vec<String> = asked
        .iter()
        .map(|&t| {
            let m = (((t / tau_of(stat, 2, tau0)).round().max(1.0) as usize) * 2).min(largest_even);
            short_number(tau_of(stat, m, tau0))
        })
        .collect();
    format!(
        "; theo1 needs τ = 0.75·m/rate with m even: nearest {} s (0.75·m·{} s)",
        nearest.join(", "),
        short_number(tau0)
    )
}

/// Six significant figures, without trailing zeros.
fn short_number(x: f64) -> String {
    let digits = (5 - x.abs().log10().floor() as i32).max(0) as usize;
    let text = format!("{x:.digits$}");
    if text.contains('.') {
        text.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        text
    }
}

/// The sorted, de-duplicated averaging factors of `spec` for `stat` on
/// `n_phase` phase points at interval `tau0`. Theo1 takes even factors only.
pub fn averaging_factors(spec: &TauSpec, stat: Stat, n_phase: usize, tau0: f64) -> Vec<usize> {
    let max_m = max_factor(stat, n_phase);
    let mut ms: Vec<usize> = match spec {
        TauSpec::Octave => std::iter::successors(Some(1usize), |m| m.checked_mul(2))
            .take_while(|&m| m <= max_m)
            .collect(),
        TauSpec::Decade => std::iter::successors(Some(1usize), |d| d.checked_mul(10))
            .take_while(|&d| d <= max_m)
            .flat_map(|d| [d, 2 * d, 4 * d])
            .filter(|&m| m <= max_m)
            .collect(),
        TauSpec::All => (1..=max_m).collect(),
        TauSpec::Many => {
            let decades = (max_m.max(1) as f64).log10();
            let count = (decades * MANY_PER_DECADE as f64).ceil() as usize;
            (0..=count)
                .map(|k| 10f64.powf(k as f64 / MANY_PER_DECADE as f64).round() as usize)
                .filter(|&m| m >= 1 && m <= max_m)
                .collect()
        }
        TauSpec::List(taus) => taus
            .iter()
            .filter_map(|&t| {
                let m = (t / tau_of(stat, 1, tau0)).round();
                (m >= 1.0 && m <= max_m as f64).then_some(m as usize)
            })
            .collect(),
    };
    if stat == Stat::Theo1 {
        ms.retain(|m| m % 2 == 0);
    }
    ms.sort_unstable();
    ms.dedup();
    ms
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn theo1_says_the_taus_it_takes() {
        // 200 Hz: τ = 0.75·m/200 with m even, 0.0075 s apart.
        let asked = TauSpec::List(vec![1.0, 10.0, 100.0]);
        let c = constraint(Stat::Theo1, &asked, 0.005, 100_000);
        assert!(c.contains("m even: nearest 0.9975, 9.9975, 99.9975 s"), "{c}");
        assert!(averaging_factors(&asked, Stat::Theo1, 240_001, 0.005).is_empty());
        assert_eq!(
            averaging_factors(
                &TauSpec::List(vec![1.5, 15.0, 150.0]),
                Stat::Theo1,
                240_001,
                0.005
            ),
            [400, 4000, 40000]
        );
        // At 1 Hz the nearest of 1 s is 1.5 s (m = 2), within the data.
        let c = constraint(Stat::Theo1, &TauSpec::List(vec![1.0, 1e9]), 1.0, 101);
        assert!(c.contains("nearest 1.5, 75 s"), "{c}");
        assert_eq!(constraint(Stat::Oadev, &asked, 0.005, 100), "");
        assert_eq!(constraint(Stat::Theo1, &TauSpec::Octave, 0.005, 100), "");
    }

    #[test]
    fn octave_stops_at_stop_ratio() {
        // 1001 phase points, OADEV stop ratio 4: m ≤ 250.
        let ms = averaging_factors(&TauSpec::Octave, Stat::Oadev, 1001, 1.0);
        assert_eq!(ms, vec![1, 2, 4, 8, 16, 32, 64, 128]);
        // SP 1065 Table 30: 10 phase points, ADEV at τ = 1 and 2.
        let ms = averaging_factors(&TauSpec::Octave, Stat::Adev, 10, 1.0);
        assert_eq!(ms, vec![1, 2]);
    }

    #[test]
    fn decade_and_many_grids() {
        let ms = averaging_factors(&TauSpec::Decade, Stat::Totdev, 1001, 1.0);
        assert_eq!(ms, vec![1, 2, 4, 10, 20, 40, 100, 200, 400]);
        let many = averaging_factors(&TauSpec::Many, Stat::Oadev, 4_000_001, 1.0);
        assert!(many.len() > 250 && many.len() < 400, "{}", many.len());
        assert!(many.windows(2).all(|w| w[0] < w[1]));
        assert_eq!(*many.last().unwrap(), 1_000_000);
    }

    #[test]
    fn explicit_list_rounds_and_drops() {
        let spec: TauSpec = "0.5, 1, 1.01, 300".parse().unwrap();
        // rate 2 Hz: τ0 = 0.5 s; 300 s needs m = 600 > 1000/4.
        let ms = averaging_factors(&spec, Stat::Oadev, 1000, 0.5);
        assert_eq!(ms, vec![1, 2]);
        assert!("1,-2".parse::<TauSpec>().is_err());
        assert!("fast".parse::<TauSpec>().is_err());
        assert!("".parse::<TauSpec>().is_err());
    }

    #[test]
    fn theo1_keeps_even_factors() {
        let ms = averaging_factors(&TauSpec::Octave, Stat::Theo1, 1001, 1.0);
        assert_eq!(ms, vec![2, 4, 8, 16, 32, 64, 128, 256, 512]);
        let spec = TauSpec::List(vec![7.5]);
        assert_eq!(averaging_factors(&spec, Stat::Theo1, 1001, 1.0), vec![10]);
    }
}
