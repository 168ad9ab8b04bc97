//! What the reader's integration tests share.

// Each file in `tests/` is its own crate and uses only part of this module.
#![allow(dead_code)]

use imu::ReadReport;

/// Whether a note of `report` says `words`; the notes are shown when a
/// check fails.
pub fn has_note(report: &ReadReport, words: &str) -> bool {
    report.notes.iter().any(|n| n.contains(words))
}

/// Fails, showing the notes, unless one of them says `words`.
#[track_caller]
pub fn assert_note(report: &ReadReport, words: &str) {
    assert!(
        has_note(report, words),
        "no note says {words:?}: {:?}",
        report.notes
    );
}

/// Fails, showing the notes, if one of them says `words`.
#[track_caller]
pub fn assert_no_note(report: &ReadReport, words: &str) {
    assert!(
        !has_note(report, words),
        "a note says {words:?}: {:?}",
        report.notes
    );
}
