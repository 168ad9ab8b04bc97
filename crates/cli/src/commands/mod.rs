//! One module per subcommand.

pub mod adev;
pub mod demo;
pub mod experiment;
pub mod info;
pub mod noise;
pub mod record;
pub mod report;
pub mod selection;
pub mod simulate;
pub mod tcal;
pub mod thermal;
