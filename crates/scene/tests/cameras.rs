//! Cameras against the geometry of their definitions (Mitsuba's `thinlens` and
//! `orthographic`): a thin lens images a point of its plane of focus sharp and blurs
//! any other point into the thin-lens circle of confusion; orthographic rays are
//! parallel and cover the documented view size.

use glam::{Vec2, Vec3};
use irradia_scene::{Camera, FovAxis, Projection};

const W: u32 = 200;
const H: u32 = 150;

fn thin_lens(aperture_radius: f32, focus_distance: f32) -> Camera {
    Camera::new(
        Vec3::new(0.0, 0.0, 10.0),
        Vec3::ZERO,
        Vec3::Y,
        Projection::ThinLens {
            fov_degrees: 30.0,
            axis: FovAxis::Horizontal,
            aperture_radius,
            focus_distance,
        },
    )
}

/// Renders a small sphere of radius `r` centred on the view axis at distance `depth`
/// from the lens, by brute force: for image points on a fine grid around the centre and
/// lens points on a fine grid, whether the camera ray meets the sphere. Returns the
/// image points weighted by the fraction of the lens that sees the sphere through them,
/// as (offset from the image centre in pixels, weight).
fn image_of_point(camera: &Camera, depth: f32, r: f32, window: f32) -> Vec<(Vec2, f32)> {
    let rays = camera.rays(W, H);
    let centre = camera.eye + (camera.look_at - camera.eye).normalize() * depth;
    let (steps, lens_steps) = (120, 24);
    let mut out = Vec::new();
    for iy in 0..steps {
        for ix in 0..steps {
            let off = Vec2::new(
                (ix as f32 + 0.5) / steps as f32 - 0.5,
                (iy as f32 + 0.5) / steps as f32 - 0.5,
            ) * (2.0 * window);
            let (x, y) = (0.5 * W as f32 + off.x, 0.5 * H as f32 + off.y);
            let mut hits = 0;
            for ly in 0..lens_steps {
                for lx in 0..lens_steps {
                    let lens = Vec2::new(
                        (lx as f32 + 0.5) / lens_steps as f32,
                        (ly as f32 + 0.5) / lens_steps as f32,
                    );
                    let ray = rays.ray_lens(x, y, lens);
                    // Distance from the sphere's centre to the ray's line.
                    let oc = centre - ray.origin;
                    let t = oc.dot(ray.dir);
                    if (oc - ray.dir * t).length() <= r {
                        hits += 1;
                    }
                }
            }
            if hits > 0 {
                out.push((off, hits as f32 / (lens_steps * lens_steps) as f32));
            }
        }
    }
    out
}

/// Pixels per unit of the image plane at distance 1.
fn pixels_per_unit(camera: &Camera) -> f32 {
    0.5 * W as f32 / camera.half_extents(W, H).x
}

#[test]
fn a_point_on_the_plane_of_focus_images_sharp() {
    let camera = thin_lens(0.5, 10.0);
    // Every lens point's ray through one image point meets the plane of focus at the
    // same place.
    let rays = camera.rays(W, H);
    for (x, y) in [(100.0, 75.0), (13.5, 140.25), (190.0, 3.0)] {
        let points: Vec<Vec3> = (0..16)
            .map(|k| {
                let lens = Vec2::new((k % 4) as f32 / 4.0 + 0.1, (k / 4) as f32 / 4.0 + 0.2);
                let ray = rays.ray_lens(x, y, lens);
                let t = -ray.origin.z / ray.dir.z; // the plane z = 0, 10 in front
                ray.origin + ray.dir * t
            })
            .collect();
        for p in &points {
            assert!((*p - points[0]).length() < 1e-4, "{p} vs {}", points[0]);
        }
    }
    // A small sphere there covers only its own (pinhole) image.
    let r = 0.02;
    let img = image_of_point(&camera, 10.0, r, 3.0);
    let radius_px = r / 10.0 * pixels_per_unit(&camera);
    let reach = img.iter().map(|(o, _)| o.length()).fold(0.0, f32::max);
    assert!(
        reach <= radius_px + 0.1,
        "sharp image reaches {reach} px, the sphere's own image is {radius_px} px"
    );
}

#[test]
fn an_out_of_focus_point_blurs_into_the_thin_lens_circle_of_confusion() {
    let (a, s) = (0.25f32, 10.0f32);
    let camera = thin_lens(a, s);
    for depth in [6.0f32, 16.0] {
        // Thin lens, image plane at distance 1: the point at depth d is seen through
        // image points within a·|d − s| / (d·s) of its pinhole image.
        let coc = a * (depth - s).abs() / (depth * s) * pixels_per_unit(&camera);
        let r = 0.01;
        let img = image_of_point(&camera, depth, r, 1.3 * coc);
        let total: f32 = img.iter().map(|(_, w)| w).sum();
        let second: f32 = img.iter().map(|(o, w)| o.length_squared() * w).sum::<f32>() / total;
        // A uniform disk of radius R has E[ρ²] = R² / 2.
        let radius = (2.0 * second).sqrt();
        assert!(
            (radius - coc).abs() < 0.03 * coc,
            "depth {depth}: blur radius {radius} px, circle of confusion {coc} px"
        );
        // Nothing beyond the circle widened by the sphere's own image and a grid step.
        let reach = img.iter().map(|(o, _)| o.length()).fold(0.0, f32::max);
        let limit = coc + r / depth * pixels_per_unit(&camera) + 2.6 * coc / 120.0;
        assert!(reach <= limit, "depth {depth}: reaches {reach} > {limit}");
    }
}

#[test]
fn orthographic_rays_are_parallel_and_cover_the_view_height() {
    let camera = Camera::new(
        Vec3::new(1.0, 2.0, 3.0),
        Vec3::new(1.0, 2.0, 0.0),
        Vec3::Y,
        Projection::Orthographic { height: 4.0 },
    );
    let rays = camera.rays(W, H);
    let corners = [
        (0.0, 0.0),
        (W as f32, 0.0),
        (0.0, H as f32),
        (W as f32, H as f32),
    ];
    for (x, y) in corners {
        assert!((rays.ray(x, y).dir - -Vec3::Z).length() < 1e-6);
    }
    let o = |x: f32, y: f32| rays.ray(x, y).origin;
    let height = (o(0.0, 0.0) - o(0.0, H as f32)).length();
    let width = (o(0.0, 0.0) - o(W as f32, 0.0)).length();
    assert!((height - 4.0).abs() < 1e-5, "{height}");
    assert!((width - 4.0 * W as f32 / H as f32).abs() < 1e-5, "{width}");
    // The top-left corner is up and to the left of the eye.
    let tl = o(0.0, 0.0) - camera.eye;
    assert!(tl.x < 0.0 && tl.y > 0.0 && tl.z.abs() < 1e-6);
}
