//! Every BSDF, one file each, with Mitsuba 3's parameter names and definitions
//! (<https://mitsuba.readthedocs.io/en/latest/src/generated/plugins_bsdfs.html>).

pub mod blend;
pub mod conductor;
pub mod dielectric;
pub mod diffuse;
pub mod lecture;
pub mod mask;
pub mod normalmap;
pub mod plastic;
pub mod principled;
pub mod principledthin;
pub mod roughconductor;
pub mod roughdielectric;
pub mod roughplastic;
pub mod thindielectric;
pub mod twosided;

pub use blend::Blend;
pub use conductor::Conductor;
pub use dielectric::Dielectric;
pub use diffuse::Diffuse;
pub use lecture::{LectureLobe, LectureMix};
pub use mask::Mask;
pub use normalmap::NormalMap;
pub use plastic::{fresnel_diffuse_reflectance, Plastic};
pub use principled::Principled;
pub use principledthin::PrincipledThin;
pub use roughconductor::RoughConductor;
pub use roughdielectric::RoughDielectric;
pub use roughplastic::{RoughPlastic, RoughPlasticTables};
pub use thindielectric::ThinDielectric;
pub use twosided::TwoSided;
