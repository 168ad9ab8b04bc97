//! A population of units around one configuration: what a production line
//! makes from one design. Each unit's noise terms and bias polynomials
//! scatter around the configuration's (the population's centre), drawn from
//! a stream seeded by the unit's id alone, so that every run of a unit (a
//! static run, a thermal run, a held-out run) is the same board; the run's
//! own seed still picks the noise realisation.
//!
//! A unit may carry a planted [`Defect`], sized against the centre rather
//! than against the unit, so that a test knows exactly what it planted:
//! three times the noise, a bias slope five times the population's, or a
//! dead axis.
//!
//! ```
//! use imusim::population::{Defect, Scatter, draw};
//! use imusim::presets;
//!
//! let centre = presets::preset("mpu9250-thesis").unwrap();
//! let a = draw(&centre, "SN-0001", Scatter::default(), None).unwrap();
//! let again = draw(&centre, "SN-0001", Scatter::default(), None).unwrap();
//! assert_eq!(a, again);
//! let noisy = draw(&centre, "SN-0001", Scatter::default(), Some(&Defect::Noise3x)).unwrap();
//! assert_eq!(noisy.gyro.terms[0].n, 3.0 * a.gyro.terms[0].n);
//! ```

use rand::{Rng, SeedableRng};
use rand_distr::{Distribution, StandardNormal};
use rand_xoshiro::Xoshiro256PlusPlus;

use crate::SimError;
use crate::config::{GroupConfig, SimConfig};

/// The relative spread of the units around the centre (one standard
/// deviation).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Scatter {
    /// Of the noise terms: each term of each axis is multiplied by
    /// exp(σ·z), a log-normal factor (a noise density is never negative).
    pub noise: f64,
    /// Of the bias polynomial: each coefficient c becomes c·(1 + σ·z).
    pub bias: f64,
}

impl Default for Scatter {
    /// 10 % on the noise terms, 20 % on the bias coefficients: within the
    /// spread of the thesis's three axes (N 0.0084–0.0088 °/√s) and of the
    /// MPU-9250's datasheet offsets (±5 °/s, ±80 mg), which a production
    /// line sees between boards.
    fn default() -> Self {
        Scatter {
            noise: 0.1,
            bias: 0.2,
        }
    }
}

impl Scatter {
    /// Reads `NOISE,BIAS` (relative, e.g. `0.1,0.2`).
    pub fn parse(spec: &str) -> Result<Scatter, SimError> {
        let bad = |why| SimError::Population(format!("scatter '{spec}': {why}"));
        let (n, b) = spec
            .split_once(',')
            .ok_or_else(|| bad("expected NOISE,BIAS, e.g. 0.1,0.2"))?;
        let value = |s: &str| -> Result<f64, SimError> {
            let v: f64 = s.trim().parse().map_err(|_| bad("not a number"))?;
            if v.is_finite() && (0.0..=1.0).contains(&v) {
                Ok(v)
            } else {
                Err(bad("each spread must be a fraction from 0 to 1"))
            }
        };
        Ok(Scatter {
            noise: value(n)?,
            bias: value(b)?,
        })
    }
}

/// A fault planted in a unit.
#[derive(Debug, Clone, PartialEq)]
pub enum Defect {
    /// Every noise term of every axis three times the unit's own.
    Noise3x,
    /// Every axis's linear bias coefficient five times the centre's.
    Slope5x,
    /// One axis stuck: no noise and a constant output (its bias at the
    /// reference temperature), as a broken sense element or a stuck
    /// register reads.
    DeadAxis(String),
}

/// The channels a dead axis may be.
pub const AXES: [&str; 6] = ["accel_x", "accel_y", "accel_z", "gyro_x", "gyro_y", "gyro_z"];

impl Defect {
    /// Reads `noise-3x`, `slope-5x` or `dead-axis[:CHANNEL]` (gyro_z by
    /// default).
    pub fn parse(spec: &str) -> Result<Defect, SimError> {
        let s = spec.trim().to_ascii_lowercase();
        match s.split_once(':') {
            None if s == "noise-3x" => Ok(Defect::Noise3x),
            None if s == "slope-5x" => Ok(Defect::Slope5x),
            None if s == "dead-axis" => Ok(Defect::DeadAxis("gyro_z".into())),
            Some(("dead-axis", axis)) if AXES.contains(&axis) => Ok(Defect::DeadAxis(axis.into())),
            Some(("dead-axis", axis)) => Err(SimError::Population(format!(
                "dead axis '{axis}': expected one of {}",
                AXES.join(", ")
            ))),
            _ => Err(SimError::Population(format!(
                "defect '{spec}': expected noise-3x, slope-5x or dead-axis[:CHANNEL]"
            ))),
        }
    }

