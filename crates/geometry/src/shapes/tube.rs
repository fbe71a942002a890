//! Mitsuba 3's `cylinder`, called `tube` in Irradia's scene format (Irradia's
//! `cylinder` is the lecture's solid quadric): the open side surface, without caps, of
//! radius `r` around the segment from `p0` to `p1`. Mitsuba's parameterisation: with
//! `(s, t, a)` Mitsuba's frame around the axis `a = (p1 - p0) / L` (see
//! [`mitsuba_frame`]) and a point `p0 + x s + y t + z a`, `uv = (phi / 2π, z / L)`
//! with `phi = atan2(y, x)` in `[0, 2π)`. The normal points away from the axis, or
//! towards it with `flip_normals`. Not a solid.

use crate::shape::{Facets, Hit, Shape, Span};
use crate::shapes::mitsuba_frame::{mitsuba_frame, turn_fraction};
use crate::shapes::shape_error::{finite, positive, ShapeError};
use glam::{DVec3, Vec2, Vec3};
use irradia_core::{Aabb, Ray};
use std::f64::consts::TAU;

#[derive(Clone, Debug)]
pub struct Tube {
    p0: DVec3,
    s: DVec3,
    t: DVec3,
    axis: DVec3,
    length: f64,
    radius: f64,
    flipped: bool,
}

impl Tube {
    /// The tube of `radius` from `p0` to `p1`; errors on non-finite input, a
    /// non-positive radius or `p0 == p1`.
    pub fn new(p0: Vec3, p1: Vec3, radius: f32) -> Result<Self, ShapeError> {
        finite("tube p0", &p0.as_dvec3().to_array())?;
        finite("tube p1", &p1.as_dvec3().to_array())?;
        positive("tube radius", radius as f64)?;
        let d = p1.as_dvec3() - p0.as_dvec3();
        let length = d.length();
        if length <= 0.0 || !length.is_finite() {
            return Err(ShapeError::Coincident {
                what: "tube p0 and p1",
            });
        }
        let axis = d / length;
        let (s, t) = mitsuba_frame(axis);
        Ok(Self {
            p0: p0.as_dvec3(),
            s,
            t,
            axis,
            length,
            radius: radius as f64,
            flipped: false,
        })
    }

    /// The same tube with its normals towards the axis (Mitsuba's `flip_normals`).
    pub fn with_flipped_normals(mut self, flip: bool) -> Self {
        self.flipped = flip;
        self
    }

    /// The ray in the tube's frame (unit radius is not applied: lengths are kept).
    fn local(&self, ray: &Ray) -> (DVec3, DVec3) {
        let o = ray.origin.as_dvec3() - self.p0;
        let d = ray.dir.as_dvec3();
        let f = |v: DVec3| DVec3::new(v.dot(self.s), v.dot(self.t), v.dot(self.axis));
        (f(o), f(d))
    }

    /// The nearest crossing of the side with `0 < t < t_max` and its local point.
    fn crossing(&self, ray: &Ray, t_max: f32) -> Option<(f64, DVec3)> {
        let (o, d) = self.local(ray);
        let a = d.x * d.x + d.y * d.y;
        if a == 0.0 {
            return None; // parallel to the axis
        }
        let b = o.x * d.x + o.y * d.y;
        let r = self.radius;
        // As the sphere: the discriminant on the offset of the closest approach.
        let (lx, ly) = (o.x - d.x * (b / a), o.y - d.y * (b / a));
        let disc = a * (r * r - (lx * lx + ly * ly));
        if disc < 0.0 {
            return None;
        }
        let q = -b - b.signum() * disc.sqrt();
        let (t0, t1) = if q == 0.0 {
            (0.0, 0.0)
        } else {
            (q / a, (o.x * o.x + o.y * o.y - r * r) / q)
        };
        let (t0, t1) = if t0 <= t1 { (t0, t1) } else { (t1, t0) };
        [t0, t1].into_iter().find_map(|t| {
            let p = o + d * t;
            (t > 0.0 && t < t_max as f64 && p.z >= 0.0 && p.z <= self.length).then_some((t, p))
        })
    }
}

