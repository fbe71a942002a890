//! Physically based materials as data: every Mitsuba 3 BSDF plugin with Mitsuba's
//! parameter names and defaults (its plugin documentation, "Surface scattering models").
//! Parameters Mitsuba accepts as textures are [`ColorTexture`] / [`FloatTexture`] here.
//! Named conductors (`material = "Au"`) and named IORs (`int_ior = "bk7"`) are resolved
//! when the scene is read, so a description holds numbers only.
//!
//! The BSDFs themselves (evaluate, sample, pdf) live in `irradia-scatter`; the lecture
//! fields a description also fills in [`crate::Material`] follow [`lecture`].

pub mod lecture;
pub mod principled;
pub mod visit;

pub use principled::{Principled, PrincipledSpecular, PrincipledThin};
pub use visit::TextureParam;

use crate::texture::{ColorTexture, FloatTexture};
use irradia_core::Rgb;

/// Mitsuba's `distribution` of the rough plugins.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Distribution {
    #[default]
    Beckmann,
    Ggx,
}

/// Microfacet roughness: `alpha`, or `alpha_u` and `alpha_v` for an anisotropic surface
/// (Mitsuba's default `alpha = 0.1`).
#[derive(Clone, Debug, PartialEq)]
pub enum Roughness {
    Isotropic(FloatTexture),
    Anisotropic {
        alpha_u: FloatTexture,
        alpha_v: FloatTexture,
    },
}

impl Default for Roughness {
    fn default() -> Self {
        Roughness::Isotropic(FloatTexture::Value(0.1))
    }
}

impl Roughness {
    /// One representative α: the constant, or the geometric mean `sqrt(α_u α_v)` of
    /// the means.
    pub fn mean_alpha(&self) -> f32 {
        match self {
            Roughness::Isotropic(a) => a.mean(),
            Roughness::Anisotropic { alpha_u, alpha_v } => (alpha_u.mean() * alpha_v.mean()).sqrt(),
        }
    }
}

/// A microfacet distribution with its roughness (Mitsuba's `distribution`, `alpha` /
/// `alpha_u` / `alpha_v`, `sample_visible`).
#[derive(Clone, Debug, PartialEq)]
pub struct Microfacet {
    pub distribution: Distribution,
    pub alpha: Roughness,
    /// Sample only the visible normals (Heitz and d'Eon 2014); Mitsuba's default true.
    pub sample_visible: bool,
}

impl Default for Microfacet {
    fn default() -> Self {
        Microfacet {
            distribution: Distribution::Beckmann,
            alpha: Roughness::default(),
            sample_visible: true,
        }
    }
}

/// Mitsuba's `diffuse`: a Lambertian reflector.
#[derive(Clone, Debug, PartialEq)]
pub struct Diffuse {
    /// Default 0.5.
    pub reflectance: ColorTexture,
}

/// Mitsuba's `conductor` and `roughconductor`: a metal with complex IOR `eta + i k`
/// (relative to the outside medium), either named (`material`) or given.
#[derive(Clone, Debug, PartialEq)]
pub struct Conductor {
    /// The `material` name the IOR came from, if one was given.
    pub material: Option<String>,
    /// Real part; Mitsuba's default (`material = "none"`) is 0 with `k = 1`: a perfect mirror.
    pub eta: ColorTexture,
    pub k: ColorTexture,
    /// Default 1.
    pub specular_reflectance: ColorTexture,
}

/// Mitsuba's `dielectric`, `roughdielectric` and `thindielectric`: the IORs inside
/// (`int_ior`, default "bk7" = 1.5046) and outside (`ext_ior`, default "air" = 1.000277).
#[derive(Clone, Debug, PartialEq)]
pub struct Dielectric {
    pub int_ior: f32,
    pub ext_ior: f32,
    /// Default 1.
    pub specular_reflectance: ColorTexture,
    /// Default 1.
    pub specular_transmittance: ColorTexture,
}

impl Dielectric {
    /// The relative IOR `int_ior / ext_ior`.
    pub fn eta(&self) -> f32 {
        self.int_ior / self.ext_ior
    }
}

/// Mitsuba's `plastic` and `roughplastic`: a diffuse base under a dielectric coating
/// (`int_ior` default "polypropylene" = 1.49, `ext_ior` default "air").
#[derive(Clone, Debug, PartialEq)]
pub struct Plastic {
    /// Default 0.5.
    pub diffuse_reflectance: ColorTexture,
    /// Default 1.
    pub specular_reflectance: ColorTexture,
    pub int_ior: f32,
    pub ext_ior: f32,
    /// Account for the colour shift of internal scattering (Mitsuba's default false).
    pub nonlinear: bool,
}