    /// The spelling [`Defect::parse`] reads.
    pub fn name(&self) -> String {
        match self {
            Defect::Noise3x => "noise-3x".into(),
            Defect::Slope5x => "slope-5x".into(),
            Defect::DeadAxis(a) => format!("dead-axis:{a}"),
        }
    }
}

/// FNV-1a, 64 bits: a hash fixed by its definition (Fowler, Noll, Vo), so
/// that a unit id draws the same unit on every platform and release, which
/// `std`'s hasher does not promise.
pub fn unit_hash(id: &str) -> u64 {
    id.bytes().fold(0xcbf2_9ce4_8422_2325, |h, b| {
        (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

/// The unit `id` of the population around `centre`. Its seed becomes the
/// centre's seed mixed with the id's hash, so that two units simulated with
/// the same seed do not share a noise realisation.
pub fn draw(
    centre: &SimConfig,
    id: &str,
    scatter: Scatter,
    defect: Option<&Defect>,
) -> Result<SimConfig, SimError> {
    if id.is_empty() {
        return Err(SimError::Population("a unit id must not be empty".into()));
    }
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(unit_hash(id));
    let mut unit = centre.clone();
    // Accelerometer first, then gyro, each axis's terms then its
    // polynomial: the order fixes which draw goes where.
    scatter_group(&mut unit.accel, scatter, &mut rng);
    scatter_group(&mut unit.gyro, scatter, &mut rng);
    unit.seed = centre.seed ^ unit_hash(id).rotate_left(17);
    match defect {
        None => {}
        Some(Defect::Noise3x) => {
            for g in [&mut unit.accel, &mut unit.gyro] {
                for t in &mut g.terms {
                    t.q *= 3.0;
                    t.n *= 3.0;
                    t.b *= 3.0;
                    t.k *= 3.0;
                    t.r *= 3.0;
                }
            }
        }
        Some(Defect::Slope5x) => {
            for (g, c) in [(&mut unit.accel, &centre.accel), (&mut unit.gyro, &centre.gyro)] {
                for (poly, centre_poly) in g.bias.iter_mut().zip(&c.bias) {
                    let slope = centre_poly.get(1).copied().unwrap_or(0.0);
                    if poly.len() < 2 {
                        poly.resize(2, 0.0);
                    }
                    poly[1] = 5.0 * slope;
                }
            }
        }
        Some(Defect::DeadAxis(axis)) => {
            let i = AXES
                .iter()
                .position(|a| a == axis)
                .ok_or_else(|| SimError::Population(format!("dead axis '{axis}' is not a channel")))?;
            let g = if i < 3 { &mut unit.accel } else { &mut unit.gyro };
            g.terms[i % 3] = Default::default();
            g.bias[i % 3].truncate(1);
        }
    }
    unit.validate()?;
    Ok(unit)
}

/// The metadata entries that say which unit a recording is, written beside
/// the `true.*` parameters (which are the unit's own).
pub fn describe(id: &str, scatter: Scatter, defect: Option<&Defect>) -> [(String, String); 3] {
    [
        ("population.unit".into(), id.into()),
        (
            "population.scatter".into(),
            format!("noise {} bias {}", scatter.noise, scatter.bias),
        ),
        (
            "population.defect".into(),
            defect.map_or_else(|| "none".into(), Defect::name),
        ),
    ]
}

fn scatter_group(g: &mut GroupConfig, s: Scatter, rng: &mut impl Rng) {
    for axis in 0..3 {
        let t = &mut g.terms[axis];
        for v in [&mut t.q, &mut t.n, &mut t.b, &mut t.k, &mut t.r] {
            let z: f64 = StandardNormal.sample(rng);
            *v *= (s.noise * z).exp();
        }
        for c in &mut g.bias[axis] {
            let z: f64 = StandardNormal.sample(rng);
            *c *= 1.0 + s.bias * z;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::presets;

    fn centre() -> SimConfig {
        presets::preset("mpu9250-thesis").unwrap()
    }

    #[test]
    fn a_unit_is_fixed_by_its_id_and_differs_from_others() {
        let c = centre();
        let a = draw(&c, "U001", Scatter::default(), None).unwrap();
        assert_eq!(a, draw(&c, "U001", Scatter::default(), None).unwrap());
        let b = draw(&c, "U002", Scatter::default(), None).unwrap();
        assert_ne!(a.gyro.terms[0].n, b.gyro.terms[0].n);
        assert_ne!(a.seed, b.seed);
        // The run's seed picks the realisation, not the unit.
        let mut other_run = c.clone();
        other_run.seed = 9;
        let a9 = draw(&other_run, "U001", Scatter::default(), None).unwrap();
        assert_eq!(a9.gyro, a.gyro);
        assert_ne!(a9.seed, a.seed);
    }

    #[test]
    fn no_scatter_is_the_centre() {
        let c = centre();
        let none = Scatter {
            noise: 0.0,
            bias: 0.0,
        };
        let u = draw(&c, "U001", none, None).unwrap();
        assert_eq!((u.gyro, u.accel), (c.gyro.clone(), c.accel.clone()));
    }

    #[test]
    fn the_scatter_has_the_asked_spread() {
        // 400 units: the log of N's factor has σ 0.1 (its standard error
        // is 0.1/√800 ≈ 0.0035, so 0.085..0.115 is over four of them).
        let c = centre();
        let logs: Vec<f64> = (0..400)
            .flat_map(|i| {
                let u = draw(&c, &format!("U{i:04}"), Scatter::default(), None).unwrap();
                [
                    (u.gyro.terms[0].n / c.gyro.terms[0].n).ln(),
                    (u.accel.terms[2].n / c.accel.terms[2].n).ln(),
                ]
            })
            .collect();
        let mean = logs.iter().sum::<f64>() / logs.len() as f64;
        let sd = (logs.iter().map(|l| (l - mean).powi(2)).sum::<f64>() / (logs.len() - 1) as f64).sqrt();
        assert!(mean.abs() < 0.02, "{mean}");
        assert!((0.085..0.115).contains(&sd), "{sd}");
    }

    #[test]
    fn planted_defects_are_what_they_say() {
        let c = centre();
        let s = Scatter::default();
        let u = draw(&c, "U7", s, None).unwrap();
        let slope = draw(&c, "U7", s, Some(&Defect::Slope5x)).unwrap();
        for axis in 0..3 {
            assert_eq!(slope.gyro.bias[axis][1], 5.0 * c.gyro.bias[axis][1]);
            assert_eq!(slope.accel.bias[axis][1], 5.0 * c.accel.bias[axis][1]);
            assert_eq!(slope.gyro.bias[axis][0], u.gyro.bias[axis][0]);
        }
        let dead = draw(&c, "U7", s, Some(&Defect::parse("dead-axis:accel_y").unwrap())).unwrap();
        assert_eq!(dead.accel.terms[1], Default::default());
        assert_eq!(dead.accel.bias[1], vec![u.accel.bias[1][0]]);
        assert_eq!(dead.gyro, u.gyro);
    }

    #[test]
    fn specs_are_read_and_bad_ones_refused() {
        assert_eq!(
            Defect::parse("dead-axis").unwrap(),
            Defect::DeadAxis("gyro_z".into())
        );
        for d in ["noise-3x", "slope-5x", "dead-axis:gyro_x"] {
            assert_eq!(Defect::parse(d).unwrap().name(), d);
        }
        assert!(
            Defect::parse("dead-axis:mag_x")
                .unwrap_err()
                .to_string()
                .contains("gyro_z")
        );
        assert!(Defect::parse("noise-4x").is_err());
        assert_eq!(
            Scatter::parse("0.05, 0.3").unwrap(),
            Scatter {
                noise: 0.05,
                bias: 0.3
            }
        );
        for bad in ["0.1", "x,0.2", "-0.1,0.2", "0.1,2"] {
            assert!(Scatter::parse(bad).is_err(), "{bad}");
        }
        assert!(draw(&centre(), "", Scatter::default(), None).is_err());
    }

    #[test]
    fn the_id_hash_is_fnv1a() {
        // FNV-1a 64 test vectors of its authors (isthe.com/chongo/tech/comp/fnv):
        // "" -> cbf29ce484222325, "a" -> af63dc4c8601ec8c.
        assert_eq!(unit_hash(""), 0xcbf2_9ce4_8422_2325);
        assert_eq!(unit_hash("a"), 0xaf63_dc4c_8601_ec8c);
    }
}
