//! Mitsuba 3's `roughplastic`: a diffuse base under a rough dielectric coating
//! (Weidlich and Wilkie 2007, "Arbitrarily layered micro-facet surfaces", as Mitsuba's
//! plugin). The coating reflects by the microfacet model of Walter et al. 2007,
//! `F(wo·h) D(h) G(wo, wi, h) / (4 cos θo cos θi)` times `specular_reflectance`; light
//! it transmits scatters in the base and leaves again:
//!
//! `f_diffuse = ρ / (1 - R_int) · T(θo) T(θi) / (η² π)`.
//!
//! The internal-scattering terms are Mitsuba's, precomputed once per (distribution,
//! roughness, η) in [`RoughPlasticTables`]:
//! - `T(θ)`, the coating's directional transmittance from outside, tabulated at 64
//!   cosines `max(10⁻⁶, j / 63)` and interpolated linearly; each entry is
//!   `∫ (1 - F(wo·m)) G1(wt, m) dP(m)` over the visible normals `m` of `wo`, `wt` the
//!   direction refracted through `m`, by Gauss-Legendre quadrature (32² nodes; 128²
//!   when η < 1) on the visible-normal sampling's unit square;
//! - `R_int`, the coating's reflectance seen from inside under uniform diffuse light,
//!   `2 · mean_j (R(μ_j, 1/η) μ_j)` over the same 64 cosines (a rectangle rule for
//!   `∫ R(μ) 2μ dμ`), `R(μ) = ∫ F(wo·m, 1/η) G1(wr, m) dP(m)` by 128² (η > 1) or 32²
//!   nodes, `wr` the reflected direction;
//! - the specular sampling weight `s = mean(specular) / (mean(diffuse) +
//!   mean(specular))` (per channel mean at the point; Mitsuba takes the whole texture's
//!   mean, the same for untextured parameters); the specular lobe is sampled with
//!   probability `(1 - T(θo)) s / ((1 - T(θo)) s + T(θo) (1 - s))`.
//!
//! With `nonlinear`, `1 - R_int` becomes `1 - ρ R_int` per channel. One-sided.
//! Mitsuba supports isotropic roughness only.

use crate::bsdf::{BsdfSample, LobeFlags, Scatter};
use crate::microfacet::{Microfacet, WarpPoint};
use crate::optics::{fresnel_dielectric, reflect_about, refract_about};
use glam::{Vec2, Vec3};
use irradia_core::sampling::{cosine_hemisphere, cosine_hemisphere_pdf};
use irradia_core::Rgb;
use rayon::prelude::*;
use std::f32::consts::FRAC_1_PI;
use std::sync::Arc;

/// Entries of the transmittance table (Mitsuba's `MI_ROUGH_TRANSMITTANCE_RES`).
pub const TRANSMITTANCE_RES: usize = 64;

/// The coating's internal-scattering terms for one (distribution, roughness, η).
#[derive(Clone, Debug, PartialEq)]
pub struct RoughPlasticTables {
    /// `T(μ)` at `μ_j = max(10⁻⁶, j / 63)`.
    pub external_transmittance: [f32; TRANSMITTANCE_RES],
    /// `R_int`.
    pub internal_reflectance: f32,
}

#[derive(Clone, Debug, PartialEq)]
pub struct RoughPlastic {
    /// Mitsuba's `distribution` and `alpha` (isotropic), with `sample_visible`.
    pub distribution: Microfacet,
    /// `int_ior / ext_ior` (Mitsuba's defaults: polypropylene 1.49 over air 1.000277).
    pub eta: f32,
    /// Mitsuba's `diffuse_reflectance` (default 0.5).
    pub diffuse_reflectance: Rgb,
    /// Mitsuba's `specular_reflectance` (default 1).
    pub specular_reflectance: Rgb,
    /// Mitsuba's `nonlinear`.
    pub nonlinear: bool,
    /// Computed from `distribution` and `eta` by [`RoughPlastic::new`]; shared by every
    /// surface point of one material.
    pub tables: Arc<RoughPlasticTables>,
}

