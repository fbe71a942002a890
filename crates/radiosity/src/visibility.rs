//! Occlusion and nearest-surface queries for form factors, through the one ray-query
//! interface (`irradia_geometry::RayQuery`, answered by the scene acceleration
//! structure `irradia_geometry::Accel`, a BVH over instances): each patch (for
//! visibility) or element (for the hemisphere's nearest hits) is an instance of the
//! small planar-polygon shape below. Patches are opaque, so every query is about
//! `ObjectSet::All`.
//!
//! Rays between two surface points start and end a small distance off the surfaces
//! (along each normal, 1e-6 of the scene size, which is well above the f32 rounding of
//! the coordinates) so that neither end point's own surface blocks the ray.

use crate::geom::Poly;
use crate::mesh::Mesh;
use glam::{DVec3, Vec2, Vec3};
use irradia_core::{Aabb, Ray};
use irradia_geometry::{Accel, Hit, Instance, ObjectSet, RayQuery, Shape, Span};
use std::sync::Arc;

/// A planar triangle or convex quadrilateral as a `Shape` (f32, two-sided).
#[derive(Debug, Clone)]
pub struct PolygonShape {
    v: [Vec3; 4],
    n: u8,
    normal: Vec3,
}

impl PolygonShape {
    pub fn new(p: &Poly) -> Self {
        let c = |v: DVec3| v.as_vec3();
        Self {
            v: [c(p.v[0]), c(p.v[1]), c(p.v[2]), c(p.v[3])],
            n: p.n,
            normal: p.normal().as_vec3(),
        }
    }
    fn tri_hit(&self, a: usize, b: usize, c: usize, ray: &Ray, t_max: f32) -> Option<f32> {
        let (v0, v1, v2) = (self.v[a], self.v[b], self.v[c]);
        let e1 = v1 - v0;
        let e2 = v2 - v0;
        let pv = ray.dir.cross(e2);
        let det = e1.dot(pv);
        if det == 0.0 || !det.is_finite() {
            return None;
        }
        let inv = 1.0 / det;
        let tv = ray.origin - v0;
        let u = tv.dot(pv) * inv;
        if !(0.0..=1.0).contains(&u) {
            return None;
        }
        let qv = tv.cross(e1);
        let v = ray.dir.dot(qv) * inv;
        if v < 0.0 || u + v > 1.0 {
            return None;
        }
        let t = e2.dot(qv) * inv;
        (t > 0.0 && t < t_max).then_some(t)
    }
}

impl Shape for PolygonShape {
    fn kind(&self) -> &'static str {
        "radiosity polygon"
    }
    fn bounds(&self) -> Aabb {
        Aabb::from_points(self.v[..self.n as usize].iter().copied())
    }
    fn intersect(&self, ray: &Ray, t_max: f32) -> Option<Hit> {
        let t = self.tri_hit(0, 1, 2, ray, t_max).or_else(|| {
            if self.n == 4 {
                self.tri_hit(0, 2, 3, ray, t_max)
            } else {
                None
            }
        })?;
        Some(Hit::new(t, ray.at(t), self.normal, Vec2::ZERO))
    }
    fn occluded(&self, ray: &Ray, t_max: f32) -> bool {
        self.tri_hit(0, 1, 2, ray, t_max).is_some()
            || (self.n == 4 && self.tri_hit(0, 2, 3, ray, t_max).is_some())
    }
    fn is_solid(&self) -> bool {
        false
    }
    fn spans(&self, _ray: &Ray, _out: &mut Vec<Span>) {}
}

/// Visibility between surface points, over the patches of a mesh.
pub struct Visibility {
    accel: Accel,
    offset: f64,
}

impl Visibility {
    pub fn new(mesh: &Mesh) -> Self {
        let instances = mesh
            .patches
            .iter()
            .map(|p| Instance::untransformed(Arc::new(PolygonShape::new(&p.poly))))
            .collect();
        Self {
            accel: Accel::build(instances),
            offset: 1e-6 * mesh.scale().max(1e-300),
        }
    }

    /// How far [`Visibility::visible`] moves each end off its surface.
    pub fn offset(&self) -> f64 {
        self.offset
    }

    /// Whether the segment from `p` (on a surface with normal `np`) to `q` (normal `nq`)
    /// is free. Each end is moved off its surface towards the other end's side.
    pub fn visible(&self, p: DVec3, np: DVec3, q: DVec3, nq: DVec3) -> bool {
        let d = q - p;
        let sp = if np.dot(d) >= 0.0 { 1.0 } else { -1.0 };
        let sq = if nq.dot(-d) >= 0.0 { 1.0 } else { -1.0 };
        let a = p + np * (sp * self.offset);
        let b = q + nq * (sq * self.offset);
        let ray = Ray::new(a.as_vec3(), (b - a).as_vec3());
        !self.accel.any_hit(ObjectSet::All, &ray, 1.0)
    }
}

/// Nearest element along a ray (for the hemisphere method).
pub struct ElementTracer {
    accel: Accel,
    offset: f64,
}

impl ElementTracer {
    pub fn new(mesh: &Mesh) -> Self {
        let instances = mesh
            .elements
            .iter()
            .map(|e| Instance::untransformed(Arc::new(PolygonShape::new(&e.poly))))
            .collect();
        Self {
            accel: Accel::build(instances),
            offset: 1e-6 * mesh.scale().max(1e-300),
        }
    }

    /// The element hit first by the ray leaving `p` (normal `n`) in direction `dir`.
    pub fn nearest(&self, p: DVec3, n: DVec3, dir: DVec3) -> Option<usize> {
        self.nearest_hit(p, n, dir).map(|h| h.0)
    }

    /// The element hit first and the hit point.
    pub fn nearest_hit(&self, p: DVec3, n: DVec3, dir: DVec3) -> Option<(usize, DVec3)> {
        let o = p + n * self.offset;
        let d = dir.normalize();
        let ray = Ray::new(o.as_vec3(), d.as_vec3());
        self.accel
            .closest_hit(ObjectSet::All, &ray, f32::INFINITY)
            .map(|h| (h.instance as usize, o + d * h.hit.t as f64))
    }
}
