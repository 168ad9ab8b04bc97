//! One module per subcommand.

pub mod adev;
