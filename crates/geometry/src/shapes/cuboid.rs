//! The axis-aligned box (POV-Ray's `box`), hit by the slab method (Kay and Kajiya,
//! "Ray tracing complex scenes", SIGGRAPH 1986): the lecture's polyhedron test
//! specialised to three pairs of parallel planes. The coordinate of the hit face is
//! set exactly, so a point on a face has no error across it.

use crate::shape::{Boundary, Facets, Hit, Shape, Span};
use crate::shapes::shape_error::{finite, ShapeError};
use glam::{Vec2, Vec3};
use irradia_core::{Aabb, Ray};

/// The solid box `[min, max]`. Faces are numbered (as `Hit::prim`) -x, +x, -y, +y, -z, +z.
#[derive(Clone, Debug)]
pub struct Cuboid {
    min: Vec3,
    max: Vec3,
}

/// One end of the slab interval: parameter and face number.
#[derive(Clone, Copy, Debug)]
struct FaceT {
    t: f32,
    face: u32,
}

impl Cuboid {
    /// The box with opposite corners `a` and `b` (in any order). Errors on non-finite
    /// corners or a box that is flat along some axis.
    pub fn new(a: Vec3, b: Vec3) -> Result<Self, ShapeError> {
        finite(
            "box corner",
            &[a, b].map(|v| v.as_dvec3().to_array()).concat(),
        )?;
        let (min, max) = (a.min(b), a.max(b));
        if min.cmpeq(max).any() {
            return Err(ShapeError::OutOfRange {
                what: "box",
                why: "the corners must differ on every axis (the box is flat)",
            });
        }
        Ok(Self { min, max })
    }

    pub fn min(&self) -> Vec3 {
        self.min
    }
    pub fn max(&self) -> Vec3 {
        self.max
    }

    /// The slab interval over the whole line, `None` on a miss. Faces are `u32::MAX`
    /// at an infinite end (impossible for a box: some axis always constrains).
    #[inline]
    fn slabs(&self, ray: &Ray) -> Option<(FaceT, FaceT)> {
        let mut near = FaceT {
            t: f32::NEG_INFINITY,
            face: u32::MAX,
        };
        let mut far = FaceT {
            t: f32::INFINITY,
            face: u32::MAX,
        };
        for axis in 0..3 {
            let (o, d) = (ray.origin[axis], ray.dir[axis]);
            let (lo, hi) = (self.min[axis], self.max[axis]);
            if d == 0.0 {
                if o < lo || o > hi {
                    return None;
                }
                continue;
            }
            let inv = 1.0 / d;
            let (t_lo, t_hi) = ((lo - o) * inv, (hi - o) * inv);
            let (a, b) = if d > 0.0 {
                (
                    FaceT {
                        t: t_lo,
                        face: 2 * axis as u32,
                    },
                    FaceT {
                        t: t_hi,
                        face: 2 * axis as u32 + 1,
                    },
                )
            } else {
                (
                    FaceT {
                        t: t_hi,
                        face: 2 * axis as u32 + 1,
                    },
                    FaceT {
                        t: t_lo,
                        face: 2 * axis as u32,
                    },
                )
            };
            if a.t > near.t {
                near = a;
            }
            if b.t < far.t {
                far = b;
            }
        }
        // A zero or NaN direction leaves a face unset: no hit.
        (near.t <= far.t && near.face != u32::MAX && far.face != u32::MAX).then_some((near, far))
    }

    fn surface(&self, ray: &Ray, e: FaceT) -> (Vec3, Vec3, Vec2) {
        let axis = (e.face / 2) as usize;
        let positive = e.face % 2 == 1;
        let mut p = ray.at(e.t);
        p[axis] = if positive {
            self.max[axis]
        } else {
            self.min[axis]
        };
        let mut n = Vec3::ZERO;
        n[axis] = if positive { 1.0 } else { -1.0 };
        let rel = (p - self.min) / (self.max - self.min);
        let (u, v) = match axis {
            0 => (rel.z, rel.y),
            1 => (rel.x, rel.z),
            _ => (rel.x, rel.y),
        };
        (p, n, Vec2::new(u, v))
    }

    fn boundary(&self, ray: &Ray, e: FaceT) -> Boundary {
        let (_, n, uv) = self.surface(ray, e);
        let mut b = Boundary::new(e.t, n, uv);
        b.prim = e.face;
        b
    }
}

impl Shape for Cuboid {
    fn kind(&self) -> &'static str {
        "box"
    }

    fn bounds(&self) -> Aabb {
        Aabb::new(self.min, self.max)
    }

    fn intersect(&self, ray: &Ray, t_max: f32) -> Option<Hit> {
        let (near, far) = self.slabs(ray)?;
        let e = if near.t > 0.0 { near } else { far };
        if !(e.t > 0.0 && e.t < t_max) {
            return None;
        }
        let (p, n, uv) = self.surface(ray, e);
        let mut h = Hit::new(e.t, p, n, uv);
        h.prim = e.face;
        // Across the face the point is exact; along it, o + t d carries a few roundings.
        h.error = (ray.origin.abs().max_element() + (ray.dir * e.t).abs().max_element())
            * 2.0
            * f32::EPSILON;
        Some(h)
    }

    fn occluded(&self, ray: &Ray, t_max: f32) -> bool {
        self.slabs(ray)
            .is_some_and(|(a, b)| (a.t > 0.0 && a.t < t_max) || (b.t > 0.0 && b.t < t_max))
    }

    fn is_solid(&self) -> bool {
        true
    }

    fn spans(&self, ray: &Ray, out: &mut Vec<Span>) {
        if let Some((near, far)) = self.slabs(ray) {
            out.push(Span {
                enter: self.boundary(ray, near),
                exit: self.boundary(ray, far),
            });
        }
    }

    /// [`Self::spans`]' slab parameters without the surfaces at them.
    fn spans_t(&self, ray: &Ray, out: &mut Vec<Span>) {
        if let Some((near, far)) = self.slabs(ray) {
            out.push(Span {
                enter: Boundary::new(near.t, Vec3::ZERO, Vec2::ZERO),
                exit: Boundary::new(far.t, Vec3::ZERO, Vec2::ZERO),
            });
        }
    }

    fn facets_exact(&self) -> bool {
        true
    }

    fn facets(&self, _detail: u32) -> Option<Facets> {
        let (a, b) = (self.min, self.max);
        let vertices = (0..8)
            .map(|i| {
                Vec3::new(
                    if i & 1 == 0 { a.x } else { b.x },
                    if i & 2 == 0 { a.y } else { b.y },
                    if i & 4 == 0 { a.z } else { b.z },
                )
            })
            .collect();
        // Counter-clockwise seen from outside: -x, +x, -y, +y, -z, +z.
        let faces = vec![
            vec![0, 4, 6, 2],
            vec![1, 3, 7, 5],
            vec![0, 1, 5, 4],
            vec![2, 6, 7, 3],
            vec![0, 2, 3, 1],
            vec![4, 5, 7, 6],
        ];
        Some(Facets {
            vertices,
            faces,
            normals: Vec::new(),
        })
    }
}
