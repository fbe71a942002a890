//! The convex polyhedron as an intersection of half-spaces `nᵢ·p ≤ dᵢ`, hit as the
//! lecture says ("Ray Tracing Polyhedra"): a ray enters at the furthest intersection
//! with a front-facing plane (`nᵢ·dir < 0`), leaves at the nearest intersection with a
//! back-facing plane, and misses when the entry is beyond the exit (Haines, "Fast
//! ray-convex polyhedron intersection", Graphics Gems II, 1991). Computed in f64.
//!
//! Construction checks that the half-spaces bound a finite, non-flat solid, and finds
//! its vertices and faces (for bounds and facets) by intersecting planes three at a time.

// `!(x > 0.0)` is deliberate: it is also true for NaN, which must be refused too.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use crate::shape::{Boundary, Facets, Hit, Shape, Span};
use crate::shapes::plane::plane_point_error;
use crate::shapes::quadric::clip::{clip_interval, HalfSpace, NO_PLANE};
use crate::shapes::shape_error::{finite, ShapeError};
use glam::{DMat3, DVec3, Vec2, Vec3};
use irradia_core::{Aabb, Frame, Ray};

#[derive(Clone, Debug)]
pub struct Polyhedron {
    planes: Vec<HalfSpace>,
    frames: Vec<Frame>,
    vertices: Vec<Vec3>,
    /// For each plane, its face as a loop of vertex indices (empty for a redundant plane).
    faces: Vec<Vec<u32>>,
    bounds: Aabb,
}

impl Polyhedron {
    /// The intersection of the half-spaces `normal · p ≤ offset` given as
    /// `(normal, offset)` pairs (normals need not be unit length). Errors on non-finite
    /// input, a zero normal, or half-spaces that leave nothing, something flat, or
    /// something unbounded.
    pub fn new(half_spaces: &[(Vec3, f32)]) -> Result<Self, ShapeError> {
        let mut planes = Vec::with_capacity(half_spaces.len());
        for &(n, d) in half_spaces {
            finite(
                "polyhedron plane",
                &[n.x as f64, n.y as f64, n.z as f64, d as f64],
            )?;
            planes.push(
                HalfSpace::new(n.as_dvec3(), d as f64).ok_or(ShapeError::ZeroVector {
                    what: "polyhedron plane normal",
                })?,
            );
        }
        Self::from_half_spaces(planes)
    }

    /// As `new`, from f64 half-spaces.
    pub fn from_half_spaces(planes: Vec<HalfSpace>) -> Result<Self, ShapeError> {
        check_bounded(&planes)?;
        let scale = planes.iter().map(|h| h.offset.abs()).fold(1e-30, f64::max);
        let tol = 1e-9 * scale;
        let vertices = vertices(&planes, tol);
        if vertices.len() < 4 {
            return Err(ShapeError::EmptyPolyhedron);
        }
        let faces: Vec<Vec<u32>> = planes
            .iter()
            .map(|h| face_loop(h, &vertices, tol))
            .collect();
        let volume = volume(&vertices, &faces);
        let extent = vertices
            .iter()
            .fold(Aabb::EMPTY, |b, v| b.grow(v.as_vec3()))
            .extent()
            .max_element() as f64;
        if !(volume > 1e-9 * extent * extent * extent) {
            return Err(ShapeError::EmptyPolyhedron);
        }
        let bounds = Aabb::from_points(vertices.iter().map(|v| v.as_vec3()));
        let pad = bounds.extent().max_element() * 1e-6;
        Ok(Self {
            frames: planes
                .iter()
                .map(|h| Frame::from_normal(h.normal.as_vec3()))
                .collect(),
            planes,
            vertices: vertices.iter().map(|v| v.as_vec3()).collect(),
            faces,
            bounds: Aabb::new(bounds.min - Vec3::splat(pad), bounds.max + Vec3::splat(pad)),
        })
    }

