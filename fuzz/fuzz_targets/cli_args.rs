//! imutherm's command line on arbitrary arguments: parsed or refused with a
//! usage error, never a panic. The flag definitions are compiled in from
//! the binary's own source.
#![no_main]

use clap::Parser;
use libfuzzer_sys::fuzz_target;

#[allow(dead_code)]
#[path = "../../crates/cli/src/args.rs"]
mod args;
#[allow(dead_code)]
#[path = "../../crates/cli/src/flags.rs"]
mod flags;

#[path = "../../crates/cli/src/help_examples.rs"]
mod help_examples;

fuzz_target!(|data: &[u8]| {
    // NUL-separated arguments; the first word of the subcommands steers
    // the fuzzer towards them.
    let text = String::from_utf8_lossy(data);
    let argv = std::iter::once("imutherm").chain(text.split('\0'));
    let _ = args::Cli::try_parse_from(argv);
});
