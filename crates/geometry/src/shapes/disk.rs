//! A flat disk (POV-Ray's `disc`, Mitsuba's `disk`), optionally with a concentric
//! hole: intersect the plane, then compare the squared distance from the centre with
//! the radii.
//!
//! Texture coordinates are Mitsuba 3's: `uv = (r / radius, phi / 2π)`, `phi` in
//! `[0, 2π)` measured from `s` towards `t`, `(s, t)` Mitsuba's frame around the normal
//! ([`mitsuba_frame`]; `+x`, `+y` for a disk facing `+z`, as Mitsuba's unit disk). A hole
//! leaves `u` as it is (`u` starts at `hole / radius`). Mitsuba's `flip_normals` reverses
//! the normal and keeps uv.

// `!(x > 0.0)` is deliberate: it is also true for NaN, which must be refused too.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use crate::shape::{Facets, Hit, Shape, Span};
use crate::shapes::mitsuba_frame::{mitsuba_frame, turn_fraction};
use crate::shapes::plane::{plane_crossing, plane_point_error};
use crate::shapes::shape_error::{finite, positive, ShapeError};
use glam::{DVec3, Vec2, Vec3};
use irradia_core::{Aabb, Ray};
use std::f64::consts::TAU;

/// An open surface facing `normal` (not a solid).
#[derive(Clone, Debug)]
pub struct Disk {
    center: DVec3,
    normal: DVec3,
    s: DVec3,
    t: DVec3,
    radius: f64,
    hole: f64,
}

impl Disk {
    /// The disk of `radius` around `center` facing `normal` (any non-zero length).
    pub fn new(center: Vec3, normal: Vec3, radius: f32) -> Result<Self, ShapeError> {
        finite("disk center", &center.as_dvec3().to_array())?;
        finite("disk normal", &normal.as_dvec3().to_array())?;
        positive("disk radius", radius as f64)?;
        let n = normal.as_dvec3();
        if !(n.length() > 0.0) {
            return Err(ShapeError::ZeroVector {
                what: "disk normal",
            });
        }
        let normal = n.normalize();
        let (s, t) = mitsuba_frame(normal);
        Ok(Self {
            center: center.as_dvec3(),
            normal,
            s,
            t,
            radius: radius as f64,
            hole: 0.0,
        })
    }

    /// The same disk with a concentric hole of radius `hole` (`0 ≤ hole < radius`): an
    /// annulus.
    pub fn with_hole(mut self, hole: f32) -> Result<Self, ShapeError> {
        finite("disk hole radius", &[hole as f64])?;
        if !(hole >= 0.0 && (hole as f64) < self.radius) {
            return Err(ShapeError::OutOfRange {
                what: "disk hole radius",
                why: "must be at least 0 and below the radius",
            });
        }
        self.hole = hole as f64;
        Ok(self)
    }

    /// The same disk facing the other way (Mitsuba's `flip_normals`); uv is unchanged.
    pub fn with_flipped_normals(mut self, flip: bool) -> Self {
        if flip {
            self.normal = -self.normal;
        }
        self
    }

    fn crossing(&self, ray: &Ray, t_max: f32) -> Option<(f64, DVec3)> {
        let offset = self.normal.dot(self.center);
        let (t, p) = plane_crossing(
            self.normal,
            offset,
            ray.origin.as_dvec3(),
            ray.dir.as_dvec3(),
        )?;
        let r2 = (p - self.center).length_squared();
        (t > 0.0
            && t < t_max as f64
            && r2 <= self.radius * self.radius
            && r2 >= self.hole * self.hole)
            .then_some((t, p))
    }
}

impl Shape for Disk {
    fn kind(&self) -> &'static str {
        "disk"
    }

    fn bounds(&self) -> Aabb {
        let ext = (DVec3::ONE - self.normal * self.normal)
            .max(DVec3::ZERO)
            .map(f64::sqrt)
            * self.radius;
        let pad = ext.max_element() * 1e-6 + 1e-30;
        Aabb::new(
            (self.center - ext - DVec3::splat(pad)).as_vec3(),
            (self.center + ext + DVec3::splat(pad)).as_vec3(),
        )
    }

    fn intersect(&self, ray: &Ray, t_max: f32) -> Option<Hit> {
        let (t, p) = self.crossing(ray, t_max)?;
        let r = p - self.center;
        let u = (r.length() / self.radius).min(1.0);
        let v = turn_fraction(r.dot(self.t), r.dot(self.s));
        let mut h = Hit::new(
            t as f32,
            p.as_vec3(),
            self.normal.as_vec3(),
            Vec2::new(u as f32, v as f32),
        );
        h.error = plane_point_error(p, self.normal, self.normal.dot(self.center));
        Some(h)
    }

    /// `p = c + u R (cos φ s + sin φ t)` with φ = 2π v.
    fn uv_derivatives(&self, _p: Vec3, uv: Vec2, _prim: u32) -> (Vec3, Vec3) {
        let (sp, cp) = (std::f64::consts::TAU * uv.y as f64).sin_cos();
        let dpdu = (self.s * cp + self.t * sp) * self.radius;
        let dpdv =
            (self.t * cp - self.s * sp) * (std::f64::consts::TAU * uv.x as f64 * self.radius);
        (dpdu.as_vec3(), dpdv.as_vec3())
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
        let point = |r: f64, i: usize| {
            let a = TAU * i as f64 / n as f64;
            (self.center + (self.s * a.cos() + self.t * a.sin()) * r).as_vec3()
        };
        let mut f = Facets::default();
        f.vertices.extend((0..n).map(|i| point(self.radius, i)));
        if self.hole == 0.0 {
            f.faces.push((0..n as u32).collect());
        } else {
            f.vertices.extend((0..n).map(|i| point(self.hole, i)));
            for i in 0..n {
                let j = (i + 1) % n;
                f.faces
                    .push(vec![i as u32, j as u32, (n + j) as u32, (n + i) as u32]);
            }
        }
        // (s, t) turn counter-clockwise about the original normal: a flipped disk's
        // faces are wound the other way.
        if self.s.cross(self.t).dot(self.normal) < 0.0 {
            for face in &mut f.faces {
                face.reverse();
            }
        }
        Some(f)
    }
}
