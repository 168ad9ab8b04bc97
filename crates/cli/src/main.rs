//! `imutherm`: the command line over imutherm's libraries.
//!
//! Thin glue: flags are defined in [`args`], their values checked in
//! [`flags`] and turned into the libraries' options in `options`; the
//! libraries' messages name settings as flags through [`naming`]; each
//! subcommand lives in [`commands`], and this is the only crate that prints. Exit status: 0
//! success, 1 runtime error, 2 usage error.

#[cfg(not(any(feature = "analysis", feature = "record")))]
compile_error!("imutherm needs the feature `analysis`, `record` or both");

mod args;
mod commands;
mod flags;
mod help_examples;
mod naming;
#[cfg(feature = "analysis")]
mod options;
#[cfg(feature = "analysis")]
mod print;

use std::process::ExitCode;

use clap::Parser;

fn main() -> ExitCode {
    quiet_on_closed_stdout();
    naming::install();
    let cli = args::Cli::parse();
    let result = match cli.command {
        #[cfg(feature = "analysis")]
        args::Command::Demo(a) => commands::demo::run(&a),
        #[cfg(feature = "analysis")]
        args::Command::Adev(a) => commands::adev::run(&a),
        #[cfg(feature = "analysis")]
        args::Command::Info(a) => commands::info::run(&a),
        #[cfg(feature = "analysis")]
        args::Command::Noise(a) => commands::noise::run(&a),
        #[cfg(feature = "analysis")]
        args::Command::Simulate(a) => commands::simulate::run(&a),
        #[cfg(feature = "analysis")]
        args::Command::Thermal(a) => commands::thermal::run(&a),
        #[cfg(feature = "analysis")]
        args::Command::Report(a) => commands::report::run(&a),
        #[cfg(feature = "record")]
        args::Command::Record(a) => commands::record::run(&a),
        #[cfg(feature = "analysis")]
        args::Command::Tcal(args::TcalCommand::Fit(a)) => commands::tcal::fit(&a),
        #[cfg(feature = "analysis")]
        args::Command::Tcal(args::TcalCommand::Apply(a)) => commands::tcal::apply(&a),
        #[cfg(feature = "analysis")]
        args::Command::Tcal(args::TcalCommand::Eval(a)) => commands::tcal::eval(&a),
        #[cfg(feature = "analysis")]
        args::Command::Tcal(args::TcalCommand::Export(a)) => commands::tcal_export::run(&a),
        #[cfg(feature = "analysis")]
        args::Command::Ins(a) => commands::ins::run(&a),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        // The reader of the output left (`imutherm adev f | head -1`): it
        // has all it wanted, which is success (as ripgrep does).
        Err(e) if is_broken_pipe(&e) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            #[cfg(feature = "analysis")]
            if let Some(hint) = hint(&e) {
                eprintln!("{hint}");
            }
            ExitCode::from(if e.is::<flags::UsageError>() { 2 } else { 1 })
        }
    }
}

/// What a flag does about a refused line, said beside the refusal.
#[cfg(feature = "analysis")]
fn hint(e: &anyhow::Error) -> Option<&'static str> {
    let refused_line = e.chain().any(|c| {
        let read = c.downcast_ref::<imu::ReadError>().or(match c.downcast_ref() {
            Some(analysis::AnalysisError::Read(r)) => Some(r),
            _ => None,
        });
        read.is_some_and(|r| {
            matches!(
                r.kind,
                imu::ReadErrorKind::NotANumber { .. } | imu::ReadErrorKind::FieldCount { .. }
            )
        })
    });
    refused_line.then_some(
        "hint: --skip-bad-lines reads a malformed line as a gap (one missing sample) and reports it with its line",
    )
}

fn is_broken_pipe(e: &anyhow::Error) -> bool {
    e.chain().any(|c| {
        c.downcast_ref::<std::io::Error>()
            .is_some_and(|io| io.kind() == std::io::ErrorKind::BrokenPipe)
    })
}

/// `print!` panics when standard output fails. A closed pipe ends the
/// program quietly with status 0; any other failure (`> /dev/full`) is an
/// error with status 1, not a panic's backtrace.
fn quiet_on_closed_stdout() {
    let default = std::panic::take_hook();
    std::panic::set_hook(Box::new(move |info| {
        let message = info
            .payload()
            .downcast_ref::<String>()
            .map(String::as_str)
            .or_else(|| info.payload().downcast_ref::<&str>().copied())
            .unwrap_or("");
        // std's own wording (library/std/src/io/stdio.rs, `print_to`).
        if let Some(reason) = message.strip_prefix("failed printing to stdout: ") {
            if reason.starts_with("Broken pipe") {
                std::process::exit(0);
            }
            eprintln!("error: writing to standard output: {reason}");
            std::process::exit(1);
        }
        default(info);
    }));
}
