//! Mitsuba 3's `roughconductor` with the isotropic GGX distribution in every lane of the
//! wide kernel's vector stage (see [`super`]): the scatter crate's `RoughConductor`
//! and `Microfacet` (Walter, Marschner, Li and Torrance 2007, "Microfacet Models for
//! Refraction through Rough Surfaces", eqs. 20 and 33; Smith's separable masking,
//! Heitz 2014, "Understanding the Masking-Shadowing Function", §5; visible normals
//! sampled as Heitz 2018, "Sampling the GGX Distribution of Visible Normals", JCGT
//! 7(4)) with their arithmetic in the same order, in `f32`:
//!
//! - `D` and `Λ` are `f64` in the scalar code; here they are `f32`, with `Λ` in the
//!   cancellation-free form `½ t² / (√(1 + t²) + 1)` (the scalar `½ (√(1 + t²) − 1)`
//!   rounded in `f32` would lose the small `Λ` of the nearly smooth plates, α = 0.005),
//!   so they agree with the scalar values to a few `f32` ulps;
//! - the azimuth's sine and cosine come from [`sin_cos_two_pi`], a polynomial after an
//!   exact reduction to the first octant (a few ulps from `f32::sin_cos`);
//! - the conductor's Fresnel reflectance stays per lane, in `f64`, as the smooth
//!   conductor's does ([`super::bsdf::conductor_fresnel`]): its `f32` form loses too
//!   much for a perfect mirror (η = 0, k = 1).

use super::bsdf::conductor_fresnel;
use super::gather::{checked, field};
use super::{mat, WideScene};
use irradia_geometry::packet::lanes::{sin_cos_quarter_pi, Fw, Mw, V3, W};
use std::f32::consts::{PI, TAU};

/// `sin 2πu` and `cos 2πu` for `u` in `[0, 1)` (the azimuth of a warp): `u` is reduced
/// exactly to the first octant (`u − q/4` and `1/4 − r` are exact by Sterbenz's lemma),
/// where [`sin_cos_quarter_pi`] applies, and the quadrant's symmetries give the rest.
#[inline(always)]
pub(super) fn sin_cos_two_pi(u: Fw) -> (Fw, Fw) {
    // The quadrant `⌊4u⌋` by comparisons (no call of `floorf`).
    let one = Fw::splat(1.0);
    let q = u.ge(0.25).keep(one) + u.ge(0.5).keep(one) + u.ge(0.75).keep(one);
    let r = u - q * 0.25;
    let upper = r.gt(0.125);
    let a = TAU * upper.select(0.25 - r, r);
    let (s, c) = sin_cos_quarter_pi(a);
    // The first quadrant: swap where the angle was reflected about π/4.
    let (s0, c0) = (upper.select(c, s), upper.select(s, c));
    // Rotate by q quarter turns: (sin, cos) of x + qπ/2.
    let q1 = q.eq(1.0);
    let q2 = q.eq(2.0);
    let q3 = q.eq(3.0);
    let sin = q1.select(c0, q2.select(-s0, q3.select(-c0, s0)));
    let cos = q1.select(-s0, q2.select(-c0, q3.select(s0, c0)));
    (sin, cos)
}

/// GGX's distribution of normals `D(m) = 1 / (π α² (tan²θ/α² + 1)² cos⁴θ)` (written
/// as Mitsuba does, `1 / (π α² (slope² + cos²θ)²)`), zero below the horizon and where
/// `D cos θ ≤ 1e-20` (as the scalar code).
#[inline(always)]
pub(super) fn d(m: V3, alpha: Fw) -> Fw {
    let a2 = alpha * alpha;
    let cos2 = m.z * m.z;
    let slope2 = (m.x * m.x + m.y * m.y) / a2;
    let t = slope2 + cos2;
    let r = 1.0 / (PI * a2 * t * t);
    (m.z.gt(0.0) & (r * m.z).gt(1e-20)).keep(r)
}

/// Smith's `G1(v, m) = χ⁺(v·m / v·n) / (1 + Λ(v))` with GGX's closed-form `Λ`.
#[inline(always)]
pub(super) fn g1(v: V3, m: V3, alpha: Fw) -> Fw {
    let t2 = alpha * alpha * (v.x * v.x + v.y * v.y) / (v.z * v.z);
    let lambda = 0.5 * t2 / ((1.0 + t2).sqrt() + 1.0);
    let g = 1.0 / (1.0 + lambda);
    (v.dot(m) * v.z)
        .gt(0.0)
        .keep(t2.finite().select(g, Fw::ZERO))
}

