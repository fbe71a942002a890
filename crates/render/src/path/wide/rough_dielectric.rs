//! Mitsuba 3's `roughdielectric` with the isotropic GGX distribution and visible-normal
//! sampling in every lane of the wide kernel's vector stage (see [`super`]): the
//! scatter crate's `RoughDielectric` (Walter, Marschner, Li and Torrance 2007,
//! "Microfacet Models for Refraction through Rough Surfaces": reflection about the half
//! vector, eq. 20; refraction about the generalised half vector `-(wo + η wi)`, eqs. 16
//! and 21, with the radiance compression `1/η²` of Veach 1997, §5.2; the lobe chosen by
//! the lobe number against the Fresnel reflectance of the sampled normal) with its
//! arithmetic in the same order, in `f32`, on the lane functions of [`super::ggx`]
//! (`D`, Smith's `G1`, Heitz 2018's visible normals) and the exact dielectric Fresnel
//! equations of [`fresnel_dielectric`] (Born and Wolf §1.5.2, as
//! `irradia_scatter::optics::fresnel_dielectric`).
//!
//! A glossy lobe on both sides of the surface: the kernel weights its light samples
//! (either side) against [`RoughSample::pdf_light`] and its own samples
//! against the light's density, and Russian roulette judges `max(beta) η²` with the
//! relative index `eta` of a refraction (as the smooth dielectric).

use super::ggx::{d, g1, pdf_visible, sample_visible, shading, RoughSample};
use super::{mat, WideScene};
use irradia_geometry::packet::lanes::{Fw, Mw, V3, W};

/// The four values of Mitsuba's `fresnel(cos_theta_i, eta)` in every lane.
pub(super) struct Fresnel {
    /// The reflectance (1 under total internal reflection, 0 for `η = 1`).
    pub r: Fw,
    /// The refracted cosine, of the sign opposite to `cos θi`'s (0 under total
    /// internal reflection).
    pub cos_t: Fw,
    /// `η_t / η_i` and `η_i / η_t` for light crossing from the side of `cos θi`.
    pub eta_it: Fw,
    pub eta_ti: Fw,
}

/// `fresnel_dielectric(cos_i, eta)` of the scatter crate's optics in every lane, the
/// same operations in the same order.
#[inline(always)]
pub(super) fn fresnel_dielectric(cos_theta_i: Fw, eta: Fw) -> Fresnel {
    let outside = cos_theta_i.ge(0.0);
    let inv = 1.0 / eta;
    let eta_it = outside.select(eta, inv);
    let eta_ti = outside.select(inv, eta);
    let cos2_t = 1.0 - (1.0 - cos_theta_i * cos_theta_i) * eta_ti * eta_ti;
    let cos_i = cos_theta_i.abs();
    let cos_t = cos2_t.max(0.0).sqrt();
    let r_s = (cos_i - eta_it * cos_t) / (cos_i + eta_it * cos_t);
    let r_p = (eta_it * cos_i - cos_t) / (eta_it * cos_i + cos_t);
    let r = 0.5 * (r_s * r_s + r_p * r_p);
    let r = (cos_i.eq(0.0) | cos2_t.le(0.0)).select(Fw::splat(1.0), r);
    let r = eta.eq(1.0).select(Fw::ZERO, r);
    Fresnel {
        r,
        cos_t: outside.select(-cos_t, cos_t),
        eta_it,
        eta_ti,
    }
}

/// `w` turned to the side of +z where `s < 0` (Mitsuba's `mulsign`).
#[inline(always)]
fn mulsign(w: V3, s: Fw) -> V3 {
    V3::select(s.lt(0.0), w.neg(), w)
}

/// What the rough dielectric gives the vector stage: the glossy lobe's values and
/// sample (its weight `f |cos θi| / pdf`), and the sample's relative index (`η_t/η_i`
/// of a refraction, 1 for a reflection).
pub(super) struct RoughDielectricLanes {
    pub lobe: RoughSample,
    pub eta: Fw,
}