impl Shape for Tube {
    fn kind(&self) -> &'static str {
        "tube"
    }

    fn bounds(&self) -> Aabb {
        let ext = (DVec3::ONE - self.axis * self.axis)
            .max(DVec3::ZERO)
            .map(f64::sqrt)
            * self.radius;
        let p1 = self.p0 + self.axis * self.length;
        let pad = DVec3::splat((self.p0.abs().max(p1.abs()).max_element() + self.radius) * 1e-6);
        Aabb::new(
            (self.p0.min(p1) - ext - pad).as_vec3(),
            (self.p0.max(p1) + ext + pad).as_vec3(),
        )
    }

    fn intersect(&self, ray: &Ray, t_max: f32) -> Option<Hit> {
        let (t, p) = self.crossing(ray, t_max)?;
        // Project onto the surface to remove the error of t.
        let rho = (p.x * p.x + p.y * p.y).sqrt();
        let (x, y) = (p.x / rho, p.y / rho);
        let radial = self.s * x + self.t * y;
        let point = self.p0 + radial * self.radius + self.axis * p.z;
        let n = if self.flipped { -radial } else { radial };
        let uv = Vec2::new(turn_fraction(y, x) as f32, (p.z / self.length) as f32);
        let mut h = Hit::new(t as f32, point.as_vec3(), n.as_vec3(), uv);
        h.error = ((self.p0.abs().max_element() + self.radius + self.length)
            * 8.0
            * f32::EPSILON as f64) as f32;
        Some(h)
    }

    /// With φ = 2π u: dp/du = 2π R (−sin φ s + cos φ t), dp/dv = L a.
    fn uv_derivatives(&self, _p: Vec3, uv: Vec2, _prim: u32) -> (Vec3, Vec3) {
        let (y, x) = (std::f64::consts::TAU * uv.x as f64).sin_cos();
        let dpdu = (self.t * x - self.s * y) * (std::f64::consts::TAU * self.radius);
        ((dpdu).as_vec3(), (self.axis * self.length).as_vec3())
    }

    fn occluded(&self, ray: &Ray, t_max: f32) -> bool {
        self.crossing(ray, t_max).is_some()
    }

    fn is_solid(&self) -> bool {
        false
    }

    fn spans(&self, _ray: &Ray, _out: &mut Vec<Span>) {}

    fn facets(&self, detail: u32) -> Option<Facets> {
        let n = detail.max(3) as usize;
        let mut f = Facets::default();
        let p1 = self.p0 + self.axis * self.length;
        for end in [self.p0, p1] {
            for i in 0..n {
                let a = TAU * i as f64 / n as f64;
                let radial = self.s * a.cos() + self.t * a.sin();
                f.vertices.push((end + radial * self.radius).as_vec3());
                f.normals
                    .push(if self.flipped { -radial } else { radial }.as_vec3());
            }
        }
        for i in 0..n {
            let j = (i + 1) % n;
            // Counter-clockwise seen from outside: bottom i, j, then top j, i.
            let mut face = vec![i as u32, j as u32, (n + j) as u32, (n + i) as u32];
            if self.flipped {
                face.reverse();
            }
            f.faces.push(face);
        }
        Some(f)
    }

    fn area(&self) -> Option<f32> {
        Some((TAU * self.radius * self.length) as f32)
    }

    fn sample_surface(&self, u: Vec2) -> Option<(Vec3, Vec3)> {
        let a = TAU * u.x as f64;
        let radial = self.s * a.cos() + self.t * a.sin();
        let p = self.p0 + radial * self.radius + self.axis * (u.y as f64 * self.length);
        let n = if self.flipped { -radial } else { radial };
        Some((p.as_vec3(), n.as_vec3()))
    }
}
