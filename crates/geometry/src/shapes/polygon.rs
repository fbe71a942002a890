//! A planar polygon, convex or not (lecture: "Ray Tracing a Polygon"): intersect its
//! plane, then decide inside/outside in the plane by the even-odd rule with the
//! crossings test (Haines, "Point in Polygon Strategies", Graphics Gems IV, 1994): a
//! half-line from the point crosses the boundary an odd number of times iff the point
//! is inside. Self-intersecting outlines (a pentagram) follow the same rule, so a
//! pentagram's centre is outside.

// `!(x > 0.0)` is deliberate: it is also true for NaN, which must be refused too.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use crate::shape::{Facets, Hit, Shape, Span};
use crate::shapes::plane::{plane_crossing, plane_point_error};
use crate::shapes::shape_error::ShapeError;
use glam::{DVec2, DVec3, Vec2, Vec3};
use irradia_core::{Aabb, Ray};

/// How far (relative to the polygon's size, the diagonal of its bounding box) a vertex
/// may lie from the best-fit plane: f32 vertices of a rotated flat polygon are off by
/// about 1e-7 relative; anything beyond 1e-5 is a real bend.
pub const PLANARITY_TOLERANCE: f64 = 1e-5;

/// An open surface: not a solid, so it has no spans and cannot take part in CSG.
#[derive(Clone, Debug)]
pub struct Polygon {
    vertices: Vec<Vec3>,
    /// Unit normal by Newell's method: the vertices wind counter-clockwise around it.
    normal: DVec3,
    offset: f64,
    origin: DVec3,
    s: DVec3,
    t: DVec3,
    /// Vertices in the plane frame `(s, t)` around `origin`.
    points: Vec<DVec2>,
    /// The texture axes in the plane (u along the first edge).
    uv_u: DVec3,
    uv_v: DVec3,
    uv_min: DVec2,
    uv_size: DVec2,
    convex: bool,
    /// No two edges cross (facets exist only for simple outlines).
    simple: bool,
    bounds: Aabb,
}

impl Polygon {
    /// A polygon through `vertices` in order. Errors: fewer than 3 vertices, a NaN or
    /// infinite coordinate, zero area (collinear or coincident vertices), or a vertex
    /// off the plane by more than [`PLANARITY_TOLERANCE`] times the polygon's size.
    pub fn new(vertices: Vec<Vec3>) -> Result<Self, ShapeError> {
        if vertices.len() < 3 {
            return Err(ShapeError::TooFewVertices {
                count: vertices.len(),
            });
        }
        if !vertices.iter().all(|v| v.is_finite()) {
            return Err(ShapeError::NotFinite {
                what: "polygon vertex",
            });
        }
        let pts: Vec<DVec3> = vertices.iter().map(|v| v.as_dvec3()).collect();
        let origin = pts.iter().sum::<DVec3>() / pts.len() as f64;
        // Newell's method, around the centroid for accuracy.
        let mut newell = DVec3::ZERO;
        for (i, a) in pts.iter().enumerate() {
            let b = pts[(i + 1) % pts.len()];
            newell += (*a - origin).cross(b - origin);
        }
        let bounds = Aabb::from_points(vertices.iter().copied());
        let size = bounds.extent().length() as f64;
        if !(newell.length() > 1e-12 * size * size) || size == 0.0 {
            return Err(ShapeError::ZeroArea);
        }
        let normal = newell.normalize();
        let offset = normal.dot(origin);
        let tolerance = PLANARITY_TOLERANCE * size;
        for (i, p) in pts.iter().enumerate() {
            let distance = (normal.dot(*p) - offset).abs();
            if distance > tolerance {
                return Err(ShapeError::NotPlanar {
                    vertex: i,
                    distance,
                    tolerance,
                });
            }
        }
        let s = normal.any_orthonormal_vector();
        let t = normal.cross(s);
        let points: Vec<DVec2> = pts
            .iter()
            .map(|p| DVec2::new((*p - origin).dot(s), (*p - origin).dot(t)))
            .collect();
        // The uv axes: u along the first edge of non-zero length (so a rectangle's
        // texture lines up with its sides), v = n × u in the plane; the inside test
        // keeps its own frame (s, t).
        let uv_u = pts
            .iter()
            .zip(pts.iter().cycle().skip(1))
            .map(|(a, b)| *b - *a)
            .map(|e| e - normal * normal.dot(e))
            .find(|e| e.length() > 1e-9 * size)
            .map(|e| e.normalize())
            .unwrap_or(s);
        let uv_v = normal.cross(uv_u);
        let in_uv = |p: &DVec3| DVec2::new((*p - origin).dot(uv_u), (*p - origin).dot(uv_v));
        let uv_min = pts
            .iter()
            .map(in_uv)
            .fold(DVec2::splat(f64::INFINITY), |m, p| m.min(p));
        let uv_max = pts
            .iter()
            .map(in_uv)
            .fold(DVec2::splat(f64::NEG_INFINITY), |m, p| m.max(p));
        let convex = is_convex(&points);
        let simple = convex || is_simple(&points);
        let pad = bounds.extent().max_element() * 1e-6 + 1e-30;
        Ok(Self {
            vertices,
            normal,
            offset,
            origin,
            s,
            t,
            points,
            uv_u,
            uv_v,
            uv_min,
            uv_size: (uv_max - uv_min).max(DVec2::splat(1e-300)),
            convex,
            simple,
            bounds: Aabb::new(bounds.min - Vec3::splat(pad), bounds.max + Vec3::splat(pad)),
        })
    }