/// A rough dielectric's parameters in every lane.
pub(super) struct DielectricParams {
    pub alpha: Fw,
    /// `int_ior / ext_ior`.
    pub eta: Fw,
    pub spec_r: V3,
    pub spec_t: V3,
}

impl DielectricParams {
    /// The materials' parameters from the shading table (α times the test factor).
    #[inline(always)]
    pub(super) fn gather(ws: &WideScene<'_, '_>, material: &[u32; W]) -> Self {
        let rgb = |at: usize| {
            V3::new(
                shading(ws, material, at),
                shading(ws, material, at + 1),
                shading(ws, material, at + 2),
            )
        };
        Self {
            alpha: shading(ws, material, mat::ALPHA) * ws.alpha_scale,
            eta: shading(ws, material, mat::ETA),
            spec_r: rgb(mat::SPEC_R),
            spec_t: rgb(mat::SPEC_T),
        }
    }
}

/// `RoughDielectric::{eval, pdf}` for the light direction `wi` in the lanes of `light`,
/// and `RoughDielectric::sample` with the numbers `u_lobe`, `u` in the lanes of
/// `active`. Both sides of the surface scatter.
#[inline(always)]
pub(super) fn rough_dielectric(
    p: &DielectricParams,
    wo: V3,
    wi: V3,
    u_lobe: Fw,
    u: [Fw; 2],
    light: Mw,
    active: Mw,
) -> RoughDielectricLanes {
    let (alpha, eta_m, spec_r, spec_t) = (p.alpha, p.eta, p.spec_r, p.spec_t);

    // The light direction: `half_vector`, then `eval` and `pdf`.
    let reflection = (wo.z * wi.z).gt(0.0);
    let eta = wo.z.gt(0.0).select(eta_m, 1.0 / eta_m);
    let h = wo.add(wi.scale(reflection.select(Fw::splat(1.0), eta)));
    let h = h.normalize();
    let h = mulsign(h, h.z);
    let valid = light
        & wo.z.ne(0.0)
        & wi.z.ne(0.0)
        & h.finite()
        & (wo.dot(h) * wo.z).gt(0.0)
        & (wi.dot(h) * wi.z).gt(0.0);
    let dh = d(h, alpha);
    let f = fresnel_dielectric(wo.dot(h), eta_m).r;
    let g = g1(wo, h, alpha) * g1(wi, h, alpha);
    let cos = (wo.z * wi.z).abs();
    let f_r = spec_r.scale(f * dh * g / (4.0 * cos));
    let (oh, ih) = (wo.dot(h), wi.dot(h));
    let denom = oh + eta * ih;
    let value = (1.0 - f) * dh * g * eta * eta * (oh * ih).abs() / (cos * denom * denom);
    let f_t = spec_t.scale(value / (eta * eta));
    let f_light = V3::select(reflection, f_r, f_t).keep(valid & dh.ne(0.0));
    let jacobian = reflection.select(
        1.0 / (4.0 * ih.abs()),
        eta * eta * ih.abs() / (denom * denom),
    );
    let p_m = pdf_visible(mulsign(wo, wo.z), h, alpha);
    let pdf_light = valid.keep((p_m * reflection.select(f, 1.0 - f) * jacobian).abs());

    // The sample: a visible normal of `wo` turned up, then reflection or refraction.
    let wo_up = mulsign(wo, wo.z);
    let m = sample_visible(wo_up, u, alpha);
    let m_ok = wo_up.z.gt(0.0) & m.finite() & m.z.gt(0.0);
    let pdf_m = m_ok.keep(pdf_visible(wo_up, m, alpha));
    let wo_m = wo.dot(m);
    let ok = active & wo.z.ne(0.0) & pdf_m.gt(0.0) & (wo_m * wo.z).gt(0.0);
    let fr = fresnel_dielectric(wo_m, eta_m);
    let reflects = u_lobe.le(fr.r);
    let reflected = m.scale(2.0 * wo_m).sub(wo);
    let refracted = m
        .scale(wo_m * fr.eta_ti + fr.cos_t)
        .sub(wo.scale(fr.eta_ti));
    let wi_s = V3::select(reflects, reflected, refracted);
    let wi_m = wi_s.dot(m);
    let denom = wo_m + fr.eta_it * wi_m;
    let jacobian = reflects.select(
        1.0 / (4.0 * wi_m).abs(),
        (fr.eta_it * fr.eta_it * wi_m / (denom * denom)).abs(),
    );
    let lobe_pdf = reflects.select(fr.r, 1.0 - fr.r);
    let wi_s = wi_s.normalize();
    let side = wo.z * wi_s.z;
    let valid = (reflects & side.gt(0.0)) | (!reflects & side.lt(0.0));
    let pdf = pdf_m * lobe_pdf * jacobian;
    let ok = ok & valid & wi_s.finite() & pdf.gt(0.0);
    let ratio = g1(wi_s, m, alpha);
    let weight = V3::select(
        reflects,
        spec_r.scale(ratio),
        spec_t.scale(ratio * fr.eta_ti * fr.eta_ti),
    );
    RoughDielectricLanes {
        lobe: RoughSample {
            f_light,
            pdf_light,
            ok,
            wi: wi_s,
            weight,
            pdf: ok.keep(pdf),
        },
        eta: reflects.select(Fw::splat(1.0), fr.eta_it),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{Vec2, Vec3};
    use irradia_core::Rng;
    use irradia_scatter::optics;

    #[test]
    fn fresnel_matches_the_scalar_optics_on_both_sides() {
        let mut rng = Rng::new(4, 7);
        for _ in 0..500 {
            let mut c = Fw::ZERO;
            let mut e = Fw::ZERO;
            for lane in 0..W {
                c.0[lane] = 2.0 * rng.next_f32() - 1.0;
                e.0[lane] = [1.33, 1.5, 1.7, 1.0, 1.0 / 1.5, 2.4, 1.05, 0.75][lane % 8];
            }
            if rng.next_f32() < 0.1 {
                c.0[0] = 0.0;
            }
            let f = fresnel_dielectric(c, e);
            for lane in 0..W {
                let want = optics::fresnel_dielectric(c.0[lane], e.0[lane]);
                assert_eq!(f.r.0[lane], want.reflectance, "F at {}", c.0[lane]);
                assert_eq!(f.cos_t.0[lane], want.cos_theta_t);
                assert_eq!(f.eta_it.0[lane], want.eta_it);
                assert_eq!(f.eta_ti.0[lane], want.eta_ti);
            }
        }
    }

    /// Lanes of `RoughDielectric` against the scalar BSDF, both sides, α 0.01 to 0.8,
    /// η 1.33 to 1.7 (a unit test of the BSDF alone; the kernel's agreement is
    /// tests/path_wide_rough*.rs).
    #[test]
    fn value_density_and_sample_match_the_scalar_bsdf() {
        use irradia_scatter::bsdfs::RoughDielectric;
        use irradia_scatter::microfacet::{Microfacet, MicrofacetType};
        use irradia_scatter::Scatter;
        let close = |a: f32, b: f32| (a - b).abs() <= 2e-4 * a.abs().max(b.abs()) + 1e-6;
        let mut rng = Rng::new(21, 3);
        let mut checked = [0usize; 2];
        for _ in 0..3000 {
            let alpha = [0.01, 0.05, 0.2, 0.8][(rng.next_f32() * 4.0) as usize % 4];
            let eta = [1.33, 1.5, 1.7][(rng.next_f32() * 3.0) as usize % 3];
            let bsdf = RoughDielectric {
                distribution: Microfacet::new(MicrofacetType::Ggx, alpha, alpha, true),
                eta,
                specular_reflectance: irradia_core::Rgb::new(1.0, 0.9, 0.8),
                specular_transmittance: irradia_core::Rgb::new(0.7, 0.8, 1.0),
            };
            let mut dir = || {
                let z = (2.0 * rng.next_f32() - 1.0) * 0.98;
                let phi = std::f32::consts::TAU * rng.next_f32();
                let s = (1.0 - z * z).sqrt();
                Vec3::new(s * phi.cos(), s * phi.sin(), z)
            };
            let (wo, wi) = (dir(), dir());
            let (u_lobe, u) = (rng.next_f32(), Vec2::new(rng.next_f32(), rng.next_f32()));
            let got = lanes_of(&bsdf, wo, wi, u_lobe, u);
            let f = bsdf.eval(wo, wi);
            let p = bsdf.pdf(wo, wi);
            assert!(
                close(got.f.x, f.r) && close(got.f.y, f.g) && close(got.f.z, f.b),
                "f {:?} vs {f:?} (α {alpha}, η {eta}, {wo:?}, {wi:?})",
                got.f
            );
            assert!(close(got.pdf, p), "pdf {} vs {p}", got.pdf);
            match bsdf.sample(wo, u_lobe, u) {
                Some(s) => {
                    assert!(got.ok, "no lane sample where the scalar has one");
                    assert!((got.wi - s.wi).abs().max_element() < 1e-4);
                    // Near the horizon the sampled direction's few-ulp differences
                    // (the polynomial azimuth) are amplified in wi.z and so in G1(wi).
                    let tol = if s.wi.z.abs() < 0.05 { 2e-3 } else { 2e-4 };
                    let near = |a: f32, b: f32| (a - b).abs() <= tol * a.abs().max(b.abs()) + 1e-6;
                    assert!(near(got.pdf_s, s.pdf), "{} vs {}", got.pdf_s, s.pdf);
                    let w = got.weight;
                    assert!(
                        near(w.x, s.weight.r) && near(w.y, s.weight.g),
                        "weight {w:?} vs {:?} (α {alpha}, η {eta}, {wo:?}, wi {:?}, u {u_lobe} {u:?})",
                        s.weight,
                        s.wi
                    );
                    assert!(near(w.z, s.weight.b));
                    assert_eq!(got.eta, s.eta);
                    checked[(s.wi.z * wo.z < 0.0) as usize] += 1;
                }
                None => assert!(!got.ok, "a lane sample where the scalar has none"),
            }
        }
        // Both lobes were exercised.
        assert!(checked[0] > 300 && checked[1] > 300, "{checked:?}");
    }

    struct One {
        f: Vec3,
        pdf: f32,
        ok: bool,
        wi: Vec3,
        weight: Vec3,
        pdf_s: f32,
        eta: f32,
    }

    /// The lane code on one material in every lane (the same case in all W).
    fn lanes_of(
        b: &irradia_scatter::bsdfs::RoughDielectric,
        wo: Vec3,
        wi: Vec3,
        u_lobe: f32,
        u: Vec2,
    ) -> One {
        let v = |w: Vec3| {
            let mut l = V3::ZERO;
            for lane in 0..W {
                l.set_lane(lane, w);
            }
            l
        };
        let (r, t) = (b.specular_reflectance, b.specular_transmittance);
        let p = DielectricParams {
            alpha: Fw::splat(b.distribution.alpha_u),
            eta: Fw::splat(b.eta),
            spec_r: v(Vec3::new(r.r, r.g, r.b)),
            spec_t: v(Vec3::new(t.r, t.g, t.b)),
        };
        let s = rough_dielectric(
            &p,
            v(wo),
            v(wi),
            Fw::splat(u_lobe),
            [Fw::splat(u.x), Fw::splat(u.y)],
            Mw::TRUE,
            Mw::TRUE,
        );
        One {
            f: s.lobe.f_light.lane(3),
            pdf: s.lobe.pdf_light.0[3],
            ok: s.lobe.ok.get(3),
            wi: s.lobe.wi.lane(3),
            weight: s.lobe.weight.lane(3),
            pdf_s: s.lobe.pdf.0[3],
            eta: s.eta.0[3],
        }
    }
}
