//! Every BSDF, one file each, with Mitsuba 3's parameter names and definitions
//! (<https://mitsuba.readthedocs.io/en/latest/src/generated/plugins_bsdfs.html>).

pub mod conductor;
pub mod dielectric;
pub mod diffuse;
pub mod lecture;
pub mod roughconductor;
pub mod roughdielectric;
pub mod thindielectric;

pub use conductor::Conductor;
pub use dielectric::Dielectric;
pub use diffuse::Diffuse;
pub use lecture::{LectureLobe, LectureMix};
pub use roughconductor::RoughConductor;
pub use roughdielectric::RoughDielectric;
pub use thindielectric::ThinDielectric;