    pub fn vertices(&self) -> &[Vec3] {
        &self.vertices
    }
    /// The unit normal; the vertices wind counter-clockwise around it.
    pub fn normal(&self) -> Vec3 {
        self.normal.as_vec3()
    }
    pub fn is_convex(&self) -> bool {
        self.convex
    }

    /// Whether the point of the plane with frame coordinates `q` is inside (even-odd).
    pub fn contains_2d(&self, q: DVec2) -> bool {
        let mut inside = false;
        let n = self.points.len();
        let mut j = n - 1;
        for i in 0..n {
            let (a, b) = (self.points[i], self.points[j]);
            if (a.y > q.y) != (b.y > q.y) && q.x < a.x + (q.y - a.y) * (b.x - a.x) / (b.y - a.y) {
                inside = !inside;
            }
            j = i;
        }
        inside
    }

    /// The point's coordinates in the plane frame.
    pub fn to_plane(&self, p: DVec3) -> DVec2 {
        DVec2::new((p - self.origin).dot(self.s), (p - self.origin).dot(self.t))
    }

    fn crossing(&self, ray: &Ray, t_max: f32) -> Option<(f64, DVec3, DVec2)> {
        let (t, p) = plane_crossing(
            self.normal,
            self.offset,
            ray.origin.as_dvec3(),
            ray.dir.as_dvec3(),
        )?;
        if !(t > 0.0 && t < t_max as f64) {
            return None;
        }
        let q = self.to_plane(p);
        self.contains_2d(q).then_some((t, p, q))
    }

    /// Triangles (or the polygon itself when convex) by ear clipping (Eberly,
    /// "Triangulation by Ear Clipping", 2002); `None` for a self-intersecting outline.
    fn triangulate(&self) -> Option<Vec<Vec<u32>>> {
        let n = self.points.len();
        if self.convex {
            return Some(vec![(0..n as u32).collect()]);
        }
        if !self.simple {
            return None;
        }
        let p = &self.points;
        let cross = |a: DVec2, b: DVec2, c: DVec2| (b - a).perp_dot(c - a);
        let mut idx: Vec<usize> = (0..n).collect();
        let mut out = Vec::new();
        while idx.len() > 3 {
            let m = idx.len();
            let ear = (0..m).find(|&k| {
                let (a, b, c) = (p[idx[(k + m - 1) % m]], p[idx[k]], p[idx[(k + 1) % m]]);
                cross(a, b, c) > 0.0
                    && idx.iter().all(|&v| {
                        let q = p[v];
                        q == a
                            || q == b
                            || q == c
                            || !(cross(a, b, q) >= 0.0
                                && cross(b, c, q) >= 0.0
                                && cross(c, a, q) >= 0.0)
                    })
            })?;
            let m = idx.len();
            out.push(vec![
                idx[(ear + m - 1) % m] as u32,
                idx[ear] as u32,
                idx[(ear + 1) % m] as u32,
            ]);
            idx.remove(ear);
        }
        out.push(idx.iter().map(|&i| i as u32).collect());
        Some(out)
    }
}