    /// The regular tetrahedron (4), cube (6), octahedron (8), dodecahedron (12) or
    /// icosahedron (20) with inradius 1, centred at the origin.
    pub fn platonic(faces: u32) -> Result<Self, ShapeError> {
        let phi = (1.0 + 5f64.sqrt()) / 2.0;
        let mut normals: Vec<DVec3> = Vec::new();
        let signs = [-1.0, 1.0];
        match faces {
            4 => {
                normals = vec![
                    DVec3::new(1.0, 1.0, 1.0),
                    DVec3::new(1.0, -1.0, -1.0),
                    DVec3::new(-1.0, 1.0, -1.0),
                    DVec3::new(-1.0, -1.0, 1.0),
                ]
            }
            6 => {
                for a in [DVec3::X, DVec3::Y, DVec3::Z] {
                    normals.extend([-a, a]);
                }
            }
            8 | 20 => {
                for x in signs {
                    for y in signs {
                        for z in signs {
                            normals.push(DVec3::new(x, y, z));
                        }
                    }
                }
                if faces == 20 {
                    for a in signs {
                        for b in signs {
                            normals.push(DVec3::new(0.0, a / phi, b * phi));
                            normals.push(DVec3::new(a / phi, b * phi, 0.0));
                            normals.push(DVec3::new(a * phi, 0.0, b / phi));
                        }
                    }
                }
            }
            12 => {
                for a in signs {
                    for b in signs {
                        normals.push(DVec3::new(0.0, a, b * phi));
                        normals.push(DVec3::new(a, b * phi, 0.0));
                        normals.push(DVec3::new(a * phi, 0.0, b));
                    }
                }
            }
            _ => {
                return Err(ShapeError::OutOfRange {
                    what: "platonic solid",
                    why: "the number of faces must be 4, 6, 8, 12 or 20",
                })
            }
        }
        Self::from_half_spaces(
            normals
                .into_iter()
                .map(|n| HalfSpace::new(n, n.length()).expect("non-zero normal"))
                .collect(),
        )
    }

    pub fn planes(&self) -> &[HalfSpace] {
        &self.planes
    }

    fn surface(&self, o: DVec3, d: DVec3, t: f64, plane: u32) -> (DVec3, Vec3, Vec2) {
        let h = &self.planes[plane as usize];
        let p = o + d * t;
        let p = p - h.normal * (h.normal.dot(p) - h.offset);
        let f = &self.frames[plane as usize];
        let pf = p.as_vec3();
        (p, h.normal.as_vec3(), Vec2::new(pf.dot(f.s), pf.dot(f.t)))
    }
}

/// The half-spaces bound a finite set only if no direction `v ≠ 0` has `nᵢ·v ≤ 0` for
/// every `i` (a recession direction). If one exists, one exists along an edge of the
/// recession cone, which lies on two of its planes: `v = ±(nᵢ × nⱼ)`; and if the
/// normals span less than 3D, a vector perpendicular to all of them is one.
fn check_bounded(planes: &[HalfSpace]) -> Result<(), ShapeError> {
    let tol = 1e-9;
    let recedes = |v: DVec3| planes.iter().all(|h| h.normal.dot(v) <= tol);
    let mut rank3 = false;
    for (i, a) in planes.iter().enumerate() {
        for b in &planes[i + 1..] {
            let v = a.normal.cross(b.normal);
            if v.length() < 1e-9 {
                continue;
            }
            let v = v.normalize();
            for v in [v, -v] {
                if recedes(v) {
                    return Err(ShapeError::UnboundedPolyhedron {
                        direction: v.to_array(),
                    });
                }
            }
            if planes.iter().any(|c| c.normal.dot(v).abs() > 1e-9) {
                rank3 = true;
            }
        }
    }
    if !rank3 {
        let direction = planes
            .first()
            .map_or(DVec3::X, |h| h.normal.any_orthonormal_vector());
        return Err(ShapeError::UnboundedPolyhedron {
            direction: direction.to_array(),
        });
    }
    Ok(())
}

