//! One module per subcommand.

pub mod render;
pub mod scenes;
pub mod trace_pixel;
