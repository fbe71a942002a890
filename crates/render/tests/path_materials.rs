//! The physically based materials (Mitsuba 3's BSDFs, `material.bsdf`) in the path
//! tracer: every type renders a finite image, and in a white furnace (a uniform
//! environment of radiance 1, the scene's `background`) the lossless ones are
//! invisible: a diffuse ball of reflectance 1, a perfect mirror (`conductor` without a
//! `material`, Mitsuba's "none") and a smooth glass ball all return the environment's
//! radiance; so do a blend of two of them, a mask of a two-sided one and a two-sided
//! one. Every description becomes its own scatter BSDF (not the lecture fields).

use irradia_render::driver::ProgressiveOptions;
use irradia_render::path::{self, PathParams};
use irradia_render::Film;
use irradia_scene::Scene;
use std::path::Path;
use std::time::Duration;

/// A unit ball of material `bsdf` (the body of a `[materials.ball]` table) seen from
/// z = 4 under a uniform environment of radiance 1.
fn ball_scene(bsdf: &str) -> Scene {
    let text = format!(
        r#"
[image]
width = 24
height = 18

[camera]
eye = [0, 0, 4]
look_at = [0, 0, 0]
fov = 35
fov_axis = "vertical"

[render]
integrator = "path"
max_depth = 64
background = 1
ambient_light = 0

[materials.ball]
{bsdf}

[[objects]]
name = "ball"
type = "sphere"
center = [0, 0, 0]
radius = 1
material = "ball"
"#
    );
    irradia_scene::load_str(
        &text,
        irradia_scene::SceneSyntax::Toml,
        Path::new("ball.toml"),
    )
    .unwrap_or_else(|e| panic!("{e}\n{text}"))
}

fn render(scene: &Scene, spp: u32) -> Film {
    let params = PathParams {
        max_depth: scene.settings.max_depth,
        rr_depth: 5,
    };
    let opts = ProgressiveOptions {
        spp,
        checkpoint_interval: Duration::from_secs(3600),
        ..Default::default()
    };
    let film = Film::new(scene.settings.width, scene.settings.height).unwrap();
    path::render(scene, &params, &opts, film, |_, _| {})
        .unwrap()
        .film
}

/// Pixels whose whole footprint sees the ball (the ray through the pixel's centre
/// passes within 0.85 of its centre).
fn ball_pixels(scene: &Scene) -> Vec<usize> {
    let (w, h) = (scene.settings.width, scene.settings.height);
    let cam = scene.camera.rays(w, h);
    (0..h)
        .flat_map(|y| (0..w).map(move |x| (x, y)))
        .filter(|&(x, y)| {
            let r = cam.ray(x as f32 + 0.5, y as f32 + 0.5);
            let d = r.dir.normalize();
            let to_c = -r.origin;
            (to_c - d * to_c.dot(d)).length() < 0.85
        })
        .map(|(x, y)| (y * w + x) as usize)
        .collect()
}

const TYPES: &[(&str, &str)] = &[
    ("diffuse", "type = \"diffuse\"\nreflectance = [0.8, 0.4, 0.2]"),
    ("conductor", "type = \"conductor\"\nmaterial = \"Au\""),
    (
        "roughconductor",
        "type = \"roughconductor\"\nmaterial = \"Cu\"\ndistribution = \"ggx\"\nalpha = 0.3",
    ),
    (
        "anisotropic roughconductor",
        "type = \"roughconductor\"\nmaterial = \"Al\"\nalpha_u = 0.05\nalpha_v = 0.4",
    ),
    ("dielectric", "type = \"dielectric\"\nint_ior = \"bk7\""),
    (
        "roughdielectric",
        "type = \"roughdielectric\"\nint_ior = 1.5\nalpha = 0.2\ndistribution = \"ggx\"",
    ),
    ("thindielectric", "type = \"thindielectric\""),
    (
        "textured diffuse",
        "type = \"diffuse\"\nreflectance = { type = \"checkerboard\", color0 = 0.1, color1 = 0.9, to_uv = [{ scale = 8 }] }",
    ),
];

