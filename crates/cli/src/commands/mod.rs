//! One module per subcommand.

pub mod adev;
pub mod demo;
pub mod experiment;
pub mod info;
pub mod ins;
pub mod noise;
pub mod record;
pub mod report;
pub mod robot_logs;
pub mod run_identity;
pub mod selection;
pub mod simulate;
pub mod tcal;
pub mod tcal_export;
pub mod thermal;
