//! Mitsuba's `principledthin` through the harness of `common`: χ² of sampling against
//! the pdf, weights against eval and pdf, the pdf's mass, the albedo bound and
//! reciprocity, from both sides of the sheet; plus the symmetry of a thin sheet (the
//! same seen from the back) and the lobe flags. Its values against Mitsuba itself are in
//! tests/mitsuba_layered.rs.

mod common;

use common::check_bsdf;
use glam::Vec3;
use irradia_core::{Rgb, Rng};
use irradia_scatter::bsdfs::PrincipledThin;
use irradia_scatter::{Bsdf, LobeFlags, Scatter};
use std::f32::consts::{PI, TAU};

/// The number of χ² tests in this file, for the Sidak correction.
const TESTS: usize = 36;

/// The cases: the roughnesses keep the transmission's GGX α (from the roughness scaled
/// by `0.65 eta - 0.35`, squared) at 0.1 or more, as tests/bsdfs.rs does, so that the χ²
/// quadrature resolves the lobes; narrower ones are compared with Mitsuba in
/// tests/mitsuba_layered.rs.
fn cases() -> Vec<PrincipledThin> {
    vec![
        PrincipledThin::default(),
        // Mostly glossy, tinted, anisotropic, with some diffuse transmission.
        PrincipledThin {
            base_color: Rgb::new(0.7, 0.1, 0.1),
            roughness: 0.6,
            spec_tint: 0.1,
            anisotropic: 0.5,
            spec_trans: 0.8,
            diff_trans: 0.3,
            ..PrincipledThin::default()
        },
        // A leaf: diffuse transmission, sheen, fake subsurface, a little gloss.
        PrincipledThin {
            base_color: Rgb::new(0.2, 0.6, 0.1),
            roughness: 0.6,
            diff_trans: 1.2,
            sheen: 0.5,
            sheen_tint: 0.4,
            flatness: 0.5,
            spec_trans: 0.2,
            ..PrincipledThin::default()
        },
        // Uneven sampling rates, a dense sheet (wider transmission lobe).
        PrincipledThin {
            base_color: Rgb::new(0.5, 0.4, 0.3),
            roughness: 0.5,
            spec_trans: 0.5,
            diff_trans: 0.8,
            eta: 1.6,
            specular_reflectance_sampling_rate: 0.5,
            specular_transmittance_sampling_rate: 2.0,
            diffuse_reflectance_sampling_rate: 1.5,
            diffuse_transmittance_sampling_rate: 0.7,
            ..PrincipledThin::default()
        },
        // All specular, no diffuse part at all; and all diffuse transmission.
        PrincipledThin {
            base_color: Rgb::new(0.9, 0.9, 0.8),
            roughness: 0.55,
            spec_trans: 1.0,
            ..PrincipledThin::default()
        },
        PrincipledThin {
            base_color: Rgb::new(0.8, 0.7, 0.6),
            diff_trans: 2.0,
            ..PrincipledThin::default()
        },
    ]
}

#[test]
fn principledthin_harness_both_sides() {
    for (k, p) in cases().into_iter().enumerate() {
        check_bsdf(&format!("principledthin #{k}"), &Bsdf::from(p), true, TESTS);
    }
}

/// A thin sheet has no inside: turning both directions over changes nothing, and
/// without the glossy lobes `f(wo, wi) = f(wi, wo)` holds through the sheet too (no
/// refraction, no radiance compression). The glossy transmission is not reciprocal: see
/// [`principledthin_glossy_transmission_is_not_reciprocal_as_mitsuba`].
#[test]
fn principledthin_is_the_same_from_the_back() {
    let mut rng = Rng::new(5, 3);
    for p in cases() {
        for _ in 0..500 {
            let u = rng.next_2d();
            let v = rng.next_2d();
            let wo = common::dir((u.x * PI).max(0.01), u.y * TAU);
            let wi = common::dir((v.x * PI).max(0.01), v.y * TAU);
            let (f, g) = (p.eval(wo, wi), p.eval(-wo, -wi));
            for c in 0..3 {
                assert!(
                    (f[c] - g[c]).abs() <= 1e-5 * f[c].abs().max(1.0),
                    "{p:?}: {f:?} vs {g:?}"
                );
            }
            let h = p.eval(wi, wo);
            for c in 0..3 {
                if p.spec_trans != 0.0 && wo.z * wi.z < 0.0 {
                    break;
                }
                assert!(
                    (f[c] - h[c]).abs() <= 1e-3 * f[c].abs().max(h[c].abs()) + 1e-6,
                    "{p:?} wo={wo} wi={wi}: f {f:?} but f(wi, wo) {h:?}"
                );
            }
            let (a, b) = (p.pdf(wo, wi), p.pdf(-wo, -wi));
            assert!((a - b).abs() <= 1e-5 * a.max(1.0), "{p:?}: pdf {a} vs {b}");
        }
    }
}

#[test]
fn principledthin_flags_follow_the_weights() {
    let d = PrincipledThin::default().flags();
    assert!(d.intersects(LobeFlags::DIFFUSE_REFLECTION));
    assert!(!d.intersects(LobeFlags::TRANSMISSION | LobeFlags::GLOSSY));
    assert!(d.intersects(LobeFlags::FRONT_SIDE) && d.intersects(LobeFlags::BACK_SIDE));
    let g = cases()[1].flags();
    for f in [
        LobeFlags::GLOSSY_REFLECTION,
        LobeFlags::GLOSSY_TRANSMISSION,
        LobeFlags::DIFFUSE_TRANSMISSION,
        LobeFlags::ANISOTROPIC,
    ] {
        assert!(g.intersects(f), "{g:?} lacks {f:?}");
    }
    // The default scatters nothing to the other side.
    let wo = Vec3::new(0.3, 0.1, 0.9).normalize();
    assert!(PrincipledThin::default()
        .eval(wo, Vec3::new(0.0, 0.2, -0.9).normalize())
        .is_black());
}

/// Mitsuba's glossy transmission mirrors `wi` up to find the half vector `h` but tests
/// the microfacet's sidedness (`wi·h < 0`) with `wi` itself, and that test is not
/// symmetric in `wo` and `wi`: through the sheet towards a steep `wi` from a shallow
/// `wo` the lobe is there, the other way round it is cut off and only the diffuse
/// transmission remains. Kept as Mitsuba has it; the values are pip Mitsuba 3.9.1's.
#[test]
fn principledthin_glossy_transmission_is_not_reciprocal_as_mitsuba() {
    let p = PrincipledThin {
        base_color: Rgb::new(0.7, 0.1, 0.1),
        roughness: 0.6,
        spec_tint: 0.1,
        anisotropic: 0.5,
        spec_trans: 0.8,
        diff_trans: 0.3,
        ..PrincipledThin::default()
    };
    let wo = Vec3::new(0.010_814_955, 0.959_805_85, 0.280_456_36);
    let wi = Vec3::new(-0.042_515_803, -0.619_905_1, -0.783_524_16);
    for (f, want) in [
        (p.eval(wo, wi), [0.110_060_56, 0.015_722_94, 0.015_722_94]),
        (p.eval(wi, wo), [0.006_684_51, 0.000_954_93, 0.000_954_93]),
    ] {
        for c in 0..3 {
            assert!(
                (f[c] - want[c]).abs() <= 1e-4 * want[c],
                "{f:?} vs {want:?}"
            );
        }
    }
}
