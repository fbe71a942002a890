//! The conductor's Fresnel reflectance for the W lanes at once (the smooth `conductor`
//! and `roughconductor` of the wide kernel): the scalar `fresnel_conductor`'s `f64`
//! arithmetic (the exact reflectance of a complex index `η + ik`, Born and Wolf,
//! "Principles of Optics", §14.2; the form of Mitsuba 3's `fresnel_conductor`) in the
//! same order, with the W lanes of a channel as `f64` vectors ([`Dw`]),
//! so the reflectance equals the scalar one bit for bit. (An `f32` form loses too much
//! near grazing angles for the kernel's agreement bar.)

// Lane loops index several arrays by the lane on purpose.
#![allow(clippy::needless_range_loop)]

use super::dw::Dw;
use super::WideScene;
use irradia_geometry::packet::lanes::{Fw, Mw, V3, W};

/// `fresnel_conductor(cos, eta, k)` in every lane (`cos` clamped to `[0, 1]` in `f32`
/// as there, a NaN passing through).
#[inline(always)]
pub(crate) fn fresnel_conductor_lanes(cos: Fw, eta: Dw, k: Dw) -> Fw {
    let mut c = [0.0; W];
    for i in 0..W {
        c[i] = cos.0[i].clamp(0.0, 1.0) as f64;
    }
    let cos_i = Dw(c);
    let cos2_i = cos_i * cos_i;
    let sin2_i = 1.0 - cos2_i;
    let sin4_i = sin2_i * sin2_i;
    let temp = eta * eta - k * k - sin2_i;
    // a² + b² = |η̂² - sin²θi|, a = Re sqrt(η̂² - sin²θi).
    let a2_plus_b2 = (temp * temp + 4.0 * k * k * eta * eta).max(0.0).sqrt();
    let a = (0.5 * (a2_plus_b2 + temp)).max(0.0).sqrt();
    let term_1 = a2_plus_b2 + cos2_i;
    let term_2 = 2.0 * cos_i * a;
    let term_3 = a2_plus_b2 * cos2_i + sin4_i;
    let term_4 = term_2 * sin2_i;
    // R = (R_s + R_p) / 2 with R_s = (t1 - t2) / (t1 + t2) and R_p = R_s (t3 - t4) /
    // (t3 + t4), which is R_s t3 / (t3 + t4): one division.
    ((term_1 - term_2) * term_3 / ((term_1 + term_2) * (term_3 + term_4))).narrow()
}

/// The conductor Fresnel reflectance (`fresnel_conductor_rgb` times the test's
/// `fresnel_scale`) of the lanes' materials at cosine `cos` in the lanes of `active`
/// whose material is a conductor, zero elsewhere.
#[inline(always)]
pub(crate) fn conductor_fresnel(
    ws: &WideScene<'_, '_>,
    material: &[u32; W],
    cos: Fw,
    active: Mw,
) -> V3 {
    if !active.any() {
        return V3::ZERO;
    }
    // The lanes' indices (per channel), gathered; lanes without a conductor compute
    // with a placeholder index and are zeroed.
    let mut eta = [Dw::splat(1.0); 3];
    let mut k = [Dw::ZERO; 3];
    let mut some = Mw::FALSE;
    for lane in active.lanes() {
        if let Some((e, kk)) = ws.materials[material[lane] as usize].conductor {
            some.set(lane, true);
            for (ch, (ev, kv)) in [(e.r, kk.r), (e.g, kk.g), (e.b, kk.b)].iter().enumerate() {
                eta[ch].0[lane] = *ev as f64;
                k[ch].0[lane] = *kv as f64;
            }
        }
    }
    if !some.any() {
        return V3::ZERO;
    }
    let s = ws.fresnel_scale;
    V3::new(
        some.keep(fresnel_conductor_lanes(cos, eta[0], k[0]) * s),
        some.keep(fresnel_conductor_lanes(cos, eta[1], k[1]) * s),
        some.keep(fresnel_conductor_lanes(cos, eta[2], k[2]) * s),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use irradia_scatter::ior::conductor_ior;
    use irradia_scatter::optics::fresnel_conductor;

    /// The lanes' reflectance equals the scalar `f64` one bit for bit for the speed
    /// suite's metals (and a few others) over the whole range of angles, grazing and
    /// normal incidence, out-of-range cosines and NaN included.
    #[test]
    fn lane_reflectance_equals_the_scalar_one() {
        let mut cosines: Vec<f32> = (0..=4000).map(|i| i as f32 / 4000.0).collect();
        cosines.extend([
            -0.5,
            -0.0,
            1e-8,
            1e-4,
            0.999_999,
            1.0 + 1e-6,
            2.0,
            f32::NAN,
            f32::MIN_POSITIVE,
        ]);
        while !cosines.len().is_multiple_of(W) {
            cosines.push(0.5);
        }
        let mut metals = 0;
        for name in ["Al", "Au", "Cu", "Ag", "Cr"] {
            let Some((eta, k)) = conductor_ior(name) else {
                continue;
            };
            metals += 1;
            for (e, kk) in [(eta.r, k.r), (eta.g, k.g), (eta.b, k.b)] {
                for chunk in cosines.chunks(W) {
                    let cos = Fw(chunk.try_into().unwrap());
                    let got =
                        fresnel_conductor_lanes(cos, Dw::splat(e as f64), Dw::splat(kk as f64));
                    for lane in 0..W {
                        let want = fresnel_conductor(chunk[lane], e, kk);
                        let g = got.0[lane];
                        assert!(
                            g.to_bits() == want.to_bits() || (g.is_nan() && want.is_nan()),
                            "{name} cos {}: {g} vs {want}",
                            chunk[lane]
                        );
                    }
                }
            }
        }
        assert!(metals >= 3, "the suite's metals Al, Au, Cu are known");
    }
}
