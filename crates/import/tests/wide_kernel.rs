//! The speed suite's scenes that qualify for the wide path kernel, imported from
//! Mitsuba XML, run in it sample for sample: the kernel's samples are the scalar
//! estimator's (same random streams) up to rounding, as crates/render/tests/path_wide*.rs
//! check for hand-built scenes. `suite/glass_mirror.xml`: the Cornell box with a smooth
//! `dielectric` and a smooth `conductor` sphere; `suite/veach_mis.xml`: four GGX
//! `roughconductor` plates of α 0.005 to 0.1, four emissive spheres and a dim
//! `constant` sky; `veach_mis_black.xml`: the same without its sky;
//! `suite/rough_balls.xml`: a GGX `roughconductor`, `roughdielectric` and `roughplastic`
//! ball under Mitsuba's museum.exr `envmap`.

use irradia_core::{Rgb, Rng};
use irradia_import::{load, Options};
use irradia_render::filter::FilterSampler;
use irradia_render::path::flat_scene::FlatScene;
use irradia_render::path::integrator::{radiance_in, PathScene};
use irradia_render::path::lights::LightSampler;
use irradia_render::path::wide::{samples_agreeing, WideScene};
use irradia_render::path::{PathCounters, PathParams};
use irradia_render::sampler::{camera_sample, Sampler};
use std::path::Path;

#[test]
fn imported_glass_mirror_scene_runs_in_the_wide_kernel_sample_for_sample() {
    agrees_with_the_scalar_estimator("suite/glass_mirror.xml", 2);
}

#[test]
fn imported_veach_mis_scene_runs_in_the_wide_kernel_sample_for_sample() {
    agrees_with_the_scalar_estimator("suite/veach_mis.xml", 4);
}

#[test]
fn imported_rough_balls_scene_runs_in_the_wide_kernel_sample_for_sample() {
    agrees_with_the_scalar_estimator("suite/rough_balls.xml", 3);
}

#[test]
fn imported_veach_mis_scene_without_its_sky_runs_in_the_wide_kernel_sample_for_sample() {
    agrees_with_the_scalar_estimator("veach_mis_black.xml", 4);
}

/// The scene `file` of bench/pathtrace/ at 32 x 32, 2 spp: its `spheres` spheres stay
/// unbaked, it qualifies, its samples agree with the scalar estimator's, and another
/// stream's do not.
fn agrees_with_the_scalar_estimator(file: &str, spheres: usize) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../bench/pathtrace")
        .join(file);
    let opts = Options {
        defines: vec![("res".into(), "32".into())],
        strict: false,
    };
    let (scene, _) = load(&path, &opts).unwrap_or_else(|e| panic!("{file} imports: {e}"));
    let params = PathParams::for_settings(&scene.settings);
    let lights = LightSampler::new(&scene);
    let ps = PathScene::new(&scene, FlatScene::new(&scene), &lights);
    assert_eq!(
        ps.tracer.generic_objects(),
        spheres,
        "{file}: the spheres are not baked"
    );
    let wide = WideScene::new(&ps).expect("the scene qualifies for the wide kernel");
    let (w, h) = (scene.settings.width, scene.settings.height);
    assert!(w <= 32 && h <= 32, "{w} x {h}");
    let cam = scene.camera.rays(w, h);
    let filter = FilterSampler::new(Default::default());
    let spp = 2u32;
    let n = (w * h * spp) as usize;
    let sample = |k: usize, seed: u32| -> (irradia_core::Ray, Rng) {
        let (pixel, i) = (k as u32 / spp, k as u32 % spp);
        let s = camera_sample(
            &cam,
            &filter,
            Sampler::Independent { seed },
            pixel % w,
            pixel / w,
            i,
        );
        (s.ray, s.rng)
    };
    let scalar = |seed: u32| -> Vec<Rgb> {
        let mut c = PathCounters::default();
        (0..n)
            .map(|k| {
                let (ray, mut rng) = sample(k, seed);
                radiance_in(&ps, &params, ray, &mut rng, &mut c)
            })
            .collect()
    };
    let mut out = vec![Rgb::splat(f32::NAN); n];
    let mut c = PathCounters::default();
    wide.radiance_batch(&params, |k| sample(k, 0), &mut out, &mut c);
    assert!(out.iter().all(|c| c.is_finite()), "unwritten sample");
    let same = samples_agreeing(&scalar(0), &out);
    println!("{file}: {:.2}% of samples agree", same * 100.0);
    assert!(same > 0.999, "only {:.1}% of samples agree", same * 100.0);
    // The comparison can fail: another stream's samples do not agree (counted where
    // the kernel's sample is not black: most paths leave the scene at once, and black
    // agrees with black in any stream).
    let lit: Vec<usize> = (0..n).filter(|&k| !out[k].is_black()).collect();
    assert!(lit.len() > n / 10, "{} of {n} samples lit", lit.len());
    let pick = |v: &[Rgb]| -> Vec<Rgb> { lit.iter().map(|&k| v[k]).collect() };
    let chance = samples_agreeing(&pick(&scalar(7)), &pick(&out));
    assert!(chance < 0.5, "{:.1}% agree by chance", chance * 100.0);
}
