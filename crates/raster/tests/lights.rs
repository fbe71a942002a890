//! The pipeline's lights against the Whitted ray tracer on shadow-free scenes (a floor
//! and one light, so shadows play no part): both use the same lighting model (no 1/π,
//! `I / r²`, the shared spot falloff), so per-pixel Phong must equal the tracer pixel
//! by pixel, Gouraud on a fine mesh must come close, and area lights, replaced by sample
//! points, must approach the tracer's soft lighting as the points grow. Also: Phong uses
//! the vertex colours as the diffuse base, as Gouraud does.

#[allow(dead_code)]
mod common;

use common::pixel_ray;
use glam::Vec3;
use irradia_core::{Ray, Rgb, Rng};
use irradia_geometry::shapes::Plane;
use irradia_geometry::Instance;
use irradia_raster::{
    ColorBuffer, ColorFormat, Framebuffer, Lights, Material, Mesh, Pipeline, RasterLight, Shading,
    ViewParams,
};
use irradia_render::{AovSample, Integrator, Stats, Whitted};
use irradia_scene::{Camera, FovAxis, Light, Object, Projection, RenderSettings, Scene, Texture};
use std::sync::Arc;

const W: u32 = 64;
const H: u32 = 48;

fn view() -> ViewParams {
    ViewParams::look_at_perspective(
        Vec3::new(0.0, 3.5, 3.5),
        Vec3::new(0.0, 0.0, -0.3),
        Vec3::Y,
        50.0,
        W as f32 / H as f32,
        0.1,
        30.0,
    )
}

/// The floor y = 0 over [-3, 3]², cut into `n x n` squares, normals up.
fn floor(n: u32) -> Mesh {
    let mut pos = Vec::new();
    for j in 0..=n {
        for i in 0..=n {
            pos.push(Vec3::new(
                -3.0 + 6.0 * i as f32 / n as f32,
                0.0,
                -3.0 + 6.0 * j as f32 / n as f32,
            ));
        }
    }
    let mut idx = Vec::new();
    for j in 0..n {
        for i in 0..n {
            let a = j * (n + 1) + i;
            idx.push([a, a + n + 1, a + 1]);
            idx.push([a + 1, a + n + 1, a + n + 2]);
        }
    }
    let mut m = Mesh::new(pos, idx);
    m.normals = vec![Vec3::Y; m.positions.len()];
    m
}

/// Red channel of the raster image (RGBA32F), NaN where the floor is not drawn.
fn raster(lights: Lights, shading: Shading, mesh: &Mesh) -> Vec<f32> {
    let mut p = Pipeline::new(W, H);
    p.view = view();
    p.lights = lights;
    p.shading = shading;
    p.material = Material {
        diffuse: Rgb::WHITE,
        specular: Rgb::BLACK,
        shininess: 1.0,
        two_sided: true,
        ..Material::default()
    };
    let mut fb = Framebuffer::new(W, H, ColorFormat::Rgba32F).unwrap();
    p.render_mesh(mesh, &mut fb).unwrap();
    let ColorBuffer::Rgba32F(px) = &fb.color else {
        unreachable!()
    };
    px.iter()
        .zip(&fb.depth)
        .map(|(c, &d)| if d < 1.0 { c[0] } else { f32::NAN })
        .collect()
}

/// Red channel of the Whitted tracer through every pixel centre (an infinite white
/// floor, k_d = 1, no ambient), averaged over `runs` random streams.
fn whitted(light: Light, runs: u64) -> Vec<f32> {
    let objects = vec![Object {
        name: "floor".into(),
        material: 0,
        leaf_materials: Vec::new(),
    }];
    let instances = vec![Instance::untransformed(Arc::new(
        Plane::new(Vec3::Y, 0.0).unwrap(),
    ))];
    let material = irradia_scene::Material {
        name: "white".into(),
        color: Texture::Solid(Rgb::WHITE),
        ambient: 0.0,
        diffuse: 1.0,
        specular: 0.0,
        ..irradia_scene::Material::default()
    };
    let camera = Camera {
        eye: Vec3::new(0.0, 3.5, 3.5),
        look_at: Vec3::ZERO,
        up: Vec3::Y,
        projection: Projection::Perspective {
            fov_degrees: 50.0,
            axis: FovAxis::Vertical,
        },
        near_clip: 0.0,
    };
    let settings = RenderSettings {
        width: W,
        height: H,
        ..RenderSettings::default()
    };
    let scene = Scene::new(
        camera,
        settings,
        vec![material],
        vec![light],
        objects,
        instances,
    );
    let tracer = Whitted::new(&scene);
    let v = view();
    let mut stats = Stats::default();
    let mut out = Vec::with_capacity((W * H) as usize);
    for y in 0..H {
        for x in 0..W {
            let (o, d) = pixel_ray(&v, W, H, x, y);
            let ray = Ray::new(o.as_vec3(), d.as_vec3());
            let mut sum = 0.0;
            for s in 0..runs {
                let mut rng = Rng::new((y * W + x) as u64, s);
                sum += tracer
                    .sample(&ray, &mut rng, &mut stats, &mut AovSample::default())
                    .r;
            }
            out.push(sum / runs as f32);
        }
    }
    out
}

