//! What a column is, judged from its header: imutherm's name, quantity,
//! axis and unit, with the units given by the user or the file's metadata.

use crate::header::{split_name_unit, split_unit_suffix};
use crate::names::quantity_of_name;
use crate::recording::{Axis, standard_name};
use crate::units::{Quantity, Unit, UnitOverride, UnitSource, parse_unit};

/// What a column is, judged from its header.
#[derive(Debug, Clone, PartialEq)]
pub struct ColumnKind {
    /// imutherm's name (`gyro_x`, `temp`) or the header's name.
    pub name: String,
    /// What it measures.
    pub quantity: Quantity,
    /// The axis of an inertial channel.
    pub axis: Option<Axis>,
    /// The conversion of its values to SI.
    pub unit: Unit,
    /// The unit of the converted values.
    pub unit_label: String,
    /// Where the unit came from.
    pub unit_source: UnitSource,
    /// A unit text that was given but is not one imutherm knows.
    pub unknown_unit: Option<String>,
}

/// Judges a column from its header (`name[unit]`, `name(unit)`,
/// `name_unit`), or from `unit_override` when given: the unit decides the
/// quantity when imutherm knows it; a name imutherm recognises
/// ([`crate::names`]) with no unit is taken as already in SI, and the unit
/// is marked [`UnitSource::Assumed`]; the last character `1/2/3` or `x/y/z`
/// gives the axis.
pub fn classify_header(header: &str, unit_override: Option<&str>) -> ColumnKind {
    classify(header, unit_override.map(|u| (u, UnitSource::Flag)))
}

/// [`classify_header`] with the unit from `overrides` when one names this
/// column by its header, its header without the unit, or its imutherm name
/// (`gyro_x`).
pub fn classify_with_overrides(header: &str, overrides: &[UnitOverride]) -> ColumnKind {
    classify_with_sources(header, overrides, &[])
}

/// [`classify_with_overrides`], with units from the file's metadata
/// (`# unit.gyro_x: deg/s`) below those of the command line.
pub fn classify_with_sources(
    header: &str,
    overrides: &[UnitOverride],
    metadata: &[(String, String)],
) -> ColumnKind {
    let plain = classify(header, None);
    if let Some(o) = overrides
        .iter()
        .find(|o| names_column(&o.column, header, &plain.name))
    {
        return classify(header, Some((&o.unit_text, UnitSource::Flag)));
    }
    if let Some((_, u)) = metadata
        .iter()
        .find(|(c, _)| names_column(c, header, &plain.name))
    {
        return classify(header, Some((u, UnitSource::Metadata)));
    }
    plain
}

/// Whether `wanted` names the column of `header` (imutherm name `name`):
/// by the whole header, the header without its unit, imutherm's name, or
/// its sensor (`gyro`, `accel`: every axis).
pub(super) fn names_column(wanted: &str, header: &str, name: &str) -> bool {
    let w = wanted.trim();
    let (bare, _) = split_name_unit(header);
    let stem = split_unit_suffix(bare).map_or(bare, |(s, _)| s);
    // A group, as a channel choice names it: every axis of the sensor.
    let group = match w.to_ascii_lowercase().as_str() {
        "gyro" | "gyros" => Some("gyro_"),
        "accel" | "accels" | "acc" => Some("accel_"),
        _ => None,
    };
    group.is_some_and(|g| name.starts_with(g))
        || [header, bare, stem, name]
            .iter()
            .any(|n| n.eq_ignore_ascii_case(w))
}

fn classify(header: &str, unit_override: Option<(&str, UnitSource)>) -> ColumnKind {
    let (mut name, mut unit_text) = split_name_unit(header);
    // A number in brackets is an index, not a unit: PX4's ulog2csv writes
    // `gyro_rad[0]` … `gyro_rad[2]` (pyulog, core.py flattening of arrays).
    let index_axis = unit_text.parse::<usize>().ok().map(|i| match i {
        0 => Some(Axis::X),
        1 => Some(Axis::Y),
        2 => Some(Axis::Z),
        _ => None,
    });
    if index_axis.is_some() {
        unit_text = "";
    }
    // A suffix is a unit only when what is left is a name that says the
    // same quantity: `acc_x_g` is in g, `gyro_x_s` is no time column.
    if unit_text.is_empty()
        && let Some((stem, suffix)) = split_unit_suffix(name)
        && let (Some((q, _)), Some(u)) = (quantity_of_name(stem), parse_unit(suffix))
        && q == u.quantity
    {
        name = stem;
        unit_text = suffix;
    }
    let mut source = if unit_text.is_empty() {
        UnitSource::Assumed
    } else {
        UnitSource::Header
    };
    if let Some((u, from)) = unit_override {
        unit_text = u;
        source = from;
    }
    let by_name = quantity_of_name(name);
    let parsed = parse_unit(unit_text);
    let unknown_unit = (!unit_text.is_empty() && parsed.is_none()).then(|| unit_text.to_string());
    // The unit decides the quantity when it is known; the name only when the
    // header carries no unit (imutherm's names are in SI).
    let unit = match (parsed, by_name) {
        (Some(u), _) => u,
        (None, Some((q, _))) if unit_text.is_empty() && q != Quantity::Time => Unit::si(q),
        (None, Some((Quantity::Time, _))) if unit_text.is_empty() => Unit {
            quantity: Quantity::Time,
            scale: 1.0,
            offset: 0.0,
        },
        _ => Unit {
            quantity: Quantity::Other,
            scale: 1.0,
            offset: 0.0,
        },
    };
    let quantity = unit.quantity;
    let axis = match (by_name, index_axis) {
        _ if !matches!(quantity, Quantity::Acceleration | Quantity::AngularRate) => None,
        (_, Some(a)) => a,
        (Some((_, a)), None) => a.or_else(|| trailing_axis(name)),
        (None, None) => trailing_axis(name),
    };
    let imu_name = match (quantity, axis) {
        (Quantity::Acceleration | Quantity::AngularRate, Some(_)) | (Quantity::Temperature, _) => {
            standard_name(quantity, axis)
        }
        _ => name.to_string(),
    };
    let unit_label = match quantity {
        Quantity::Other => unit_text.to_string(),
        q => q.si_unit().to_string(),
    };
    if quantity == Quantity::Other {
        source = if unit_text.is_empty() {
            UnitSource::Assumed
        } else {
            source
        };
    }
    ColumnKind {
        name: imu_name,
        quantity,
        axis,
        unit,
        unit_label,
        unit_source: source,
        unknown_unit,
    }
}

/// The axis a name's last character gives (`1/2/3`, `x/y/z`).
fn trailing_axis(name: &str) -> Option<Axis> {
    match name.to_ascii_lowercase().chars().last() {
        Some('1' | 'x') => Some(Axis::X),
        Some('2' | 'y') => Some(Axis::Y),
        Some('3' | 'z') => Some(Axis::Z),
        _ => None,
    }
}
