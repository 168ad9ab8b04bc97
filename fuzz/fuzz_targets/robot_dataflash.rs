//! The reader of ArduPilot DataFlash logs on arbitrary bytes.
#![no_main]

#[path = "robot_log.rs"]
mod robot_log;

use libfuzzer_sys::fuzz_target;

fuzz_target!(|bytes: &[u8]| robot_log::run(robotlogs::Format::DataFlash, "bin", bytes));