fn spot() -> Light {
    Light::Spot {
        position: Vec3::new(0.2, 2.0, -0.4),
        direction: Vec3::new(0.1, -1.0, 0.05),
        intensity: Rgb::splat(6.0),
        cos_inner: 20f32.to_radians().cos(),
        cos_outer: 35f32.to_radians().cos(),
        profile: irradia_scene::SpotProfile::Smooth,
        texture: None,
    }
}

/// With `LIGHTS_TEST_PNG=DIR`, writes the image (scaled so `peak` is white) for a look.
fn dump(name: &str, img: &[f32], peak: f32) {
    if let Ok(dir) = std::env::var("LIGHTS_TEST_PNG") {
        let px: Vec<u8> = img
            .iter()
            .map(|v| {
                if v.is_nan() {
                    40
                } else {
                    (v / peak * 255.0).clamp(0.0, 255.0) as u8
                }
            })
            .collect();
        image::save_buffer(format!("{dir}/{name}.png"), &px, W, H, image::ColorType::L8).unwrap();
    }
}

/// Largest per-pixel difference over the pixels both images cover, and their count.
fn max_diff(a: &[f32], b: &[f32]) -> (f32, usize) {
    let mut worst = 0f32;
    let mut n = 0;
    for (x, y) in a.iter().zip(b) {
        if x.is_nan() {
            continue;
        }
        worst = worst.max((x - y).abs());
        n += 1;
    }
    (worst, n)
}

#[test]
fn a_spot_light_lights_its_cone_and_falls_off_like_the_ray_tracer() {
    let truth = whitted(spot(), 1);
    let peak = truth.iter().cloned().fold(0.0, f32::max);
    // The cone is on screen: bright inside, dark outside, a smooth edge between.
    assert!(peak > 1.0, "peak {peak}");
    let dark = truth.iter().filter(|&&v| v == 0.0).count();
    let edge = truth
        .iter()
        .filter(|&&v| v > 0.05 * peak && v < 0.5 * peak)
        .count();
    assert!(dark > 500 && edge > 50, "dark {dark}, edge {edge}");

    // Phong: the same model at every pixel.
    let lights = Lights::from_scene(&[spot()], Rgb::BLACK);
    let phong = raster(lights.clone(), Shading::Phong, &floor(4));
    dump("spot-whitted", &truth, peak);
    dump("spot-phong", &phong, peak);
    let (worst, n) = max_diff(&phong, &truth);
    assert!(n > 2000, "floor covers {n} pixels");
    assert!(
        worst < 2e-3 * peak,
        "Phong differs by {worst} (peak {peak})"
    );

    // Gouraud on a fine mesh: vertex lighting interpolated across 1/8-unit squares.
    let gouraud = raster(lights, Shading::Gouraud, &floor(48));
    dump("spot-gouraud", &gouraud, peak);
    let (worst, _) = max_diff(&gouraud, &truth);
    assert!(
        worst < 0.05 * peak,
        "Gouraud differs by {worst} (peak {peak})"
    );

    // Without the cone (a point light of the same intensity) the images differ: the test
    // can fail.
    let point = Lights {
        ambient: Rgb::BLACK,
        lights: vec![RasterLight::Point {
            position: Vec3::new(0.2, 2.0, -0.4),
            color: Rgb::splat(6.0),
        }],
    };
    let (worst, _) = max_diff(&raster(point, Shading::Phong, &floor(4)), &truth);
    assert!(worst > 0.5 * peak, "{worst}");
}

/// Mean absolute difference over covered pixels.
fn mean_diff(a: &[f32], b: &[f32]) -> f32 {
    let (mut s, mut n) = (0.0, 0);
    for (x, y) in a.iter().zip(b) {
        if !x.is_nan() {
            s += (x - y).abs();
            n += 1;
        }
    }
    s / n as f32
}