/// Gauss-Legendre nodes and weights on [-1, 1] (Newton's iteration on the Legendre
/// recurrence, as Numerical Recipes' `gauleg`, in double precision).
fn gauss_legendre(n: usize) -> Vec<(f64, f64)> {
    let mut out = vec![(0.0, 0.0); n];
    for i in 0..n.div_ceil(2) {
        let mut z = (std::f64::consts::PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
        let mut dp = 0.0;
        for _ in 0..100 {
            let (mut p1, mut p2) = (1.0, 0.0);
            for j in 0..n {
                let p3 = p2;
                p2 = p1;
                p1 = ((2 * j + 1) as f64 * z * p2 - j as f64 * p3) / (j + 1) as f64;
            }
            dp = n as f64 * (z * p1 - p2) / (z * z - 1.0);
            let dz = p1 / dp;
            z -= dz;
            if dz.abs() < 1e-15 {
                break;
            }
        }
        let w = 2.0 / ((1.0 - z * z) * dp * dp);
        out[i] = (-z, w);
        out[n - 1 - i] = (z, w);
    }
    out
}

/// The `n²` Gauss-Legendre nodes of the unit square, as [`WarpPoint`]s with their two
/// weights on [-1, 1], from `gl` = [`gauss_legendre`]`(n)`: computed once per table and
/// warped for every direction.
fn unit_square_nodes(gl: &[(f64, f64)]) -> Vec<(WarpPoint, f64, f64)> {
    let mut nodes = Vec::with_capacity(gl.len() * gl.len());
    for &(x, wx) in gl {
        for &(y, wy) in gl {
            let u = Vec2::new((0.5 * x + 0.5) as f32, (0.5 * y + 0.5) as f32);
            nodes.push((WarpPoint::new(u), wx, wy));
        }
    }
    nodes
}

/// `∫ term(m) dP(m)` over the visible normals of `wo`, by Gauss-Legendre quadrature on
/// the sampling's unit square (Mitsuba's `eval_reflectance` / `eval_transmittance`),
/// `nodes` being [`unit_square_nodes`].
fn visible_normal_integral(
    distr: &Microfacet,
    wo: Vec3,
    nodes: &[(WarpPoint, f64, f64)],
    term: impl Fn(Vec3) -> f64,
) -> f64 {
    let sampler = distr.sampler_from(wo);
    let mut sum = 0.0;
    for (p, wx, wy) in nodes {
        let (m, pdf) = sampler.sample(p);
        if pdf > 0.0 {
            sum += term(m) * wx * wy * 0.25;
        }
    }
    sum
}

impl RoughPlasticTables {
    /// Mitsuba's precomputation for `distribution` (visible normals are used whatever
    /// its `sample_visible`) and `eta`.
    pub fn new(distribution: &Microfacet, eta: f32) -> Self {
        let distr = Microfacet {
            sample_visible: true,
            ..*distribution
        };
        let mus: Vec<f32> = (0..TRANSMITTANCE_RES)
            .map(|j| (j as f32 / (TRANSMITTANCE_RES - 1) as f32).max(1e-6))
            .collect();
        let wo_of = |mu: f32| Vec3::new((1.0 - mu * mu).sqrt(), 0.0, mu);
        let res = |eta: f32| if eta > 1.0 { 32 } else { 128 };
        let inv_eta = 1.0 / eta;
        let (gl_t, gl_r) = (
            unit_square_nodes(&gauss_legendre(res(eta))),
            unit_square_nodes(&gauss_legendre(res(inv_eta))),
        );
        // The cosines' integrals are independent: computed on the current rayon pool
        // (a million microfacet samples for the internal reflectance alone), each
        // alone as before, so the tables do not depend on the thread count.
        let mut external_transmittance = [0.0; TRANSMITTANCE_RES];
        let transmittance: Vec<f32> = mus
            .par_iter()
            .map(|&mu| {
                let wo = wo_of(mu);
                visible_normal_integral(&distr, wo, &gl_t, |m| {
                    let f = fresnel_dielectric(wo.dot(m), eta);
                    let wt = refract_about(wo, m, f.cos_theta_t, f.eta_ti);
                    if wt.z * wo.z >= 0.0 {
                        0.0
                    } else {
                        (distr.g1(wt, m) * f.transmittance()) as f64
                    }
                }) as f32
            })
            .collect();
        external_transmittance.copy_from_slice(&transmittance);
        let reflectances: Vec<f64> = mus
            .par_iter()
            .map(|&mu| {
                let wo = wo_of(mu);
                let r = visible_normal_integral(&distr, wo, &gl_r, |m| {
                    let wr = reflect_about(wo, m);
                    if wr.z <= 0.0 {
                        0.0
                    } else {
                        (distr.g1(wr, m) * fresnel_dielectric(wo.dot(m), inv_eta).reflectance)
                            as f64
                    }
                });
                r * mu as f64
            })
            .collect();
        // Summed in order, as before.
        let mean = reflectances.iter().sum::<f64>() / mus.len() as f64;
        Self {
            external_transmittance,
            internal_reflectance: (2.0 * mean) as f32,
        }
    }

    /// `T(cos θ)`, linearly interpolated (Mitsuba's `lerp_gather`).
    pub fn transmittance(&self, cos_theta: f32) -> f32 {
        let x = cos_theta * (TRANSMITTANCE_RES - 1) as f32;
        let i = (x.max(0.0) as usize).min(TRANSMITTANCE_RES - 2);
        let (v0, v1) = (
            self.external_transmittance[i],
            self.external_transmittance[i + 1],
        );
        v0 + (v1 - v0) * (x - i as f32)
    }
}

impl RoughPlastic {
    /// A rough plastic with its internal-scattering tables computed.
    pub fn new(
        distribution: Microfacet,
        eta: f32,
        diffuse_reflectance: Rgb,
        specular_reflectance: Rgb,
        nonlinear: bool,
    ) -> Self {
        Self {
            distribution,
            eta,
            diffuse_reflectance,
            specular_reflectance,
            nonlinear,
            tables: Arc::new(RoughPlasticTables::new(&distribution, eta)),
        }
    }

    /// `ρ / (1 - R_int) / η²`, the base seen through the coating without the
    /// transmittances.
    fn diffuse_through_coating(&self) -> Rgb {
        let r_int = self.tables.internal_reflectance;
        let rho = self.diffuse_reflectance;
        let denom = if self.nonlinear {
            Rgb::WHITE - rho * r_int
        } else {
            Rgb::splat(1.0 - r_int)
        };
        Rgb::new(rho.r / denom.r, rho.g / denom.g, rho.b / denom.b) / (self.eta * self.eta)
    }

    /// The probability of sampling the specular lobe from `wo`.
    fn prob_specular(&self, wo: Vec3) -> f32 {
        let s_mean = self.specular_reflectance.mean();
        let total = self.diffuse_reflectance.mean() + s_mean;
        let sw = if total > 0.0 { s_mean / total } else { 0.0 };
        let t_o = self.tables.transmittance(wo.z);
        let (s, d) = ((1.0 - t_o) * sw, t_o * (1.0 - sw));
        if s + d > 0.0 {
            s / (s + d)
        } else {
            0.0
        }
    }
}

impl Scatter for RoughPlastic {
    fn flags(&self) -> LobeFlags {
        LobeFlags::GLOSSY_REFLECTION | LobeFlags::DIFFUSE_REFLECTION | LobeFlags::FRONT_SIDE
    }

    fn eval(&self, wo: Vec3, wi: Vec3) -> Rgb {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return Rgb::BLACK;
        }
        let h = (wo + wi).normalize();
        let d = self.distribution.d(h);
        let specular = if d > 0.0 {
            let f = fresnel_dielectric(wo.dot(h), self.eta).reflectance;
            let g = self.distribution.g(wo, wi, h);
            self.specular_reflectance * (f * d * g / (4.0 * wo.z * wi.z))
        } else {
            Rgb::BLACK
        };
        let t = self.tables.transmittance(wo.z) * self.tables.transmittance(wi.z);
        specular + self.diffuse_through_coating() * (FRAC_1_PI * t)
    }

    fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return 0.0;
        }
        let p_spec = self.prob_specular(wo);
        let h = (wo + wi).normalize();
        let wi_h = wi.dot(h);
        let specular = if wi_h > 0.0 {
            self.distribution.pdf(wo, h) / (4.0 * wi_h)
        } else {
            0.0
        };
        p_spec * specular + (1.0 - p_spec) * cosine_hemisphere_pdf(wi.z)
    }

    fn sample(&self, wo: Vec3, u_lobe: f32, u: Vec2) -> Option<BsdfSample> {
        if wo.z <= 0.0 {
            return None;
        }
        let (wi, lobe) = if u_lobe < self.prob_specular(wo) {
            let (m, pdf_m) = self.distribution.sample(wo, u);
            if pdf_m <= 0.0 {
                return None;
            }
            (
                reflect_about(wo, m).normalize(),
                LobeFlags::GLOSSY_REFLECTION,
            )
        } else {
            (cosine_hemisphere(u), LobeFlags::DIFFUSE_REFLECTION)
        };
        let pdf = self.pdf(wo, wi);
        if wi.z <= 0.0 || pdf <= 0.0 {
            return None;
        }
        Some(BsdfSample {
            wi,
            weight: self.eval(wo, wi) * (wi.z / pdf),
            pdf,
            lobe,
            eta: 1.0,
        })
    }
}
