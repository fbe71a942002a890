//! Mitsuba 3's `rectangle`: the square `[-1, 1]²` in the plane `z = 0` of its own
//! frame, facing `+z` (or `-z` with `flip_normals`), placed by the object's transform.
//! Its texture coordinates are Mitsuba's: `uv = ((x + 1) / 2, (y + 1) / 2)`, so the
//! corner `(-1, -1)` has `uv = (0, 0)` and `(1, 1)` has `(1, 1)`. An open surface.

use crate::shape::{Facets, Hit, Shape, Span};
use glam::{DVec3, Vec2, Vec3};
use irradia_core::{Aabb, Ray};

#[derive(Clone, Debug, Default)]
pub struct Rectangle {
    flipped: bool,
}

impl Rectangle {
    /// The unit rectangle facing `+z`.
    pub fn new() -> Self {
        Self { flipped: false }
    }

    /// The same rectangle facing `-z` (Mitsuba's `flip_normals`); uv is unchanged.
    pub fn flipped(flip: bool) -> Self {
        Self { flipped: flip }
    }

    fn normal(&self) -> Vec3 {
        if self.flipped {
            -Vec3::Z
        } else {
            Vec3::Z
        }
    }

    /// The crossing of `z = 0` inside the square: `(t, x, y)`.
    fn crossing(&self, ray: &Ray, t_max: f32) -> Option<(f64, f64, f64)> {
        let o = ray.origin.as_dvec3();
        let d = ray.dir.as_dvec3();
        if d.z == 0.0 {
            return None;
        }
        let t = -o.z / d.z;
        if !(t > 0.0 && t < t_max as f64) {
            return None;
        }
        let (x, y) = (o.x + d.x * t, o.y + d.y * t);
        (x.abs() <= 1.0 && y.abs() <= 1.0).then_some((t, x, y))
    }
}

impl Shape for Rectangle {
    fn kind(&self) -> &'static str {
        "rectangle"
    }

    fn bounds(&self) -> Aabb {
        Aabb::new(Vec3::new(-1.0, -1.0, -1e-6), Vec3::new(1.0, 1.0, 1e-6))
    }

    fn intersect(&self, ray: &Ray, t_max: f32) -> Option<Hit> {
        let (t, x, y) = self.crossing(ray, t_max)?;
        let p = DVec3::new(x, y, 0.0);
        let mut h = Hit::new(
            t as f32,
            p.as_vec3(),
            self.normal(),
            Vec2::new(((x + 1.0) * 0.5) as f32, ((y + 1.0) * 0.5) as f32),
        );
        // z is exact; x and y carry the rounding of the f64 crossing converted to f32.
        h.error = 2.0 * f32::EPSILON;
        Some(h)
    }

    fn occluded(&self, ray: &Ray, t_max: f32) -> bool {
        self.crossing(ray, t_max).is_some()
    }

    /// uv = ((x + 1)/2, (y + 1)/2): dp/du = (2, 0, 0), dp/dv = (0, 2, 0).
    fn uv_derivatives(&self, _p: Vec3, _uv: Vec2, _prim: u32) -> (Vec3, Vec3) {
        (Vec3::new(2.0, 0.0, 0.0), Vec3::new(0.0, 2.0, 0.0))
    }

    fn is_solid(&self) -> bool {
        false
    }

    fn spans(&self, _ray: &Ray, _out: &mut Vec<Span>) {}

    // The facets are the surface itself (the path tracer's flat scene bakes them only
    // for materials that read neither uv nor the tangent frame).
    fn facets_exact(&self) -> bool {
        true
    }

    fn facets(&self, _detail: u32) -> Option<Facets> {
        let face = if self.flipped {
            vec![0, 3, 2, 1]
        } else {
            vec![0, 1, 2, 3]
        };
        Some(Facets {
            vertices: vec![
                Vec3::new(-1.0, -1.0, 0.0),
                Vec3::new(1.0, -1.0, 0.0),
                Vec3::new(1.0, 1.0, 0.0),
                Vec3::new(-1.0, 1.0, 0.0),
            ],
            faces: vec![face],
            normals: Vec::new(),
        })
    }

    fn area(&self) -> Option<f32> {
        Some(4.0)
    }

    fn sample_surface(&self, u: Vec2) -> Option<(Vec3, Vec3)> {
        Some((
            Vec3::new(2.0 * u.x - 1.0, 2.0 * u.y - 1.0, 0.0),
            self.normal(),
        ))
    }
}