/// Every point where three planes meet and no plane is violated (beyond `tol`),
/// without duplicates.
fn vertices(planes: &[HalfSpace], tol: f64) -> Vec<DVec3> {
    let mut out: Vec<DVec3> = Vec::new();
    let n = planes.len();
    for i in 0..n {
        for j in i + 1..n {
            for k in j + 1..n {
                let (a, b, c) = (&planes[i], &planes[j], &planes[k]);
                let m = DMat3::from_cols(a.normal, b.normal, c.normal).transpose();
                let det = m.determinant();
                if det.abs() < 1e-12 {
                    continue;
                }
                let p = m.inverse() * DVec3::new(a.offset, b.offset, c.offset);
                if planes.iter().all(|h| h.normal.dot(p) <= h.offset + tol)
                    && !out.iter().any(|q| (*q - p).length() <= 10.0 * tol)
                {
                    out.push(p);
                }
            }
        }
    }
    out
}

/// The vertices on plane `h`, ordered counter-clockwise seen from outside.
fn face_loop(h: &HalfSpace, vertices: &[DVec3], tol: f64) -> Vec<u32> {
    let on: Vec<u32> = (0..vertices.len() as u32)
        .filter(|&i| (h.normal.dot(vertices[i as usize]) - h.offset).abs() <= 10.0 * tol)
        .collect();
    if on.len() < 3 {
        return Vec::new();
    }
    let centre = on.iter().map(|&i| vertices[i as usize]).sum::<DVec3>() / on.len() as f64;
    let s = h.normal.any_orthonormal_vector();
    let t = h.normal.cross(s);
    let angle = |i: u32| {
        let r = vertices[i as usize] - centre;
        r.dot(t).atan2(r.dot(s))
    };
    let mut on = on;
    on.sort_by(|&a, &b| angle(a).total_cmp(&angle(b)));
    on
}

/// Volume by the divergence theorem over the faces (each fanned from its first vertex).
fn volume(vertices: &[DVec3], faces: &[Vec<u32>]) -> f64 {
    let mut v = 0.0;
    for f in faces.iter().filter(|f| f.len() >= 3) {
        let a = vertices[f[0] as usize];
        for w in f[1..].windows(2) {
            let (b, c) = (vertices[w[0] as usize], vertices[w[1] as usize]);
            v += a.dot(b.cross(c)) / 6.0;
        }
    }
    v
}

impl Shape for Polyhedron {
    fn kind(&self) -> &'static str {
        "polyhedron"
    }

    fn bounds(&self) -> Aabb {
        self.bounds
    }

    fn intersect(&self, ray: &Ray, t_max: f32) -> Option<Hit> {
        let (o, d) = (ray.origin.as_dvec3(), ray.dir.as_dvec3());
        let c = clip_interval(&self.planes, o, d)?;
        if c.plane_in == NO_PLANE || c.plane_out == NO_PLANE {
            return None; // only a zero direction can do this: the solid is bounded
        }
        let (t, plane) = if c.t_in > 0.0 {
            (c.t_in, c.plane_in)
        } else {
            (c.t_out, c.plane_out)
        };
        if !(t > 0.0 && t < t_max as f64) {
            return None;
        }
        let (p, n, uv) = self.surface(o, d, t, plane);
        let mut h = Hit::new(t as f32, p.as_vec3(), n, uv);
        h.prim = plane;
        let hs = &self.planes[plane as usize];
        h.error = plane_point_error(p, hs.normal, hs.offset);
        Some(h)
    }

    fn is_solid(&self) -> bool {
        true
    }

    fn spans(&self, ray: &Ray, out: &mut Vec<Span>) {
        let (o, d) = (ray.origin.as_dvec3(), ray.dir.as_dvec3());
        let Some(c) = clip_interval(&self.planes, o, d) else {
            return;
        };
        if c.plane_in == NO_PLANE || c.plane_out == NO_PLANE {
            return;
        }
        let end = |t: f64, plane: u32| {
            let (_, n, uv) = self.surface(o, d, t, plane);
            let mut b = Boundary::new(t as f32, n, uv);
            b.prim = plane;
            b
        };
        out.push(Span {
            enter: end(c.t_in, c.plane_in),
            exit: end(c.t_out, c.plane_out),
        });
    }

    fn facets_exact(&self) -> bool {
        true
    }

    fn facets(&self, _detail: u32) -> Option<Facets> {
        Some(Facets {
            vertices: self.vertices.clone(),
            faces: self
                .faces
                .iter()
                .filter(|f| f.len() >= 3)
                .cloned()
                .collect(),
            normals: Vec::new(),
        })
    }
}
