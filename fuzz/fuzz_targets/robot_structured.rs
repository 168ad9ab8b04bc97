//! The ULog and MCAP readers on files whose structure the fuzzer's bytes
//! choose (see `structured.rs`): formats nesting and containing
//! themselves, appended offsets, garbage between syncs; chunks of every
//! codec declaring right, wrong and absurd sizes. The first byte picks the
//! format. A bomb or a loop fails the run by its memory (`-rss_limit_mb`)
//! or time (`-timeout`) limit.
#![no_main]

#[path = "robot_log.rs"]
mod robot_log;
mod structured;

use libfuzzer_sys::fuzz_target;

fuzz_target!(|bytes: &[u8]| {
    let Some((&which, rest)) = bytes.split_first() else {
        return;
    };
    if which % 2 == 0 {
        robot_log::run(robotlogs::Format::ULog, "ulg", &structured::ulog::build(rest));
    } else {
        robot_log::run(robotlogs::Format::Mcap, "mcap", &structured::mcap::build(rest));
    }
});
