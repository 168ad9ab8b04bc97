//! One module per subcommand.

#[cfg(feature = "analysis")]
pub mod adev;
#[cfg(feature = "analysis")]
pub mod demo;
#[cfg(feature = "analysis")]
pub mod info;
#[cfg(feature = "analysis")]
pub mod ins;
#[cfg(feature = "analysis")]
pub mod noise;
#[cfg(feature = "record")]
pub mod record;
#[cfg(feature = "analysis")]
pub mod report;
#[cfg(feature = "analysis")]
pub mod simulate;
#[cfg(feature = "analysis")]
pub mod tcal;
#[cfg(feature = "analysis")]
pub mod tcal_export;
#[cfg(feature = "analysis")]
pub mod thermal;
