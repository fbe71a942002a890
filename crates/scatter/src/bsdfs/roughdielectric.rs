//! Mitsuba 3's `roughdielectric`: the microfacet dielectric of Walter, Marschner, Li
//! and Torrance 2007 ("Microfacet Models for Refraction through Rough Surfaces"),
//! Beckmann or GGX, isotropic or anisotropic, two-sided. Reflection
//! `f_r = F D G / (4 |cos θo cos θi|)` about the half vector `h = wo + wi` (eq. 20);
//! refraction `f_t = (1 - F) D G η² |wo·h| |wi·h| / (|cos θo cos θi| (wo·h + η wi·h)²)`
//! about the generalised half vector `h = -(wo + η wi)` (eqs. 16, 21) with `η = η_t/η_i`
//! for light arriving on the side of `wo`; in radiance transport refraction also
//! carries the compression `1/η²` (Veach 1997, §5.2). The microfacet normal is sampled
//! (visible normals by default; otherwise all normals from the distribution widened by
//! `1.2 - 0.2 sqrt|cos θo|`, Walter et al. §5.3), then the lobe in proportion to F.

use crate::bsdf::{BsdfSample, LobeFlags, Scatter};
use crate::microfacet::Microfacet;
use crate::optics::{fresnel_dielectric, reflect_about, refract_about};
use glam::{Vec2, Vec3};
use irradia_core::Rgb;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RoughDielectric {
    /// Mitsuba's `distribution`, `alpha` or `alpha_u`/`alpha_v`, and `sample_visible`.
    pub distribution: Microfacet,
    /// `int_ior / ext_ior`.
    pub eta: f32,
    pub specular_reflectance: Rgb,
    pub specular_transmittance: Rgb,
}

/// `w` flipped to the side of +z when `s < 0` (Mitsuba's `mulsign`).
#[inline]
fn mulsign(w: Vec3, s: f32) -> Vec3 {
    if s < 0.0 {
        -w
    } else {
        w
    }
}

impl RoughDielectric {
    /// The distribution normals are sampled from (and whose pdf `pdf` reports).
    fn sampling_distribution(&self, cos_theta_o: f32) -> Microfacet {
        if self.distribution.sample_visible {
            self.distribution
        } else {
            self.distribution
                .scaled(1.2 - 0.2 * cos_theta_o.abs().sqrt())
        }
    }

    /// The half vector of the pair, on the side of +z, and whether it is a reflection.
    fn half_vector(&self, wo: Vec3, wi: Vec3) -> Option<(Vec3, bool, f32)> {
        if wo.z == 0.0 || wi.z == 0.0 {
            return None;
        }
        let reflection = wo.z * wi.z > 0.0;
        let eta = if wo.z > 0.0 { self.eta } else { 1.0 / self.eta };
        let h = wo + wi * if reflection { 1.0 } else { eta };
        let h = h.normalize();
        let h = mulsign(h, h.z);
        // A microfacet is seen from the side of each direction's macrosurface only.
        if !h.is_finite() || wo.dot(h) * wo.z <= 0.0 || wi.dot(h) * wi.z <= 0.0 {
            return None;
        }
        Some((h, reflection, eta))
    }
}

impl Scatter for RoughDielectric {
    fn flags(&self) -> LobeFlags {
        let f = LobeFlags::GLOSSY_REFLECTION
            | LobeFlags::GLOSSY_TRANSMISSION
            | LobeFlags::FRONT_SIDE
            | LobeFlags::BACK_SIDE;
        if self.distribution.is_anisotropic() {
            f | LobeFlags::ANISOTROPIC
        } else {
            f
        }
    }

    fn eval(&self, wo: Vec3, wi: Vec3) -> Rgb {
        let Some((h, reflection, eta)) = self.half_vector(wo, wi) else {
            return Rgb::BLACK;
        };
        let d = self.distribution.d(h);
        if d == 0.0 {
            return Rgb::BLACK;
        }
        let f = fresnel_dielectric(wo.dot(h), self.eta).reflectance;
        let g = self.distribution.g(wo, wi, h);
        let cos = (wo.z * wi.z).abs();
        if reflection {
            self.specular_reflectance * (f * d * g / (4.0 * cos))
        } else {
            let (oh, ih) = (wo.dot(h), wi.dot(h));
            let denom = oh + eta * ih;
            // Radiance transport: the factor (η_i/η_t)² = 1/η².
            let value = (1.0 - f) * d * g * eta * eta * (oh * ih).abs() / (cos * denom * denom);
            self.specular_transmittance * (value / (eta * eta))
        }
    }

    fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        let Some((h, reflection, eta)) = self.half_vector(wo, wi) else {
            return 0.0;
        };
        let ih = wi.dot(h);
        let jacobian = if reflection {
            1.0 / (4.0 * ih.abs())
        } else {
            let denom = wo.dot(h) + eta * ih;
            eta * eta * ih.abs() / (denom * denom)
        };
        let f = fresnel_dielectric(wo.dot(h), self.eta).reflectance;
        let p_m = self.sampling_distribution(wo.z).pdf(mulsign(wo, wo.z), h);
        (p_m * if reflection { f } else { 1.0 - f } * jacobian).abs()
    }

    fn sample(&self, wo: Vec3, u_lobe: f32, u: Vec2) -> Option<BsdfSample> {
        if wo.z == 0.0 {
            return None;
        }
        let sampling = self.sampling_distribution(wo.z);
        let (m, pdf_m) = sampling.sample(mulsign(wo, wo.z), u);
        // A normal facing away from wo (possible when sampling all normals) is masked.
        if pdf_m <= 0.0 || wo.dot(m) * wo.z <= 0.0 {
            return None;
        }
        let fr = fresnel_dielectric(wo.dot(m), self.eta);
        let reflection = u_lobe <= fr.reflectance;
        let (wi, lobe, eta, lobe_pdf, jacobian) = if reflection {
            let wi = reflect_about(wo, m);
            let jac = 1.0 / (4.0 * wi.dot(m)).abs();
            (wi, LobeFlags::GLOSSY_REFLECTION, 1.0, fr.reflectance, jac)
        } else {
            let wi = refract_about(wo, m, fr.cos_theta_t, fr.eta_ti);
            let denom = wo.dot(m) + fr.eta_it * wi.dot(m);
            let jac = (fr.eta_it * fr.eta_it * wi.dot(m) / (denom * denom)).abs();
            (
                wi,
                LobeFlags::GLOSSY_TRANSMISSION,
                fr.eta_it,
                fr.transmittance(),
                jac,
            )
        };
        let wi = wi.normalize();
        let valid = if reflection {
            wo.z * wi.z > 0.0
        } else {
            wo.z * wi.z < 0.0
        };
        if !valid || !wi.is_finite() {
            return None;
        }
        let pdf = pdf_m * lobe_pdf * jacobian;
        if !(pdf > 0.0) {
            return None;
        }
        // f |cos θi| / pdf: G1(wi) for visible normals (the Fresnel factors cancel with
        // the lobe choice), the general quotient for the widened distribution.
        let ratio = if self.distribution.sample_visible {
            self.distribution.g1(wi, m)
        } else {
            self.distribution.d(m) * self.distribution.g(wo, wi, m) * wo.dot(m).abs()
                / (pdf_m * wo.z.abs())
        };
        let weight = if reflection {
            self.specular_reflectance * ratio
        } else {
            self.specular_transmittance * (ratio * fr.eta_ti * fr.eta_ti)
        };
        Some(BsdfSample {
            wi,
            weight,
            pdf,
            lobe,
            eta,
        })
    }
}
