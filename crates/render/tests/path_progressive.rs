//! The path tracer's progressive machinery: resume equals an uninterrupted render,
//! thread count does not change the image, and the estimator is unbiased (the mean of
//! independent renders converges to a closed-form radiance with error falling as
//! 1/sqrt(N)).

mod path_common;

use irradia_render::driver::{ProgressiveOptions, StopReason};
use irradia_render::path::{self, PathParams};
use irradia_render::Film;
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
    let fp = path::fingerprint(&scene, &params);
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
    let err = Film::load_checkpoint(&ckpt, path::fingerprint(&scene, &other)).unwrap_err();
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

/// Unbiasedness against a closed form, not against the estimator itself: inside a
/// closed ellipsoid whose surface emits `e` everywhere and reflects by a mixture of a
/// Lambertian lobe (albedo ρ_d) and a perfect mirror (reflectance ρ_m), whose albedo is
/// ρ = ρ_d + ρ_m in every direction, the radiance is e + ρ e + ρ² e + ... = e / (1 − ρ)
/// everywhere. The mixture exercises lobe selection, MIS on emitter hits after smooth
/// bounces (weight 1 after the mirror), next-event estimation and Russian roulette.
///
/// The mean of N independent 1-sample renders (seeds 1..=N) must approach the exact
/// image with RMS error falling as 1/sqrt(N) (a bias would flatten the slope), the mean
/// over all pixels and renders must lie within 4.5 standard errors of e / (1 − ρ) (the
/// standard error from the spread of the renders' image means) while rejecting a value
/// 2% off, and the pixels' squared errors must be those of noise alone.
#[test]
fn mean_of_independent_renders_converges_as_one_over_sqrt_n() {
    let (rho_d, rho_m, e) = (0.5f32, 0.3f32, 0.25f32);
    let mut scene = path_common::furnace_sphere(rho_d, e);
    scene.materials[0].reflection = irradia_core::Rgb::splat(rho_m);
    let exact = (e / (1.0 - rho_d - rho_m)) as f64;
    let params = PathParams {
        max_depth: 200,
        rr_depth: 5,
    };
    let pixels = (scene.settings.width * scene.settings.height) as usize;
    let mut sum = vec![0.0f64; pixels];
    let mut sum_sq = vec![0.0f64; pixels];
    let mut image_means = Vec::new();
    let mut errors = Vec::new();
    let checkpoints = [4u32, 16, 64, 256, 1024];
    let n_max = *checkpoints.last().unwrap();
    for n in 1..=n_max {
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
        // The green channel (the scene is grey: all three are the same estimate).
        let values: Vec<f64> = one.pixels().iter().map(|p| p.g as f64).collect();
        for ((s, s2), v) in sum.iter_mut().zip(&mut sum_sq).zip(&values) {
            *s += v;
            *s2 += v * v;
        }
        image_means.push(values.iter().sum::<f64>() / pixels as f64);
        if checkpoints.contains(&n) {
            let mse = sum
                .iter()
                .map(|s| (s / n as f64 - exact).powi(2))
                .sum::<f64>()
                / pixels as f64;
            errors.push((n as f64, mse.sqrt()));
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

    // The mean over every pixel and render, with its standard error from the spread of
    // the independent renders' image means.
    let n = n_max as f64;
    let mean = image_means.iter().sum::<f64>() / n;
    let se = (image_means.iter().map(|m| (m - mean).powi(2)).sum::<f64>() / (n - 1.0) / n).sqrt();
    let k = 4.5;
    assert!(
        se < 0.005 * exact,
        "standard error {se} too large to tell a 2% bias"
    );
    assert!(
        (mean - exact).abs() <= k * se,
        "mean {mean} ± {se}, exact e/(1-ρ) = {exact} ({:+.1} standard errors)",
        (mean - exact) / se
    );
    for wrong in [1.02 * exact, 0.98 * exact] {
        assert!(
            (mean - wrong).abs() > k * se,
            "the comparison cannot tell {wrong} from {exact} (mean {mean} ± {se})"
        );
    }
    // Per pixel: the squared errors against the exact value are those of noise alone
    // (chi-square with one degree of freedom per pixel, each pixel's variance of the
    // mean estimated from its N samples).
    let chi2: f64 = sum
        .iter()
        .zip(&sum_sq)
        .map(|(s, s2)| {
            let m = s / n;
            let var_of_mean = (s2 / n - m * m) * n / (n - 1.0) / n;
            (m - exact).powi(2) / var_of_mean
        })
        .sum();
    let dof = pixels as f64;
    println!(
        "slope {slope:.3} (errors {errors:?}); mean {mean:.5} ± {se:.5}, exact {exact}; \
         chi-square {chi2:.1} for {dof} pixels"
    );
    assert!(
        chi2 <= dof + 5.0 * (2.0 * dof).sqrt(),
        "per-pixel chi-square {chi2:.1} for {dof} pixels"
    );
}
