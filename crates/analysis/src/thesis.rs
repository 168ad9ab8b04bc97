//! The thesis's noise tables as data: one table per sensor and term, rows
//! the axes, columns the runs (by mean temperature). The text table of
//! `imutherm noise` and the HTML tables of a report are both drawn from
//! this one model; only their cell formats differ.

use allan::noise_terms::{NoiseTerms, Term};
use imu::Quantity;

use crate::selection::SelectedChannel;
use crate::term_law::{At, LAW_TERMS, Law, Reading};

/// The tables.
pub struct ThesisTables<'a> {
    /// One column per run: its mean temperature, °C, when it has one.
    pub columns: Vec<Option<f64>>,
    /// Accelerometers, gyroscopes, then any other channels; groups
    /// without a channel are left out.
    pub groups: Vec<ThesisGroup<'a>>,
}

/// The rows of one sensor.
pub struct ThesisGroup<'a> {
    /// Acceleration, angular rate, or [`Quantity::Other`] for the rest.
    pub quantity: Quantity,
    /// "Accelerometer", "Gyroscope" or "Other".
    pub title: &'static str,
    /// One row per channel, in the order the runs first name them.
    pub rows: Vec<ThesisRow<'a>>,
}

/// One channel across the runs.
pub struct ThesisRow<'a> {
    /// The channel's name.
    pub name: &'a str,
    /// One cell per column; `None` where that run has no such channel.
    pub cells: Vec<Option<ThesisCell<'a>>>,
}

/// A channel of one run: its terms, in the unit of its data.
#[derive(Clone, Copy)]
pub struct ThesisCell<'a> {
    /// The channel.
    pub channel: &'a SelectedChannel,
    /// Its noise terms.
    pub terms: &'a NoiseTerms,
}

impl<'a> ThesisTables<'a> {
    /// The tables of `runs` runs, from each analysed channel with the index
    /// of its run; `columns` holds each run's mean temperature.
    pub fn new(
        columns: Vec<Option<f64>>,
        channels: impl IntoIterator<Item = (usize, &'a SelectedChannel, &'a NoiseTerms)>,
    ) -> Self {
        let channels: Vec<_> = channels.into_iter().collect();
        let mut names: Vec<(&str, Quantity)> = Vec::new();
        for (_, c, _) in &channels {
            if !names.iter().any(|(n, _)| *n == c.name) {
                names.push((c.name.as_str(), c.quantity));
            }
        }
        let groups = [
            (Quantity::Acceleration, "Accelerometer"),
            (Quantity::AngularRate, "Gyroscope"),
            (Quantity::Other, "Other"),
        ]
        .into_iter()
        .filter_map(|(q, title)| {
            let rows: Vec<ThesisRow> = names
                .iter()
                .filter(|(_, nq)| {
                    *nq == q
                        || (q == Quantity::Other
                            && !matches!(nq, Quantity::Acceleration | Quantity::AngularRate))
                })
                .map(|(name, _)| ThesisRow {
                    name,
                    cells: (0..columns.len())
                        .map(|i| {
                            channels
                                .iter()
                                .find(|(run, c, _)| *run == i && c.name == *name)
                                .map(|(_, channel, terms)| ThesisCell { channel, terms })
                        })
                        .collect(),
                })
                .collect();
            (!rows.is_empty()).then_some(ThesisGroup {
                quantity: q,
                title,
                rows,
            })
        })
        .collect();
        ThesisTables { columns, groups }
    }

    /// Every axis's law of each of [`LAW_TERMS`] over the runs'
    /// temperatures ([`ThesisRow::law`]), axis by axis: the table's
    /// differences, which are real and which are not.
    pub fn laws(&self, confidence: f64) -> Vec<(&'a str, Law)> {
        self.groups
            .iter()
            .flat_map(|g| &g.rows)
            .flat_map(|row| {
                LAW_TERMS
                    .iter()
                    .map(|&t| (row.name, row.law(&self.columns, t, confidence)))
            })
            .collect()
    }

    /// Whether at least two runs have a temperature: a law needs two.
    pub fn over_temperature(&self) -> bool {
        self.columns.iter().flatten().count() >= 2
    }

    /// The group of `quantity`, if any channel measures it.
    pub fn group(&self, quantity: Quantity) -> Option<&ThesisGroup<'a>> {
        self.groups.iter().find(|g| g.quantity == quantity)
    }
}

impl ThesisRow<'_> {
    /// `term` of this axis over the runs' temperatures (`columns`, the
    /// table's), intervals at `confidence`: its law and every pair of runs
    /// compared. A run without a temperature takes no part.
    pub fn law(&self, columns: &[Option<f64>], term: Term, confidence: f64) -> Law {
        let at: Vec<At> = self
            .cells
            .iter()
            .zip(columns)
            .filter_map(|(cell, t)| {
                Some(At {
                    t_c: (*t)?,
                    reading: Reading::of(cell.as_ref()?.terms, term),
                })
            })
            .collect();
        Law::fit(term, &at, confidence)
    }
}

impl ThesisGroup<'_> {
    /// The unit of the group's data: its first channel's.
    pub fn data_unit(&self) -> &str {
        self.rows
            .iter()
            .flat_map(|r| r.cells.iter().flatten())
            .map(|c| c.channel.unit.as_str())
            .next()
            .unwrap_or("")
    }
}
