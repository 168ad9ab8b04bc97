//! One unit system for every noise figure of a page: the summary, the
//! answer, the thesis tables and the ADEV charts, in SI, the datasheets' or
//! the thesis's units (the vocabulary of `noise --units`), chosen once.
//!
//! `analysis` computes in SI and its [`Summary`] in the datasheets' units
//! (its comparisons are made there); this module only rescales and
//! relabels what the page shows, never what a JSON document carries.

use std::f64::consts::PI;

use allan::Point;
use allan::noise_terms::Term;
use analysis::datasheet::Figure;
use analysis::summary::{DatasheetCell, Summary};
pub use analysis::units::Units;
use imu::Quantity;
use imu::units::STANDARD_GRAVITY;

/// What a figure on the page measures.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// White noise N (a density in the datasheets' units).
    WhiteNoise,
    /// Bias instability B, σ_min and every ADEV value (a level of the rate).
    Instability,
    /// Rate random walk K.
    RandomWalk,
    /// A bias and a residual bias (the datasheets quote it in °/s and mg).
    Bias,
    /// A bias's slope over temperature.
    BiasSlope,
}

const KINDS: [Kind; 5] = [
    Kind::WhiteNoise,
    Kind::Instability,
    Kind::RandomWalk,
    Kind::Bias,
    Kind::BiasSlope,
];

/// The factor from the SI value of a `kind` figure of `quantity` to
/// `units`, and its unit; none for a quantity other than an angular rate or
/// an acceleration (those stay in their channel's unit).
pub fn unit(quantity: Quantity, kind: Kind, units: Units) -> Option<(f64, &'static str)> {
    let deg = 180.0 / PI;
    let (mg, ug) = (1.0 / (STANDARD_GRAVITY * 1e-3), 1.0 / (STANDARD_GRAVITY * 1e-6));
    Some(match (quantity, units, kind) {
        (Quantity::AngularRate, Units::Si, k) => match k {
            Kind::WhiteNoise => (1.0, "rad/√s"),
            Kind::Instability | Kind::Bias => (1.0, "rad/s"),
            Kind::RandomWalk => (1.0, "rad/s/√s"),
            Kind::BiasSlope => (1.0, "rad/s/°C"),
        },
        (Quantity::AngularRate, Units::Datasheet, k) => match k {
            // PS-MPU-9250A-01 §3.1: the rate noise spectral density.
            Kind::WhiteNoise => (deg, "°/s/√Hz"),
            Kind::Instability => (deg * 3600.0, "°/h"),
            Kind::RandomWalk => (deg * 216_000.0, "°/h/√h"),
            Kind::Bias => (deg, "°/s"),
            Kind::BiasSlope => (deg, "°/s/°C"),
        },
        (Quantity::AngularRate, Units::Thesis, k) => match k {
            Kind::WhiteNoise => (deg, "°/√s"),
            Kind::Instability | Kind::Bias => (deg, "°/s"),
            Kind::RandomWalk => (deg, "°/s/√s"),
            Kind::BiasSlope => (deg, "°/s/°C"),
        },
        (Quantity::Acceleration, Units::Datasheet, k) => match k {
            // PS-MPU-9250A-01 §3.2: µg/√Hz, and mg/°C for the offset.
            Kind::WhiteNoise => (ug, "µg/√Hz"),
            Kind::Instability => (ug, "µg"),
            Kind::RandomWalk => (ug, "µg/√s"),
            Kind::Bias => (mg, "mg"),
            Kind::BiasSlope => (mg, "mg/°C"),
        },
        // The thesis quotes its accelerometers in SI.
        (Quantity::Acceleration, _, k) => match k {
            Kind::WhiteNoise => (1.0, "m/s/√s"),
            Kind::Instability | Kind::Bias => (1.0, "m/s²"),
            Kind::RandomWalk => (1.0, "m/s²/√s"),
            Kind::BiasSlope => (1.0, "m/s²/°C"),
        },
        _ => return None,
    })
}

/// The page's kind of a noise term (Q and R are drawn, not tabulated, and
/// take the instability's level).
pub fn kind_of(term: Term) -> Kind {
    match term {
        Term::WhiteNoise => Kind::WhiteNoise,
        Term::RateRandomWalk => Kind::RandomWalk,
        _ => Kind::Instability,
    }
}

/// The factor and unit of a `kind` figure of a channel of `quantity` in
/// `data_unit` (its own unit, factor 1, when not an inertial channel).
pub fn unit_or(quantity: Quantity, data_unit: &str, kind: Kind, units: Units) -> (f64, String) {
    unit(quantity, kind, units).map_or_else(|| (1.0, data_unit.to_string()), |(f, u)| (f, u.to_string()))
}

/// The ADEV points of a channel in the page's units: the SI values times `factor`.
pub fn scaled(points: &[Point], factor: f64) -> Vec<Point> {
    points
        .iter()
        .map(|p| Point {
            dev: p.dev * factor,
            dev_lo: p.dev_lo * factor,
            dev_hi: p.dev_hi * factor,
            ..*p
        })
        .collect()
}

