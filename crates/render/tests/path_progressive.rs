//! The path tracer's progressive machinery: resume equals an uninterrupted render,
//! thread count does not change the image, and the estimator is unbiased (the mean of
//! independent renders converges to a reference with error falling as 1/sqrt(N)).

mod path_common;

use irradia_render::path::{self, Film, PathParams, ProgressiveOptions, StopReason};
use std::time::Duration;

fn options(spp: u32) -> ProgressiveOptions {
    ProgressiveOptions {
        spp,
        checkpoint_interval: Duration::ZERO,
        ..Default::default()
    }
}

fn new_film(scene: &irradia_scene::Scene) -> Film {
    Film::new(scene.settings.width, scene.settings.height).unwrap()
}

#[test]
fn interrupted_and_resumed_render_equals_uninterrupted() {
    let scene = path_common::small_room();
    let params = PathParams::default();
    let whole = path::render(&scene, &params, &options(12), new_film(&scene), |_, _| {}).unwrap();

    let dir = tempfile::tempdir().unwrap();
    let ckpt = dir.path().join("room.ckpt");
    let fp = path::progressive::fingerprint(&scene, &params);
    // "Interrupted" after 5 samples (a checkpoint is written at the end of every pass).
    let first = ProgressiveOptions {
        checkpoint: Some(ckpt.clone()),
        ..options(5)
    };
    path::render(&scene, &params, &first, new_film(&scene), |_, _| {}).unwrap();
    let film = Film::load_checkpoint(&ckpt, fp).unwrap();
    assert_eq!(film.samples(), 5);
    let resumed = path::render(&scene, &params, &options(12), film, |_, _| {}).unwrap();
    assert_eq!(
        resumed.film, whole.film,
        "resumed film differs from the uninterrupted one"
    );
    assert_eq!(resumed.film.image(), whole.film.image());
}

#[test]
fn checkpoint_of_another_scene_is_refused() {
    let scene = path_common::small_room();
    let params = PathParams::default();
    let dir = tempfile::tempdir().unwrap();
    let ckpt = dir.path().join("a.ckpt");
    path::render(
        &scene,
        &params,
        &ProgressiveOptions {
            checkpoint: Some(ckpt.clone()),
            ..options(2)
        },
        new_film(&scene),
        |_, _| {},
    )
    .unwrap();
    let other = PathParams {
        max_depth: 3,
        ..params
    };
    let err =
        Film::load_checkpoint(&ckpt, path::progressive::fingerprint(&scene, &other)).unwrap_err();
    assert!(err.to_string().contains("another scene"), "{err}");
    std::fs::write(&ckpt, b"garbage").unwrap();
    assert!(Film::load_checkpoint(&ckpt, 0).is_err());
}

#[test]
fn image_does_not_depend_on_thread_count() {
    let scene = path_common::small_room();
    let params = PathParams::default();
    let run = |threads| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            path::render(&scene, &params, &options(6), new_film(&scene), |_, _| {})
                .unwrap()
                .film
        })
    };
    assert_eq!(run(1), run(2));
}

#[test]
fn target_error_and_time_budget_stop_the_render() {
    let scene = path_common::small_room();
    let params = PathParams::default();
    let o = ProgressiveOptions {
        target_error: Some(0.2),
        ..options(100_000)
    };
    let r = path::render(&scene, &params, &o, new_film(&scene), |_, _| {}).unwrap();
    assert_eq!(r.stop, StopReason::TargetError);
    assert!(r.film.relative_error() <= 0.2 && r.film.samples() < 100_000);
    let o = ProgressiveOptions {
        time_limit: Some(Duration::from_millis(1)),
        ..options(100_000)
    };
    let r = path::render(&scene, &params, &o, new_film(&scene), |_, _| {}).unwrap();
    assert_eq!(r.stop, StopReason::Time);
}

/// Unbiasedness: the mean of N independent 1-sample renders approaches a reference
/// render made from other random streams, with RMS error falling as 1/sqrt(N).
#[test]
fn mean_of_independent_renders_converges_as_one_over_sqrt_n() {
    let scene = path_common::soft_room();
    let params = PathParams::default();
    let reference = path::render(
        &scene,
        &params,
        &ProgressiveOptions {
            seed: 1_000_000,
            ..options(2048)
        },
        new_film(&scene),
        |_, _| {},
    )
    .unwrap()
    .film
    .image();
    let mut sum = vec![irradia_core::Rgb::BLACK; reference.pixels().len()];
    let mut errors = Vec::new();
    let checkpoints = [4u32, 16, 64, 256];
    for n in 1..=*checkpoints.last().unwrap() {
        let one = path::render(
            &scene,
            &params,
            &ProgressiveOptions {
                seed: n,
                ..options(1)
            },
            new_film(&scene),
            |_, _| {},
        )
        .unwrap()
        .film
        .image();
        for (s, p) in sum.iter_mut().zip(one.pixels()) {
            *s += *p;
        }
        if checkpoints.contains(&n) {
            let mean = irradia_core::Image::from_pixels(
                reference.width(),
                reference.height(),
                sum.iter().map(|s| *s / n as f32).collect(),
            );
            errors.push((n as f64, mean.rmse(&reference)));
        }
    }
    // Slope of log(error) against log(N): -1/2 for an unbiased estimator; a bias would
    // flatten it towards 0.
    let (xs, ys): (Vec<f64>, Vec<f64>) = errors.iter().map(|(n, e)| (n.ln(), e.ln())).unzip();
    let mx = xs.iter().sum::<f64>() / xs.len() as f64;
    let my = ys.iter().sum::<f64>() / ys.len() as f64;
    let slope = xs
        .iter()
        .zip(&ys)
        .map(|(x, y)| (x - mx) * (y - my))
        .sum::<f64>()
        / xs.iter().map(|x| (x - mx).powi(2)).sum::<f64>();
    assert!(
        (-0.65..=-0.35).contains(&slope),
        "error slope {slope}, errors {errors:?}"
    );
}
