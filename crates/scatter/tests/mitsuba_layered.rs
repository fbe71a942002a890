//! `plastic`, `roughplastic`, `principled` and `principledthin` against pip Mitsuba 3.9.1
//! (scalar_rgb): tests/data/mitsuba_layered.csv, written by
//! tests/data/mitsuba_layered.py, holds Mitsuba's eval (cosine divided out) and pdf at
//! fixed directions, and the smooth plastic's specular samples;
//! tests/data/mitsuba_principledthin.csv, written by
//! tests/data/mitsuba_principledthin.py, the same for `principledthin` from both sides
//! of the sheet.
//!
//! Rough plastic's diffuse part rests on tabulated integrals (the coating's
//! transmittance and internal reflectance) that Irradia computes by the same
//! Gauss-Legendre rule over its own visible-normal sampler, so it agrees to ~1e-3
//! rather than to float precision; Beckmann's specular part differs by Mitsuba's
//! rational approximation of the masking function (see tests/mitsuba.rs), up to ~0.5%.

use glam::{Vec2, Vec3};
use irradia_core::Rgb;
use irradia_scatter::bsdfs::*;
use irradia_scatter::microfacet::{Microfacet, MicrofacetType::*};
use irradia_scatter::{Bsdf, Scatter};

fn config(name: &str) -> (Bsdf, f32) {
    let rp = |d: Microfacet, eta: f32, rho: Rgb, spec: Rgb, nonlinear: bool| {
        Bsdf::from(RoughPlastic::new(d, eta, rho, spec, nonlinear))
    };
    let orange = Rgb::new(0.7, 0.4, 0.1);
    match name {
        "plastic_default" => (Bsdf::from(Plastic::default()), 1e-4),
        "plastic_linear" => (
            Bsdf::from(Plastic {
                diffuse_reflectance: Rgb::new(0.8, 0.4, 0.1),
                specular_reflectance: Rgb::splat(0.9),
                eta: 1.6 / 1.1,
                nonlinear: false,
            }),
            1e-4,
        ),
        "plastic_nonlinear" => (
            Bsdf::from(Plastic {
                diffuse_reflectance: Rgb::new(0.8, 0.4, 0.1),
                specular_reflectance: Rgb::WHITE,
                eta: 1.9,
                nonlinear: true,
            }),
            1e-4,
        ),
        "rp_ggx_01" => (
            rp(
                Microfacet::new(Ggx, 0.1, 0.1, true),
                1.5,
                orange,
                Rgb::WHITE,
                false,
            ),
            2e-3,
        ),
        "rp_ggx_04_nonlinear" => (
            rp(
                Microfacet::new(Ggx, 0.4, 0.4, true),
                1.49 / 1.000277,
                orange,
                Rgb::splat(0.8),
                true,
            ),
            2e-3,
        ),
        "rp_beckmann_03" => (
            rp(
                Microfacet::new(Beckmann, 0.3, 0.3, true),
                1.7,
                Rgb::new(0.2, 0.5, 0.9),
                Rgb::WHITE,
                false,
            ),
            6e-3,
        ),
        "rp_ggx_02_all" => (
            rp(
                Microfacet::new(Ggx, 0.2, 0.2, false),
                1.5,
                Rgb::splat(0.5),
                Rgb::WHITE,
                false,
            ),
            2e-3,
        ),
        "pr_default" => (Bsdf::from(Principled::default()), 1e-3),
        "pr_metal_aniso" => (
            Bsdf::from(Principled {
                base_color: Rgb::new(0.9, 0.6, 0.2),
                roughness: 0.3,
                metallic: 0.8,
                anisotropic: 0.5,
                spec_tint: 0.4,
                ..Principled::default()
            }),
            1e-3,
        ),
        "pr_sheen_cc" => (
            Bsdf::from(Principled {
                base_color: Rgb::new(0.2, 0.4, 0.8),
                roughness: 0.6,
                sheen: 0.7,
                sheen_tint: 0.5,
                clearcoat: 0.8,
                clearcoat_gloss: 0.6,
                eta: Principled::eta_from_specular(0.3),
                ..Principled::default()
            }),
            1e-3,
        ),
        "pr_glass" => (
            Bsdf::from(Principled {
                base_color: Rgb::new(0.9, 0.9, 0.7),
                roughness: 0.7,
                spec_trans: 0.7,
                eta: 1.45,
                ..Principled::default()
            }),
            1e-3,
        ),
        "pr_flat" => (
            Bsdf::from(Principled {
                base_color: Rgb::new(0.6, 0.5, 0.4),
                roughness: 0.8,
                flatness: 0.6,
                metallic: 0.1,
                ..Principled::default()
            }),
            1e-3,
        ),
        "pt_default" => (Bsdf::from(PrincipledThin::default()), 1e-3),
        "pt_glass" => (
            Bsdf::from(PrincipledThin {
                base_color: Rgb::new(0.9, 0.8, 0.7),
                roughness: 0.3,
                spec_trans: 0.8,
                eta: 1.33,
                spec_tint: 0.3,
                ..PrincipledThin::default()
            }),
            1e-3,
        ),
        "pt_aniso" => (
            Bsdf::from(PrincipledThin {
                base_color: Rgb::new(0.7, 0.1, 0.1),
                roughness: 0.15,
                spec_tint: 0.1,
                anisotropic: 0.5,
                spec_trans: 0.8,
                diff_trans: 0.3,
                eta: 1.33,
                ..PrincipledThin::default()
            }),
            1e-3,
        ),
        "pt_leaf" => (
            Bsdf::from(PrincipledThin {
                base_color: Rgb::new(0.2, 0.6, 0.1),
                roughness: 0.6,
                diff_trans: 1.2,
                sheen: 0.5,
                sheen_tint: 0.4,
                flatness: 0.5,
                spec_trans: 0.2,
                ..PrincipledThin::default()
            }),
            1e-3,
        ),
        "pt_rates" => (
            Bsdf::from(PrincipledThin {
                base_color: Rgb::new(0.5, 0.4, 0.3),
                roughness: 0.4,
                spec_trans: 0.5,
                diff_trans: 0.8,
                eta: 1.6,
                specular_reflectance_sampling_rate: 0.5,
                specular_transmittance_sampling_rate: 2.0,
                diffuse_reflectance_sampling_rate: 1.5,
                diffuse_transmittance_sampling_rate: 0.7,
                ..PrincipledThin::default()
            }),
            1e-3,
        ),
        _ => panic!("unknown config {name}"),
    }
}

