//! The film's pixel filters, crop windows and AOVs through the one driver:
//! - a render of a sharp edge with the tent or Gaussian filter equals the edge
//!   convolved with the filter in closed form;
//! - a crop-window render equals the same pixels of the full render, bit for bit, for
//!   both integrators;
//! - the path tracer's depth, normal and object AOVs equal the Whitted tracer's
//!   first-hit AOVs of the same camera rays;
//! - a one-sample render's film of values gives the image a film of sums gives, bit
//!   for bit.

use irradia_render::filter::{erf, FilterSampler};
use irradia_render::sampler::{camera_sample, Sampler};
use irradia_render::{render, Aov, AovSample, Integrator, RenderOptions, Stats, Whitted};
use irradia_scene::{builtin, CropWindow, Integrator as Method, PixelFilter, Scene, SceneSyntax};
use std::path::Path;

/// An orthographic view of a white half-plane (x < `EDGE` in image columns) on black,
/// one world unit per pixel, unlit: every pixel's value is the part of its filter that
/// falls on the white side.
const EDGE: f64 = 16.3;

fn edge_scene(filter: &str) -> Scene {
    let text = format!(
        r#"
[image]
width = 32
height = 4
filter = {filter}

[camera]
type = "orthographic"
eye = [0, 0, 5]
look_at = [0, 0, 0]
height = 4

[render]
spp = 1024
max_depth = 1
background = 0
ambient_light = 1

[materials.white]
color = 1
ambient = 1
diffuse = 0

[[objects]]
type = "box"
min = [-100, -100, -1]
max = [{x}, 100, 0]
material = "white"
"#,
        x = EDGE - 16.0
    );
    irradia_scene::load_str(&text, SceneSyntax::Toml, Path::new("edge.toml")).unwrap()
}

/// The normalised filter's distribution function at `t` (the part of the filter left
/// of `t`), in closed form.
fn filter_cdf(f: PixelFilter, t: f64) -> f64 {
    match f {
        PixelFilter::Box { radius } => {
            ((t + radius as f64) / (2.0 * radius as f64)).clamp(0.0, 1.0)
        }
        PixelFilter::Tent { radius } => {
            let r = radius as f64;
            let t = t.clamp(-r, r);
            if t < 0.0 {
                (t + r).powi(2) / (2.0 * r * r)
            } else {
                1.0 - (r - t).powi(2) / (2.0 * r * r)
            }
        }
        PixelFilter::Gaussian { stddev } => {
            let s = stddev as f64;
            let r = 4.0 * s;
            let t = t.clamp(-r, r);
            let bias = (-r * r / (2.0 * s * s)).exp();
            let g = |x: f64| s * (std::f64::consts::PI / 2.0).sqrt() * erf(x / (s * 2f64.sqrt()));
            let z = g(r) - g(-r) - 2.0 * r * bias;
            (g(t) - g(-r) - bias * (t + r)) / z
        }
    }
}

