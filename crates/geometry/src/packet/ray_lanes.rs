//! W rays against every triangle of a small flat scene at once: the SIMD lanes hold
//! rays instead of triangles (the ray-packet layout of Wald, Slusallek, Benthin,
//! Wagner, "Interactive Rendering with Coherent Ray Tracing", Eurographics 2001, here
//! with incoherent rays: Mitsuba 3's `llvm` variants trace their lanes' rays the same
//! way, a wavefront at a time). For the Cornell box (36 triangles) one pass over the
//! triangles costs less than a walk of the flat scene's packets per lane, and the
//! per-lane calls disappear.
//!
//! The test is [`TrianglePacket`](super::triangle8::TrianglePacket)'s
//! Möller-Trumbore form with the precomputed normal, with the same products and sums
//! (fused where its AVX2 version fuses them, `FMA = true`, not where its SSE version
//! does not), and the triangles are visited in the flat scene's packet order keeping
//! the first of equally near hits, so the hits are the flat scene's up to the rounding
//! of a comparison at a tie.

use super::lanes::{Fw, Mw, V3, W};
use glam::Vec3;

/// Scenes of at most this many triangles are traced W rays at a time.
pub const MAX_TRIANGLES: usize = 64;

/// The triangles as the ray-lane test reads them.
#[derive(Clone, Debug)]
pub struct RayLaneTriangles {
    /// Per triangle: `v0`, `e1 = v1 - v0`, `e2 = v2 - v0`, `n = e1 × e2`.
    records: Vec<[f32; 12]>,
    /// The triangle index of each record.
    ids: Vec<u32>,
}

/// The nearest hits of W rays.
#[derive(Clone, Copy, Debug)]
pub struct LaneHits {
    pub hit: Mw,
    pub triangle: [u32; W],
    pub t: Fw,
    pub b1: Fw,
    pub b2: Fw,
}

impl LaneHits {
    /// No lane hits anything.
    pub const NONE: LaneHits = LaneHits {
        hit: Mw::FALSE,
        triangle: [0; W],
        t: Fw::ZERO,
        b1: Fw::ZERO,
        b2: Fw::ZERO,
    };
}

#[inline(always)]
fn fmadd<const FMA: bool>(a: Fw, b: Fw, c: Fw) -> Fw {
    if FMA {
        a.mul_add(b, c)
    } else {
        a * b + c
    }
}

/// `a b - c`, fused when `FMA` (as `_mm256_fmsub_ps`).
#[inline(always)]
fn fmsub<const FMA: bool>(a: Fw, b: Fw, c: Fw) -> Fw {
    if FMA {
        a.mul_add(b, -c)
    } else {
        a * b - c
    }
}

/// `a · (r[k], r[k+1], r[k+2])` summed as the packet test sums it.
#[inline(always)]
fn dot<const FMA: bool>(a: V3, r: &[f32; 12], k: usize) -> Fw {
    let (x, y, z) = (Fw::splat(r[k]), Fw::splat(r[k + 1]), Fw::splat(r[k + 2]));
    if FMA {
        fmadd::<true>(a.z, z, fmadd::<true>(a.y, y, a.x * x))
    } else {
        a.x * x + a.y * y + a.z * z
    }
}

/// One triangle against W rays: the hit mask (`0 < t < t_max`), the sign-corrected
/// numerators of `b1`, `b2`, `t` and `|den|`.
#[inline(always)]
fn test<const FMA: bool>(r: &[f32; 12], o: V3, d: V3, t_max: Fw) -> (Mw, Fw, Fw, Fw, Fw) {
    let sv = V3::new(o.x - r[0], o.y - r[1], o.z - r[2]);
    let rv = V3::new(
        fmsub::<FMA>(d.y, sv.z, d.z * sv.y),
        fmsub::<FMA>(d.z, sv.x, d.x * sv.z),
        fmsub::<FMA>(d.x, sv.y, d.y * sv.x),
    );
    let den = dot::<FMA>(d, r, 9);
    let sign = den.sign_bit();
    let abs_den = den.xor_bits(sign);
    let u = dot::<FMA>(rv, r, 6).xor_bits(sign);
    let v = -dot::<FMA>(rv, r, 3).xor_bits(sign);
    let t = -dot::<FMA>(sv, r, 9).xor_bits(sign);
    let ok = u.ge(0.0)
        & v.ge(0.0)
        & (u + v).le(abs_den)
        & t.gt(0.0)
        & t.lt(abs_den * t_max)
        & abs_den.gt(0.0);
    (ok, u, v, t, abs_den)
}

