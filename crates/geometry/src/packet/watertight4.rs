//! Four triangles tested against one ray at once (SSE), Embree's "Triangle4" leaves.
//!
//! The SIMD test computes, lane by lane, exactly the single-precision operations of
//! the scalar watertight test in [`crate::triangle`] (same operands, same order, no
//! fused multiply-add), so it rejects exactly the lanes the scalar test rejects. It is
//! used as a filter: the few lanes it keeps (and any lane with an edge function that
//! is exactly zero, which the scalar test redoes in double precision) are decided by
//! the scalar test, so the answer is bit-for-bit that of the scalar test and the mesh
//! stays watertight.
//!
//! A leaf holds up to eight triangles in two adjacent packets; with AVX2 both are
//! filtered in one pass of 256-bit instructions ([`intersect_leaf`]; Embree's leaves
//! of 4 and 8 triangles, Wald et al., "Embree", SIGGRAPH 2014), with the same
//! operations lane by lane, so the lanes kept are the same.

use crate::packet::has_avx2;
use crate::triangle::{TriangleHit, TriangleRay};
use glam::Vec3;

/// Corners of up to four triangles, structure of arrays: `p[corner][axis][lane]`, and
/// the caller's id of each lane's triangle (160 bytes). The ids ride in the packet, as
/// Embree's Triangle4 leaves carry their primitive ids, so reporting a hit reads the
/// cache lines the test has just loaded instead of missing in a separate array (on
/// incoherent rays that miss was about 15% of the traversal's samples).
#[derive(Clone, Copy, Debug)]
#[repr(C, align(16))]
pub struct Triangle4 {
    pub p: [[[f32; 4]; 3]; 3],
    pub ids: [u32; 4],
}

impl Triangle4 {
    /// Packs up to four triangles; missing lanes repeat the last triangle (the caller
    /// masks them out by count). Every id is `u32::MAX` (see [`Triangle4::with_ids`]).
    pub fn new(tris: &[[Vec3; 3]]) -> Self {
        assert!(!tris.is_empty() && tris.len() <= 4);
        let mut p = [[[0f32; 4]; 3]; 3];
        for lane in 0..4 {
            let t = &tris[lane.min(tris.len() - 1)];
            for (c, corner) in t.iter().enumerate() {
                for axis in 0..3 {
                    p[c][axis][lane] = corner[axis];
                }
            }
        }
        Self {
            p,
            ids: [u32::MAX; 4],
        }
    }

    /// The packet with lane `i`'s id set to `ids[i]` (missing lanes keep `u32::MAX`).
    pub fn with_ids(mut self, ids: &[u32]) -> Self {
        self.ids[..ids.len()].copy_from_slice(ids);
        self
    }

    #[inline]
    pub fn corners(&self, lane: usize) -> [Vec3; 3] {
        std::array::from_fn(|c| {
            Vec3::new(self.p[c][0][lane], self.p[c][1][lane], self.p[c][2][lane])
        })
    }