/// The factor from a datasheet-unit label to `units`, and the new label.
fn from_datasheet(label: &str, units: Units) -> Option<(f64, &'static str)> {
    [Quantity::AngularRate, Quantity::Acceleration]
        .into_iter()
        .flat_map(|q| KINDS.into_iter().map(move |k| (q, k)))
        .find_map(|(q, k)| {
            let (ds, l) = unit(q, k, Units::Datasheet)?;
            (l == label).then_some((q, k, ds))
        })
        .and_then(|(q, k, ds)| unit(q, k, units).map(|(f, l)| (f / ds, l)))
}

/// A datasheet-unit value and its unit, in `units` (unchanged when the
/// label is not one of the datasheets').
fn convert(value: &mut f64, label: &mut &'static str, units: Units) {
    if let Some((f, l)) = from_datasheet(label, units) {
        *value *= f;
        *label = l;
    }
}

fn convert_figure(figure: &mut Figure, units: Units) {
    let Some(label) = figure.unit.as_deref() else {
        return;
    };
    if let Some((f, l)) = from_datasheet(label, units) {
        figure.value = figure.value.map(|v| v * f);
        figure.unit = Some(l.to_string());
    }
}

fn convert_cell(cell: &mut DatasheetCell, units: Units) {
    if let DatasheetCell::Given { figure, .. } = cell {
        convert_figure(figure, units);
    }
}

/// The summary as the page shows it in `units`: every value with a unit
/// rescaled and relabelled, the datasheet's figures too; the verdicts stay
/// those made in the datasheets' units.
pub fn summary_in(summary: &Summary, units: Units) -> Summary {
    let mut s = summary.clone();
    for a in &mut s.axes {
        for t in &mut a.terms {
            if let Some((f, l)) = from_datasheet(t.unit, units) {
                for v in [&mut t.value, &mut t.lo, &mut t.hi].into_iter().flatten() {
                    *v *= f;
                }
                t.unit = l;
            }
            convert_cell(&mut t.datasheet, units);
        }
        if let Some(b) = &mut a.bias_slope {
            let mut label = b.unit;
            convert(&mut b.half_width, &mut label, units);
            convert(&mut b.value, &mut b.unit, units);
        }
        convert_cell(&mut a.bias_datasheet, units);
    }
    for c in &mut s.compensation {
        let mut label = c.unit;
        convert(&mut c.raw, &mut label, units);
        convert(&mut c.compensated, &mut c.unit, units);
    }
    for r in &mut s.gyro_noise_by_run {
        convert(&mut r.value, &mut r.unit, units);
    }
    if let Some((_, b)) = &mut s.steepest_gyro {
        let mut label = b.unit;
        convert(&mut b.half_width, &mut label, units);
        convert(&mut b.value, &mut b.unit, units);
    }
    s
}

/// Every unit label of `units` (for a page's checks).
pub fn labels(units: Units) -> Vec<&'static str> {
    [Quantity::AngularRate, Quantity::Acceleration]
        .into_iter()
        .flat_map(|q| {
            KINDS
                .into_iter()
                .filter_map(move |k| unit(q, k, units).map(|u| u.1))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use analysis::datasheet::summary_unit;
    use analysis::units::unit_of;

    /// The terms' units are those `noise --units` prints (N as the
    /// datasheets' density), so a page and `noise` agree.
    #[test]
    fn the_terms_units_are_those_of_noise_units() {
        for q in [Quantity::AngularRate, Quantity::Acceleration] {
            for units in [Units::Si, Units::Datasheet, Units::Thesis] {
                for t in [Term::BiasInstability, Term::RateRandomWalk] {
                    let (f, l) = unit_of(t, q, "", units);
                    let (g, m) = unit(q, kind_of(t), units).unwrap();
                    assert_eq!((l.as_str(), f), (m, g), "{q:?} {t:?} {units:?}");
                }
            }
            // The summary's own units are the datasheet system's.
            for t in [Term::WhiteNoise, Term::BiasInstability, Term::RateRandomWalk] {
                assert_eq!(
                    summary_unit(q, t),
                    unit(q, kind_of(t), Units::Datasheet).map(|u| u.1)
                );
            }
        }
        assert_eq!(unit(Quantity::Other, Kind::Bias, Units::Si), None);
    }

    /// 1 °/h is π/180/3600 rad/s and 1/3600 °/s; 1 mg/°C is g·10⁻³ m/s²/°C.
    #[test]
    fn a_datasheet_figure_converts_to_each_system() {
        let (f, l) = from_datasheet("°/h", Units::Si).unwrap();
        assert_eq!(l, "rad/s");
        assert!((f - PI / 180.0 / 3600.0).abs() < 1e-18);
        assert_eq!(from_datasheet("°/h", Units::Thesis).map(|u| u.1), Some("°/s"));
        let (f, l) = from_datasheet("mg/°C", Units::Thesis).unwrap();
        assert_eq!(l, "m/s²/°C");
        assert!((f - STANDARD_GRAVITY * 1e-3).abs() < 1e-15);
        assert_eq!(from_datasheet("µg", Units::Datasheet), Some((1.0, "µg")));
        assert_eq!(from_datasheet("m", Units::Si), None);
    }
}
