//! One module per subcommand.

pub mod bench;
pub mod parallel;
pub mod render;
pub mod scenes;
pub mod trace_pixel;
pub mod wall;
