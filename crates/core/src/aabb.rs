//! Axis-aligned bounding boxes: the bounds every shape reports and the BVH is built on.

use crate::ray::Ray;
use glam::{Affine3A, Vec3};

/// An axis-aligned box `[min, max]`. The empty box has `min = +inf, max = -inf`, so
/// that growing it by any point or box gives that point or box.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    pub min: Vec3,
    pub max: Vec3,
}

impl Default for Aabb {
    fn default() -> Self {
        Self::EMPTY
    }
}

impl Aabb {
    pub const EMPTY: Aabb = Aabb {
        min: Vec3::splat(f32::INFINITY),
        max: Vec3::splat(f32::NEG_INFINITY),
    };
    pub const INFINITE: Aabb = Aabb {
        min: Vec3::splat(f32::NEG_INFINITY),
        max: Vec3::splat(f32::INFINITY),
    };

    #[inline]
    pub fn new(min: Vec3, max: Vec3) -> Self {
        Self { min, max }
    }

    pub fn from_points(points: impl IntoIterator<Item = Vec3>) -> Self {
        points.into_iter().fold(Self::EMPTY, |b, p| b.grow(p))
    }

    #[inline]
    pub fn grow(self, p: Vec3) -> Self {
        Self {
            min: self.min.min(p),
            max: self.max.max(p),
        }
    }

    #[inline]
    pub fn union(self, o: Aabb) -> Self {
        Self {
            min: self.min.min(o.min),
            max: self.max.max(o.max),
        }
    }

    #[inline]
    pub fn intersection(self, o: Aabb) -> Self {
        Self {
            min: self.min.max(o.min),
            max: self.max.min(o.max),
        }
    }

    #[inline]
    pub fn is_empty(&self) -> bool {
        self.min.x > self.max.x || self.min.y > self.max.y || self.min.z > self.max.z
    }

    /// True when every coordinate is finite (an unbounded shape such as a plane is not).
    #[inline]
    pub fn is_finite(&self) -> bool {
        self.min.is_finite() && self.max.is_finite()
    }

    #[inline]
    pub fn extent(&self) -> Vec3 {
        self.max - self.min
    }

    #[inline]
    pub fn center(&self) -> Vec3 {
        0.5 * (self.min + self.max)
    }

    /// Surface area, the cost measure of the surface area heuristic.
    #[inline]
    pub fn surface_area(&self) -> f32 {
        if self.is_empty() {
            return 0.0;
        }
        let e = self.extent();
        2.0 * (e.x * e.y + e.y * e.z + e.z * e.x)
    }

    #[inline]
    pub fn contains(&self, p: Vec3) -> bool {
        p.cmpge(self.min).all() && p.cmple(self.max).all()
    }

    /// Index of the longest axis.
    pub fn largest_axis(&self) -> usize {
        let e = self.extent();
        if e.x >= e.y && e.x >= e.z {
            0
        } else if e.y >= e.z {
            1
        } else {
            2
        }
    }

    /// The box around this box after an affine map (Arvo's method, exact for boxes).
    pub fn transformed(&self, m: &Affine3A) -> Aabb {
        if !self.is_finite() {
            if self.is_empty() {
                return *self;
            }
            return Aabb::INFINITE;
        }
        let t: Vec3 = m.translation.into();
        let (mut lo, mut hi) = (t, t);
        let cols = [
            Vec3::from(m.matrix3.x_axis),
            Vec3::from(m.matrix3.y_axis),
            Vec3::from(m.matrix3.z_axis),
        ];
        for (j, col) in cols.iter().enumerate() {
            let a = *col * self.min[j];
            let b = *col * self.max[j];
            lo += a.min(b);
            hi += a.max(b);
        }
        Aabb::new(lo, hi)
    }

    /// Slab test: the parameter interval `[t0, t1]` in which the ray is inside the box,
    /// clipped to `[0, t_max]`, or `None` when it misses.
    #[inline]
    pub fn hit(&self, ray: &Ray, t_max: f32) -> Option<(f32, f32)> {
        self.hit_inv(ray.origin, ray.dir.recip(), t_max)
    }

