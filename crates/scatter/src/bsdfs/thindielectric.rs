//! Mitsuba 3's `thindielectric`: an infinitely thin slab of dielectric (a window pane),
//! whose two parallel interfaces reflect and transmit along the incident direction with
//! the Fresnel reflectance summed over the internal reflections,
//! `R' = R + T² R / (1 - R²) = 2R / (1 + R)`. Transmission passes straight through
//! (`wi = -wo`, a null interaction with no refraction). Two-sided; weights
//! `specular_reflectance` and `specular_transmittance`.

use crate::bsdf::{BsdfSample, LobeFlags, Scatter};
use crate::optics::{fresnel_dielectric, reflect};
use glam::{Vec2, Vec3};
use irradia_core::Rgb;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ThinDielectric {
    /// `int_ior / ext_ior` of the slab.
    pub eta: f32,
    pub specular_reflectance: Rgb,
    pub specular_transmittance: Rgb,
}

impl Scatter for ThinDielectric {
    fn flags(&self) -> LobeFlags {
        LobeFlags::DELTA_REFLECTION | LobeFlags::NULL | LobeFlags::FRONT_SIDE | LobeFlags::BACK_SIDE
    }

    fn eval(&self, _wo: Vec3, _wi: Vec3) -> Rgb {
        Rgb::BLACK
    }

    fn pdf(&self, _wo: Vec3, _wi: Vec3) -> f32 {
        0.0
    }

    fn sample(&self, wo: Vec3, u_lobe: f32, _u: Vec2) -> Option<BsdfSample> {
        let r = fresnel_dielectric(wo.z.abs(), self.eta).reflectance;
        // Both interfaces and the light bouncing between them.
        let r = if r < 1.0 { 2.0 * r / (1.0 + r) } else { 1.0 };
        if u_lobe <= r {
            Some(BsdfSample {
                wi: reflect(wo),
                weight: self.specular_reflectance,
                pdf: r,
                lobe: LobeFlags::DELTA_REFLECTION,
                eta: 1.0,
            })
        } else {
            Some(BsdfSample {
                wi: -wo,
                weight: self.specular_transmittance,
                pdf: 1.0 - r,
                lobe: LobeFlags::NULL,
                eta: 1.0,
            })
        }
    }
}