#[test]
fn a_filtered_edge_is_the_edge_convolved_with_the_filter() {
    for (text, filter) in [
        (r#"{ type = "tent" }"#, PixelFilter::Tent { radius: 1.0 }),
        (
            r#"{ type = "tent", radius = 2.5 }"#,
            PixelFilter::Tent { radius: 2.5 },
        ),
        (
            r#"{ type = "gaussian" }"#,
            PixelFilter::Gaussian { stddev: 0.5 },
        ),
        (
            r#"{ type = "gaussian", stddev = 0.8 }"#,
            PixelFilter::Gaussian { stddev: 0.8 },
        ),
        (r#""box""#, PixelFilter::Box { radius: 0.5 }),
    ] {
        let scene = edge_scene(text);
        assert_eq!(scene.settings.filter, filter);
        let image = render(&scene, &RenderOptions::default()).unwrap().image;
        let mut worst = 0.0f64;
        for x in 0..32u32 {
            let exact = filter_cdf(filter, EDGE - (x as f64 + 0.5));
            for y in 0..4 {
                let got = image.get(x, y).g as f64;
                worst = worst.max((got - exact).abs());
            }
        }
        // 1024 stratified samples: a pixel is within a few thousandths of its value.
        assert!(worst < 4e-3, "{filter:?}: off by {worst}");
    }
    // The comparison tells filters apart: the tent's image is not the Gaussian's.
    let tent = render(&edge_scene(r#""tent""#), &RenderOptions::default()).unwrap();
    let exact = filter_cdf(PixelFilter::Gaussian { stddev: 0.5 }, EDGE - 16.5);
    assert!((tent.image.get(16, 0).g as f64 - exact).abs() > 0.02);
}

/// The full render and a crop of it, by the scene's integrator.
fn full_and_crop(mut scene: Scene, crop: CropWindow, aovs: &[Aov]) {
    let options = RenderOptions {
        aovs: aovs.to_vec(),
        tile_size: 16,
        ..RenderOptions::default()
    };
    let full = render(&scene, &options).unwrap();
    scene.settings.crop = Some(crop);
    let part = render(
        &scene,
        &RenderOptions {
            tile_size: 7,
            ..options
        },
    )
    .unwrap();
    assert_eq!(
        (part.image.width(), part.image.height()),
        (crop.width, crop.height)
    );
    let same = |a: &irradia_core::Image, b: &irradia_core::Image, what: &str| {
        for y in 0..crop.height {
            for x in 0..crop.width {
                let (p, q) = (b.get(x, y), a.get(crop.x + x, crop.y + y));
                assert!(
                    p.r.to_bits() == q.r.to_bits()
                        && p.g.to_bits() == q.g.to_bits()
                        && p.b.to_bits() == q.b.to_bits(),
                    "{what} pixel ({}, {}): {p:?} vs {q:?}",
                    crop.x + x,
                    crop.y + y
                );
            }
        }
    };
    same(&full.image, &part.image, "colour");
    for ((a, fa), (_, pa)) in full.aovs.iter().zip(&part.aovs) {
        same(fa, pa, a.name());
    }
}

#[test]
fn a_crop_window_equals_the_same_pixels_of_the_full_render() {
    let crop = CropWindow {
        x: 13,
        y: 9,
        width: 21,
        height: 17,
    };
    let mut whitted = builtin::load("whitted").unwrap();
    whitted.settings.width = 64;
    whitted.settings.height = 48;
    whitted.settings.spp = 4;
    whitted.settings.filter = PixelFilter::Gaussian { stddev: 0.5 };
    full_and_crop(whitted, crop, &[Aov::Depth, Aov::Normal]);

    let mut adaptive = builtin::load("whitted").unwrap();
    adaptive.settings.width = 64;
    adaptive.settings.height = 48;
    adaptive.settings.adaptive_threshold = Some(0.05);
    full_and_crop(adaptive, crop, &[Aov::ObjectId]);

    let mut cornell = builtin::load("cornell").unwrap();
    cornell.settings.width = 48;
    cornell.settings.height = 40;
    cornell.settings.spp = 3;
    cornell.settings.filter = PixelFilter::Tent { radius: 1.0 };
    assert_eq!(cornell.settings.integrator, Method::Path);
    full_and_crop(cornell, crop, &[Aov::Depth]);
}

#[test]
fn path_tracer_aovs_equal_the_whitted_first_hit_aovs() {
    for name in ["cornell", "whitted"] {
        let mut scene = builtin::load(name).unwrap();
        scene.settings.width = 40;
        scene.settings.height = 30;
        scene.settings.spp = 2;
        scene.settings.integrator = Method::Path;
        let aovs = [Aov::Depth, Aov::Normal, Aov::ObjectId];
        let out = render(
            &scene,
            &RenderOptions {
                aovs: aovs.to_vec(),
                ..RenderOptions::default()
            },
        )
        .unwrap();
        // The Whitted tracer's first hit of each pixel's sample 0 as the path tracer
        // draws it.
        let (w, h) = (scene.settings.width, scene.settings.height);
        let cam = scene.camera.rays(w, h);
        let filter = FilterSampler::new(scene.settings.filter);
        let whitted = Whitted::new(&scene);
        let mut mismatched = 0;
        for y in 0..h {
            for x in 0..w {
                let mut cs =
                    camera_sample(&cam, &filter, Sampler::Independent { seed: 0 }, x, y, 0);
                let mut a = AovSample::default();
                whitted.sample(&cs.ray, &mut cs.rng, &mut Stats::default(), &mut a);
                let depth = out.aovs[0].1.get(x, y).r;
                let n = out.aovs[1].1.get(x, y);
                let object = out.aovs[2].1.get(x, y).r;
                let close = |p: f32, q: f32| (p - q).abs() <= 1e-4 * p.abs().max(1.0) || p == q;
                let agree = object == a.object as f32
                    && close(depth, a.depth)
                    && close(n.r, a.normal.x)
                    && close(n.g, a.normal.y)
                    && close(n.b, a.normal.z);
                if !agree {
                    mismatched += 1;
                    println!("{name} ({x}, {y}): path {depth} {n:?} {object}, whitted {a:?}");
                }
            }
        }
        // Rays that graze an edge between two faces may find either face first.
        assert!(
            mismatched * 200 <= w * h,
            "{name}: {mismatched} pixels differ"
        );
        // And the record is a real one: some pixels see objects, at finite depth.
        assert!(out.aovs[2].1.pixels().iter().any(|p| p.r >= 0.0));
    }
}

/// A one-sample render keeps pixel values, not sums (`Film::for_one_sample`); asking
/// for a checkpoint makes the driver keep the sums. Both images must agree bit for bit:
/// with the Gaussian filter (weights other than 1 where adaptive sampling adds four
/// samples), a crop window, both integrators, and through the public `Film` too.
#[test]
fn a_one_sample_film_of_values_gives_the_image_of_sums() {
    let dir = tempfile::tempdir().unwrap();
    let mut scenes = Vec::new();
    let whitted = || {
        let mut s = builtin::load("whitted").unwrap();
        s.settings.width = 64;
        s.settings.height = 48;
        s.settings.filter = PixelFilter::Gaussian { stddev: 0.5 };
        s
    };
    let mut adaptive = whitted();
    adaptive.settings.adaptive_threshold = Some(0.05);
    scenes.push(("whitted adaptive", adaptive));
    let mut whitted = whitted();
    whitted.settings.crop = Some(CropWindow {
        x: 5,
        y: 3,
        width: 40,
        height: 31,
    });
    scenes.push(("whitted crop", whitted));
    let mut cornell = builtin::load("cornell").unwrap();
    cornell.settings.width = 40;
    cornell.settings.height = 30;
    cornell.settings.filter = PixelFilter::Tent { radius: 1.0 };
    assert_eq!(cornell.settings.integrator, Method::Path);
    scenes.push(("cornell", cornell));
    for (what, mut scene) in scenes {
        scene.settings.spp = 1;
        let options = RenderOptions {
            tile_size: 16,
            ..RenderOptions::default()
        };
        let values = render(&scene, &options).unwrap();
        let sums = render(
            &scene,
            &RenderOptions {
                checkpoint: Some(dir.path().join(format!("{what}.film"))),
                ..options
            },
        )
        .unwrap();
        assert_eq!(values.samples, 1);
        assert_eq!(sums.samples, 1);
        assert!(values.relative_error.is_infinite() && sums.relative_error.is_infinite());
        let bits = |im: &irradia_core::Image| {
            im.pixels()
                .iter()
                .flat_map(|p| [p.r.to_bits(), p.g.to_bits(), p.b.to_bits()])
                .collect::<Vec<_>>()
        };
        let (a, b) = (bits(&values.image), bits(&sums.image));
        let differ = a.iter().zip(&b).filter(|(x, y)| x != y).count();
        assert_eq!(differ, 0, "{what}: {differ} of {} channels differ", a.len());
        assert!(values.image.pixels().iter().any(|p| p.r > 0.0), "{what}");
    }
}

#[test]
fn a_film_of_values_keeps_no_sums() {
    use irradia_render::Film;
    let w = CropWindow {
        x: 0,
        y: 0,
        width: 3,
        height: 2,
    };
    let film = Film::for_one_sample(w).unwrap();
    assert_eq!(film.len(), 6);
    assert!(film.sums().is_none());
    assert!(film.relative_error().is_infinite());
    assert!(film.variance_of_mean().iter().all(|v| v.is_infinite()));
    let dir = tempfile::tempdir().unwrap();
    assert!(film.save_checkpoint(&dir.path().join("f"), 0).is_err());
    assert_eq!(
        film.into_image().pixels(),
        Film::for_window(w).unwrap().image().pixels()
    );
}

#[test]
fn bad_filters_and_crop_windows_name_their_field() {
    let base = |image: &str| {
        format!(
            "[image]\nwidth = 20\nheight = 10\n{image}\n[camera]\neye = [0, 0, 5]\nlook_at = [0, 0, 0]\n"
        )
    };
    for (image, field) in [
        (
            r#"filter = { type = "gaussian", stddev = -1 }"#,
            "image.filter.stddev",
        ),
        (r#"filter = { type = "mitchell" }"#, "image.filter.type"),
        (
            r#"filter = { type = "tent", stdev = 1 }"#,
            "image.filter.stdev",
        ),
        ("crop_offset_x = 15\ncrop_width = 10", "image.crop_offset_x"),
        ("crop_height = 0", "image.crop_height"),
    ] {
        let err = irradia_scene::load_str(&base(image), SceneSyntax::Toml, Path::new("bad.toml"))
            .expect_err(image);
        let text = err.to_string();
        assert!(
            text.contains("bad.toml") && text.contains(field),
            "{image}: {text}"
        );
    }
    let ok = irradia_scene::load_str(
        &base("crop_offset_x = 5\ncrop_offset_y = 2"),
        SceneSyntax::Toml,
        Path::new("ok.toml"),
    )
    .unwrap();
    assert_eq!(
        ok.settings.crop,
        Some(CropWindow {
            x: 5,
            y: 2,
            width: 15,
            height: 8
        })
    );
}
