//! Every BSDF, one file each, with Mitsuba 3's parameter names and definitions
//! (<https://mitsuba.readthedocs.io/en/latest/src/generated/plugins_bsdfs.html>).

pub mod diffuse;
pub mod lecture;

pub use diffuse::Diffuse;
pub use lecture::{LectureLobe, LectureMix};
