//! Mitsuba 3's `dielectric`: a smooth interface between two dielectrics, a delta
//! reflection and a delta refraction chosen in proportion to the exact Fresnel
//! reflectance, so the weights are `specular_reflectance` and
//! `specular_transmittance (η_i/η_t)²`; the last factor is radiance transport's
//! compression of solid angle across the interface (Veach 1997, §5.2). Two-sided:
//! light from inside (-z) sees the relative index 1/eta and may be totally reflected.

use crate::bsdf::{BsdfSample, LobeFlags, Scatter};
use crate::optics::{fresnel_dielectric, reflect, refract};
use glam::{Vec2, Vec3};
use irradia_core::Rgb;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Dielectric {
    /// `int_ior / ext_ior`.
    pub eta: f32,
    /// Mitsuba's `specular_reflectance` and `specular_transmittance` (1 physically).
    pub specular_reflectance: Rgb,
    pub specular_transmittance: Rgb,
}

impl Scatter for Dielectric {
    fn flags(&self) -> LobeFlags {
        LobeFlags::DELTA_REFLECTION
            | LobeFlags::DELTA_TRANSMISSION
            | LobeFlags::FRONT_SIDE
            | LobeFlags::BACK_SIDE
    }

    fn eval(&self, _wo: Vec3, _wi: Vec3) -> Rgb {
        Rgb::BLACK
    }

    fn pdf(&self, _wo: Vec3, _wi: Vec3) -> f32 {
        0.0
    }

    fn sample(&self, wo: Vec3, u_lobe: f32, _u: Vec2) -> Option<BsdfSample> {
        let f = fresnel_dielectric(wo.z, self.eta);
        if u_lobe <= f.reflectance {
            Some(BsdfSample {
                wi: reflect(wo),
                weight: self.specular_reflectance,
                pdf: f.reflectance,
                lobe: LobeFlags::DELTA_REFLECTION,
                eta: 1.0,
            })
        } else {
            Some(BsdfSample {
                wi: refract(wo, f.cos_theta_t, f.eta_ti),
                weight: self.specular_transmittance * (f.eta_ti * f.eta_ti),
                pdf: f.transmittance(),
                lobe: LobeFlags::DELTA_TRANSMISSION,
                eta: f.eta_it,
            })
        }
    }
}
