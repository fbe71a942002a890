//! Agreement with Mitsuba 3: the mean radiance of every surface, per RGB channel, of
//! the built-in `cornell` (Mitsuba's `mi.cornell_box()`) and of
//! `tests/data/cornell_specular.toml` (glass, a mirror and a smooth-shaded triangle
//! mesh), against values rendered by Mitsuba 3.9.1 and stored in
//! `tests/data/mitsuba_reference.json` (made by `bench/pathtrace/mitsuba_reference.py`;
//! its `note` and `mitsuba` fields say how: variant scalar_rgb, path integrator, max
//! depth 8, box filter, independent sampler, resolution, samples and seeds).
//!
//! Surfaces are Irradia's objects, masked by the stored labels (the object-id AOV at
//! the pixel centres, eroded by 2 pixels); the test first checks that Irradia's own
//! first hits still give exactly those labels. Both estimates carry a standard error
//! measured from independent renders (seeds), never from the spread of pixels: a
//! surface-channel agrees when |irradia - mitsuba| <= K sqrt(se_i² + se_m²). So that the
//! test cannot pass by being noisy, every combined standard error must be below
//! `MAX_REL_SE` of the value, and the same comparison must reject Irradia's means
//! scaled by 1.02 or 0.98 (a 2% bias) on at least `MIN_POWER` of the surface-channels.

use irradia_core::Rgb;
use irradia_render::driver::ProgressiveOptions;
use irradia_render::path::path_integrator::{render_with, Kernel};
use irradia_render::path::PathParams;
use irradia_render::Film;
use irradia_scene::Scene;
use serde_json::Value;
use std::time::{Duration, Instant};

/// Agreement within this many combined standard errors.
const K: f64 = 4.5;
/// Largest combined standard error allowed, relative to the value (most are 0.1-0.4%).
const MAX_REL_SE: f64 = 0.01;
/// Least fraction of the surface-channels that must each reject a 2% bias (the dim or
/// indirectly lit ones, with standard errors of 0.4-0.8%, may not).
const MIN_POWER: f64 = 2.0 / 3.0;
/// Erosion of the object-id masks, in pixels (as the stored labels).
const ERODE: i64 = 2;

const REFERENCE: &str = include_str!("data/mitsuba_reference.json");

fn reference() -> Value {
    serde_json::from_str(REFERENCE).expect("mitsuba_reference.json parses")
}

/// One surface of a scene: its object index and Mitsuba's mean and standard error.
struct Surface {
    name: String,
    object: i32,
    mean: [f64; 3],
    se: [f64; 3],
}

fn triple(v: &Value) -> [f64; 3] {
    let a = v.as_array().expect("an array of three numbers");
    assert_eq!(a.len(), 3);
    [0, 1, 2].map(|i| a[i].as_f64().unwrap())
}

fn surfaces(scene: &Value) -> Vec<Surface> {
    scene["surfaces"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| Surface {
            name: s["name"].as_str().unwrap().to_string(),
            object: s["object"].as_i64().unwrap() as i32,
            mean: triple(&s["mean"]),
            se: triple(&s["se"]),
        })
        .collect()
}

/// The stored labels: per pixel (rows from the top) the object index, or -1.
fn stored_labels(scene: &Value, w: usize, h: usize) -> Vec<i32> {
    let rows = scene["labels"].as_array().unwrap();
    assert_eq!(rows.len(), h);
    let mut out = Vec::with_capacity(w * h);
    for row in rows {
        let row = row.as_str().unwrap();
        assert_eq!(row.len(), w);
        out.extend(row.bytes().map(|c| match c {
            b'.' => -1,
            c => (c - b'0') as i32,
        }));
    }
    out
}

/// Irradia's first hit through every pixel centre: the object index, or -1.
fn object_ids(scene: &Scene, w: u32, h: u32) -> Vec<i32> {
    let cam = scene.camera.rays(w, h);
    let mut ids = Vec::with_capacity((w * h) as usize);
    for y in 0..h {
        for x in 0..w {
            let ray = cam.ray(x as f32 + 0.5, y as f32 + 0.5);
            ids.push(
                scene
                    .accel
                    .intersect(&ray, f32::INFINITY)
                    .map_or(-1, |hit| hit.instance as i32),
            );
        }
    }
    ids
}