impl RayLaneTriangles {
    /// The triangles (corners) in the order `order` (the flat scene's packet order),
    /// or `None` when there are too many for this test to pay off.
    pub fn new(corners: &[[Vec3; 3]], order: &[u32]) -> Option<Self> {
        if order.is_empty() || order.len() > MAX_TRIANGLES {
            return None;
        }
        let mut records = Vec::new();
        for &i in order {
            let t = corners.get(i as usize)?;
            // As `TrianglePacket::new`.
            let (e1, e2) = (t[1] - t[0], t[2] - t[0]);
            let n = e1.cross(e2);
            let mut r = [0.0; 12];
            for (k, v) in [t[0], e1, e2, n].iter().enumerate() {
                r[3 * k..3 * k + 3].copy_from_slice(&v.to_array());
            }
            records.push(r);
        }
        Some(Self {
            records,
            ids: order.to_vec(),
        })
    }

    /// The nearest hit (`t > 0`) of each ray of `active`.
    #[inline(always)]
    pub fn nearest<const FMA: bool>(&self, o: V3, d: V3, active: Mw) -> LaneHits {
        self.nearest_within::<FMA>(o, d, Fw::splat(f32::INFINITY), active)
    }

    /// The nearest hit with `0 < t < t_max` of each ray of `active`.
    #[inline(always)]
    pub fn nearest_within<const FMA: bool>(&self, o: V3, d: V3, t_max: Fw, active: Mw) -> LaneHits {
        // Inactive lanes get t_max = -inf: nothing is accepted.
        let mut best = active.select(t_max, Fw::splat(f32::NEG_INFINITY));
        let mut h = LaneHits::NONE;
        // The ids ride in `f32` lanes as bit patterns: a select only moves bits, and it
        // compiles to one masked move, where a `[u32; W]` blend was rebuilt lane by lane.
        let mut ids = Fw::ZERO;
        for (r, &id) in self.records.iter().zip(&self.ids) {
            let (ok, u, v, t, abs_den) = test::<FMA>(r, o, d, best);
            if !ok.any() {
                continue;
            }
            // As `triangle8::nearest_lane`: t = t' / |den| by a reciprocal,
            // strictly nearer than the best so far.
            let inv = 1.0 / abs_den;
            let th = t * inv;
            let take = ok & th.lt(best);
            best = take.select(th, best);
            h.b1 = take.select(u * inv, h.b1);
            h.b2 = take.select(v * inv, h.b2);
            ids = take.select(Fw::splat(f32::from_bits(id)), ids);
            h.hit = h.hit | take;
        }
        h.triangle = ids.0.map(f32::to_bits);
        h.t = best;
        h
    }

    /// Which rays of `active` hit a triangle with `0 < t < t_max`.
    #[inline(always)]
    pub fn occluded<const FMA: bool>(&self, o: V3, d: V3, t_max: Fw, active: Mw) -> Mw {
        let mut hit = Mw::FALSE;
        for (k, r) in self.records.iter().enumerate() {
            let (ok, ..) = test::<FMA>(r, o, d, t_max);
            hit = hit | ok;
            // Every packet's worth of triangles, stop once every ray is blocked.
            if k % 8 == 7 && !(active.and_not(hit)).any() {
                break;
            }
        }
        hit & active
    }
}
