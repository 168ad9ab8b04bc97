//! `imutherm`: the command line over imutherm's libraries.
//!
//! Thin glue: flags are defined in [`args`], each subcommand lives in
//! [`commands`], and this is the only crate that prints. Exit status: 0
//! success, 1 runtime error, 2 usage error.

mod args;
mod commands;
mod flags;

use std::process::ExitCode;

use clap::Parser;

fn main() -> ExitCode {
    let cli = args::Cli::parse();
    let result = match cli.command {
        args::Command::Demo(a) => commands::demo::run(&a),
        args::Command::Adev(a) => commands::adev::run(&a),
        args::Command::Info(a) => commands::info::run(&a),
        args::Command::Noise(a) => commands::noise::run(&a),
        args::Command::Simulate(a) => commands::simulate::run(&a),
        args::Command::Thermal(a) => commands::thermal::run(&a),
        args::Command::Report(a) => commands::report::run(&a),
        args::Command::Record(a) => commands::record::run(&a),
        args::Command::Tcal(args::TcalCommand::Fit(a)) => commands::tcal::fit(&a),
        args::Command::Tcal(args::TcalCommand::Apply(a)) => commands::tcal::apply(&a),
        args::Command::Tcal(args::TcalCommand::Eval(a)) => commands::tcal::eval(&a),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::from(if e.is::<flags::UsageError>() { 2 } else { 1 })
        }
    }
}
