//! Mitsuba 3's `conductor`: a smooth conductor, a perfect mirror weighted by the exact
//! conductor Fresnel reflectance of the complex index `eta + i k` (relative to the
//! exterior) times `specular_reflectance`. One-sided: light arriving from the back side
//! (-z) is not scattered. A single delta lobe, so `eval` and `pdf` are 0.

use crate::bsdf::{BsdfSample, LobeFlags, Scatter};
use crate::optics::{fresnel_conductor_rgb, reflect};
use glam::{Vec2, Vec3};
use irradia_core::Rgb;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Conductor {
    /// Real part of the index of refraction (Mitsuba's `eta`).
    pub eta: Rgb,
    /// Imaginary part, the absorption coefficient (Mitsuba's `k`).
    pub k: Rgb,
    /// Mitsuba's `specular_reflectance`: a factor on the reflectance (1 physically).
    pub specular_reflectance: Rgb,
}

impl Scatter for Conductor {
    fn flags(&self) -> LobeFlags {
        LobeFlags::DELTA_REFLECTION | LobeFlags::FRONT_SIDE
    }

    fn eval(&self, _wo: Vec3, _wi: Vec3) -> Rgb {
        Rgb::BLACK
    }

    fn pdf(&self, _wo: Vec3, _wi: Vec3) -> f32 {
        0.0
    }

    fn sample(&self, wo: Vec3, _u_lobe: f32, _u: Vec2) -> Option<BsdfSample> {
        if wo.z <= 0.0 {
            return None;
        }
        Some(BsdfSample {
            wi: reflect(wo),
            weight: self.specular_reflectance * fresnel_conductor_rgb(wo.z, self.eta, self.k),
            pdf: 1.0,
            lobe: LobeFlags::DELTA_REFLECTION,
            eta: 1.0,
        })
    }
}
