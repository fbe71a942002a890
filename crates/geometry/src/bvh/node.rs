//! The wide (8-ary) BVH node and its SIMD box test.
//!
//! Eight child boxes are stored "structure of arrays" (all eight `min.x`, then all
//! eight `min.y`, ...) so one AVX instruction handles one slab of all eight boxes, as
//! Embree's BVH8 does (Wald, Woop, Benthin, Johnson, Ernst, "Embree: A Kernel Framework
//! for Efficient CPU Ray Tracing", SIGGRAPH 2014; Benthin, Boulos, Lacewell, Wald,
//! "Combining Single and Packet-Ray Tracing for Arbitrary Ray Distributions on the
//! Intel MIC Architecture", IEEE TVCG 2012, on 8- and 16-wide nodes; Wald, Benthin,
//! Boulos, "Getting Rid of Packets", RT 2008). Without AVX2 (checked once at run time)
//! the same test runs as two 4-wide SSE halves. Every path computes the same
//! subtractions and products (no fused multiply-add), so they agree bit for bit with
//! [`WideNode::intersect_scalar`], and the test stays conservative (Ize 2013).

use glam::Vec3;
use irradia_core::Aabb;

/// Width of a node.
pub const WIDTH: usize = 8;

/// `1 + 2 γ(3)`: stretching the far slab distance by this factor makes the box test
/// conservative under rounding (Ize, "Robust BVH Ray Traversal", JCGT 2013).
pub(crate) const ROBUST_FAR: f32 = 1.0 + 2.0 * gamma(3);

/// `n ε / (1 - n ε)` with ε the unit roundoff (pbrt-v4, section 6.8).
pub const fn gamma(n: i32) -> f32 {
    let e = f32::EPSILON * 0.5;
    (n as f32 * e) / (1.0 - n as f32 * e)
}

/// A reference to a child: an inner node (`count == 0`, `index` is the node) or a leaf
/// (`count > 0` primitives starting at slot `index`). An empty slot has `index ==
/// u32::MAX` and an inverted box that no ray enters.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ChildRef {
    pub index: u32,
    pub count: u32,
}

impl ChildRef {
    pub const EMPTY: ChildRef = ChildRef {
        index: u32::MAX,
        count: 0,
    };
    #[inline]
    pub fn is_leaf(self) -> bool {
        self.count > 0
    }
    #[inline]
    pub fn is_empty(self) -> bool {
        self.index == u32::MAX && self.count == 0
    }
}

/// Eight child boxes and their references: 256 bytes, four cache lines.
/// `bounds[k][i]` holds coordinate `k` of child `i`: k = 0..3 are `min.x, min.y, min.z`,
/// k = 3..6 are `max.x, max.y, max.z`.
#[derive(Clone, Copy, Debug)]
#[repr(C, align(64))]
pub struct WideNode {
    pub bounds: [[f32; WIDTH]; 6],
    pub child: [u32; WIDTH],
    pub count: [u32; WIDTH],
}

impl WideNode {
    pub const EMPTY: WideNode = WideNode {
        bounds: [
            [f32::INFINITY; WIDTH],
            [f32::INFINITY; WIDTH],
            [f32::INFINITY; WIDTH],
            [f32::NEG_INFINITY; WIDTH],
            [f32::NEG_INFINITY; WIDTH],
            [f32::NEG_INFINITY; WIDTH],
        ],
        child: [u32::MAX; WIDTH],
        count: [0; WIDTH],
    };

    pub fn set(&mut self, i: usize, b: Aabb, r: ChildRef) {
        for k in 0..3 {
            self.bounds[k][i] = b.min[k];
            self.bounds[k + 3][i] = b.max[k];
        }
        self.child[i] = r.index;
        self.count[i] = r.count;
    }

    #[inline]
    pub fn child_ref(&self, i: usize) -> ChildRef {
        ChildRef {
            index: self.child[i],
            count: self.count[i],
        }
    }