/// The density of visible normals, `D(m) G1(wo, m) |wo·m| / cos θo` (`wo.z > 0`).
#[inline(always)]
pub(super) fn pdf_visible(wo: V3, m: V3, alpha: Fw) -> Fw {
    let p = d(m, alpha) * g1(wo, m, alpha) * wo.dot(m).abs() / wo.z;
    wo.z.gt(0.0).keep(p)
}

/// Heitz 2018's visible-normal sample for `wo.z > 0`: stretch, sample the projected
/// hemisphere, unstretch (`Microfacet::sample_visible_ggx`).
#[inline(always)]
pub(super) fn sample_visible(wo: V3, u: [Fw; 2], alpha: Fw) -> V3 {
    let vh = V3::new(alpha * wo.x, alpha * wo.y, wo.z).normalize();
    let len2 = vh.x * vh.x + vh.y * vh.y;
    let inv = 1.0 / len2.sqrt();
    let tilted = len2.gt(0.0);
    let t1 = V3::new(
        tilted.select(-vh.y * inv, Fw::splat(1.0)),
        tilted.keep(vh.x * inv),
        Fw::ZERO,
    );
    // `vh × t1` in glam's order.
    let t2 = V3::new(
        vh.y * t1.z - t1.y * vh.z,
        vh.z * t1.x - t1.z * vh.x,
        vh.x * t1.y - t1.x * vh.y,
    );
    let r = u[0].sqrt();
    let (s_phi, c_phi) = sin_cos_two_pi(u[1]);
    let p1 = r * c_phi;
    let s = 0.5 * (1.0 + vh.z);
    let p2 = (1.0 - s) * (1.0 - p1 * p1).max(0.0).sqrt() + s * r * s_phi;
    let nz = (1.0 - p1 * p1 - p2 * p2).max(0.0).sqrt();
    let nh = t1.scale(p1).add(t2.scale(p2)).add(vh.scale(nz));
    V3::new(alpha * nh.x, alpha * nh.y, nh.z.max(0.0)).normalize()
}

/// Field `at` of the materials' shading records.
#[inline(always)]
pub(super) fn shading(ws: &WideScene<'_, '_>, material: &[u32; W], at: usize) -> Fw {
    checked(&ws.shading, material);
    field(&ws.shading, material, at)
}

/// What the rough conductor gives the vector stage: its value and density for the light
/// sample's direction, and its own sample.
pub(super) struct RoughSample {
    /// `f(wo, wi)` and its density for the light direction `wi` (zero where not asked).
    pub f_light: V3,
    pub pdf_light: Fw,
    /// A valid sample: its direction, weight `f cos θi / pdf` and density.
    pub ok: Mw,
    pub wi: V3,
    pub weight: V3,
    pub pdf: Fw,
}

