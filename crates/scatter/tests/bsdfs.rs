//! Every BSDF of the crate through the harness of `common`: χ² of sampling against the
//! pdf, weights against eval and pdf, the pdf's mass, the albedo bound and reciprocity,
//! at several incident angles (both sides for the two-sided ones), roughnesses
//! (isotropic and anisotropic) and both microfacet sampling strategies.

mod common;

use common::check_bsdf;
use irradia_core::Rgb;
use irradia_scatter::bsdfs::*;
use irradia_scatter::ior::conductor_ior;
use irradia_scatter::microfacet::{Microfacet, MicrofacetType};
use irradia_scatter::Bsdf;

/// The number of χ² tests in this file, for the Sidak correction.
const TESTS: usize = 200;

fn roughnesses() -> Vec<(f32, f32)> {
    vec![(0.15, 0.15), (0.5, 0.5), (0.1, 0.45)]
}

fn distributions() -> Vec<Microfacet> {
    let mut v = Vec::new();
    for kind in [MicrofacetType::Beckmann, MicrofacetType::Ggx] {
        for (au, av) in roughnesses() {
            for visible in [true, false] {
                v.push(Microfacet::new(kind, au, av, visible));
            }
        }
    }
    v
}

fn label(name: &str, d: &Microfacet) -> String {
    format!(
        "{name}({:?}, α=({}, {}), visible={})",
        d.kind, d.alpha_u, d.alpha_v, d.sample_visible
    )
}

#[test]
fn diffuse() {
    let b = Bsdf::from(Diffuse {
        reflectance: Rgb::new(0.8, 0.5, 0.2),
    });
    check_bsdf("diffuse", &b, true, TESTS);
}

#[test]
fn smooth_conductor() {
    let (eta, k) = conductor_ior("Au").unwrap();
    let b = Bsdf::from(Conductor {
        eta,
        k,
        specular_reflectance: Rgb::WHITE,
    });
    check_bsdf("conductor(Au)", &b, true, TESTS);
}

#[test]
fn rough_conductor() {
    let (eta, k) = conductor_ior("Cu").unwrap();
    for d in distributions() {
        let b = Bsdf::from(RoughConductor {
            distribution: d,
            eta,
            k,
            specular_reflectance: Rgb::new(1.0, 0.9, 0.8),
        });
        check_bsdf(&label("roughconductor", &d), &b, true, TESTS);
    }
}

#[test]
fn smooth_dielectric() {
    for eta in [1.5f32, 1.0 / 1.33] {
        let b = Bsdf::from(Dielectric {
            eta,
            specular_reflectance: Rgb::WHITE,
            specular_transmittance: Rgb::WHITE,
        });
        check_bsdf(&format!("dielectric(η={eta})"), &b, true, TESTS);
    }
}

#[test]
fn thin_dielectric() {
    let b = Bsdf::from(ThinDielectric {
        eta: 1.5,
        specular_reflectance: Rgb::WHITE,
        specular_transmittance: Rgb::new(0.9, 0.9, 0.7),
    });
    check_bsdf("thindielectric", &b, true, TESTS);
}

#[test]
fn rough_dielectric() {
    for d in distributions() {
        let b = Bsdf::from(RoughDielectric {
            distribution: d,
            eta: 1.5,
            specular_reflectance: Rgb::WHITE,
            specular_transmittance: Rgb::WHITE,
        });
        check_bsdf(&label("roughdielectric", &d), &b, true, TESTS);
    }
}
