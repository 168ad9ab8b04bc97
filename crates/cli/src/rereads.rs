//! The commands that read an input more than once, each with its reason,
//! in one place: a pipe, a FIFO or standard input gives its bytes once, so
//! these refuse one before any work instead of waiting for a second read
//! that never comes. Every other command reads each input once.

use std::path::PathBuf;

use analysis::source::require_rereadable;

use crate::args::{Command, TcalCommand};

/// Refuses a stream given to a command that reads its inputs twice.
pub fn refuse_streams(command: &Command) -> Result<(), analysis::AnalysisError> {
    let (files, why): (&[PathBuf], &'static str) = match command {
        Command::Report(a) => (&a.files, "the report reads each recording more than once"),
        Command::Tcal(TcalCommand::Fit(a)) => (
            &a.files,
            "the model keeps a digest of each fitted run, read from its bytes apart from its samples",
        ),
        Command::Tcal(TcalCommand::Eval(a)) => (
            &a.files,
            "each run is told from the fitted ones by a digest of its bytes, read apart from its samples",
        ),
        _ => return Ok(()),
    };
    files.iter().try_for_each(|f| require_rereadable(f, why))
}