/// `RoughConductor::{eval, pdf}` for the light direction `wi` in the lanes of `light`,
/// and `RoughConductor::sample` with the direction numbers `u` in the lanes of
/// `active`, for the materials `material` (their α and `specular_reflectance` from the
/// shading table, the Fresnel reflectance per lane). `wo.z > 0` in those lanes (the
/// kernel stops one-sided BSDFs seen from behind before).
#[inline(always)]
pub(super) fn rough_conductor(
    ws: &WideScene<'_, '_>,
    material: &[u32; W],
    wo: V3,
    wi: V3,
    u: [Fw; 2],
    light: Mw,
    active: Mw,
) -> RoughSample {
    let alpha = shading(ws, material, mat::ALPHA) * ws.alpha_scale;
    let spec_r = V3::new(
        shading(ws, material, mat::SPEC_R),
        shading(ws, material, mat::SPEC_R + 1),
        shading(ws, material, mat::SPEC_R + 2),
    );
    let front = wo.z.gt(0.0);

    // The light direction: `eval` and `pdf` about the half vector.
    let both = front & wi.z.gt(0.0);
    let h = wo.add(wi).normalize();
    let dh = d(h, alpha);
    let g = g1(wo, h, alpha) * g1(wi, h, alpha);
    let light = light & both;
    let fresnel_h = spec_r.mul(conductor_fresnel(ws, material, wo.dot(h), light));
    let f_light = fresnel_h
        .scale(dh * g / (4.0 * wo.z * wi.z))
        .keep(light & dh.ne(0.0));
    let wi_h = wi.dot(h);
    let pdf_light = (light & wi_h.gt(0.0)).keep(pdf_visible(wo, h, alpha) / (4.0 * wi_h));

    // The sample: a visible normal, the reflection about it.
    let m = sample_visible(wo, u, alpha);
    let m_ok = m.finite() & m.z.gt(0.0);
    let pdf_m = m_ok.keep(pdf_visible(wo, m, alpha));
    let wo_m = wo.dot(m);
    let wi_s = m.scale(2.0 * wo_m).sub(wo).normalize();
    let wi_m = wi_s.dot(m);
    let ok = active & front & pdf_m.gt(0.0) & wi_s.z.gt(0.0) & wi_m.gt(0.0);
    let fresnel_m = spec_r.mul(conductor_fresnel(ws, material, wo_m, ok));
    RoughSample {
        f_light,
        pdf_light,
        ok,
        wi: wi_s,
        weight: fresnel_m.scale(g1(wi_s, m, alpha)),
        pdf: ok.keep(pdf_m / (4.0 * wi_m)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;
    use irradia_core::Rng;
    use irradia_scatter::microfacet::{Microfacet, MicrofacetType};

    #[test]
    fn sine_and_cosine_of_every_turn_match_the_library() {
        let mut worst = 0f32;
        let mut rng = Rng::new(3, 4);
        for k in 0..4000 {
            let mut u = Fw::ZERO;
            for lane in 0..W {
                // The octant and quadrant ends, then random turns.
                u.0[lane] = if k == 0 {
                    [0.0, 0.125, 0.25, 0.375, 0.5, 0.625, 0.75, 1.0 - 1e-7][lane % 8]
                } else {
                    rng.next_f32()
                };
            }
            let (s, c) = sin_cos_two_pi(u);
            for lane in 0..W {
                let (ws, wc) = (TAU * u.0[lane]).sin_cos();
                worst = worst.max((s.0[lane] - ws).abs().max((c.0[lane] - wc).abs()));
            }
        }
        assert!(worst < 1e-6, "worst difference {worst}");
    }

    /// The lane functions against `Microfacet`'s for random directions and roughnesses
    /// from nearly smooth to rough.
    #[test]
    fn distribution_masking_and_samples_match_the_scalar_microfacet() {
        let mut rng = Rng::new(8, 1);
        let close = |a: f32, b: f32, tol: f32| (a - b).abs() <= tol * a.abs().max(b.abs()) + 1e-6;
        for _ in 0..400 {
            let mut wo = V3::ZERO;
            let mut m = V3::ZERO;
            let mut u = [Fw::ZERO; 2];
            let mut alpha = Fw::ZERO;
            let mut want = Vec::new();
            for lane in 0..W {
                let a = [0.005, 0.02, 0.1, 0.5][lane % 4];
                alpha.0[lane] = a;
                let mf = Microfacet::new(MicrofacetType::Ggx, a, a, true);
                let v = Vec3::new(
                    rng.next_f32() - 0.5,
                    rng.next_f32() - 0.5,
                    rng.next_f32() * 0.9 + 0.05,
                )
                .normalize();
                let uu = rng.next_2d();
                let (mm, pdf) = mf.sample(v, uu);
                wo.set_lane(lane, v);
                m.set_lane(lane, mm);
                u[0].0[lane] = uu.x;
                u[1].0[lane] = uu.y;
                want.push((mf, v, mm, pdf));
            }
            let got_m = sample_visible(wo, u, alpha);
            let d_ = d(m, alpha);
            let g = g1(wo, m, alpha);
            let p = pdf_visible(wo, m, alpha);
            for (lane, (mf, v, mm, pdf)) in want.iter().enumerate() {
                assert!(
                    (got_m.lane(lane) - *mm).abs().max_element() < 2e-5,
                    "normal {:?} vs {mm:?}",
                    got_m.lane(lane)
                );
                assert!(close(d_.0[lane], mf.d(*mm), 2e-5), "D");
                assert!(close(g.0[lane], mf.g1(*v, *mm), 2e-6), "G1");
                assert!(close(p.0[lane], *pdf, 2e-5), "pdf");
            }
        }
    }
}
