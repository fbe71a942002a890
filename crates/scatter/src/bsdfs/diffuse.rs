//! Mitsuba 3's `diffuse`: the ideal Lambertian reflector, `f = reflectance / π`, one-sided
//! (light arriving from the back side, -z, is not scattered; wrap it in `twosided` for
//! both). Sampled by the cosine-weighted hemisphere (Malley's method).

use crate::bsdf::{BsdfSample, LobeFlags, Scatter};
use glam::{Vec2, Vec3};
use irradia_core::sampling::{cosine_hemisphere, cosine_hemisphere_pdf};
use irradia_core::Rgb;
use std::f32::consts::FRAC_1_PI;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Diffuse {
    /// Mitsuba's `reflectance` (the albedo), evaluated at the surface point.
    pub reflectance: Rgb,
}

impl Scatter for Diffuse {
    fn flags(&self) -> LobeFlags {
        LobeFlags::DIFFUSE_REFLECTION | LobeFlags::FRONT_SIDE
    }

    fn eval(&self, wo: Vec3, wi: Vec3) -> Rgb {
        if wo.z > 0.0 && wi.z > 0.0 {
            self.reflectance * FRAC_1_PI
        } else {
            Rgb::BLACK
        }
    }

    fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        if wo.z > 0.0 && wi.z > 0.0 {
            cosine_hemisphere_pdf(wi.z)
        } else {
            0.0
        }
    }

    fn sample(&self, wo: Vec3, _u_lobe: f32, u: Vec2) -> Option<BsdfSample> {
        if wo.z <= 0.0 {
            return None;
        }
        let wi = cosine_hemisphere(u);
        let pdf = cosine_hemisphere_pdf(wi.z);
        (pdf > 0.0 && wi.z > 0.0).then_some(BsdfSample {
            wi,
            weight: self.reflectance,
            pdf,
            lobe: LobeFlags::DIFFUSE_REFLECTION,
            eta: 1.0,
        })
    }
}