    /// Lanes (bits) among the first `lanes` that may be hit with `0 < t < t_max`:
    /// every lane the scalar test would accept is in the mask.
    #[inline(always)]
    pub fn candidates(&self, ray: &TriangleRay, lanes: usize, t_max: f32) -> u32 {
        let valid = (1u32 << lanes) - 1;
        #[cfg(target_arch = "x86_64")]
        {
            // SAFETY: SSE2 is in the x86_64 baseline; the arrays are 16-byte aligned.
            unsafe { self.candidates_sse(ray, t_max) & valid }
        }
        #[cfg(not(target_arch = "x86_64"))]
        {
            let _ = (ray, t_max);
            valid
        }
    }

    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    unsafe fn candidates_sse(&self, r: &TriangleRay, t_max: f32) -> u32 {
        use std::arch::x86_64::*;
        let (kx, ky, kz) = r.axes();
        let o = r.origin().to_array();
        let (ox, oy, oz) = (_mm_set1_ps(o[kx]), _mm_set1_ps(o[ky]), _mm_set1_ps(o[kz]));
        let (sx, sy) = r.shear_xy();
        let (sx, sy, sz) = (_mm_set1_ps(sx), _mm_set1_ps(sy), _mm_set1_ps(r.shear_z()));
        let load = |c: usize, axis: usize| _mm_load_ps(self.p[c][axis].as_ptr());
        // Corner c relative to the origin, sheared: (x, y, z before scaling).
        let corner = |c: usize| {
            let z = _mm_sub_ps(load(c, kz), oz);
            let x = _mm_add_ps(_mm_sub_ps(load(c, kx), ox), _mm_mul_ps(sx, z));
            let y = _mm_add_ps(_mm_sub_ps(load(c, ky), oy), _mm_mul_ps(sy, z));
            (x, y, z)
        };
        let (ax, ay, az) = corner(0);
        let (bx, by, bz) = corner(1);
        let (cx, cy, cz) = corner(2);
        let u = _mm_sub_ps(_mm_mul_ps(cx, by), _mm_mul_ps(cy, bx));
        let v = _mm_sub_ps(_mm_mul_ps(ax, cy), _mm_mul_ps(ay, cx));
        let w = _mm_sub_ps(_mm_mul_ps(bx, ay), _mm_mul_ps(by, ax));
        let zero = _mm_setzero_ps();
        let any_zero = _mm_or_ps(
            _mm_cmpeq_ps(u, zero),
            _mm_or_ps(_mm_cmpeq_ps(v, zero), _mm_cmpeq_ps(w, zero)),
        );
        let any_neg = _mm_or_ps(
            _mm_cmplt_ps(u, zero),
            _mm_or_ps(_mm_cmplt_ps(v, zero), _mm_cmplt_ps(w, zero)),
        );
        let any_pos = _mm_or_ps(
            _mm_cmpgt_ps(u, zero),
            _mm_or_ps(_mm_cmpgt_ps(v, zero), _mm_cmpgt_ps(w, zero)),
        );
        let inside = _mm_andnot_ps(
            _mm_and_ps(any_neg, any_pos),
            _mm_castsi128_ps(_mm_set1_epi32(-1)),
        );
        let det = _mm_add_ps(_mm_add_ps(u, v), w);
        let t_scaled = _mm_add_ps(
            _mm_add_ps(
                _mm_mul_ps(u, _mm_mul_ps(az, sz)),
                _mm_mul_ps(v, _mm_mul_ps(bz, sz)),
            ),
            _mm_mul_ps(w, _mm_mul_ps(cz, sz)),
        );
        // Same range tests as the scalar code for det > 0 and det < 0.
        let tm = _mm_mul_ps(_mm_set1_ps(t_max), det);
        let pos_ok = _mm_and_ps(
            _mm_cmpgt_ps(det, zero),
            _mm_and_ps(_mm_cmpgt_ps(t_scaled, zero), _mm_cmplt_ps(t_scaled, tm)),
        );
        let neg_ok = _mm_and_ps(
            _mm_cmplt_ps(det, zero),
            _mm_and_ps(_mm_cmplt_ps(t_scaled, zero), _mm_cmpgt_ps(t_scaled, tm)),
        );
        let pass = _mm_and_ps(inside, _mm_or_ps(pos_ok, neg_ok));
        _mm_movemask_ps(_mm_or_ps(pass, any_zero)) as u32
    }

    /// The nearest hit among the first `lanes` triangles with `0 < t < t_max`, as
    /// (lane, hit).
    #[inline(always)]
    pub fn intersect(
        &self,
        ray: &TriangleRay,
        lanes: usize,
        t_max: f32,
    ) -> Option<(usize, TriangleHit)> {
        let mut mask = self.candidates(ray, lanes, t_max);
        let mut best = None;
        let mut t_max = t_max;
        while mask != 0 {
            let lane = mask.trailing_zeros() as usize;
            mask &= mask - 1;
            let [a, b, c] = self.corners(lane);
            if let Some(h) = ray.intersect(a, b, c, t_max) {
                t_max = h.t;
                best = Some((lane, h));
            }
        }
        best
    }
}

