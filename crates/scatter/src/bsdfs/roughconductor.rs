//! Mitsuba 3's `roughconductor`: the microfacet conductor of Walter et al. 2007 (eq. 20)
//! with Beckmann or GGX normals, isotropic or anisotropic,
//! `f = F(wo·h) D(h) G(wo, wi, h) / (4 cos θo cos θi)` with the exact conductor Fresnel
//! of `eta + i k` times `specular_reflectance` and the separable Smith `G`. One-sided
//! (black from the back). Sampled through the microfacet normals (visible ones by
//! default, Heitz and d'Eon 2014), reflected about them.

use crate::bsdf::{BsdfSample, LobeFlags, Scatter};
use crate::microfacet::Microfacet;
use crate::optics::{fresnel_conductor_rgb, reflect_about};
use glam::{Vec2, Vec3};
use irradia_core::Rgb;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RoughConductor {
    /// Mitsuba's `distribution`, `alpha` or `alpha_u`/`alpha_v`, and `sample_visible`.
    pub distribution: Microfacet,
    /// Mitsuba's `eta` and `k`.
    pub eta: Rgb,
    pub k: Rgb,
    /// Mitsuba's `specular_reflectance`.
    pub specular_reflectance: Rgb,
}

impl RoughConductor {
    fn fresnel(&self, cos: f32) -> Rgb {
        self.specular_reflectance * fresnel_conductor_rgb(cos, self.eta, self.k)
    }
}

impl Scatter for RoughConductor {
    fn flags(&self) -> LobeFlags {
        let f = LobeFlags::GLOSSY_REFLECTION | LobeFlags::FRONT_SIDE;
        if self.distribution.is_anisotropic() {
            f | LobeFlags::ANISOTROPIC
        } else {
            f
        }
    }

    fn eval(&self, wo: Vec3, wi: Vec3) -> Rgb {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return Rgb::BLACK;
        }
        let h = (wo + wi).normalize();
        let d = self.distribution.d(h);
        if d == 0.0 {
            return Rgb::BLACK;
        }
        let g = self.distribution.g(wo, wi, h);
        self.fresnel(wo.dot(h)) * (d * g / (4.0 * wo.z * wi.z))
    }

    fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return 0.0;
        }
        let h = (wo + wi).normalize();
        let wi_h = wi.dot(h);
        if wi_h <= 0.0 {
            return 0.0;
        }
        // The Jacobian of reflection, dωh / dωi = 1 / (4 wi·h) (Walter et al., eq. 14).
        self.distribution.pdf(wo, h) / (4.0 * wi_h)
    }

    fn sample(&self, wo: Vec3, _u_lobe: f32, u: Vec2) -> Option<BsdfSample> {
        if wo.z <= 0.0 {
            return None;
        }
        let (m, pdf_m) = self.distribution.sample(wo, u);
        if pdf_m <= 0.0 {
            return None;
        }
        let wi = reflect_about(wo, m).normalize();
        let wi_m = wi.dot(m);
        if wi.z <= 0.0 || wi_m <= 0.0 {
            return None;
        }
        // f cos θi / pdf simplifies: G1(wi) for visible normals, G (wo·m)/(cos θo cos θm)
        // for all normals.
        let ratio = if self.distribution.sample_visible {
            self.distribution.g1(wi, m)
        } else {
            self.distribution.g(wo, wi, m) * wo.dot(m) / (wo.z * m.z)
        };
        Some(BsdfSample {
            wi,
            weight: self.fresnel(wo.dot(m)) * ratio,
            pdf: pdf_m / (4.0 * wi_m),
            lobe: LobeFlags::GLOSSY_REFLECTION,
            eta: 1.0,
        })
    }
}
