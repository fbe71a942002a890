//! Mitsuba 3's `principled` and `principledthin`: the Disney principled BSDF (Burley
//! 2012, 2015) with Mitsuba's parameter names and defaults.

use crate::texture::{ColorTexture, FloatTexture};

/// How `principled` is told its dielectric IOR: by `eta` or by `specular` (Mitsuba
/// accepts one of the two, default `specular = 0.5`); both are constants, not textures.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PrincipledSpecular {
    Eta(f32),
    Specular(f32),
}

impl PrincipledSpecular {
    /// The IOR: `eta`, or from `specular` by the Disney relation
    /// `F0 = 0.08 · specular = ((η - 1) / (η + 1))²`, so `η = 2 / (1 - √(0.08 s)) - 1`.
    pub fn eta(self) -> f32 {
        match self {
            PrincipledSpecular::Eta(e) => e,
            PrincipledSpecular::Specular(s) => 2.0 / (1.0 - (0.08 * s).sqrt()) - 1.0,
        }
    }
}

/// Mitsuba's `principled`.
#[derive(Clone, Debug, PartialEq)]
pub struct Principled {
    /// Default 0.5.
    pub base_color: ColorTexture,
    /// Default 0.5.
    pub roughness: FloatTexture,
    /// Default 0.
    pub anisotropic: FloatTexture,
    /// Default 0.
    pub metallic: FloatTexture,
    /// Default 0.
    pub spec_trans: FloatTexture,
    pub specular: PrincipledSpecular,
    /// Default 0.
    pub spec_tint: FloatTexture,
    /// Default 0.
    pub sheen: FloatTexture,
    /// Default 0.
    pub sheen_tint: FloatTexture,
    /// Default 0.
    pub flatness: FloatTexture,
    /// Default 0.
    pub clearcoat: FloatTexture,
    /// Default 0.
    pub clearcoat_gloss: FloatTexture,
    /// Default 1.
    pub main_specular_sampling_rate: f32,
    /// Default 1.
    pub clearcoat_sampling_rate: f32,
    /// Default 1.
    pub diffuse_reflectance_sampling_rate: f32,
}

impl Default for Principled {
    fn default() -> Self {
        Principled {
            base_color: ColorTexture::Value(irradia_core::Rgb::splat(0.5)),
            roughness: 0.5.into(),
            anisotropic: 0.0.into(),
            metallic: 0.0.into(),
            spec_trans: 0.0.into(),
            specular: PrincipledSpecular::Specular(0.5),
            spec_tint: 0.0.into(),
            sheen: 0.0.into(),
            sheen_tint: 0.0.into(),
            flatness: 0.0.into(),
            clearcoat: 0.0.into(),
            clearcoat_gloss: 0.0.into(),
            main_specular_sampling_rate: 1.0,
            clearcoat_sampling_rate: 1.0,
            diffuse_reflectance_sampling_rate: 1.0,
        }
    }
}

/// Mitsuba's `principledthin`: the thin-surface variant (no metallic, no clearcoat;
/// `eta` may be a texture; diffuse transmission `diff_trans`).
#[derive(Clone, Debug, PartialEq)]
pub struct PrincipledThin {
    /// Default 0.5.
    pub base_color: ColorTexture,
    /// Default 0.5.
    pub roughness: FloatTexture,
    /// Default 0.
    pub anisotropic: FloatTexture,
    /// Default 0.
    pub spec_trans: FloatTexture,
    /// Default 1.5.
    pub eta: FloatTexture,
    /// Default 0.
    pub spec_tint: FloatTexture,
    /// Default 0.
    pub sheen: FloatTexture,
    /// Default 0.
    pub sheen_tint: FloatTexture,
    /// Default 0.
    pub flatness: FloatTexture,
    /// Default 0.
    pub diff_trans: FloatTexture,
    /// Default 1.
    pub specular_reflectance_sampling_rate: f32,
    /// Default 1.
    pub diffuse_reflectance_sampling_rate: f32,
    /// Default 1.
    pub diffuse_transmittance_sampling_rate: f32,
    /// Default 1.
    pub specular_transmittance_sampling_rate: f32,
}

impl Default for PrincipledThin {
    fn default() -> Self {
        PrincipledThin {
            base_color: ColorTexture::Value(irradia_core::Rgb::splat(0.5)),
            roughness: 0.5.into(),
            anisotropic: 0.0.into(),
            spec_trans: 0.0.into(),
            eta: 1.5.into(),
            spec_tint: 0.0.into(),
            sheen: 0.0.into(),
            sheen_tint: 0.0.into(),
            flatness: 0.0.into(),
            diff_trans: 0.0.into(),
            specular_reflectance_sampling_rate: 1.0,
            diffuse_reflectance_sampling_rate: 1.0,
            diffuse_transmittance_sampling_rate: 1.0,
            specular_transmittance_sampling_rate: 1.0,
        }
    }
}