    /// [`Aabb::hit`] for a ray given by its origin and the reciprocal of its direction
    /// (computed once per ray by callers that test many boxes).
    ///
    /// Written as pbrt-v4's `Bounds3::IntersectP` (Pharr, Jakob, Humphreys, *Physically
    /// Based Rendering*, 4th ed., §6.1.2): per axis a compare-and-select, which compiles
    /// to single min/max instructions (`f32::min` needs several to honour NaN). A
    /// `0 * inf` NaN (a ray lying in a slab's plane) fails every comparison and so
    /// leaves the interval unchanged: such a ray counts as inside that slab. The far end
    /// is widened by 4 ulp so that rounding in the products never loses a grazing hit.
    #[inline]
    pub fn hit_inv(&self, origin: Vec3, inv: Vec3, t_max: f32) -> Option<(f32, f32)> {
        let t_a = (self.min - origin) * inv;
        let t_b = (self.max - origin) * inv;
        let mut t0 = 0.0f32;
        let mut t1 = t_max;
        for (a, b) in [(t_a.x, t_b.x), (t_a.y, t_b.y), (t_a.z, t_b.z)] {
            let (near, far) = if a > b { (b, a) } else { (a, b) };
            t0 = if near > t0 { near } else { t0 };
            t1 = if far < t1 { far } else { t1 };
        }
        let t1 = t1 * (1.0 + 4.0 * f32::EPSILON);
        (t0 <= t1).then_some((t0, t1))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn transformed_box_contains_transformed_corners() {
        let b = Aabb::new(Vec3::new(-1.0, 0.0, 2.0), Vec3::new(1.0, 3.0, 4.0));
        let m = Affine3A::from_scale_rotation_translation(
            Vec3::new(2.0, 0.5, 1.0),
            glam::Quat::from_rotation_y(0.7),
            Vec3::new(5.0, -1.0, 0.0),
        );
        let tb = b.transformed(&m);
        for i in 0..8 {
            let c = Vec3::new(
                if i & 1 == 0 { b.min.x } else { b.max.x },
                if i & 2 == 0 { b.min.y } else { b.max.y },
                if i & 4 == 0 { b.min.z } else { b.max.z },
            );
            let p = m.transform_point3(c);
            assert!(tb.grow(p) == tb || (tb.grow(p).extent() - tb.extent()).length() < 1e-5);
        }
    }

    #[test]
    fn a_ray_in_a_face_plane_counts_as_inside_that_slab() {
        // x - min.x = 0 and 1 / dir.x = inf: the 0 * inf NaN must not reject the box.
        let b = Aabb::new(Vec3::splat(-1.0), Vec3::splat(1.0));
        for x in [-1.0, 1.0] {
            let r = Ray::new(Vec3::new(x, 0.0, -5.0), Vec3::Z);
            let (t0, t1) = b.hit(&r, f32::INFINITY).expect("a grazing ray hits");
            assert!((t0 - 4.0).abs() < 1e-5 && (t1 - 6.0).abs() < 1e-4);
        }
        let r = Ray::new(Vec3::new(1.5, 0.0, -5.0), Vec3::Z);
        assert!(b.hit(&r, f32::INFINITY).is_none());
    }

    #[test]
    fn slab_hit_and_miss() {
        let b = Aabb::new(Vec3::splat(-1.0), Vec3::splat(1.0));
        let r = Ray::new(Vec3::new(0.0, 0.0, -5.0), Vec3::Z);
        let (t0, t1) = b.hit(&r, f32::INFINITY).unwrap();
        assert!((t0 - 4.0).abs() < 1e-5 && (t1 - 6.0).abs() < 1e-4);
        let r = Ray::new(Vec3::new(2.0, 0.0, -5.0), Vec3::Z);
        assert!(b.hit(&r, f32::INFINITY).is_none());
        assert!(b
            .hit(&Ray::new(Vec3::new(0.0, 0.0, -5.0), Vec3::Z), 3.0)
            .is_none());
    }
}
