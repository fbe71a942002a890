//! The wide kernel's ray queries on scenes too large for W rays against every
//! triangle (see [`super`]): the live lanes' rays walk the
//! [`FlatScene`](crate::path::flat_scene::FlatScene)'s hierarchy in turns, one node or
//! leaf each (geometry's `bvh::interleaved`), so one ray's cache misses overlap the
//! others' work; each answer is exactly its single ray's. Nearest hits, and any hit
//! for shadow rays with a bound per ray. A scene without triangles (spheres only: the
//! speed suite's rough_balls) asks nothing.
//!
//! The live lanes are walked one ray at a time, not as packets (Wald et al. 2001;
//! Benthin et al. 2012's hybrid), although a tile's samples come pixel by pixel:
//! a lane takes the next camera sample as soon as its path ends, so a query holds
//! about W / 5.4 fresh camera rays on the bunny (5.4 rays a sample), and the other
//! lanes' bounce and shadow rays go every way. Measured on the bunny (16 spp, one
//! thread, CPU of the render, paired, load 5-7): the lanes of one direction octant
//! walked as 8-ray packets (geometry's `bvh::packet_traverse`, with the mesh batches'
//! tie rule so every answer stays the single ray's) from 3 lanes up 1.04x, from 6
//! up 1.045x, shadow rays likewise 1.036x (branch `walk7-experiments`).
//!
//! The camera rays are traced as packets before lanes take them, where they are
//! coherent: the W samples made at once ([`super::starts`]), eight rays of a pixel or
//! two neighbours a packet. A lane that took such a sample brings its hit
//! ([`KnownHits`]) and is not walked again here.

use super::{smooth, tri, WideScene};
use crate::path::flat_scene::prefetch_bytes;
use glam::Vec3;
use irradia_core::Ray;
use irradia_geometry::packet::lanes::{Fw, Mw, V3, W};
use irradia_geometry::packet::ray_lanes::LaneHits;
use irradia_geometry::packet::{PacketHit, SimdBuild};

/// The lanes whose nearest hit is already known (bit `lane` of `lanes`), and the hits:
/// fresh camera rays traced as packets ([`super::starts`]).
pub(super) struct KnownHits {
    pub(super) lanes: u32,
    pub(super) hit: [Option<(u32, PacketHit)>; W],
}

impl KnownHits {
    pub(super) const NONE: Self = Self {
        lanes: 0,
        hit: [None; W],
    };
}

/// The nearest triangle hits of the rays `(origin, dir)` of the `live` lanes, those of
/// `known`'s lanes as it holds them. Where the flat scene tests some triangles before
/// its hierarchy (a large scene's large triangles, [`WideScene::first`]), the lanes
/// test them W at once, and only the lanes whose ray may meet the tree's box before
/// that hit ([`WideScene::tree_box`]) walk the tree, bounded by it.
#[inline(always)]
fn nearest_body<const FMA: bool>(
    ws: &WideScene<'_, '_>,
    origin: &V3,
    dir: &V3,
    live: Mw,
    known: &KnownHits,
) -> LaneHits {
    let mut h = LaneHits::NONE;
    if !ws.has_triangles() {
        return h;
    }
    let mut which = [0usize; W];
    let mut rays = [Ray::new(Vec3::ZERO, Vec3::X); W];
    let mut found = [None; W];
    let mut bound = [f32::INFINITY; W];
    let mut walked = Mw::FALSE;
    let mut k = W;
    for lane in live.lanes() {
        if known.lanes >> lane & 1 != 0 {
            // Kept at the end, after the rays walked here.
            k -= 1;
            which[k] = lane;
            found[k] = known.hit[lane];
        } else {
            walked.set(lane, true);
        }
    }
    if let Some(first) = &ws.first {
        h = first.nearest::<FMA>(*origin, *dir, walked);
        if let Some(tree_box) = &ws.tree_box {
            let t_max = h.hit.select(h.t, Fw::splat(f32::INFINITY));
            walked = walked & tree_box.may_hit_within(*origin, *dir, t_max);
        }
    }
    let mut n = 0;
    for lane in walked.lanes() {
        which[n] = lane;
        rays[n] = Ray::new(origin.lane(lane), dir.lane(lane));
        n += 1;
    }
    if ws.first.is_some() {
        for (b, &lane) in bound.iter_mut().zip(&which[..n]) {
            if h.hit.get(lane) {
                *b = h.t.0[lane];
            }
        }
        let tracer = &ws.ps.tracer;
        tracer.nearest_in_tree(&rays[..n], &bound[..n], &mut found[..n]);
    } else {
        ws.ps.tracer.nearest_triangles(&rays[..n], &mut found[..n]);
    }
    for (&lane, found) in which[..n]
        .iter()
        .chain(&which[k..])
        .zip(found[..n].iter().chain(&found[k..]))
    {
        if let Some((t, ph)) = *found {
            h.hit.set(lane, true);
            h.triangle[lane] = t;
            h.t.0[lane] = ph.t;
            h.b1.0[lane] = ph.b1;
            h.b2.0[lane] = ph.b2;
        }
    }
    for lane in h.hit.lanes() {
        // Start loading what the next stages read of the triangle while the other
        // lanes are traced (large scenes: not in cache).
        let t_ = h.triangle[lane] as usize;
        prefetch_bytes(&ws.triangle_owner[t_], 8);
        prefetch_bytes(&ws.triangles[t_], 4 * tri::LEN);
        if let Some(table) = &ws.smooth {
            prefetch_bytes(&table[t_], 4 * smooth::LEN);
        }
    }
    h
}

