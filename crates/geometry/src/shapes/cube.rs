//! Mitsuba 3's `cube`: the solid `[-1, 1]³` of its own frame, placed by the object's
//! transform, with Mitsuba's texture coordinates: every face maps onto `[0, 1]²` as
//! Mitsuba's 12-triangle mesh lays it out (the uv of its 24 vertices, affine on each
//! face). With `p` the hit point, face by face:
//!
//! | face | u | v |
//! |---|---|---|
//! | -x | (y + 1) / 2 | (z + 1) / 2 |
//! | +x | (y + 1) / 2 | (1 - z) / 2 |
//! | -y | (z + 1) / 2 | (x + 1) / 2 |
//! | +y | (1 - x) / 2 | (1 - z) / 2 |
//! | -z | (1 - y) / 2 | (x + 1) / 2 |
//! | +z | (y + 1) / 2 | (x + 1) / 2 |
//!
//! The slab test is the box's ([`Cuboid`]); only the uv differ. `flip_normals` turns
//! the normals inward, and the cube is then an open surface (not usable in CSG).

use crate::shape::{Boundary, Facets, Hit, Shape, Span};
use crate::shapes::cuboid::Cuboid;
use glam::{Vec2, Vec3};
use irradia_core::{Aabb, Ray};

#[derive(Clone, Debug)]
pub struct Cube {
    cuboid: Cuboid,
    flipped: bool,
}

impl Default for Cube {
    fn default() -> Self {
        Self::new(false)
    }
}

/// Mitsuba's uv of the point `p` on the face whose outward normal is `n`.
pub fn cube_uv(p: Vec3, n: Vec3) -> Vec2 {
    let h = |a: f32| (a + 1.0) * 0.5;
    let l = |a: f32| (1.0 - a) * 0.5;
    let uv = if n.x < -0.5 {
        (h(p.y), h(p.z))
    } else if n.x > 0.5 {
        (h(p.y), l(p.z))
    } else if n.y < -0.5 {
        (h(p.z), h(p.x))
    } else if n.y > 0.5 {
        (l(p.x), l(p.z))
    } else if n.z < -0.5 {
        (l(p.y), h(p.x))
    } else {
        (h(p.y), h(p.x))
    };
    Vec2::new(uv.0, uv.1)
}

/// `(dp/du, dp/dv)` of [`cube_uv`] on the face whose outward normal is `n`.
pub fn cube_uv_derivatives(n: Vec3) -> (Vec3, Vec3) {
    let (x, y, z) = (Vec3::X * 2.0, Vec3::Y * 2.0, Vec3::Z * 2.0);
    if n.x < -0.5 {
        (y, z)
    } else if n.x > 0.5 {
        (y, -z)
    } else if n.y < -0.5 {
        (z, x)
    } else if n.y > 0.5 {
        (-x, -z)
    } else if n.z < -0.5 {
        (-y, x)
    } else {
        (y, x)
    }
}

impl Cube {
    /// The cube `[-1, 1]³`; `flip_normals` turns its normals inward.
    pub fn new(flip_normals: bool) -> Self {
        Self {
            cuboid: Cuboid::new(-Vec3::ONE, Vec3::ONE).expect("the unit cube is valid"),
            flipped: flip_normals,
        }
    }

    fn sign(&self) -> f32 {
        if self.flipped {
            -1.0
        } else {
            1.0
        }
    }
}

impl Shape for Cube {
    fn kind(&self) -> &'static str {
        "cube"
    }

    fn bounds(&self) -> Aabb {
        self.cuboid.bounds()
    }

    fn intersect(&self, ray: &Ray, t_max: f32) -> Option<Hit> {
        let mut h = self.cuboid.intersect(ray, t_max)?;
        h.uv = cube_uv(h.point, h.normal);
        h.normal *= self.sign();
        h.shading_normal = h.normal;
        Some(h)
    }

    fn uv_derivatives(&self, p: Vec3, _uv: Vec2, _prim: u32) -> (Vec3, Vec3) {
        // The face is the axis the point lies furthest along.
        let a = p.abs();
        let n = if a.x >= a.y && a.x >= a.z {
            Vec3::X * p.x.signum()
        } else if a.y >= a.z {
            Vec3::Y * p.y.signum()
        } else {
            Vec3::Z * p.z.signum()
        };
        cube_uv_derivatives(n)
    }

    fn occluded(&self, ray: &Ray, t_max: f32) -> bool {
        self.cuboid.occluded(ray, t_max)
    }

    fn is_solid(&self) -> bool {
        !self.flipped
    }

    fn spans(&self, ray: &Ray, out: &mut Vec<Span>) {
        if self.flipped {
            return;
        }
        let start = out.len();
        self.cuboid.spans(ray, out);
        let fix = |b: &mut Boundary| b.uv = cube_uv(ray.at(b.t), b.normal);
        for s in &mut out[start..] {
            fix(&mut s.enter);
            fix(&mut s.exit);
        }
    }

    // The facets are the surface itself (the path tracer's flat scene bakes them only
    // for materials that read neither uv nor the tangent frame).
    fn facets_exact(&self) -> bool {
        true
    }

    fn facets(&self, detail: u32) -> Option<Facets> {
        let mut f = self.cuboid.facets(detail)?;
        if self.flipped {
            for face in &mut f.faces {
                face.reverse();
            }
        }
        Some(f)
    }

    fn area(&self) -> Option<f32> {
        Some(24.0)
    }

    fn sample_surface(&self, u: Vec2) -> Option<(Vec3, Vec3)> {
        // Pick a face by u.x, then a point on it.
        let k = ((u.x * 6.0) as usize).min(5);
        let a = u.x * 6.0 - k as f32;
        let (axis, s) = (k / 2, if k.is_multiple_of(2) { -1.0 } else { 1.0 });
        let mut p = Vec3::ZERO;
        p[axis] = s;
        p[(axis + 1) % 3] = 2.0 * a - 1.0;
        p[(axis + 2) % 3] = 2.0 * u.y - 1.0;
        let mut n = Vec3::ZERO;
        n[axis] = s * self.sign();
        Some((p, n))
    }
}