/// Keeps a pixel's id where every pixel within `r` (Chebyshev) lies in the image and has
/// the same id.
fn erode(ids: &[i32], w: usize, h: usize, r: i64) -> Vec<i32> {
    let mut out = vec![-1; ids.len()];
    for y in 0..h as i64 {
        for x in 0..w as i64 {
            let id = ids[(y * w as i64 + x) as usize];
            let keep = id >= 0
                && (-r..=r).all(|dy| {
                    (-r..=r).all(|dx| {
                        let (u, v) = (x + dx, y + dy);
                        u >= 0
                            && v >= 0
                            && u < w as i64
                            && v < h as i64
                            && ids[(v * w as i64 + u) as usize] == id
                    })
                });
            if keep {
                out[(y * w as i64 + x) as usize] = id;
            }
        }
    }
    out
}

/// Irradia's estimate of each surface's mean radiance: the mean over `batches`
/// independent renders (seeds) of `spp` samples per pixel, and its standard error from
/// the spread of the renders' surface means.
struct Estimate {
    mean: Vec<[f64; 3]>,
    se: Vec<[f64; 3]>,
}

fn irradia_estimate(
    scene: &Scene,
    params: &PathParams,
    labels: &[i32],
    surfaces: &[Surface],
    (w, h): (u32, u32),
    (batches, spp, kernel): (u32, u32, Kernel),
) -> Estimate {
    let mut per_batch: Vec<Vec<[f64; 3]>> = Vec::new();
    for b in 0..batches {
        let opts = ProgressiveOptions {
            spp,
            checkpoint_interval: Duration::from_secs(3600),
            // Seeds of their own: not the stream family of the default image (0).
            seed: 7001 + b,
            ..Default::default()
        };
        let film = render_with(
            scene,
            params,
            &opts,
            kernel,
            Film::new(w, h).unwrap(),
            |_, _| {},
        )
        .unwrap()
        .film;
        let image = film.image();
        let means = surfaces
            .iter()
            .map(|s| {
                let mut sum = [0.0f64; 3];
                let mut n = 0usize;
                for (p, &l) in image.pixels().iter().zip(labels) {
                    if l == s.object {
                        let p: Rgb = *p;
                        sum[0] += p.r as f64;
                        sum[1] += p.g as f64;
                        sum[2] += p.b as f64;
                        n += 1;
                    }
                }
                sum.map(|v| v / n as f64)
            })
            .collect();
        per_batch.push(means);
    }
    let nb = batches as f64;
    let mut mean = vec![[0.0; 3]; surfaces.len()];
    let mut se = vec![[0.0; 3]; surfaces.len()];
    for k in 0..surfaces.len() {
        for c in 0..3 {
            let m = per_batch.iter().map(|b| b[k][c]).sum::<f64>() / nb;
            let var = per_batch.iter().map(|b| (b[k][c] - m).powi(2)).sum::<f64>() / (nb - 1.0);
            mean[k][c] = m;
            se[k][c] = (var / nb).sqrt();
        }
    }
    Estimate { mean, se }
}

/// The surface-channels where Irradia's means times `scale` disagree with Mitsuba's by
/// more than K combined standard errors, as messages.
fn disagreements(est: &Estimate, surfaces: &[Surface], scale: f64) -> Vec<String> {
    let mut out = Vec::new();
    for (k, s) in surfaces.iter().enumerate() {
        for (c, channel) in ["r", "g", "b"].iter().enumerate() {
            let ours = est.mean[k][c] * scale;
            let sigma = (est.se[k][c].powi(2) * scale * scale + s.se[c].powi(2)).sqrt();
            let z = (ours - s.mean[c]) / sigma;
            if z.abs() > K {
                out.push(format!(
                    "{} {channel}: irradia {ours:.5} mitsuba {:.5} ({:+.2}%), {z:+.1} sigma",
                    s.name,
                    s.mean[c],
                    (ours / s.mean[c] - 1.0) * 100.0
                ));
            }
        }
    }
    out
}

