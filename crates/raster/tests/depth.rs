//! The z-buffer against a ray caster: the stored NDC depth, converted back to eye
//! space, equals the ray's hit distance along the view axis.
//!
//! Tolerances: snapping vertices to the 1/256-pixel grid moves a vertex by at most
//! 1/512 pixel per axis, which shifts the interpolated depth by at most the depth
//! gradient per pixel times a few 1/256 (more for facets smaller than a pixel, so
//! the sphere here is tessellated into facets several pixels wide).

mod common;

use common::{eye, pixel_ray, ray_triangle};
use glam::Vec3;
use irradia_core::Ray;
use irradia_geometry::shapes::Sphere;
use irradia_geometry::Shape;
use irradia_raster::{ColorFormat, Framebuffer, Mesh, Pipeline, ViewParams};

fn forward(view: &ViewParams) -> glam::DVec3 {
    -view.view.inverse().z_axis.truncate().as_dvec3().normalize()
}

#[test]
fn depth_of_a_tilted_plane_matches_the_ray_hit() {
    let (w, h) = (64, 48);
    let mut p = Pipeline::new(w, h);
    p.view = ViewParams::look_at_perspective(
        Vec3::new(0.5, 1.0, 4.0),
        Vec3::ZERO,
        Vec3::Y,
        50.0,
        64.0 / 48.0,
        0.5,
        20.0,
    );
    let q = [
        Vec3::new(-3.0, -1.0, 2.0),
        Vec3::new(3.0, -0.5, 2.0),
        Vec3::new(3.0, 0.5, -6.0),
        Vec3::new(-3.0, 0.0, -6.0),
    ];
    let mesh = Mesh::new(q.to_vec(), vec![[0, 1, 2], [0, 2, 3]]);
    let mut fb = Framebuffer::new(w, h, ColorFormat::Rgba8).unwrap();
    p.render_mesh(&mesh, &mut fb).unwrap();
    let (e, fwd) = (eye(&p.view), forward(&p.view));
    // The plane's eye depth through any pixel centre (also outside the quad).
    let n = (q[1] - q[0]).cross(q[2] - q[0]).as_dvec3();
    let plane_depth = |x: u32, y: u32| {
        let (_, d) = pixel_ray(&p.view, w, h, x, y);
        (q[0].as_dvec3() - e).dot(n) / d.dot(n) * d.dot(fwd)
    };
    let mut checked = 0;
    for y in 0..h - 1 {
        for x in 0..w - 1 {
            let (_, d) = pixel_ray(&p.view, w, h, x, y);
            let hit = ray_triangle(e, d, q[0], q[1], q[2])
                .or_else(|| ray_triangle(e, d, q[0], q[2], q[3]));
            let z = fb.depth_at(x, y);
            if hit.is_none() || z >= 1.0 {
                continue; // not on the quad, or an edge pixel left to its neighbour
            }
            let truth = plane_depth(x, y);
            let gradient = (plane_depth(x + 1, y) - truth)
                .abs()
                .max((plane_depth(x, y + 1) - truth).abs());
            let got = p.view.eye_depth(z) as f64;
            let tol = 2e-5 * truth + gradient * 4.0 / 256.0;
            assert!(
                (got - truth).abs() <= tol,
                "pixel ({x}, {y}): z-buffer {got}, ray {truth}, tolerance {tol}"
            );
            checked += 1;
        }
    }
    assert!(checked > 1500, "{checked}");
}

#[test]
fn depth_of_a_tessellated_sphere_matches_the_analytic_sphere() {
    let (w, h) = (64, 48);
    let sphere = Sphere::new(Vec3::new(0.2, -0.1, 0.0), 1.0);
    let detail = 24;
    let mut p = Pipeline::new(w, h);
    p.view = ViewParams::look_at_perspective(
        Vec3::new(0.0, 0.0, 3.5),
        Vec3::ZERO,
        Vec3::Y,
        45.0,
        64.0 / 48.0,
        0.5,
        10.0,
    );
    let mesh = Mesh::from_facets(&sphere.facets(detail).unwrap());
    let mut fb = Framebuffer::new(w, h, ColorFormat::Rgba8).unwrap();
    p.render_mesh(&mesh, &mut fb).unwrap();
    let (e, fwd) = (eye(&p.view), forward(&p.view));
    // The facets lie inside the sphere by at most the chord sagitta.
    // (Bound it with twice the angular step, as quads near the poles are uneven.)
    let sagitta = 1.0 - (2.0 * std::f64::consts::PI / detail as f64).cos();
    let mut checked = 0;
    for y in 0..h {
        for x in 0..w {
            let (_, d) = pixel_ray(&p.view, w, h, x, y);
            let ray = Ray::new(e.as_vec3(), d.as_vec3());
            let Some(hit) = sphere.intersect(&ray, f32::INFINITY) else {
                continue;
            };
            // Away from the silhouette, where the facet error stays small.
            let cos = -(hit.normal.as_dvec3().dot(d));
            if cos < 0.5 {
                continue;
            }
            let truth = hit.t as f64 * d.dot(fwd);
            let got = p.view.eye_depth(fb.depth_at(x, y)) as f64;
            // Depth change per pixel on the sphere here: pixel footprint / cos.
            let footprint = truth * 2.0 * (22.5f64.to_radians()).tan() / h as f64;
            let snap = footprint * (1.0 - cos * cos).sqrt() / cos * 4.0 / 256.0;
            assert!(
                got >= truth - snap - 2e-5 * truth && got - truth <= sagitta / cos + snap,
                "pixel ({x}, {y}): z-buffer {got}, sphere {truth}"
            );
            checked += 1;
        }
    }
    assert!(checked > 300, "{checked}");
}
