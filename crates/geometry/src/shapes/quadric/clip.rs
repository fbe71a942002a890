//! Clipping a quadric by half-spaces `n·p ≤ d`: along a ray the half-spaces keep one
//! convex interval, found as for a convex polyhedron (lecture: "Ray Tracing Polyhedra":
//! enter at the furthest front-facing plane, leave at the nearest back-facing one).

use glam::{DAffine3, DVec3};

/// The half-space `normal · p ≤ offset`, with a unit `normal` pointing out of it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HalfSpace {
    pub normal: DVec3,
    pub offset: f64,
}

impl HalfSpace {
    /// `normal` need not be unit length; it is normalised (with `offset` scaled alike).
    /// Returns `None` for a zero or non-finite normal.
    pub fn new(normal: DVec3, offset: f64) -> Option<Self> {
        let len = normal.length();
        (len > 0.0 && len.is_finite() && offset.is_finite()).then(|| Self {
            normal: normal / len,
            offset: offset / len,
        })
    }

    /// The same half-space after the object-to-world map `to_world`.
    pub fn transformed(&self, to_world: &DAffine3) -> Self {
        // n·q ≤ d with q = N p + s  ⇔  (Nᵀn)·p ≤ d - n·s.
        let inv = to_world.inverse();
        let n = inv.matrix3.transpose() * self.normal;
        let d = self.offset - self.normal.dot(inv.translation);
        Self::new(n, d).expect("an invertible map keeps a normal non-zero")
    }
}

/// Where a ray is inside every half-space: `[t_in, t_out]`, with the index of the
/// plane at each end (`u32::MAX` for an end at infinity).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ClipInterval {
    pub t_in: f64,
    pub plane_in: u32,
    pub t_out: f64,
    pub plane_out: u32,
}

pub const NO_PLANE: u32 = u32::MAX;

/// The interval of the line `o + t d` inside all `planes`, or `None` when it is empty.
/// Ties keep the earlier plane, so the choice is deterministic.
#[inline]
pub fn clip_interval(planes: &[HalfSpace], o: DVec3, d: DVec3) -> Option<ClipInterval> {
    let mut c = ClipInterval {
        t_in: f64::NEG_INFINITY,
        plane_in: NO_PLANE,
        t_out: f64::INFINITY,
        plane_out: NO_PLANE,
    };
    for (i, h) in planes.iter().enumerate() {
        let den = h.normal.dot(d);
        let num = h.offset - h.normal.dot(o);
        if den < 0.0 {
            let t = num / den;
            if t > c.t_in {
                c.t_in = t;
                c.plane_in = i as u32;
            }
        } else if den > 0.0 {
            let t = num / den;
            if t < c.t_out {
                c.t_out = t;
                c.plane_out = i as u32;
            }
        } else if num < 0.0 {
            // Parallel to the plane and outside it.
            return None;
        }
    }
    (c.t_in <= c.t_out).then_some(c)
}
