//! Mitsuba's `direct` integrator against the path tracer limited to direct light
//! (`max_depth = 2`: emitters seen directly plus one bounce): on the Cornell box both
//! estimate the same integral, so the mean radiance of every surface agrees within
//! the noise, for every split of samples between the emitters and the BSDF.

use irradia_render::driver::ProgressiveOptions;
use irradia_render::path::tracer::{AccelTracer, Tracer};
use irradia_render::path::{self, PathParams};
use irradia_render::Film;
use irradia_scene::{Integrator, Scene};
use std::time::Duration;

fn render(scene: &Scene, spp: u32) -> Film {
    let params = PathParams {
        max_depth: 2,
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

/// Per object the pixel centres see: (mean luminance, squared standard error).
fn surface_means(scene: &Scene, film: &Film) -> Vec<(String, f64, f64)> {
    let (w, h) = (scene.settings.width, scene.settings.height);
    let cam = scene.camera.rays(w, h);
    let tracer = AccelTracer { scene };
    let im = film.image();
    let var = film.variance_of_mean();
    let mut acc = vec![(0.0f64, 0.0f64, 0usize); scene.objects.len()];
    for y in 0..h {
        for x in 0..w {
            let i = (y * w + x) as usize;
            // Only pixels whose every corner sees the same object (no edges).
            let ids: Vec<Option<u32>> = [(0.05, 0.05), (0.95, 0.05), (0.05, 0.95), (0.95, 0.95)]
                .iter()
                .map(|&(dx, dy)| {
                    let r = cam.ray(x as f32 + dx, y as f32 + dy);
                    tracer.intersect(&r, f32::INFINITY).map(|h| h.instance)
                })
                .collect();
            let Some(id) = ids[0] else { continue };
            if ids.iter().any(|&o| o != Some(id)) {
                continue;
            }
            let a = &mut acc[id as usize];
            a.0 += im.pixels()[i].luminance() as f64;
            a.1 += var[i];
            a.2 += 1;
        }
    }
    scene
        .objects
        .iter()
        .zip(acc)
        .filter(|(_, a)| a.2 > 20)
        .map(|(o, (s, v, n))| (o.name.clone(), s / n as f64, v / (n * n) as f64))
        .collect()
}

#[test]
fn direct_agrees_with_the_path_tracer_at_depth_two_on_the_cornell_box() {
    let mut scene = irradia_scene::builtin::load("cornell").unwrap();
    scene.settings.width = 40;
    scene.settings.height = 40;
    scene.settings.integrator = Integrator::Path;
    let reference = surface_means(&scene, &render(&scene, 256));
    assert!(reference.len() >= 6, "{reference:?}");
    for (emitter_samples, bsdf_samples) in [(1, 1), (3, 1), (2, 0), (0, 3)] {
        scene.settings.integrator = Integrator::Direct {
            emitter_samples,
            bsdf_samples,
        };
        let direct = surface_means(&scene, &render(&scene, 128));
        for ((name, m_ref, v_ref), (_, m, v)) in reference.iter().zip(&direct) {
            let sigma = (v_ref + v).sqrt();
            assert!(
                (m - m_ref).abs() <= 4.0 * sigma + 1e-3 * m_ref,
                "({emitter_samples}, {bsdf_samples}) {name}: direct {m}, path {m_ref} (σ {sigma})"
            );
        }
    }
}
