//! The light choice of the wide kernel's vector stage: `LightSampler::pick_kernel`'s
//! choice of emitter and facet made for the W lanes at once, by counting the entries of
//! the sorted cumulative tables that are `<= x` (which equals the scalar code's binary
//! search), for scenes of at most `VECTOR_PICK_MAX` emitters of as many facets each.
//! An emitter at infinity (and a sphere) stands in the tables as one placeholder facet
//! of the whole area; the lanes that choose one at infinity get its sample lane by lane
//! from `LightSampler::kernel_light` with the numbers as drawn ([`far_lights`]).

use super::background::Background;
use super::gather::{checked, field, lookup, Table};
use crate::path::lights::{KernelLight, LightSampler};
use glam::Vec2;
use irradia_geometry::packet::lanes::{Fw, Mw, W};

/// What choosing a light facet reads (`LightSampler::pick_kernel`, lane by lane): the
/// emitters' cumulative probabilities, then within the chosen emitter its facets'
/// cumulative areas. Both are searched by counting the entries `<= x`, which equals
/// the scalar code's binary search on these sorted tables.
pub(crate) struct LightPick {
    pub emitter_cdf: Vec<f32>,
    /// Per emitter: probability of choosing it and its total facet area.
    pub probability: Table<1>,
    pub total: Table<1>,
    /// Per emitter: its first facet (in `WideScene::facets` and `facet_cdf`) and
    /// how many it has.
    pub start: Vec<u32>,
    pub len: Vec<u32>,
    /// The cumulative areas, aligned with `WideScene::facets`.
    pub facet_cdf: Table<1>,
    /// The most facets of one emitter.
    pub max_len: usize,
    /// Per emitter: 1 for an emitter at infinity (the constant environment, an
    /// environment map), else 0; and whether any is.
    pub far: Table<1>,
    pub any_far: bool,
}

/// The lanes of `active` whose chosen `emitter` (as [`pick_lights`] gives it) is at
/// infinity.
#[inline(always)]
pub(super) fn at_infinity(lp: &LightPick, emitter: &[u32; W], active: Mw) -> Mw {
    if !lp.any_far {
        return Mw::FALSE;
    }
    checked(&lp.far, emitter);
    active & field(&lp.far, emitter, 0).ne(0.0)
}

/// The light samples of the lanes of `far`, which chose the emitter at infinity
/// `emitter` with probability `pick`, with the numbers `u` as drawn (not the facet
/// choice's): lane by lane, what `LightSampler::pick_kernel` gives for them (the
/// constant environment's whole sample, or the map to sample in lanes), recorded in
/// `bg` as the per-lane choice records it.
#[inline(always)]
pub(super) fn far_lights(
    lights: &LightSampler,
    far: Mw,
    emitter: &[u32; W],
    pick: Fw,
    u: [Fw; 2],
    bg: &mut Background,
    scale: f32,
) {
    for lane in far.lanes() {
        let u = Vec2::new(u[0].0[lane], u[1].0[lane]);
        match lights.kernel_light(emitter[lane] as usize, pick.0[lane], u) {
            Some(KernelLight::AtInfinity(ls)) => bg.light(lane, &ls, scale),
            Some(KernelLight::Envmap(map, p)) => bg.pick_map(lane, map, p, u),
            _ => {}
        }
    }
}

