//! Ray-casting oracles for the rasterizer tests.

use glam::{DVec3, Vec3, Vec4};
use irradia_raster::ViewParams;

/// The world-space ray through the centre of pixel (x, y), by unprojecting the pixel
/// centre at the near and far planes: (origin, unit direction).
pub fn pixel_ray(view: &ViewParams, w: u32, h: u32, x: u32, y: u32) -> (DVec3, DVec3) {
    let inv = view.view_proj().inverse();
    let nx = (x as f32 + 0.5) / w as f32 * 2.0 - 1.0;
    let ny = 1.0 - (y as f32 + 0.5) / h as f32 * 2.0;
    let un = |z: f32| {
        let p = inv * Vec4::new(nx, ny, z, 1.0);
        (p.truncate() / p.w).as_dvec3()
    };
    let a = un(0.0);
    let b = un(1.0);
    (a, (b - a).normalize())
}

/// The eye position of a view.
pub fn eye(view: &ViewParams) -> DVec3 {
    view.view.inverse().transform_point3(Vec3::ZERO).as_dvec3()
}

/// Möller-Trumbore in f64: (t, u, v) with the hit at `o + t d` and barycentrics
/// (1-u-v, u, v) of (a, b, c).
pub fn ray_triangle(o: DVec3, d: DVec3, a: Vec3, b: Vec3, c: Vec3) -> Option<(f64, f64, f64)> {
    let (a, b, c) = (a.as_dvec3(), b.as_dvec3(), c.as_dvec3());
    let e1 = b - a;
    let e2 = c - a;
    let p = d.cross(e2);
    let det = e1.dot(p);
    if det.abs() < 1e-14 {
        return None;
    }
    let s = o - a;
    let u = s.dot(p) / det;
    let q = s.cross(e1);
    let v = d.dot(q) / det;
    if u < 0.0 || v < 0.0 || u + v > 1.0 {
        return None;
    }
    Some((e2.dot(q) / det, u, v))
}
