//! The lecture's mixture, Mitsuba's plastics and the wrapping BSDFs (blend, mask,
//! twosided, normal map) through the harness of `common`: χ² of sampling against the
//! pdf, weights against eval and pdf, the pdf's mass, the albedo bound and reciprocity,
//! plus what each wrapper promises of its nested BSDFs.

mod common;

use common::{check_bsdf, check_samples, chi2_sampling, incident_directions};
use glam::{Vec2, Vec3};
use irradia_core::{Rgb, Rng};
use irradia_scatter::bsdfs::*;
use irradia_scatter::microfacet::{Microfacet, MicrofacetType};
use irradia_scatter::{Bsdf, LobeFlags, Scatter};

/// The number of χ² tests in this file, for the Sidak correction.
const TESTS: usize = 120;

fn diffuse(r: f32, g: f32, b: f32) -> Bsdf {
    Bsdf::from(Diffuse {
        reflectance: Rgb::new(r, g, b),
    })
}

fn rough_plastic(kind: MicrofacetType, alpha: f32, visible: bool, nonlinear: bool) -> Bsdf {
    Bsdf::from(RoughPlastic::new(
        Microfacet::new(kind, alpha, alpha, visible),
        1.49 / 1.000277,
        Rgb::new(0.7, 0.4, 0.1),
        Rgb::splat(0.9),
        nonlinear,
    ))
}

#[test]
fn lecture_mixtures() {
    let mixes = [
        LectureMix::new()
            .with(LectureLobe::Lambert {
                albedo: Rgb::new(0.5, 0.3, 0.2),
            })
            .with(LectureLobe::Phong {
                ks: Rgb::splat(0.3),
                exponent: 8.0,
            }),
        LectureMix::new()
            .with(LectureLobe::Lambert {
                albedo: Rgb::splat(0.3),
            })
            .with(LectureLobe::Phong {
                ks: Rgb::splat(0.3),
                exponent: 30.0,
            })
            .with(LectureLobe::Mirror { r: Rgb::splat(0.3) }),
        LectureMix::new()
            .with(LectureLobe::Lambert {
                albedo: Rgb::splat(0.3),
            })
            .with(LectureLobe::Dielectric {
                eta: 1.5,
                tint: Rgb::new(1.0, 0.8, 0.5),
                weight: 0.7,
            }),
    ];
    for (k, m) in mixes.into_iter().enumerate() {
        assert!(m.flags().intersects(LobeFlags::BACK_SIDE));
        check_bsdf(&format!("lecture mix #{k}"), &Bsdf::from(m), true, TESTS);
    }
}

#[test]
fn plastic() {
    for nonlinear in [false, true] {
        for eta in [1.49f32, 2.0] {
            let b = Bsdf::from(Plastic {
                diffuse_reflectance: Rgb::new(0.8, 0.4, 0.1),
                specular_reflectance: Rgb::splat(0.9),
                eta,
                nonlinear,
            });
            check_bsdf(
                &format!("plastic(η={eta}, nonlinear={nonlinear})"),
                &b,
                false,
                TESTS,
            );
        }
    }
}

#[test]
fn rough_plastics() {
    for kind in [MicrofacetType::Beckmann, MicrofacetType::Ggx] {
        for (alpha, visible, nonlinear) in [(0.1, true, false), (0.4, false, true)] {
            let b = rough_plastic(kind, alpha, visible, nonlinear);
            let label = format!("roughplastic({kind:?}, α={alpha}, visible={visible})");
            check_bsdf(&label, &b, false, TESTS);
        }
    }
}

/// The coating's tabulated terms against their smooth limits: as α → 0 the
/// transmittance at normal incidence tends to 1 - F(0) and the internal diffuse
/// reflectance to the smooth interface's F_dr(1/η); the transmittance falls towards
/// grazing.
#[test]
fn rough_plastic_tables_approach_the_smooth_limits() {
    let eta = 1.5f32;
    let smooth =
        RoughPlasticTables::new(&Microfacet::new(MicrofacetType::Ggx, 0.01, 0.01, true), eta);
    let f0 = ((eta - 1.0) / (eta + 1.0)).powi(2);
    assert!(
        (smooth.transmittance(1.0) - (1.0 - f0)).abs() < 2e-3,
        "T(1) = {}",
        smooth.transmittance(1.0)
    );
    let fdr = fresnel_diffuse_reflectance(1.0 / eta);
    assert!(
        (smooth.internal_reflectance - fdr).abs() < 0.01,
        "R_int {} vs F_dr(1/η) {fdr}",
        smooth.internal_reflectance
    );
    let rough = RoughPlasticTables::new(
        &Microfacet::new(MicrofacetType::Beckmann, 0.5, 0.5, false),
        eta,
    );
    let t = &rough.external_transmittance;
    assert!(t[63] > t[8] && t[8] > 0.0 && t[63] <= 1.0, "{t:?}");
}

