//! The parameter window a CSG node still cares about, and a conservative slab test of
//! an operand's bounds against it: an operand whose box the ray misses inside the
//! window contributes no spans there, so its shape is never asked.

use glam::Vec3;
use irradia_core::{Aabb, Ray};

/// A ray with its reciprocal direction, computed once per node visit.
#[derive(Clone, Copy, Debug)]
pub struct SlabRay {
    origin: Vec3,
    inv_dir: Vec3,
}

impl SlabRay {
    #[inline]
    pub fn new(ray: &Ray) -> Self {
        Self {
            origin: ray.origin,
            inv_dir: ray.dir.recip(),
        }
    }

    /// Whether the ray may be inside `b` for some `t` in `[lo, hi]`. Conservative: the
    /// slab parameters are widened by a few ulps (Ize, "Robust BVH Ray Traversal", JCGT
    /// 2013, shows 2 ulps suffice for the rounding of `(b - o) · (1/d)`).
    #[inline]
    pub fn overlaps(&self, b: &Aabb, lo: f32, hi: f32) -> bool {
        if b.is_empty() {
            return false;
        }
        let ta = (b.min - self.origin) * self.inv_dir;
        let tb = (b.max - self.origin) * self.inv_dir;
        // min/max_element skip a NaN lane (0 · ∞ when the origin lies on a slab plane).
        let near = ta.min(tb).max_element();
        let far = ta.max(tb).min_element();
        let near = near - near.abs() * (4.0 * f32::EPSILON);
        let far = far + far.abs() * (4.0 * f32::EPSILON);
        near.max(lo) <= far.min(hi)
    }
}
