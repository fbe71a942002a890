//! The part of space each rank's objects occupy, so that a query goes only to the
//! ranks it may concern.
//!
//! Reinhard and Jansen (1997) route a ray to the processors owning the voxels it
//! crosses; here each rank's domain is the bounding box of its block of objects (any
//! objects, as in sort-last rendering, so the boxes may overlap), exchanged once.
//! A query whose segment `0 < t < t_max` misses a rank's box is not sent there: that
//! rank's answer is known (no hit, not blocked). The box is padded and the slab test
//! widened so that it can only err towards sending (the objects' own hit tests are
//! bounded by the same boxes, unpadded); an unbounded object (a plane) makes its rank's
//! domain everything.

use irradia_core::{Aabb, Ray};
use irradia_scene::Scene;

/// Where a rank's objects may be hit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Domain {
    /// The rank owns no object.
    Nothing,
    /// Inside this (padded) box.
    Inside(Aabb),
    /// Anywhere (an unbounded object).
    Everywhere,
}

/// Bytes of a domain on the wire: a tag and six `f32`s.
pub const DOMAIN_BYTES: usize = 25;

impl Domain {
    /// The domain of `scene`'s objects `objects`.
    pub fn of(scene: &Scene, objects: std::ops::Range<usize>) -> Self {
        if objects.is_empty() {
            return Domain::Nothing;
        }
        let mut b = Aabb::EMPTY;
        for inst in &scene.accel.instances()[objects] {
            let ib = inst.bounds();
            if !ib.is_finite() {
                return Domain::Everywhere;
            }
            if !ib.is_empty() {
                b = b.union(ib);
            }
        }
        if b.is_empty() {
            return Domain::Nothing;
        }
        // Pad by a little of the box's size and of its distance from the origin.
        let scale = b.min.abs().max(b.max.abs());
        let pad = (b.max - b.min) * 1e-4 + scale * 1e-5 + glam::Vec3::splat(1e-6);
        Domain::Inside(Aabb::new(b.min - pad, b.max + pad))
    }

    /// Whether the segment `0 < t < t_max` of `ray` may hit an object of the domain.
    /// Errs only towards `true` (a NaN in the slab test counts as a hit).
    pub fn may_hit(&self, ray: &Ray, t_max: f32) -> bool {
        let b = match self {
            Domain::Nothing => return false,
            Domain::Everywhere => return true,
            Domain::Inside(b) => b,
        };
        let (mut t0, mut t1) = (0.0f32, t_max);
        for a in 0..3 {
            let (o, d) = (ray.origin[a], ray.dir[a]);
            let (lo, hi) = (b.min[a], b.max[a]);
            if d == 0.0 {
                if o < lo || o > hi {
                    return false;
                }
                continue;
            }
            let (mut ta, mut tb) = ((lo - o) / d, (hi - o) / d);
            if ta > tb {
                std::mem::swap(&mut ta, &mut tb);
            }
            if ta > t0 {
                t0 = ta;
            }
            let tb = tb * (1.0 + 8.0 * f32::EPSILON);
            if tb < t1 {
                t1 = tb;
            }
            if t0 > t1 {
                return false;
            }
        }
        true
    }

    pub fn encode(&self, out: &mut Vec<u8>) {
        let (tag, b) = match self {
            Domain::Nothing => (0u8, Aabb::EMPTY),
            Domain::Inside(b) => (1, *b),
            Domain::Everywhere => (2, Aabb::EMPTY),
        };
        out.push(tag);
        for v in [b.min.x, b.min.y, b.min.z, b.max.x, b.max.y, b.max.z] {
            out.extend_from_slice(&v.to_le_bytes());
        }
    }

    pub fn decode(bytes: &[u8]) -> Option<Self> {
        if bytes.len() != DOMAIN_BYTES {
            return None;
        }
        let f = |i: usize| f32::from_le_bytes(bytes[1 + 4 * i..5 + 4 * i].try_into().unwrap());
        match bytes[0] {
            0 => Some(Domain::Nothing),
            1 => Some(Domain::Inside(Aabb::new(
                glam::Vec3::new(f(0), f(1), f(2)),
                glam::Vec3::new(f(3), f(4), f(5)),
            ))),
            2 => Some(Domain::Everywhere),
            _ => None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    #[test]
    fn segments_that_miss_the_box_are_not_sent() {
        let d = Domain::Inside(Aabb::new(Vec3::splat(-1.0), Vec3::splat(1.0)));
        let towards = Ray::new(Vec3::new(0.0, 0.0, 5.0), Vec3::new(0.0, 0.0, -1.0));
        assert!(d.may_hit(&towards, f32::INFINITY));
        assert!(d.may_hit(&towards, 4.5));
        assert!(!d.may_hit(&towards, 3.5), "the segment ends before the box");
        let away = Ray::new(Vec3::new(0.0, 0.0, 5.0), Vec3::new(0.0, 0.0, 1.0));
        assert!(!d.may_hit(&away, f32::INFINITY));
        let beside = Ray::new(Vec3::new(2.0, 0.0, 5.0), Vec3::new(0.0, 0.0, -1.0));
        assert!(!d.may_hit(&beside, f32::INFINITY));
        let inside = Ray::new(Vec3::ZERO, Vec3::new(0.3, -0.2, 0.1));
        assert!(d.may_hit(&inside, 1e-3));
        assert!(Domain::Everywhere.may_hit(&away, 1.0));
        assert!(!Domain::Nothing.may_hit(&towards, f32::INFINITY));
        for dom in [d, Domain::Nothing, Domain::Everywhere] {
            let mut buf = Vec::new();
            dom.encode(&mut buf);
            assert_eq!(buf.len(), DOMAIN_BYTES);
            assert_eq!(Domain::decode(&buf), Some(dom));
        }
    }
}