#[test]
fn blend_of_diffuse_and_rough_plastic() {
    for weight in [0.0f32, 0.3, 1.0] {
        let b = Bsdf::from(Blend {
            weight,
            bsdf_0: Box::new(diffuse(0.8, 0.2, 0.2)),
            bsdf_1: Box::new(rough_plastic(MicrofacetType::Ggx, 0.2, true, false)),
        });
        check_bsdf(&format!("blend(w={weight})"), &b, false, TESTS);
    }
    // A delta lobe inside a blend keeps its own weight.
    let b = Bsdf::from(Blend {
        weight: 0.5,
        bsdf_0: Box::new(diffuse(0.5, 0.5, 0.5)),
        bsdf_1: Box::new(Bsdf::from(Plastic::default())),
    });
    check_bsdf("blend(diffuse, plastic)", &b, false, TESTS);
}

#[test]
fn blend_is_the_weighted_sum() {
    let (a, b) = (diffuse(0.8, 0.2, 0.2), Bsdf::from(Plastic::default()));
    let blend = Bsdf::from(Blend {
        weight: 0.25,
        bsdf_0: Box::new(a.clone()),
        bsdf_1: Box::new(b.clone()),
    });
    let mut rng = Rng::new(1, 2);
    for _ in 0..200 {
        let (wo, wi) = (hemisphere(rng.next_2d()), hemisphere(rng.next_2d()));
        let want = a.eval(wo, wi) * 0.75 + b.eval(wo, wi) * 0.25;
        let got = blend.eval(wo, wi);
        for c in 0..3 {
            assert!((got[c] - want[c]).abs() < 1e-6, "{got:?} vs {want:?}");
        }
        let want = a.pdf(wo, wi) * 0.75 + b.pdf(wo, wi) * 0.25;
        assert!((blend.pdf(wo, wi) - want).abs() < 1e-6);
    }
}

#[test]
fn mask_passes_light_straight_through() {
    for opacity in [0.0f32, 0.4, 1.0] {
        let b = Bsdf::from(Mask {
            opacity,
            nested_bsdf: Box::new(diffuse(0.7, 0.7, 0.7)),
        });
        assert!(b.flags().intersects(LobeFlags::NULL));
        check_bsdf(&format!("mask(opacity={opacity})"), &b, false, TESTS);
        // The null lobe: wi = -wo, weight 1, chosen with probability 1 - opacity.
        let wo = Vec3::new(0.3, -0.2, 0.9).normalize();
        let mut rng = Rng::new(4, 4);
        let n = 20_000;
        let mut through = 0;
        for _ in 0..n {
            let s = b.sample(wo, rng.next_f32(), rng.next_2d()).unwrap();
            if s.lobe == LobeFlags::NULL {
                through += 1;
                assert!(s.is_delta() && s.wi == -wo && s.weight == Rgb::WHITE);
                assert!((s.pdf - (1.0 - opacity)).abs() < 1e-6);
            }
        }
        let frac = through as f32 / n as f32;
        let sigma = (opacity * (1.0 - opacity) / n as f32).sqrt();
        assert!(
            (frac - (1.0 - opacity)).abs() <= 5.0 * sigma + 1e-6,
            "{frac}"
        );
    }
}

#[test]
fn twosided_mirrors_the_back_side() {
    let front = diffuse(0.8, 0.4, 0.2);
    let back = rough_plastic(MicrofacetType::Beckmann, 0.3, true, false);
    let same = Bsdf::from(TwoSided {
        front: Box::new(front.clone()),
        back: None,
    });
    let both = Bsdf::from(TwoSided {
        front: Box::new(front.clone()),
        back: Some(Box::new(back.clone())),
    });
    let f = same.flags();
    assert!(f.intersects(LobeFlags::FRONT_SIDE) && f.intersects(LobeFlags::BACK_SIDE));
    check_bsdf("twosided(diffuse)", &same, true, TESTS);
    check_bsdf("twosided(diffuse, roughplastic)", &both, true, TESTS);
    let flip = |w: Vec3| Vec3::new(w.x, w.y, -w.z);
    let mut rng = Rng::new(9, 9);
    for _ in 0..200 {
        let (wo, wi) = (hemisphere(rng.next_2d()), hemisphere(rng.next_2d()));
        assert_eq!(same.eval(wo, wi), front.eval(wo, wi));
        assert_eq!(same.eval(flip(wo), flip(wi)), front.eval(wo, wi));
        assert_eq!(both.eval(flip(wo), flip(wi)), back.eval(wo, wi));
        assert_eq!(both.pdf(flip(wo), flip(wi)), back.pdf(wo, wi));
        // Light does not cross a two-sided reflector.
        assert!(both.eval(wo, flip(wi)).is_black());
    }
}

