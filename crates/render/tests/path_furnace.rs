//! Furnace tests of the path tracer: closed forms the estimator must converge to.

mod path_common;

use irradia_render::path::{self, Film, PathParams, ProgressiveOptions};
use std::time::Duration;

fn render(scene: &irradia_scene::Scene, spp: u32, max_depth: u32) -> Film {
    let params = PathParams {
        max_depth,
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

/// Every pixel within five of its own standard errors of `expected`, and the image mean
/// within `rel` of it.
fn assert_converges_to(film: &Film, expected: f32, rel: f32, what: &str) {
    let im = film.image();
    let mean = im.mean();
    for c in [mean.r, mean.g, mean.b] {
        assert!(
            (c - expected).abs() < rel * expected,
            "{what}: mean {c}, expected {expected}"
        );
    }
    for (p, var) in im.pixels().iter().zip(film.variance_of_mean()) {
        let sigma = var.sqrt() as f32;
        assert!(
            (p.g - expected).abs() <= 5.0 * sigma + 1e-4,
            "{what}: pixel {p:?} (σ {sigma}), expected {expected}"
        );
    }
}

/// Inside a closed surface of reflectance ρ emitting e everywhere, radiance is
/// e + ρ e + ρ² e + ... = e / (1 − ρ) in every direction.
#[test]
fn closed_sphere_converges_to_e_over_one_minus_rho() {
    for (rho, e) in [(0.5f32, 1.0f32), (0.8, 0.25)] {
        let film = render(&path_common::furnace_sphere(rho, e), 256, 400);
        assert_converges_to(&film, e / (1.0 - rho), 0.01, &format!("rho {rho}"));
    }
}

/// A diffuse object of albedo 1 in a uniform environment reflects exactly what falls
/// on it: it disappears.
#[test]
fn white_object_disappears_in_uniform_environment() {
    let film = render(&path_common::white_sphere_in_environment(0.7), 256, 400);
    assert_converges_to(&film, 0.7, 0.01, "white sphere");
}
