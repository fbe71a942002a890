//! One module per subcommand.

pub mod bench;
pub mod bench_scale;
pub mod convert;
pub mod formfactor;
pub mod parallel;
pub mod radiosity;
pub mod radiosity_comm;
pub mod render;
pub mod render_comm;
pub mod render_path;
pub mod scenes;
pub mod trace_pixel;
pub mod wall;