#[test]
fn normal_map_evaluates_in_the_perturbed_frame() {
    let nested = rough_plastic(MicrofacetType::Ggx, 0.3, true, false);
    // The unperturbed normal: the wrapper is the nested BSDF (no shadowing at n = +z).
    let flat = Bsdf::from(NormalMap::new(Vec3::Z, nested.clone()));
    let mut rng = Rng::new(5, 6);
    for _ in 0..200 {
        let (wo, wi) = (hemisphere(rng.next_2d()), hemisphere(rng.next_2d()));
        let (a, b) = (flat.eval(wo, wi), nested.eval(wo, wi));
        for c in 0..3 {
            assert!(
                (a[c] - b[c]).abs() <= 1e-5 * b[c].max(1.0),
                "{a:?} vs {b:?}"
            );
        }
        assert!((flat.pdf(wo, wi) - nested.pdf(wo, wi)).abs() <= 1e-4 * nested.pdf(wo, wi));
    }
    // A tilted normal: sampling still matches the pdf and the weights.
    let tilted = Bsdf::from(NormalMap::new(Vec3::new(0.3, 0.1, 0.9), nested.clone()));
    for wo in incident_directions(false) {
        chi2_sampling("normalmap", &tilted, wo, TESTS);
        check_samples("normalmap", &tilted, wo);
    }
    // n in the xz plane: the perturbed frame is the rotation about y by n's polar angle,
    // and eval is the nested BSDF there times the cosine ratio.
    let n = Vec3::new(0.6, 0.0, 0.8);
    let rotated = Bsdf::from(NormalMap {
        use_shadowing_function: false,
        ..NormalMap::new(n, nested.clone())
    });
    let to_frame = |w: Vec3| Vec3::new(w.x * 0.8 - w.z * 0.6, w.y, w.x * 0.6 + w.z * 0.8);
    let mut checked = 0;
    for _ in 0..400 {
        let (wo, wi) = (hemisphere(rng.next_2d()), hemisphere(rng.next_2d()));
        let (po, pi) = (to_frame(wo), to_frame(wi));
        if wo.z * wo.dot(n) <= 0.0 || pi.z <= 0.0 {
            continue;
        }
        checked += 1;
        let want = nested.eval(po, pi) * (pi.z / wi.z);
        let got = rotated.eval(wo, wi);
        for c in 0..3 {
            assert!(
                (got[c] - want[c]).abs() <= 1e-4 * want[c].max(1e-3),
                "{got:?} vs {want:?}"
            );
        }
    }
    assert!(checked > 100);
}

fn hemisphere(u: Vec2) -> Vec3 {
    let z = u.x.max(1e-3);
    let r = (1.0 - z * z).sqrt();
    let phi = std::f32::consts::TAU * u.y;
    Vec3::new(r * phi.cos(), r * phi.sin(), z)
}

/// Mitsuba's principled BSDF without transmission: every lobe is sampled exactly by the
/// density its pdf reports (with `spec_trans > 0` Mitsuba's lobe probabilities depend on
/// the sampled normal's Fresnel term, which its pdf does not reproduce; that case is
/// compared with Mitsuba itself in tests/mitsuba_layered.rs).
#[test]
fn principled_reflection() {
    let cases = [
        Principled::default(),
        Principled {
            base_color: Rgb::new(0.6, 0.4, 0.2),
            roughness: 0.3,
            metallic: 0.7,
            anisotropic: 0.6,
            spec_tint: 0.5,
            ..Principled::default()
        },
        Principled {
            base_color: Rgb::new(0.3, 0.4, 0.5),
            roughness: 0.7,
            sheen: 0.3,
            sheen_tint: 0.5,
            clearcoat: 0.5,
            clearcoat_gloss: 0.4,
            flatness: 0.5,
            ..Principled::default()
        },
    ];
    for (k, p) in cases.into_iter().enumerate() {
        check_bsdf(&format!("principled #{k}"), &Bsdf::from(p), false, TESTS);
    }
}