/// Simple: no two non-adjacent edges meet (O(n²), done once at construction).
fn is_simple(p: &[DVec2]) -> bool {
    let n = p.len();
    let orient = |a: DVec2, b: DVec2, c: DVec2| (b - a).perp_dot(c - a);
    let meet = |a: DVec2, b: DVec2, c: DVec2, d: DVec2| {
        let (o1, o2) = (orient(a, b, c), orient(a, b, d));
        let (o3, o4) = (orient(c, d, a), orient(c, d, b));
        o1 * o2 <= 0.0
            && o3 * o4 <= 0.0
            && !(o1 == 0.0 && o2 == 0.0 && o3 == 0.0 && o4 == 0.0 && {
                // Collinear: overlap if their projections overlap.
                let e = b - a;
                let (tc, td) = ((c - a).dot(e), (d - a).dot(e));
                tc.max(td) < 0.0 || tc.min(td) > e.dot(e)
            })
    };
    for i in 0..n {
        for j in i + 1..n {
            if j == i + 1 || (i == 0 && j == n - 1) {
                continue; // adjacent edges share a vertex
            }
            if meet(p[i], p[(i + 1) % n], p[j], p[(j + 1) % n]) {
                return false;
            }
        }
    }
    true
}

/// Convex: every turn goes the same way and the outline turns around exactly once.
fn is_convex(p: &[DVec2]) -> bool {
    let n = p.len();
    let mut sign = 0.0f64;
    let mut turning = 0.0;
    for i in 0..n {
        let (a, b, c) = (p[i], p[(i + 1) % n], p[(i + 2) % n]);
        let (e0, e1) = (b - a, c - b);
        let cr = e0.perp_dot(e1);
        if cr != 0.0 {
            if sign != 0.0 && cr.signum() != sign {
                return false;
            }
            sign = cr.signum();
        }
        turning += cr.atan2(e0.dot(e1));
    }
    (turning.abs() - std::f64::consts::TAU).abs() < 1e-6
}

impl Shape for Polygon {
    fn kind(&self) -> &'static str {
        "polygon"
    }

    fn bounds(&self) -> Aabb {
        self.bounds
    }

    fn intersect(&self, ray: &Ray, t_max: f32) -> Option<Hit> {
        let (t, p, _) = self.crossing(ray, t_max)?;
        let d = p - self.origin;
        let uv = (DVec2::new(d.dot(self.uv_u), d.dot(self.uv_v)) - self.uv_min) / self.uv_size;
        let mut h = Hit::new(
            t as f32,
            p.as_vec3(),
            self.normal.as_vec3(),
            Vec2::new(uv.x as f32, uv.y as f32),
        );
        h.error = plane_point_error(p, self.normal, self.offset);
        Some(h)
    }

    fn uv_derivatives(&self, _p: Vec3, _uv: Vec2, _prim: u32) -> (Vec3, Vec3) {
        (
            (self.uv_u * self.uv_size.x).as_vec3(),
            (self.uv_v * self.uv_size.y).as_vec3(),
        )
    }

    fn occluded(&self, ray: &Ray, t_max: f32) -> bool {
        self.crossing(ray, t_max).is_some()
    }

    fn is_solid(&self) -> bool {
        false
    }

    fn spans(&self, _ray: &Ray, _out: &mut Vec<Span>) {}

    fn facets_exact(&self) -> bool {
        true
    }

    fn facets(&self, _detail: u32) -> Option<Facets> {
        Some(Facets {
            vertices: self.vertices.clone(),
            faces: self.triangulate()?,
            normals: Vec::new(),
        })
    }
}
