//! The BSDF samples of the wide kernel's vector stage, each the scalar BSDF's
//! arithmetic repeated lane by lane in the same order (see [`super`]): the cosine-weighted
//! direction of the Lambertian lobes, the smooth conductor's Fresnel reflectance and the
//! smooth dielectric's choice between reflection and refraction.

// Lane loops index several arrays by the lane on purpose.
#![allow(clippy::needless_range_loop)]

use super::WideScene;
use irradia_geometry::packet::lanes::{sin_cos_quarter_pi, Fw, Mw, V3, W};
use std::f32::consts::FRAC_PI_4;

/// `cosine_hemisphere` (Shirley-Chiu concentric disk, lifted to the hemisphere) in
/// every lane; the angle's sine and cosine come from [`sin_cos_quarter_pi`] (for the
/// second wedge, `cos(π/2 - a) = sin a` and `sin(π/2 - a) = cos a`).
#[inline(always)]
pub(super) fn cosine_hemisphere(u: [Fw; 2]) -> V3 {
    let (ox, oy) = (2.0 * u[0] - 1.0, 2.0 * u[1] - 1.0);
    let first = ox.abs().gt(oy.abs());
    let ratio = first.select(oy / ox, ox / oy);
    let (sin_a, cos_a) = sin_cos_quarter_pi(FRAC_PI_4 * ratio);
    let r = first.select(ox, oy);
    let centre = ox.eq(0.0) & oy.eq(0.0);
    let dx = (!centre).keep(r * first.select(cos_a, sin_a));
    let dy = (!centre).keep(r * first.select(sin_a, cos_a));
    let z = (1.0 - (dx * dx + dy * dy)).max(0.0).sqrt();
    V3::new(dx, dy, z)
}

/// The smooth conductor's Fresnel reflectance (`fresnel_conductor_rgb`, in `f64` as
/// the scalar BSDF computes it, W lanes at once: [`super::fresnel_lanes`]) at cosine
/// `cos` in the lanes of `active`, zero elsewhere.
#[inline(always)]
pub(super) fn conductor_fresnel(
    ws: &WideScene<'_, '_>,
    material: &[u32; W],
    cos: Fw,
    active: Mw,
) -> V3 {
    super::fresnel_lanes::conductor_fresnel(ws, material, cos, active)
}

/// The smooth dielectric's sample in every lane (`Dielectric::sample`, with
/// `fresnel_dielectric` and `refract` of the scatter crate's optics, Born and Wolf
/// §1.5.2, as Mitsuba 3's `dielectric`): whether `u_lobe` chooses the reflection, the
/// refracted direction and the relative indices `η_t/η_i`, `η_i/η_t`.
pub(super) struct DielectricSample {
    pub reflects: Mw,
    pub refracted: V3,
    pub eta_it: Fw,
    pub eta_ti: Fw,
}

#[inline(always)]
pub(super) fn dielectric(wo: V3, eta: Fw, u_lobe: Fw, scale: f32) -> DielectricSample {
    let c = wo.z;
    let outside = c.ge(0.0);
    let inv = 1.0 / eta;
    let eta_it = outside.select(eta, inv);
    let eta_ti = outside.select(inv, eta);
    // Snell's law: sin²θt = (η_i/η_t)² sin²θi.
    let cos2_t = 1.0 - (1.0 - c * c) * eta_ti * eta_ti;
    let cos_i = c.abs();
    let cos_t = cos2_t.max(0.0).sqrt();
    let r_s = (cos_i - eta_it * cos_t) / (cos_i + eta_it * cos_t);
    let r_p = (eta_it * cos_i - cos_t) / (eta_it * cos_i + cos_t);
    // (`scale` is 1 but in a test: see `WideScene::with_fresnel_scale`.)
    let fr = 0.5 * (r_s * r_s + r_p * r_p) * scale;
    let fr = (cos_i.eq(0.0) | cos2_t.le(0.0)).select(Fw::splat(1.0), fr);
    let fr = eta.eq(1.0).select(Fw::ZERO, fr);
    DielectricSample {
        reflects: u_lobe.le(fr),
        refracted: V3::new(
            -eta_ti * wo.x,
            -eta_ti * wo.y,
            outside.select(-cos_t, cos_t),
        ),
        eta_it,
        eta_ti,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;
    use irradia_core::Rng;

    #[test]
    fn cosine_directions_match_the_scalar_warp() {
        let mut rng = Rng::new(11, 2);
        let mut worst = 0f32;
        for _ in 0..500 {
            let mut us = [Fw::ZERO; 2];
            let mut want = [Vec3::ZERO; W];
            for lane in 0..W {
                let v = rng.next_2d();
                us[0].0[lane] = v.x;
                us[1].0[lane] = v.y;
                want[lane] = irradia_core::sampling::cosine_hemisphere(v);
            }
            let got = cosine_hemisphere(us);
            for (lane, w) in want.iter().enumerate() {
                worst = worst.max((got.lane(lane) - *w).abs().max_element());
            }
        }
        // A few ulps, more where z = sqrt(1 - r²) amplifies them near the horizon.
        assert!(worst < 5e-6, "worst component difference {worst}");
    }
}