fn converges(light: Light, name: &str) {
    let truth = whitted(light.clone(), 4);
    let mean = truth.iter().sum::<f32>() / truth.len() as f32;
    let errors: Vec<f32> = [1, 4, 16, 64, 256]
        .iter()
        .map(|&n| {
            let l = Lights::from_scene_with_points(std::slice::from_ref(&light), Rgb::BLACK, n);
            mean_diff(&raster(l, Shading::Phong, &floor(4)), &truth) / mean
        })
        .collect();
    eprintln!("{name}: relative mean errors for 1, 4, 16, 64, 256 points: {errors:?}");
    dump(&format!("{name}-whitted"), &truth, 4.0 * mean);
    for n in [1, 16] {
        let l = Lights::from_scene_with_points(std::slice::from_ref(&light), Rgb::BLACK, n);
        dump(
            &format!("{name}-{n}"),
            &raster(l, Shading::Phong, &floor(4)),
            4.0 * mean,
        );
    }
    for w in errors.windows(2) {
        assert!(
            w[1] < w[0],
            "{name}: relative errors {errors:?} do not fall"
        );
    }
    assert!(
        errors[0] > 0.02,
        "{name}: one point is already exact? {errors:?}"
    );
    assert!(errors[4] < 0.01, "{name}: relative errors {errors:?}");
}

#[test]
fn a_rect_light_approaches_the_ray_tracer_as_points_grow() {
    converges(
        Light::Rect {
            corner: Vec3::new(-0.8, 0.7, -0.9),
            edge_u: Vec3::new(1.6, 0.0, 0.0),
            edge_v: Vec3::new(0.0, 0.3, 1.2),
            radiance: Rgb::splat(2.0),
            samples: 1024,
        },
        "rect",
    );
}

#[test]
fn a_sphere_light_approaches_the_ray_tracer_as_points_grow() {
    converges(
        Light::Sphere {
            center: Vec3::new(0.3, 0.6, -0.2),
            radius: 0.4,
            radiance: Rgb::splat(3.0),
            samples: 1024,
        },
        "sphere",
    );
}

#[test]
fn phong_uses_the_vertex_colours_as_the_diffuse_base() {
    // A floor with a different colour at every vertex, under a directional light: per
    // pixel, Phong = cos θ E x (the interpolated colour, which the unlit pass draws).
    let mut mesh = floor(3);
    mesh.colors = (0..mesh.positions.len())
        .map(|i| {
            let t = i as f32 / mesh.positions.len() as f32;
            [1.0 - t, 0.3 + 0.5 * t, (3.0 * t).fract(), 1.0]
        })
        .collect();
    let dir = Vec3::new(0.3, -0.8, 0.2).normalize();
    let lights = Lights {
        ambient: Rgb::BLACK,
        lights: vec![RasterLight::Directional {
            direction: dir,
            color: Rgb::splat(1.0),
        }],
    };
    let render = |shading| {
        let mut p = Pipeline::new(W, H);
        p.view = view();
        p.lights = lights.clone();
        p.shading = shading;
        let mut fb = Framebuffer::new(W, H, ColorFormat::Rgba32F).unwrap();
        p.render_mesh(&mesh, &mut fb).unwrap();
        let ColorBuffer::Rgba32F(px) = fb.color else {
            unreachable!()
        };
        (px, fb.depth)
    };
    let (unlit, depth) = render(Shading::Unlit);
    let (phong, _) = render(Shading::Phong);
    let (gouraud, _) = render(Shading::Gouraud);
    let cos = -dir.y;
    let mut checked = 0;
    for i in 0..unlit.len() {
        if depth[i] >= 1.0 {
            continue;
        }
        for ch in 0..3 {
            let want = cos * unlit[i][ch];
            assert!(
                (phong[i][ch] - want).abs() < 1e-4,
                "pixel {i} channel {ch}: Phong {} vs {want}",
                phong[i][ch]
            );
            // On a plane under a directional light Gouraud is exact too.
            assert!((gouraud[i][ch] - want).abs() < 1e-4);
        }
        checked += 1;
    }
    assert!(checked > 2000);
    // The colours vary across the floor (a white base would give a grey image).
    let reds: Vec<f32> = phong.iter().map(|c| c[0] - c[1]).collect();
    let spread = reds.iter().cloned().fold(f32::MIN, f32::max)
        - reds.iter().cloned().fold(f32::MAX, f32::min);
    assert!(spread > 0.3, "{spread}");
}