/// Mitsuba's `roughplastic` roughness: one constant `alpha` (not a texture) and a
/// distribution; no anisotropy.
#[derive(Clone, Debug, PartialEq)]
pub struct PlasticRoughness {
    pub distribution: Distribution,
    pub alpha: f32,
    pub sample_visible: bool,
}

/// One BSDF description: Mitsuba 3's plugin of that name.
#[derive(Clone, Debug, PartialEq)]
pub enum BsdfDesc {
    Diffuse(Diffuse),
    Conductor(Conductor),
    RoughConductor(Conductor, Microfacet),
    Dielectric(Dielectric),
    RoughDielectric(Dielectric, Microfacet),
    ThinDielectric(Dielectric),
    Plastic(Plastic),
    RoughPlastic(Plastic, PlasticRoughness),
    Principled(Box<Principled>),
    PrincipledThin(Box<PrincipledThin>),
    /// `(1 - weight) · bsdfs[0] + weight · bsdfs[1]` (Mitsuba's `blendbsdf`, `weight`
    /// default 0.5).
    Blend {
        weight: FloatTexture,
        bsdfs: Box<[BsdfDesc; 2]>,
    },
    /// `opacity` of the nested BSDF, the rest passes straight through (default 0.5).
    Mask {
        opacity: FloatTexture,
        bsdf: Box<BsdfDesc>,
    },
    /// The front BSDF on both sides, or a different one on the back.
    TwoSided {
        front: Box<BsdfDesc>,
        back: Option<Box<BsdfDesc>>,
    },
    /// Normals perturbed by the gradient of a height texture times `scale` (default 1).
    BumpMap {
        texture: FloatTexture,
        scale: f32,
        bsdf: Box<BsdfDesc>,
    },
    /// Normals read from a tangent-space normal map (`normalmap`, usually `raw = true`).
    NormalMap {
        normalmap: ColorTexture,
        bsdf: Box<BsdfDesc>,
    },
}

impl BsdfDesc {
    /// Mitsuba's plugin name.
    pub fn type_name(&self) -> &'static str {
        match self {
            BsdfDesc::Diffuse(_) => "diffuse",
            BsdfDesc::Conductor(_) => "conductor",
            BsdfDesc::RoughConductor(..) => "roughconductor",
            BsdfDesc::Dielectric(_) => "dielectric",
            BsdfDesc::RoughDielectric(..) => "roughdielectric",
            BsdfDesc::ThinDielectric(_) => "thindielectric",
            BsdfDesc::Plastic(_) => "plastic",
            BsdfDesc::RoughPlastic(..) => "roughplastic",
            BsdfDesc::Principled(_) => "principled",
            BsdfDesc::PrincipledThin(_) => "principledthin",
            BsdfDesc::Blend { .. } => "blendbsdf",
            BsdfDesc::Mask { .. } => "mask",
            BsdfDesc::TwoSided { .. } => "twosided",
            BsdfDesc::BumpMap { .. } => "bumpmap",
            BsdfDesc::NormalMap { .. } => "normalmap",
        }
    }
}

/// Every `type` a scene file accepts for a physically based material.
pub const BSDF_TYPES: [&str; 15] = [
    "diffuse",
    "conductor",
    "roughconductor",
    "dielectric",
    "roughdielectric",
    "thindielectric",
    "plastic",
    "roughplastic",
    "principled",
    "principledthin",
    "blendbsdf",
    "mask",
    "twosided",
    "bumpmap",
    "normalmap",
];

/// Unpolarised Fresnel reflectance at normal incidence of a conductor with complex
/// relative IOR `eta + i k`: `((η-1)² + k²) / ((η+1)² + k²)` per channel.
pub fn conductor_f0(eta: Rgb, k: Rgb) -> Rgb {
    let f = |n: f32, k: f32| ((n - 1.0).powi(2) + k * k) / ((n + 1.0).powi(2) + k * k);
    Rgb::new(f(eta.r, k.r), f(eta.g, k.g), f(eta.b, k.b))
}

/// Fresnel reflectance at normal incidence of a dielectric with relative IOR `eta`.
pub fn dielectric_f0(eta: f32) -> f32 {
    ((eta - 1.0) / (eta + 1.0)).powi(2)
}