/// Lanes (bits 0..4 of `p0`, 4..8 of `p1`) that may be hit with `0 < t < t_max`: the
/// SSE filter of [`Triangle4::candidates`] on both packets at once, with the same
/// operations in each lane.
///
/// # Safety
/// The CPU must support AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
pub unsafe fn candidates_pair_avx2(
    p0: &Triangle4,
    p1: &Triangle4,
    r: &TriangleRay,
    t_max: f32,
) -> u32 {
    use std::arch::x86_64::*;
    let (kx, ky, kz) = r.axes();
    let o = r.origin().to_array();
    let (ox, oy, oz) = (
        _mm256_set1_ps(o[kx]),
        _mm256_set1_ps(o[ky]),
        _mm256_set1_ps(o[kz]),
    );
    let (sx, sy) = r.shear_xy();
    let (sx, sy, sz) = (
        _mm256_set1_ps(sx),
        _mm256_set1_ps(sy),
        _mm256_set1_ps(r.shear_z()),
    );
    let load = |c: usize, axis: usize| {
        _mm256_set_m128(
            _mm_load_ps(p1.p[c][axis].as_ptr()),
            _mm_load_ps(p0.p[c][axis].as_ptr()),
        )
    };
    let corner = |c: usize| {
        let z = _mm256_sub_ps(load(c, kz), oz);
        let x = _mm256_add_ps(_mm256_sub_ps(load(c, kx), ox), _mm256_mul_ps(sx, z));
        let y = _mm256_add_ps(_mm256_sub_ps(load(c, ky), oy), _mm256_mul_ps(sy, z));
        (x, y, z)
    };
    let (ax, ay, az) = corner(0);
    let (bx, by, bz) = corner(1);
    let (cx, cy, cz) = corner(2);
    let u = _mm256_sub_ps(_mm256_mul_ps(cx, by), _mm256_mul_ps(cy, bx));
    let v = _mm256_sub_ps(_mm256_mul_ps(ax, cy), _mm256_mul_ps(ay, cx));
    let w = _mm256_sub_ps(_mm256_mul_ps(bx, ay), _mm256_mul_ps(by, ax));
    let zero = _mm256_setzero_ps();
    let eq = |a| _mm256_cmp_ps::<_CMP_EQ_OQ>(a, zero);
    let lt = |a| _mm256_cmp_ps::<_CMP_LT_OQ>(a, zero);
    let gt = |a| _mm256_cmp_ps::<_CMP_GT_OQ>(a, zero);
    let any_zero = _mm256_or_ps(eq(u), _mm256_or_ps(eq(v), eq(w)));
    let any_neg = _mm256_or_ps(lt(u), _mm256_or_ps(lt(v), lt(w)));
    let any_pos = _mm256_or_ps(gt(u), _mm256_or_ps(gt(v), gt(w)));
    let inside = _mm256_andnot_ps(
        _mm256_and_ps(any_neg, any_pos),
        _mm256_castsi256_ps(_mm256_set1_epi32(-1)),
    );
    let det = _mm256_add_ps(_mm256_add_ps(u, v), w);
    let t_scaled = _mm256_add_ps(
        _mm256_add_ps(
            _mm256_mul_ps(u, _mm256_mul_ps(az, sz)),
            _mm256_mul_ps(v, _mm256_mul_ps(bz, sz)),
        ),
        _mm256_mul_ps(w, _mm256_mul_ps(cz, sz)),
    );
    let tm = _mm256_mul_ps(_mm256_set1_ps(t_max), det);
    let pos_ok = _mm256_and_ps(
        gt(det),
        _mm256_and_ps(gt(t_scaled), _mm256_cmp_ps::<_CMP_LT_OQ>(t_scaled, tm)),
    );
    let neg_ok = _mm256_and_ps(
        lt(det),
        _mm256_and_ps(lt(t_scaled), _mm256_cmp_ps::<_CMP_GT_OQ>(t_scaled, tm)),
    );
    let pass = _mm256_and_ps(inside, _mm256_or_ps(pos_ok, neg_ok));
    _mm256_movemask_ps(_mm256_or_ps(pass, any_zero)) as u32
}

/// Lanes of a leaf's packets (bit `4 k + lane` for lane `lane` of packet `k`) among
/// its first `count` triangles that may be hit with `0 < t < t_max`; a superset of
/// the lanes the scalar test accepts. Packets are filtered two at a time with AVX2.
#[inline(always)]
pub fn leaf_candidates(packets: &[Triangle4], count: usize, ray: &TriangleRay, t_max: f32) -> u64 {
    let mut mask = 0u64;
    let mut k = 0;
    let avx2 = packets.len() > 1 && has_avx2();
    while k < packets.len() {
        let left = count - 4 * k;
        #[cfg(target_arch = "x86_64")]
        if avx2 && k + 1 < packets.len() {
            let valid = (1u32 << left.min(8)) - 1;
            // SAFETY: `avx2` says the CPU has AVX2.
            let m = unsafe { candidates_pair_avx2(&packets[k], &packets[k + 1], ray, t_max) };
            mask |= ((m & valid) as u64) << (4 * k);
            k += 2;
            continue;
        }
        let _ = avx2;
        mask |= (packets[k].candidates(ray, left.min(4), t_max) as u64) << (4 * k);
        k += 1;
    }
    mask
}

/// The nearest hit among the first `count` triangles of a leaf's packets with
/// `0 < t < t_max`, as (index in the leaf, hit): the scalar watertight test on the
/// lanes [`leaf_candidates`] keeps, in lane order, so the answer is bit for bit that
/// of the scalar test run over the leaf.
#[inline(always)]
pub fn intersect_leaf(
    packets: &[Triangle4],
    count: usize,
    ray: &TriangleRay,
    t_max: f32,
) -> Option<(usize, TriangleHit)> {
    let mut mask = leaf_candidates(packets, count, ray, t_max);
    let mut best = None;
    let mut t_max = t_max;
    while mask != 0 {
        let i = mask.trailing_zeros() as usize;
        mask &= mask - 1;
        let [a, b, c] = packets[i / 4].corners(i % 4);
        if let Some(h) = ray.intersect(a, b, c, t_max) {
            t_max = h.t;
            best = Some((i, h));
        }
    }
    best
}

/// Whether any of the first `count` triangles of a leaf's packets is hit with
/// `0 < t < t_max` (the scalar test decides, as in [`intersect_leaf`]).
#[inline(always)]
pub fn occluded_leaf(packets: &[Triangle4], count: usize, ray: &TriangleRay, t_max: f32) -> bool {
    let mut mask = leaf_candidates(packets, count, ray, t_max);
    while mask != 0 {
        let i = mask.trailing_zeros() as usize;
        mask &= mask - 1;
        let [a, b, c] = packets[i / 4].corners(i % 4);
        if ray.intersect(a, b, c, t_max).is_some() {
            return true;
        }
    }
    false
}