    pub fn child_bounds(&self, i: usize) -> Aabb {
        Aabb::new(
            Vec3::new(self.bounds[0][i], self.bounds[1][i], self.bounds[2][i]),
            Vec3::new(self.bounds[3][i], self.bounds[4][i], self.bounds[5][i]),
        )
    }

    /// Slab test of the ray against the eight boxes: a bit mask of the children whose
    /// box the ray enters within `[0, t_max]`, and the entry distances.
    #[inline(always)]
    pub fn intersect(&self, ray: &NodeRay, t_max: f32) -> (u32, [f32; WIDTH]) {
        if ray.avx2 {
            self.intersect_with::<true>(ray, t_max)
        } else {
            self.intersect_with::<false>(ray, t_max)
        }
    }

    /// [`WideNode::intersect`] with the instruction set chosen by the caller: `AVX`
    /// only where the CPU has AVX2 (the traversal decides once per ray and runs a copy
    /// of itself compiled for AVX2, into which this test is inlined).
    #[inline(always)]
    pub(crate) fn intersect_with<const AVX: bool>(
        &self,
        ray: &NodeRay,
        t_max: f32,
    ) -> (u32, [f32; WIDTH]) {
        #[cfg(target_arch = "x86_64")]
        {
            if AVX {
                // SAFETY: callers pass `AVX` only where the CPU has AVX2.
                unsafe { self.intersect_avx2(ray, t_max) }
            } else {
                // SAFETY: SSE2 is part of the x86_64 baseline; all loads are of
                // aligned, fully initialised 16-byte halves of the rows.
                unsafe {
                    let (lo, a) = self.intersect_sse(ray, t_max, 0);
                    let (hi, b) = self.intersect_sse(ray, t_max, 4);
                    let mut out = [0f32; WIDTH];
                    out[..4].copy_from_slice(&a);
                    out[4..].copy_from_slice(&b);
                    (lo | hi << 4, out)
                }
            }
        }
        #[cfg(not(target_arch = "x86_64"))]
        {
            self.intersect_scalar(ray, t_max)
        }
    }

    /// All eight boxes in one pass of 256-bit instructions.
    ///
    /// # Safety
    /// The CPU must support AVX2.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    #[inline]
    pub unsafe fn intersect_avx2(&self, ray: &NodeRay, t_max: f32) -> (u32, [f32; WIDTH]) {
        use std::arch::x86_64::*;
        let b = self.bounds.as_ptr() as *const f32;
        let slab = |k: usize, axis: usize| -> __m256 {
            let v = _mm256_load_ps(b.add(WIDTH * k));
            _mm256_mul_ps(
                _mm256_sub_ps(v, _mm256_set1_ps(ray.origin[axis])),
                _mm256_set1_ps(ray.inv_dir[axis]),
            )
        };
        let nx = slab(ray.near[0], 0);
        let ny = slab(ray.near[1], 1);
        let nz = slab(ray.near[2], 2);
        let fx = slab(far_index(ray.near[0]), 0);
        let fy = slab(far_index(ray.near[1]), 1);
        let fz = slab(far_index(ray.near[2]), 2);
        // As in the SSE path: max/min return the second operand on NaN, so NaN slabs
        // are ignored.
        let t0 = _mm256_max_ps(
            nx,
            _mm256_max_ps(ny, _mm256_max_ps(nz, _mm256_setzero_ps())),
        );
        let t1 = _mm256_min_ps(
            fx,
            _mm256_min_ps(fy, _mm256_min_ps(fz, _mm256_set1_ps(t_max))),
        );
        let t1 = _mm256_mul_ps(t1, _mm256_set1_ps(ROBUST_FAR));
        let mask = _mm256_movemask_ps(_mm256_cmp_ps::<_CMP_LE_OQ>(t0, t1)) as u32;
        let mut out = [0f32; WIDTH];
        _mm256_storeu_ps(out.as_mut_ptr(), t0);
        (mask, out)
    }

