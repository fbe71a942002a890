//! A one-level, 8-wide hierarchy for small flat scenes: the boxes of up to eight
//! triangle packets tested against a ray in one AVX2 slab test (Kay and Kajiya, "Ray
//! tracing complex scenes", SIGGRAPH 1986; the wide-node layout of Wald, Benthin,
//! Boulos, "Getting Rid of Packets", RT 2008), so that packets the ray passes by (the
//! Cornell box's two blocks, for most rays) are not tested.
//!
//! The boxes are padded by a small relative margin and the far distance is stretched
//! (Ize, "Robust BVH Ray Traversal", JCGT 2013), so rounding never culls a packet the
//! ray hits; flat boxes (a wall has zero thickness) are thereby given some.
//! Without AVX2, or for a ray with a zero direction component (where the slab test
//! would divide zero by zero), every packet is tested.

use super::triangle8::{TrianglePacket, LANES};
use glam::Vec3;
use irradia_core::Aabb;

/// Up to eight packet boxes, structure of arrays; unused lanes hold an empty box.
#[derive(Clone, Copy, Debug)]
#[repr(C, align(32))]
pub struct PacketBounds {
    min: [[f32; LANES]; 3],
    max: [[f32; LANES]; 3],
}

impl PacketBounds {
    /// The padded boxes of `boxes` (at most eight).
    pub fn new(boxes: &[Aabb]) -> Self {
        assert!(boxes.len() <= LANES);
        let mut b = PacketBounds {
            min: [[f32::INFINITY; LANES]; 3],
            max: [[f32::NEG_INFINITY; LANES]; 3],
        };
        for (lane, bx) in boxes.iter().enumerate() {
            let pad = 1e-5 * (bx.max - bx.min).max_element()
                + 1e-5 * bx.min.abs().max(bx.max.abs()).max_element()
                + 1e-30;
            for axis in 0..3 {
                b.min[axis][lane] = bx.min[axis] - pad;
                b.max[axis][lane] = bx.max[axis] + pad;
            }
        }
        b
    }

    /// Lanes (packets) whose box the ray `o + t d` enters with `t < t_max`, and the
    /// entry distances.
    ///
    /// # Safety
    /// The CPU must support AVX2 and FMA.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma")]
    #[inline]
    pub unsafe fn enter_avx2(&self, o: Vec3, d: Vec3, t_max: f32, near: &mut [f32; LANES]) -> u32 {
        use std::arch::x86_64::*;
        if d.x == 0.0 || d.y == 0.0 || d.z == 0.0 {
            near.fill(0.0);
            return (1 << LANES) - 1;
        }
        let inv = d.recip();
        let mut t0 = _mm256_setzero_ps();
        let mut t1 = _mm256_set1_ps(t_max);
        for (axis, (oa, ia)) in [(o.x, inv.x), (o.y, inv.y), (o.z, inv.z)]
            .into_iter()
            .enumerate()
        {
            let (ov, iv) = (_mm256_set1_ps(oa), _mm256_set1_ps(ia));
            let a = _mm256_mul_ps(
                _mm256_sub_ps(_mm256_load_ps(self.min[axis].as_ptr()), ov),
                iv,
            );
            let b = _mm256_mul_ps(
                _mm256_sub_ps(_mm256_load_ps(self.max[axis].as_ptr()), ov),
                iv,
            );
            t0 = _mm256_max_ps(t0, _mm256_min_ps(a, b));
            t1 = _mm256_min_ps(t1, _mm256_max_ps(a, b));
        }
        // Ize's factor 1 + 2 γ(3) on the far distance keeps the test conservative.
        let far = _mm256_mul_ps(t1, _mm256_set1_ps(1.0 + 4.0 * f32::EPSILON));
        _mm256_storeu_ps(near.as_mut_ptr(), t0);
        _mm256_movemask_ps(_mm256_cmp_ps::<_CMP_LE_OQ>(t0, far)) as u32
    }
}

/// The nearest hit among the packets whose box the ray enters (AVX2 only).
///
/// # Safety
/// The CPU must support AVX2 and FMA.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
pub unsafe fn nearest_culled_avx2(
    packets: &[TrianglePacket],
    bounds: &PacketBounds,
    o: Vec3,
    d: Vec3,
    t_max: f32,
) -> Option<(usize, super::triangle8::PacketHit)> {
    let mut near = [0f32; LANES];
    let mut mask = bounds.enter_avx2(o, d, t_max, &mut near) & ((1u32 << packets.len()) - 1);
    let mut best = None;
    let mut t_max = t_max;
    let mut lanes = [[0f32; LANES]; 4];
    while mask != 0 {
        let k = mask.trailing_zeros() as usize;
        mask &= mask - 1;
        if near[k] > t_max {
            continue;
        }
        let m = packets[k].test_avx2(o, d, t_max, &mut lanes);
        if m != 0 {
            if let Some(h) = super::triangle8::nearest_lane(m, &lanes, t_max) {
                t_max = h.t;
                best = Some((k, h));
            }
        }
    }
    best
}

/// Whether any triangle of the packets whose box the ray enters is hit (AVX2 only).
///
/// # Safety
/// The CPU must support AVX2 and FMA.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
pub unsafe fn any_culled_avx2(
    packets: &[TrianglePacket],
    bounds: &PacketBounds,
    o: Vec3,
    d: Vec3,
    t_max: f32,
) -> bool {
    let mut near = [0f32; LANES];
    let mut mask = bounds.enter_avx2(o, d, t_max, &mut near) & ((1u32 << packets.len()) - 1);
    let mut lanes = [[0f32; LANES]; 4];
    while mask != 0 {
        let k = mask.trailing_zeros() as usize;
        mask &= mask - 1;
        if packets[k].test_avx2(o, d, t_max, &mut lanes) != 0 {
            return true;
        }
    }
    false
}