/// `LightSampler::pick_kernel` in every lane of `active`: the lanes that got a facet,
/// the facet (index into `WideScene::facets`), the probability of its emitter, the
/// point of the square to warp into the triangle, and the emitter.
#[inline(always)]
pub(super) fn pick_lights(
    lp: &LightPick,
    u_pick: Fw,
    u: [Fw; 2],
    active: Mw,
) -> (Mw, [u32; W], Fw, [Fw; 2], [u32; W]) {
    let count_le = |count: &mut [u32; W], m: Mw| {
        for i in 0..W {
            count[i] = count[i].wrapping_sub(m.0[i] as u32);
        }
    };
    let total = lp.emitter_cdf[lp.emitter_cdf.len() - 1];
    let x = u_pick * total;
    let mut emitter = [0u32; W];
    for &c in &lp.emitter_cdf {
        count_le(&mut emitter, Fw::splat(c).le(x));
    }
    let last = lp.emitter_cdf.len() as u32 - 1;
    let emitter: [u32; W] = std::array::from_fn(|i| emitter[i].min(last));
    checked(&lp.probability, &emitter);
    let pick = field(&lp.probability, &emitter, 0);
    let total_w = field(&lp.total, &emitter, 0);
    let (start, len) = (lookup(&lp.start, &emitter), lookup(&lp.len, &emitter));
    let x2 = u[0] * total_w;
    let mut k = [0u32; W];
    for j in 0..lp.max_len as u32 {
        let at: [u32; W] = std::array::from_fn(|i| start[i] + j.min(len[i] - 1));
        checked(&lp.facet_cdf, &at);
        let inside = Mw::from_fn(|i| j < len[i]);
        count_le(&mut k, inside & field(&lp.facet_cdf, &at, 0).le(x2));
    }
    let k: [u32; W] = std::array::from_fn(|i| k[i].min(len[i] - 1));
    let at_lo: [u32; W] = std::array::from_fn(|i| start[i] + k[i].max(1) - 1);
    let at_hi: [u32; W] = std::array::from_fn(|i| start[i] + k[i]);
    checked(&lp.facet_cdf, &at_lo);
    checked(&lp.facet_cdf, &at_hi);
    let first = Mw::from_fn(|i| k[i] == 0);
    let lo = first.select(Fw::ZERO, field(&lp.facet_cdf, &at_lo, 0));
    let hi = field(&lp.facet_cdf, &at_hi, 0);
    // `f32::clamp(0, 1 - ε)`.
    let r = (x2 - lo) / (hi - lo);
    let r = r.lt(0.0).select(Fw::ZERO, r);
    let r = r
        .gt(1.0 - f32::EPSILON)
        .select(Fw::splat(1.0 - f32::EPSILON), r);
    (active & pick.gt(0.0), at_hi, pick, [r, u[1]], emitter)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::path::lights::KernelLight;
    use crate::path::wide::WideScene;
    use irradia_core::Rng;

    /// With emitters at infinity (an environment map and the constant environment
    /// beside the Cornell box's light) the vector choice plus [`far_lights`] give every
    /// lane exactly `pick_kernel`'s light: the facet, or the constant environment's
    /// whole sample, or the map with the numbers as drawn.
    #[test]
    fn vector_choice_with_emitters_at_infinity_equals_the_scalar_one() {
        use crate::path::flat_scene::FlatScene;
        use crate::path::integrator::PathScene;
        use crate::path::lights::LightSampler;
        let scene = crate::path::lights::cornell_with_skies();
        let lights = LightSampler::new(&scene);
        let ps = PathScene::new(&scene, FlatScene::new(&scene), &lights);
        let ws = WideScene::new(&ps).unwrap();
        let lp = ws
            .pick
            .as_ref()
            .expect("the vector choice covers the sky too");
        let mut rng = Rng::new(5, 6);
        let (mut facets, mut constant, mut maps) = (0, 0, 0);
        for _ in 0..400 {
            let (mut up, mut u) = (Fw::ZERO, [Fw::ZERO; 2]);
            for l in 0..W {
                up.0[l] = rng.next_f32();
                u[0].0[l] = rng.next_f32();
                u[1].0[l] = rng.next_f32();
            }
            let (m, facet, pick, uu, emitter) = pick_lights(lp, up, u, Mw::TRUE);
            let far = at_infinity(lp, &emitter, m);
            let mut bg = Background::default();
            far_lights(&lights, far, &emitter, pick, u, &mut bg, 1.0);
            for l in 0..W {
                let v = Vec2::new(u[0].0[l], u[1].0[l]);
                match lights.pick_kernel(up.0[l], v) {
                    Some(KernelLight::Surface(e, p, Some((t, w)))) => {
                        facets += 1;
                        assert!(m.get(l) && !far.get(l));
                        assert!(!bg.light.get(l) && !bg.map_light.get(l));
                        assert_eq!(facet[l], ws.facet_start[e] + t as u32);
                        assert_eq!(pick.0[l], p);
                        assert_eq!((uu[0].0[l], uu[1].0[l]), (w.x, w.y));
                    }
                    Some(KernelLight::AtInfinity(ls)) => {
                        constant += 1;
                        assert!(far.get(l) && bg.light.get(l) && !bg.map_light.get(l));
                        assert_eq!(bg.wi.lane(l), ls.wi);
                        assert_eq!(bg.li.lane(l), glam::Vec3::new(ls.li.r, ls.li.g, ls.li.b));
                        assert_eq!(bg.light_pdf.0[l], ls.pdf);
                    }
                    Some(KernelLight::Envmap(k, p)) => {
                        maps += 1;
                        assert!(far.get(l) && bg.map_light.get(l) && !bg.light.get(l));
                        assert_eq!((bg.map[l], bg.map_pick.0[l]), (k as u32, p));
                        assert_eq!((bg.map_u[0].0[l], bg.map_u[1].0[l]), (v.x, v.y));
                    }
                    None => assert!(!m.get(l) && !bg.light.get(l) && !bg.map_light.get(l)),
                    other => panic!("no such light here: {other:?}"),
                }
            }
        }
        assert!(
            facets > 100 && constant > 100 && maps > 100,
            "{facets} {constant} {maps}"
        );
    }

    #[test]
    fn vector_light_choice_equals_the_scalar_one() {
        use crate::path::flat_scene::FlatScene;
        use crate::path::integrator::PathScene;
        use crate::path::lights::LightSampler;
        let scene = irradia_scene::builtin::load("cornell").unwrap();
        let lights = LightSampler::new(&scene);
        let ps = PathScene::new(&scene, FlatScene::new(&scene), &lights);
        let ws = WideScene::new(&ps).unwrap();
        let lp = ws.pick.as_ref().expect("one emitter of two facets");
        let mut rng = Rng::new(1, 2);
        let edge = [0.0, 0.5, 1.0 - f32::EPSILON / 2.0];
        for round in 0..400 {
            let (mut up, mut u) = (Fw::ZERO, [Fw::ZERO; 2]);
            for l in 0..W {
                up.0[l] = rng.next_f32();
                u[0].0[l] = if round < 3 {
                    edge[round]
                } else {
                    rng.next_f32()
                };
                u[1].0[l] = rng.next_f32();
            }
            let (m, facet, pick, uu, emitter) = pick_lights(lp, up, u, Mw::TRUE);
            for l in 0..W {
                let v = glam::Vec2::new(u[0].0[l], u[1].0[l]);
                match lights.pick_kernel(up.0[l], v) {
                    Some(KernelLight::Surface(e, p, Some((t, w)))) => {
                        assert_eq!(emitter[l], e as u32);
                        assert!(m.get(l));
                        assert_eq!(facet[l], ws.facet_start[e] + t as u32);
                        assert_eq!(pick.0[l], p);
                        assert_eq!((uu[0].0[l], uu[1].0[l]), (w.x, w.y));
                    }
                    Some(KernelLight::Surface(_, _, None)) => {
                        panic!("the Cornell box has no sphere light")
                    }
                    Some(KernelLight::AtInfinity(_)) | Some(KernelLight::Envmap(..)) => {
                        panic!("nor an environment")
                    }
                    None => assert!(!m.get(l)),
                }
            }
        }
    }
}