#[test]
fn every_bsdf_type_renders_finite() {
    for (name, body) in TYPES {
        let scene = ball_scene(body);
        let film = render(&scene, 4);
        let im = film.image();
        let px = im.pixels();
        assert!(
            px.iter()
                .all(|p| p.is_finite() && p.r.min(p.g).min(p.b) >= 0.0),
            "{name}: a pixel is not finite and non-negative"
        );
        let ball = ball_pixels(&scene);
        let mean: f32 = ball.iter().map(|&i| px[i].mean()).sum::<f32>() / ball.len() as f32;
        assert!(mean > 0.01, "{name}: the ball is black ({mean})");
    }
}

#[test]
fn lossless_balls_vanish_in_a_white_furnace() {
    for (name, body, spp) in [
        (
            "diffuse reflectance 1",
            "type = \"diffuse\"\nreflectance = 1",
            64,
        ),
        ("perfect mirror", "type = \"conductor\"", 4),
        (
            "smooth glass",
            "type = \"dielectric\"\nint_ior = 1.5\next_ior = 1",
            64,
        ),
        (
            "thin glass",
            "type = \"thindielectric\"\nint_ior = 1.5\next_ior = 1",
            16,
        ),
        (
            "blend of diffuse 1 and a mirror",
            "type = \"blendbsdf\"\nweight = 0.3\nbsdfs = [{ type = \"diffuse\", reflectance = 1 }, { type = \"conductor\" }]",
            64,
        ),
        (
            // Two-sided: light let through meets the inside of the shell.
            "mask of two-sided diffuse 1",
            "type = \"mask\"\nopacity = 0.4\nbsdf = { type = \"twosided\", bsdf = { type = \"diffuse\", reflectance = 1 } }",
            64,
        ),
        (
            "two-sided diffuse 1",
            "type = \"twosided\"\nbsdf = { type = \"diffuse\", reflectance = 1 }",
            64,
        ),
    ] {
        let scene = ball_scene(body);
        let film = render(&scene, spp);
        let im = film.image();
        let var = film.variance_of_mean();
        let ball = ball_pixels(&scene);
        assert!(ball.len() > 50, "{} ball pixels", ball.len());
        let mut sum = 0.0f64;
        for &i in &ball {
            let p = im.pixels()[i];
            let sigma = var[i].sqrt() as f32;
            for c in [p.r, p.g, p.b] {
                assert!(
                    (c - 1.0).abs() <= 5.0 * sigma + 2e-3,
                    "{name}: pixel {i} = {p:?} (σ {sigma}), expected 1"
                );
            }
            sum += p.mean() as f64;
        }
        let mean = sum / ball.len() as f64;
        assert!(
            (mean - 1.0).abs() < 0.01,
            "{name}: ball mean {mean}, expected 1"
        );
    }
}

/// Mitsuba's BSDFs are one-sided: the shading frame keeps the geometric normal's side,
/// so the inside of a diffuse shell in a lit furnace stays black (the lecture mixture,
/// two-sided, would glow).
#[test]
fn mitsuba_bsdfs_are_black_from_the_back() {
    let text = r#"
[image]
width = 8
height = 6

[camera]
eye = [0, 0, 0]
look_at = [0, 0, -1]
fov = 60

[render]
integrator = "path"
max_depth = 8
ambient_light = 0

[materials.lamp]
color = 0
diffuse = 0
emission = 1
emission_two_sided = true

[materials.shell]
type = "diffuse"
reflectance = 0.9

[[objects]]
name = "shell"
type = "sphere"
center = [0, 0, 0]
radius = 2
material = "shell"

[[objects]]
name = "lamp"
type = "sphere"
center = [0, 1, -1]
radius = 0.2
material = "lamp"
"#;
    let scene = irradia_scene::load_str(
        text,
        irradia_scene::SceneSyntax::Toml,
        Path::new("shell.toml"),
    )
    .unwrap();
    let film = render(&scene, 8);
    let im = film.image();
    // The lamp covers few pixels; everything else is the inside of the shell.
    let dark = im
        .pixels()
        .iter()
        .filter(|p| p.max_component() == 0.0)
        .count();
    assert!(
        dark >= im.pixels().len() * 3 / 4,
        "only {dark} of {} pixels black",
        im.pixels().len()
    );
}

