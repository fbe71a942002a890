//! Mitsuba 3's `projector` emitter: the reverse of a perspective camera. An image
//! (`irradiance`) on a virtual plane at distance 1 in front of a pinhole is projected
//! into the scene; Mitsuba scales the radiant intensity by the inverse of the camera's
//! importance so that the image projected onto a plane facing the projector at distance
//! `z` gives the irradiance `π · scale · E(uv) / z²` everywhere.
//!
//! Intensity towards a direction at angle θ from the axis that meets the virtual plane
//! at `uv`: `I = π · scale · E(uv) / cos³θ` (Mitsuba's `sample_direction` returns
//! `π · scale · E / (z_local² cos θ)` for a point at local depth `z_local`).

use crate::camera::FovAxis;
use glam::{Vec2, Vec3};
use irradia_core::{Image, Rgb};
use std::f32::consts::PI;
use std::sync::Arc;

#[derive(Clone, Debug, PartialEq)]
pub struct Projector {
    pub position: Vec3,
    /// Unit basis: image right, image up, and the axis the projector looks along.
    pub right: Vec3,
    pub up: Vec3,
    pub forward: Vec3,
    /// The projected image (its top row appears at the top, as a camera sees it).
    pub irradiance: Arc<Image>,
    /// Factor on the image (Mitsuba's `scale`).
    pub scale: f32,
    /// Half extents of the virtual image plane at distance 1 (`tan` of the half angles).
    pub half: Vec2,
}

/// What a projector sends to one point.
#[derive(Clone, Copy, Debug)]
pub struct ProjectorSample {
    /// Unit direction from the point towards the projector.
    pub wi: Vec3,
    pub dist: f32,
    /// `I / dist²`: the irradiance on a surface facing the projector, before the cosine.
    pub li: Rgb,
}

impl Projector {
    /// A projector at `position` looking at `look_at`, with the field of view `fov`
    /// across `axis` of the image (the one rule of [`FovAxis::half_extents`]).
    pub fn new(
        position: Vec3,
        look_at: Vec3,
        up: Vec3,
        fov_degrees: f32,
        axis: FovAxis,
        irradiance: Arc<Image>,
        scale: f32,
    ) -> Self {
        let forward = (look_at - position).normalize();
        let right = forward.cross(up).normalize();
        let up = right.cross(forward);
        let half = axis.half_extents(fov_degrees, irradiance.width(), irradiance.height());
        Self {
            position,
            right,
            up,
            forward,
            irradiance,
            scale,
            half,
        }
    }

    /// The image coordinates (u right, v down, both in [0, 1]) where the ray from the
    /// projector in local direction `(x, y, z)` (z along the axis) crosses the plane.
    #[inline]
    fn uv(&self, x: f32, y: f32, z: f32) -> Option<Vec2> {
        if z <= 0.0 {
            return None;
        }
        let u = 0.5 + 0.5 * x / (z * self.half.x);
        let v = 0.5 - 0.5 * y / (z * self.half.y);
        ((0.0..=1.0).contains(&u) && (0.0..=1.0).contains(&v)).then_some(Vec2::new(u, v))
    }

    /// The image's value at `uv`, as Mitsuba's `bitmap` texture reads it (the default
    /// the projector's `irradiance` gets): bilinear between the four texels around
    /// `uv · size − ½`, indices wrapping around (`wrap_mode` "repeat"), so the border
    /// texels blend with the opposite edge.
    #[inline]
    pub fn image_at(&self, uv: Vec2) -> Rgb {
        let (w, h) = (self.irradiance.width(), self.irradiance.height());
        let q = Vec2::new(uv.x * w as f32 - 0.5, uv.y * h as f32 - 0.5);
        let (x0, y0) = (q.x.floor(), q.y.floor());
        let (fx, fy) = (q.x - x0, q.y - y0);
        let (x0, y0) = (x0 as i64, y0 as i64);
        let at = |x: i64, y: i64| {
            self.irradiance.get(
                x.rem_euclid(i64::from(w)) as u32,
                y.rem_euclid(i64::from(h)) as u32,
            )
        };
        at(x0, y0) * ((1.0 - fx) * (1.0 - fy))
            + at(x0 + 1, y0) * (fx * (1.0 - fy))
            + at(x0, y0 + 1) * ((1.0 - fx) * fy)
            + at(x0 + 1, y0 + 1) * (fx * fy)
    }

    /// What the projector sends to world point `p`; `None` outside its frustum.
    #[inline]
    pub fn illuminate(&self, p: Vec3) -> Option<ProjectorSample> {
        let d = p - self.position;
        let (x, y, z) = (d.dot(self.right), d.dot(self.up), d.dot(self.forward));
        let uv = self.uv(x, y, z)?;
        let dist = d.length();
        let cos = z / dist;
        let e = self.image_at(uv);
        if e.is_black() {
            return None;
        }
        Some(ProjectorSample {
            wi: -d / dist,
            dist,
            li: e * (PI * self.scale / (z * z * cos)),
        })
    }

    /// Radiant power: `∫ I dω = π · scale · ∫ E dA` over the virtual plane (dω =
    /// cos³θ dA there), i.e. π · scale · mean(E) · plane area.
    pub fn power(&self) -> Rgb {
        self.irradiance.mean() * (PI * self.scale * 4.0 * self.half.x * self.half.y)
    }
}
