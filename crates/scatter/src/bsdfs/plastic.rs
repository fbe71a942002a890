//! Mitsuba 3's `plastic`: a diffuse base under a smooth dielectric coating (a polished
//! plastic). Light reflects specularly off the coating with the Fresnel reflectance
//! `F(cos θo)`, or enters, scatters diffusely in the base, with internal reflections at
//! the coating summed as a geometric series, and leaves:
//!
//! `f_diffuse = ρ / (1 - F_dr,int) · (1 - F(θo)) (1 - F(θi)) / (η² π)`,
//!
//! with `F_dr,int` the diffuse Fresnel reflectance seen from inside (Weidlich and
//! Wilkie 2007, "Arbitrarily layered micro-facet surfaces"; Mitsuba's plugin). With
//! `nonlinear`, the series keeps the colour shift of repeated bounces: the denominator
//! is `1 - ρ F_dr,int` (per channel). One-sided (black from the back).
//!
//! Sampling picks the specular lobe with probability `F(θo) s / (F(θo) s + (1 - F(θo))
//! (1 - s))`, where `s = mean(specular) / (mean(diffuse) + mean(specular))` is
//! Mitsuba's specular sampling weight (Mitsuba averages over the whole texture; here
//! over the channels of the values at the point, the same for untextured parameters).

use crate::bsdf::{BsdfSample, LobeFlags, Scatter};
use crate::optics::{fresnel_dielectric, reflect};
use glam::{Vec2, Vec3};
use irradia_core::sampling::{cosine_hemisphere, cosine_hemisphere_pdf};
use irradia_core::Rgb;
use std::f32::consts::FRAC_1_PI;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Plastic {
    /// Mitsuba's `diffuse_reflectance` (default 0.5).
    pub diffuse_reflectance: Rgb,
    /// Mitsuba's `specular_reflectance`, a factor on the coating's reflection (default 1).
    pub specular_reflectance: Rgb,
    /// `int_ior / ext_ior` (Mitsuba's defaults: polypropylene 1.49 over air 1.000277).
    pub eta: f32,
    /// Mitsuba's `nonlinear`: account for the colour shift of internal scattering.
    pub nonlinear: bool,
}

/// The diffuse Fresnel reflectance `F_dr(η) = ∫ F(cos θ, η) 2 cos θ dcos θ` (the
/// reflectance of a smooth interface under uniform diffuse light), by the polynomial
/// fits Mitsuba's `fresnel_diffuse_reflectance` uses: Egan and Hilgeman (1973) for
/// `η < 1`, d'Eon and Irving (2011, "A quantized-diffusion model for rendering
/// translucent materials") for `η ≥ 1`.
pub fn fresnel_diffuse_reflectance(eta: f32) -> f32 {
    let inv = 1.0 / eta;
    if eta < 1.0 {
        0.0636 * inv + eta * (eta * -1.4399 + 0.7099) + 0.6681
    } else {
        // Horner's scheme in 1/η.
        [0.919317, -3.4793, 6.75335, -7.80989, 4.98554, -1.36881]
            .iter()
            .rev()
            .fold(0.0, |acc, c| acc * inv + c)
    }
}

impl Default for Plastic {
    fn default() -> Self {
        Self {
            diffuse_reflectance: Rgb::splat(0.5),
            specular_reflectance: Rgb::WHITE,
            eta: 1.49 / 1.000277,
            nonlinear: false,
        }
    }
}

impl Plastic {
    /// The diffuse base seen through the coating, divided by the transmissions
    /// `(1 - F(θo)) (1 - F(θi))`: `ρ / (1 - F_dr,int) / η²`.
    fn diffuse_through_coating(&self) -> Rgb {
        let fdr_int = fresnel_diffuse_reflectance(1.0 / self.eta);
        let rho = self.diffuse_reflectance;
        let denom = if self.nonlinear {
            Rgb::WHITE - rho * fdr_int
        } else {
            Rgb::splat(1.0 - fdr_int)
        };
        Rgb::new(rho.r / denom.r, rho.g / denom.g, rho.b / denom.b) / (self.eta * self.eta)
    }

    /// Mitsuba's specular sampling weight `s`.
    fn specular_sampling_weight(&self) -> f32 {
        let s = self.specular_reflectance.mean();
        let total = self.diffuse_reflectance.mean() + s;
        if total > 0.0 {
            s / total
        } else {
            0.0
        }
    }

    /// The probability of sampling the specular lobe at incidence `f_o = F(θo)`.
    fn prob_specular(&self, f_o: f32) -> f32 {
        let sw = self.specular_sampling_weight();
        let (s, d) = (f_o * sw, (1.0 - f_o) * (1.0 - sw));
        if s + d > 0.0 {
            s / (s + d)
        } else {
            0.0
        }
    }
}

impl Scatter for Plastic {
    fn flags(&self) -> LobeFlags {
        LobeFlags::DELTA_REFLECTION | LobeFlags::DIFFUSE_REFLECTION | LobeFlags::FRONT_SIDE
    }

    fn eval(&self, wo: Vec3, wi: Vec3) -> Rgb {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return Rgb::BLACK;
        }
        let t_o = fresnel_dielectric(wo.z, self.eta).transmittance();
        let t_i = fresnel_dielectric(wi.z, self.eta).transmittance();
        self.diffuse_through_coating() * (FRAC_1_PI * t_o * t_i)
    }

    fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return 0.0;
        }
        let f_o = fresnel_dielectric(wo.z, self.eta).reflectance;
        (1.0 - self.prob_specular(f_o)) * cosine_hemisphere_pdf(wi.z)
    }

    fn sample(&self, wo: Vec3, u_lobe: f32, u: Vec2) -> Option<BsdfSample> {
        if wo.z <= 0.0 {
            return None;
        }
        let f_o = fresnel_dielectric(wo.z, self.eta).reflectance;
        let p_spec = self.prob_specular(f_o);
        if u_lobe < p_spec {
            return Some(BsdfSample {
                wi: reflect(wo),
                weight: self.specular_reflectance * (f_o / p_spec),
                pdf: p_spec,
                lobe: LobeFlags::DELTA_REFLECTION,
                eta: 1.0,
            });
        }
        let wi = cosine_hemisphere(u);
        let p_diff = 1.0 - p_spec;
        let pdf = p_diff * cosine_hemisphere_pdf(wi.z);
        if wi.z <= 0.0 || pdf <= 0.0 {
            return None;
        }
        let t_i = fresnel_dielectric(wi.z, self.eta).transmittance();
        // f cos θi / pdf: the cosine cancels the cosine-weighted density (1/π included).
        Some(BsdfSample {
            wi,
            weight: self.diffuse_through_coating() * ((1.0 - f_o) * t_i / p_diff),
            pdf,
            lobe: LobeFlags::DIFFUSE_REFLECTION,
            eta: 1.0,
        })
    }
}
