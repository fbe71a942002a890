//! White furnace of the rough conductor with F = 1 (Mitsuba's `none` material, a
//! perfect mirror's microfacets): the albedo `E(wo) = ∫ f(wo, wi) cos θi dωi` of a
//! single-scattering microfacet BRDF is below 1 by the energy of the light that
//! scatters more than once among the facets (Heitz, Hanika, d'Eon and Dachsbacher 2016,
//! "Multiple-Scattering Microfacet BSDFs with the Smith Model", Fig. 1; Kulla and Conty
//! 2017). The BSDF's own sampler estimates E(wo); an independent quadrature of
//! `D G / (4 cos θo cos θi) cos θi` over the hemisphere, with D and Λ written out here
//! from Walter et al. 2007 (eqs. 25, 27, 33, 34) rather than taken from the crate, is
//! the reference.

use glam::Vec3;
use irradia_core::{Rgb, Rng};
use irradia_scatter::bsdfs::RoughConductor;
use irradia_scatter::ior::conductor_ior;
use irradia_scatter::microfacet::{Microfacet, MicrofacetType};
use irradia_scatter::{Bsdf, Scatter};
use std::f64::consts::PI;

/// Isotropic D(θh) and Λ(θ), independently of the crate.
fn d_and_lambda(kind: MicrofacetType, alpha: f64) -> (impl Fn(f64) -> f64, impl Fn(f64) -> f64) {
    let d = move |cos_h: f64| {
        if cos_h <= 0.0 {
            return 0.0;
        }
        let c2 = cos_h * cos_h;
        let tan2 = (1.0 - c2) / c2;
        let a2 = alpha * alpha;
        match kind {
            MicrofacetType::Beckmann => (-tan2 / a2).exp() / (PI * a2 * c2 * c2),
            MicrofacetType::Ggx => a2 / (PI * c2 * c2 * (a2 + tan2).powi(2)),
        }
    };
    let lambda = move |cos: f64| {
        let tan = (1.0 - cos * cos).max(0.0).sqrt() / cos;
        if tan == 0.0 {
            return 0.0;
        }
        match kind {
            MicrofacetType::Beckmann => {
                let a = 1.0 / (alpha * tan);
                0.5 * (libm::erf(a) - 1.0) + (-a * a).exp() / (2.0 * a * PI.sqrt())
            }
            MicrofacetType::Ggx => 0.5 * ((1.0 + (alpha * tan).powi(2)).sqrt() - 1.0),
        }
    };
    (d, lambda)
}

/// E(wo) by the midpoint rule in (θi, φi) over the upper hemisphere.
fn albedo_quadrature(kind: MicrofacetType, alpha: f64, theta_o: f64) -> f64 {
    let (d, lambda) = d_and_lambda(kind, alpha);
    let wo = [theta_o.sin(), 0.0, theta_o.cos()];
    let (nt, np) = (1200, 600);
    let mut sum = 0.0;
    for i in 0..nt {
        let t = (i as f64 + 0.5) / nt as f64 * PI / 2.0;
        let (st, ct) = t.sin_cos();
        for j in 0..np {
            let p = (j as f64 + 0.5) / np as f64 * 2.0 * PI;
            let wi = [st * p.cos(), st * p.sin(), ct];
            let h = [wo[0] + wi[0], wo[1] + wi[1], wo[2] + wi[2]];
            let len = (h[0] * h[0] + h[1] * h[1] + h[2] * h[2]).sqrt();
            let cos_h = h[2] / len;
            let g = 1.0 / (1.0 + lambda(wo[2])) / (1.0 + lambda(ct));
            // f cos θi sin θi = D G / (4 cos θo) sin θi
            sum += d(cos_h) * g / (4.0 * wo[2]) * st;
        }
    }
    sum * (PI / 2.0 / nt as f64) * (2.0 * PI / np as f64)
}

#[test]
fn rough_mirror_loses_the_energy_of_multiple_scattering() {
    let (eta, k) = conductor_ior("none").unwrap();
    for kind in [MicrofacetType::Beckmann, MicrofacetType::Ggx] {
        let mut previous_loss = -1.0;
        for alpha in [0.2f32, 0.6, 1.0] {
            for theta_o in [0.0f32, 0.8, 1.3] {
                let b = Bsdf::from(RoughConductor {
                    distribution: Microfacet::new(kind, alpha, alpha, true),
                    eta,
                    k,
                    specular_reflectance: Rgb::WHITE,
                });
                let wo = Vec3::new(theta_o.sin(), 0.0, theta_o.cos());
                let n = 200_000;
                let mut rng = Rng::new(5, 1);
                let (mut sum, mut sum2) = (0.0f64, 0.0f64);
                for _ in 0..n {
                    let w = b
                        .sample(wo, rng.next_f32(), rng.next_2d())
                        .map_or(0.0, |s| s.weight.g as f64);
                    sum += w;
                    sum2 += w * w;
                }
                let mean = sum / n as f64;
                let sigma = ((sum2 / n as f64 - mean * mean).max(0.0) / n as f64).sqrt();
                let reference = albedo_quadrature(kind, alpha as f64, theta_o as f64);
                assert!(
                    (mean - reference).abs() < 5.0 * sigma + 2e-3,
                    "{kind:?} α={alpha} θo={theta_o}: sampled E = {mean:.4} ± {sigma:.4}, quadrature {reference:.4}"
                );
                assert!(reference <= 1.0 + 1e-3, "{kind:?}: E = {reference} > 1");
                if theta_o == 0.0 {
                    let loss = 1.0 - reference;
                    println!("{kind:?} α={alpha}: E(0) = {reference:.4}, single-scattering loss {loss:.4}");
                    assert!(loss > previous_loss, "the loss grows with the roughness");
                    previous_loss = loss;
                }
            }
        }
        // At normal incidence every normal tilted beyond 45° reflects below the horizon:
        // E(0) < 1 - P(θh > 45°) = 1 - exp(-1/α²) (Beckmann), 1/(1 + α²) (GGX); a
        // smooth surface loses nothing.
        for alpha in [0.6f64, 1.0] {
            let e = albedo_quadrature(kind, alpha, 0.0);
            let bound = match kind {
                MicrofacetType::Beckmann => 1.0 - (-1.0 / (alpha * alpha)).exp(),
                MicrofacetType::Ggx => 1.0 / (1.0 + alpha * alpha),
            };
            assert!(
                e < bound && e > 0.5 * bound,
                "{kind:?} α={alpha}: E(0) = {e}, bound {bound}"
            );
        }
        let e = albedo_quadrature(kind, 0.05, 0.0);
        assert!((e - 1.0).abs() < 5e-3, "{kind:?} α=0.05: E(0) = {e}");
    }
}