/// A `principledthin` description with some parameters given, and the check that its
/// BSDF has them (and Mitsuba's defaults for the rest).
const PRINCIPLED_THIN: &str = "type = \"principledthin\"
base_color = [0.7, 0.1, 0.1]
spec_trans = 0.8
diff_trans = 0.3
eta = 1.33
specular_transmittance_sampling_rate = 2.0";

fn thin_as_given(b: &irradia_scatter::Bsdf) -> bool {
    let irradia_scatter::Bsdf::PrincipledThin(p) = b else {
        return false;
    };
    p.base_color == irradia_core::Rgb::new(0.7, 0.1, 0.1)
        && (p.spec_trans, p.diff_trans, p.eta, p.roughness) == (0.8, 0.3, 1.33, 0.5)
        && p.specular_transmittance_sampling_rate == 2.0
        && p.diffuse_transmittance_sampling_rate == 1.0
}

/// Every description the scatter crate has a BSDF for becomes that BSDF in the path
/// tracer (not the lecture fields the scene derives for the Whitted tracer), nested
/// ones included.
#[test]
fn every_description_becomes_its_own_bsdf() {
    use irradia_render::path::material_map::{material_bsdf, Tangents};
    use irradia_scatter::Bsdf;
    type Case = (&'static str, fn(&Bsdf) -> bool);
    let cases: &[Case] = &[
        ("type = \"diffuse\"", |b| matches!(b, Bsdf::Diffuse(_))),
        ("type = \"conductor\"\nmaterial = \"Au\"", |b| {
            matches!(b, Bsdf::Conductor(_))
        }),
        ("type = \"roughconductor\"", |b| {
            matches!(b, Bsdf::RoughConductor(_))
        }),
        ("type = \"dielectric\"", |b| {
            matches!(b, Bsdf::Dielectric(_))
        }),
        ("type = \"roughdielectric\"", |b| {
            matches!(b, Bsdf::RoughDielectric(_))
        }),
        ("type = \"thindielectric\"", |b| {
            matches!(b, Bsdf::ThinDielectric(_))
        }),
        ("type = \"plastic\"", |b| matches!(b, Bsdf::Plastic(_))),
        ("type = \"roughplastic\"", |b| {
            matches!(b, Bsdf::RoughPlastic(_))
        }),
        ("type = \"principled\"", |b| {
            matches!(b, Bsdf::Principled(_))
        }),
        (PRINCIPLED_THIN, thin_as_given),
        (
            "type = \"blendbsdf\"\nbsdfs = [{ type = \"plastic\" }, { type = \"diffuse\" }]",
            |b| matches!(b, Bsdf::Blend(x) if matches!(*x.bsdf_0, Bsdf::Plastic(_))),
        ),
        (
            "type = \"mask\"\nbsdf = { type = \"roughplastic\" }",
            |b| matches!(b, Bsdf::Mask(x) if matches!(*x.nested_bsdf, Bsdf::RoughPlastic(_))),
        ),
        (
            "type = \"twosided\"\nbsdf = { type = \"principled\" }",
            |b| matches!(b, Bsdf::TwoSided(x) if matches!(*x.front, Bsdf::Principled(_))),
        ),
    ];
    for (body, is_it) in cases {
        let scene = ball_scene(body);
        let b = material_bsdf(
            &scene.materials[0],
            glam::Vec3::ZERO,
            glam::Vec2::ZERO,
            &Tangents::default(),
        );
        assert!(is_it(&b), "{body}: became {b:?}");
    }
}
