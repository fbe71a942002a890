//! Four triangles tested against one ray at once (SSE), Embree's "Triangle4" leaves.
//!
//! The SIMD test computes, lane by lane, exactly the single-precision operations of
//! the scalar watertight test in [`crate::triangle`] (same operands, same order, no
//! fused multiply-add), so it rejects exactly the lanes the scalar test rejects. It is
//! used as a filter: the few lanes it keeps (and any lane with an edge function that
//! is exactly zero, which the scalar test redoes in double precision) are decided by
//! the scalar test, so the answer is bit-for-bit that of the scalar test and the mesh
//! stays watertight.

use crate::triangle::{TriangleHit, TriangleRay};
use glam::Vec3;

/// Corners of up to four triangles, structure of arrays: `p[corner][axis][lane]`.
#[derive(Clone, Copy, Debug)]
#[repr(C, align(16))]
pub struct Triangle4 {
    pub p: [[[f32; 4]; 3]; 3],
}

impl Triangle4 {
    /// Packs up to four triangles; missing lanes repeat the last triangle (the caller
    /// masks them out by count).
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
        Self { p }
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
