//! One module per subcommand.

pub mod adev;
pub mod info;