fn rows(kind: &str) -> Vec<(String, Vec<f32>)> {
    rows_of(include_str!("data/mitsuba_layered.csv"), kind)
}

fn rows_of(csv: &str, kind: &str) -> Vec<(String, Vec<f32>)> {
    csv.lines()
        .filter(|l| l.starts_with(kind))
        .map(|l| {
            let mut it = l.split(',').skip(1);
            let name = it.next().unwrap().to_string();
            (name, it.map(|s| s.parse().unwrap()).collect())
        })
        .collect()
}

fn rel_err(got: f32, want: f32) -> f32 {
    (got - want).abs() / want.abs().max(1e-3)
}

#[test]
fn layered_bsdfs_evaluate_as_mitsuba() {
    let rows = rows("eval");
    assert!(rows.len() >= 140, "{} rows", rows.len());
    compare_evals(rows);
}

/// Both sides of the sheet, random pairs and pairs near the specular reflection and
/// transmission.
#[test]
fn principledthin_evaluates_as_mitsuba() {
    let rows = rows_of(include_str!("data/mitsuba_principledthin.csv"), "eval");
    assert!(rows.len() >= 100, "{} rows", rows.len());
    compare_evals(rows);
}

fn compare_evals(rows: Vec<(String, Vec<f32>)>) {
    let mut worst = Vec::new();
    for (name, v) in rows {
        let (b, tol) = config(&name);
        let wo = Vec3::new(v[0], v[1], v[2]);
        let wi = Vec3::new(v[3], v[4], v[5]);
        let f = b.eval(wo, wi);
        let p = b.pdf(wo, wi);
        let err = (0..3)
            .map(|c| rel_err(f[c], v[6 + c]))
            .fold(rel_err(p, v[9]), f32::max);
        if err > tol {
            worst.push(format!(
                "{name} wo={wo} wi={wi}: f {f:?} pdf {p} vs Mitsuba {:?} {} (err {err:.2e})",
                &v[6..9],
                v[9]
            ));
        }
    }
    assert!(worst.is_empty(), "{}", worst.join("\n"));
}

#[test]
fn smooth_plastic_specular_samples_as_mitsuba() {
    let rows = rows("sample");
    assert!(rows.len() >= 8);
    for (name, v) in rows {
        let (b, _) = config(&name);
        let wo = Vec3::new(v[0], v[1], v[2]);
        let s = b.sample(wo, v[3], Vec2::new(0.5, 0.5)).unwrap();
        assert!(s.is_delta(), "{name}: {s:?}");
        assert!((s.wi - Vec3::new(v[4], v[5], v[6])).length() < 1e-5);
        for c in 0..3 {
            assert!(
                rel_err(s.weight[c], v[7 + c]) < 1e-4,
                "{name}: {s:?} vs {v:?}"
            );
        }
        assert!(rel_err(s.pdf, v[10]) < 1e-4, "{name}: {s:?} vs {v:?}");
    }
}
