//! The reader of ROS 2 SQLite3 bags on arbitrary bytes.
#![no_main]

#[path = "robot_log.rs"]
mod robot_log;

use libfuzzer_sys::fuzz_target;

fuzz_target!(|bytes: &[u8]| robot_log::run(robotlogs::Format::Sqlite, "db3", bytes));