/// Renders `scene` with Irradia's path tracer as the stored reference of `key` was
/// rendered and asserts agreement, the sanity bound on the standard errors, and that a
/// 2% bias would be caught.
fn check_against_mitsuba(key: &str, mut scene: Scene, batches: u32, spp: u32, kernel: Kernel) {
    let reference = reference();
    let mts = &reference["mitsuba"];
    let (w, h) = (
        mts["width"].as_u64().unwrap() as u32,
        mts["height"].as_u64().unwrap() as u32,
    );
    // The image is the scene's (a film is a window of it): render at the reference size.
    scene.settings.width = w;
    scene.settings.height = h;
    let params = PathParams {
        max_depth: mts["max_depth"].as_u64().unwrap() as u32,
        rr_depth: mts["rr_depth"].as_u64().unwrap() as u32,
    };
    assert_eq!(mts["rfilter"], "box", "Irradia's pixels are box filtered");
    let stored = &reference["scenes"][key];
    let surfaces = surfaces(stored);
    let labels = stored_labels(stored, w as usize, h as usize);

    // The stored masks are Irradia's: its first hits through the pixel centres, eroded.
    let ours = erode(&object_ids(&scene, w, h), w as usize, h as usize, ERODE);
    let differing = ours.iter().zip(&labels).filter(|(a, b)| a != b).count();
    assert_eq!(
        differing, 0,
        "{key}: {differing} pixels differ from the stored masks"
    );
    for s in &surfaces {
        assert_eq!(
            scene.objects[s.object as usize].name, s.name,
            "{key}: object {} is not `{}`",
            s.object, s.name
        );
    }

    let start = Instant::now();
    let est = irradia_estimate(
        &scene,
        &params,
        &labels,
        &surfaces,
        (w, h),
        (batches, spp, kernel),
    );
    let elapsed = start.elapsed();
    for (k, s) in surfaces.iter().enumerate() {
        println!(
            "{key} {:13} irradia {:?} ± {:?}  mitsuba {:?} ± {:?}",
            s.name,
            est.mean[k].map(|v| (v * 1e5).round() / 1e5),
            est.se[k].map(|v| (v * 1e5).round() / 1e5),
            s.mean.map(|v| (v * 1e5).round() / 1e5),
            s.se.map(|v| (v * 1e5).round() / 1e5),
        );
    }
    println!("{key}: {batches} renders of {w}x{h} at {spp} spp in {elapsed:.2?}");

    // Precise enough that a 2% bias is several standard errors.
    for (k, s) in surfaces.iter().enumerate() {
        for c in 0..3 {
            let sigma = (est.se[k][c].powi(2) + s.se[c].powi(2)).sqrt();
            assert!(
                sigma <= MAX_REL_SE * s.mean[c],
                "{key} {} channel {c}: combined standard error {sigma:.2e} is {:.2}% of {:.4}",
                s.name,
                sigma / s.mean[c] * 100.0,
                s.mean[c]
            );
        }
    }
    let bad = disagreements(&est, &surfaces, 1.0);
    assert!(
        bad.is_empty(),
        "{key}: Irradia disagrees with Mitsuba 3:\n  {}",
        bad.join("\n  ")
    );
    // Power: the same comparison rejects Irradia's means scaled by 1.02 or 0.98 (a 2%
    // bias), on most surface-channels one by one.
    let total = surfaces.len() * 3;
    for scale in [1.02, 0.98] {
        let rejected = disagreements(&est, &surfaces, scale).len();
        println!("{key}: scaled by {scale}, {rejected} of {total} surface-channels reject");
        assert!(
            rejected as f64 >= MIN_POWER * total as f64,
            "{key}: means scaled by {scale} are rejected on only {rejected} of {total} surface-channels"
        );
    }
}

fn load_specular() -> Scene {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/data/cornell_specular.toml"
    );
    irradia_scene::load_file(std::path::Path::new(path)).unwrap()
}

#[test]
fn cornell_box_agrees_with_mitsuba_per_surface_and_channel() {
    // The scalar estimator: under the test profile (opt-level 2, no LTO) it is faster
    // than the wide kernel, whose samples tests/path_wide.rs shows to be the scalar
    // estimator's.
    let scene = irradia_scene::builtin::load("cornell").unwrap();
    check_against_mitsuba("cornell", scene, 32, 16, Kernel::Scalar);
}

#[test]
fn glass_mirror_and_smooth_mesh_agree_with_mitsuba_per_surface_and_channel() {
    // Not eligible for the wide kernel (spheres, glass, mirror, a smooth mesh): scalar.
    check_against_mitsuba("cornell_specular", load_specular(), 32, 24, Kernel::Auto);
}
