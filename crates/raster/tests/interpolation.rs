//! Perspective-correct interpolation: a texture coordinate on a receding quad equals
//! the analytic value at the ray hit, while screen-affine interpolation does not.

mod common;

use common::{eye, pixel_ray, ray_triangle};
use glam::{Vec2, Vec3};
use irradia_raster::interpolate::perspective_weights;
use irradia_raster::{
    for_each_fragment, varying, ColorFormat, Framebuffer, Mesh, Pipeline, Rect, Shading, ViewParams,
};

#[test]
fn texture_coordinates_are_perspective_correct() {
    let (w, h) = (64, 48);
    let mut p = Pipeline::new(w, h);
    p.shading = Shading::Unlit;
    p.view = ViewParams::look_at_perspective(
        Vec3::new(0.0, 0.6, 1.5),
        Vec3::new(0.0, 0.0, -2.0),
        Vec3::Y,
        60.0,
        64.0 / 48.0,
        0.1,
        50.0,
    );
    // A floor quad receding from 1 to 30 units away: strong perspective.
    let q = [
        Vec3::new(-2.0, 0.0, 1.0),
        Vec3::new(2.0, 0.0, 1.0),
        Vec3::new(2.0, 0.0, -30.0),
        Vec3::new(-2.0, 0.0, -30.0),
    ];
    let uv = [
        Vec2::new(0.0, 0.0),
        Vec2::new(1.0, 0.0),
        Vec2::new(1.0, 1.0),
        Vec2::new(0.0, 1.0),
    ];
    let mut mesh = Mesh::new(q.to_vec(), vec![[0, 1, 2], [0, 2, 3]]);
    mesh.uvs = uv.to_vec();
    mesh.colors = uv.iter().map(|t| [t.x, t.y, 0.0, 1.0]).collect();
    let mut fb = Framebuffer::new(w, h, ColorFormat::Rgba32F).unwrap();
    p.render_mesh(&mesh, &mut fb).unwrap();

    let analytic = |x: u32, y: u32| {
        let (_, d) = pixel_ray(&p.view, w, h, x, y);
        let e = eye(&p.view);
        let blend = |t: [usize; 3], u: f64, v: f64| {
            uv[t[0]].as_dvec2() * (1.0 - u - v) + uv[t[1]].as_dvec2() * u + uv[t[2]].as_dvec2() * v
        };
        ray_triangle(e, d, q[0], q[1], q[2])
            .map(|(_, u, v)| blend([0, 1, 2], u, v))
            .or_else(|| {
                ray_triangle(e, d, q[0], q[2], q[3]).map(|(_, u, v)| blend([0, 2, 3], u, v))
            })
    };

    // Through the framebuffer (vertex colours carry the uv).
    let mut checked = 0;
    for y in 0..h {
        for x in 0..w {
            let Some(truth) = analytic(x, y) else {
                continue;
            };
            if fb.depth_at(x, y) >= 1.0 {
                continue;
            }
            let c = fb.rgba_at(x, y);
            let err = (c[0] as f64 - truth.x)
                .abs()
                .max((c[1] as f64 - truth.y).abs());
            assert!(err < 2e-3, "pixel ({x}, {y}): {:?} vs {truth}", &c[..2]);
            checked += 1;
        }
    }
    assert!(checked > 1000, "{checked}");

    // Through the fragment interface, with the uv varying: perspective-correct weights
    // match, screen-affine weights are visibly wrong.
    let tris = p.transform_mesh(&mesh).unwrap();
    let mut worst_affine: f64 = 0.0;
    for t in &tris {
        let v = [&t.v[0], &t.v[1], &t.v[2]];
        for_each_fragment(t, &Rect::full(w, h), |x, y, l| {
            let Some(truth) = analytic(x, y) else { return };
            let pw = perspective_weights(&v, l);
            let uv_at = |wt: [f32; 3]| {
                Vec2::new(
                    wt[0] * v[0].var[varying::UV]
                        + wt[1] * v[1].var[varying::UV]
                        + wt[2] * v[2].var[varying::UV],
                    wt[0] * v[0].var[varying::UV + 1]
                        + wt[1] * v[1].var[varying::UV + 1]
                        + wt[2] * v[2].var[varying::UV + 1],
                )
            };
            let good = uv_at(pw).as_dvec2();
            assert!(
                (good - truth).abs().max_element() < 2e-3,
                "({x}, {y}): {good} vs {truth}"
            );
            worst_affine = worst_affine.max((uv_at(l).as_dvec2() - truth).abs().max_element());
        });
    }
    assert!(
        worst_affine > 0.05,
        "affine interpolation should be visibly wrong here: {worst_affine}"
    );
}