/// Which of the shadow rays `(origin, dir)` of the lanes in `active`, up to `t_max`,
/// are blocked by a triangle: by one of the flat scene's first triangles
/// ([`WideScene::first`], W lanes at once), else by one of its hierarchy's (the lanes
/// whose ray may meet the tree's box).
#[inline(always)]
fn occluded_body<const FMA: bool>(
    ws: &WideScene<'_, '_>,
    origin: &V3,
    dir: &V3,
    t_max: &Fw,
    active: Mw,
) -> Mw {
    if !ws.has_triangles() {
        return Mw::FALSE;
    }
    let (mut blocked, mut open) = match &ws.first {
        Some(first) => {
            let blocked = first.occluded::<FMA>(*origin, *dir, *t_max, active);
            (blocked, active & !blocked)
        }
        None => (Mw::FALSE, active),
    };
    if let Some(tree_box) = &ws.tree_box {
        open = open & tree_box.may_hit_within(*origin, *dir, *t_max);
    }
    let mut which = [0usize; W];
    let mut rays = [Ray::new(Vec3::ZERO, Vec3::X); W];
    let mut bound = [0.0f32; W];
    let mut n = 0;
    for lane in open.lanes() {
        which[n] = lane;
        rays[n] = Ray::new(origin.lane(lane), dir.lane(lane));
        bound[n] = t_max.0[lane];
        n += 1;
    }
    let mut hit = [false; W];
    let tracer = &ws.ps.tracer;
    match ws.first {
        Some(_) => tracer.occluded_in_tree(&rays[..n], &bound[..n], &mut hit[..n]),
        None => tracer.occluded_baked_many(&rays[..n], &bound[..n], &mut hit[..n]),
    }
    for (&lane, &h) in which[..n].iter().zip(&hit[..n]) {
        blocked.set(lane, h);
    }
    blocked
}

/// The lane queries stay out of the kernel's one big function (inlined there they made
/// the loop slower on scenes where they never run: cornell 1.11x the CPU time,
/// veach_mis 1.06x), each compiled for the three builds of the kernel
/// ([`SimdBuild`]), the running one ([`WideScene::build`]) chosen per call.
macro_rules! builds {
    ($public:ident, $body:ident, ($($arg:ident: $ty:ty),*) -> $out:ty) => {
        pub(super) fn $public(ws: &WideScene<'_, '_>, $($arg: $ty),*) -> $out {
            #[cfg(target_arch = "x86_64")]
            {
                #[target_feature(enable = "avx2,fma,avx512f,avx512vl,avx512dq,avx512bw")]
                #[inline(never)]
                unsafe fn avx512(ws: &WideScene<'_, '_>, $($arg: $ty),*) -> $out {
                    $body::<true>(ws, $($arg),*)
                }
                #[target_feature(enable = "avx2,fma")]
                #[inline(never)]
                unsafe fn avx2(ws: &WideScene<'_, '_>, $($arg: $ty),*) -> $out {
                    $body::<true>(ws, $($arg),*)
                }
                match ws.build {
                    // SAFETY: `build` is only ever a build this CPU runs (`chosen`,
                    // or `with_build`'s check).
                    SimdBuild::Avx512 => return unsafe { avx512(ws, $($arg),*) },
                    // SAFETY: as above.
                    SimdBuild::Avx2 => return unsafe { avx2(ws, $($arg),*) },
                    SimdBuild::Portable => {}
                }
            }
            #[inline(never)]
            fn portable(ws: &WideScene<'_, '_>, $($arg: $ty),*) -> $out {
                $body::<false>(ws, $($arg),*)
            }
            portable(ws, $($arg),*)
        }
    };
}

builds!(nearest_in_turns, nearest_body, (origin: &V3, dir: &V3, live: Mw, known: &KnownHits) -> LaneHits);
builds!(occluded_in_turns, occluded_body, (origin: &V3, dir: &V3, t_max: &Fw, active: Mw) -> Mw);