    /// Four boxes (`lane0..lane0 + 4`) with SSE.
    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    unsafe fn intersect_sse(&self, ray: &NodeRay, t_max: f32, lane0: usize) -> (u32, [f32; 4]) {
        use std::arch::x86_64::*;
        let b = self.bounds.as_ptr() as *const f32;
        let slab = |k: usize, axis: usize| -> __m128 {
            let v = _mm_load_ps(b.add(WIDTH * k + lane0));
            _mm_mul_ps(
                _mm_sub_ps(v, _mm_set1_ps(ray.origin[axis])),
                _mm_set1_ps(ray.inv_dir[axis]),
            )
        };
        let nx = slab(ray.near[0], 0);
        let ny = slab(ray.near[1], 1);
        let nz = slab(ray.near[2], 2);
        let fx = slab(far_index(ray.near[0]), 0);
        let fy = slab(far_index(ray.near[1]), 1);
        let fz = slab(far_index(ray.near[2]), 2);
        // `_mm_max_ps(a, b)` returns `b` when either is NaN (0 * inf for a ray in a
        // slab's plane), so NaN slabs are ignored, which keeps the test conservative.
        let t0 = _mm_max_ps(nx, _mm_max_ps(ny, _mm_max_ps(nz, _mm_setzero_ps())));
        let t1 = _mm_min_ps(fx, _mm_min_ps(fy, _mm_min_ps(fz, _mm_set1_ps(t_max))));
        let t1 = _mm_mul_ps(t1, _mm_set1_ps(ROBUST_FAR));
        let mask = _mm_movemask_ps(_mm_cmple_ps(t0, t1)) as u32;
        let mut out = [0f32; 4];
        _mm_storeu_ps(out.as_mut_ptr(), t0);
        (mask, out)
    }

    /// The same test without SIMD intrinsics (other architectures, and the reference
    /// the SSE path is tested against).
    #[inline(always)]
    pub fn intersect_scalar(&self, ray: &NodeRay, t_max: f32) -> (u32, [f32; WIDTH]) {
        let mut mask = 0;
        let mut out = [0f32; WIDTH];
        for i in 0..WIDTH {
            let mut t0 = 0f32;
            let mut t1 = t_max;
            for axis in 0..3 {
                let n = (self.bounds[ray.near[axis]][i] - ray.origin[axis]) * ray.inv_dir[axis];
                let f = (self.bounds[far_index(ray.near[axis])][i] - ray.origin[axis])
                    * ray.inv_dir[axis];
                // NaN compares false, so NaN slabs are ignored as in the SSE path.
                if n > t0 {
                    t0 = n;
                }
                if f < t1 {
                    t1 = f;
                }
            }
            if t0 <= t1 * ROBUST_FAR {
                mask |= 1 << i;
            }
            out[i] = t0;
        }
        (mask, out)
    }
}

/// Row of the far plane for a near-plane row (`min` rows 0..3 pair with `max` rows 3..6).
#[inline(always)]
fn far_index(near: usize) -> usize {
    if near >= 3 {
        near - 3
    } else {
        near + 3
    }
}

/// A ray prepared for box tests: reciprocal direction and, per axis, which bound row
/// is the near one (min for positive directions, max for negative ones). Clearing
/// `avx2` makes [`WideNode::intersect`] take the SSE path (its tests do).
#[derive(Clone, Copy, Debug)]
pub struct NodeRay {
    pub origin: [f32; 3],
    pub inv_dir: [f32; 3],
    pub near: [usize; 3],
    /// Whether the box test may use AVX2 (the CPU has it).
    pub avx2: bool,
}

impl NodeRay {
    #[inline]
    pub fn new(origin: Vec3, dir: Vec3) -> Self {
        let inv = dir.recip();
        let near = [
            if inv.x >= 0.0 { 0 } else { 3 },
            if inv.y >= 0.0 { 1 } else { 4 },
            if inv.z >= 0.0 { 2 } else { 5 },
        ];
        Self {
            origin: origin.to_array(),
            inv_dir: inv.to_array(),
            near,
            avx2: crate::packet::has_avx2(),
        }
    }
}
