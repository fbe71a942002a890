//! The kernel-against-scalar harness of the wide path kernel's agreement tests
//! (tests/path_wide*.rs): every pixel's samples by the scalar estimator `radiance_in`
//! and by the kernel, from the same per-sample random streams.

use irradia_core::{Ray, Rgb, Rng};
use irradia_geometry::packet::SimdBuild;
use irradia_render::filter::FilterSampler;
use irradia_render::path::flat_scene::FlatScene;
use irradia_render::path::integrator::{radiance_in, PathScene};
use irradia_render::path::lights::LightSampler;
use irradia_render::path::wide::WideScene;
use irradia_render::path::{PathCounters, PathParams};
use irradia_render::sampler::{camera_sample, Sampler};
use irradia_scene::camera::CameraRays;
use irradia_scene::Scene;

/// Which build of the wide kernel runs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Variant {
    /// What renders use on this CPU.
    Default,
    /// Every lane traced and given its light on its own.
    LaneByLane,
    /// The portable build (no AVX2).
    Portable,
    /// The AVX2 build (on a CPU that has it).
    Avx2,
    /// The AVX-512 build (on a CPU that has it).
    Avx512,
    /// The default build with the smooth conductor's and dielectric's Fresnel
    /// reflectance multiplied by this factor (a wrong kernel).
    WrongFresnel(f32),
    /// The default build with the rough conductor's α multiplied by this factor.
    WrongAlpha(f32),
    /// The default build with the emitters at infinity this many times as bright.
    WrongBackground(f32),
    /// The default build without the spheres' lane cull.
    NoSphereCull,
}

/// The camera ray and random stream of sample `i` of pixel `(x, y)` in stream family
/// `seed`, as renders make them.
pub fn pixel_sample(cam: &CameraRays, x: u32, y: u32, i: u32, seed: u32) -> (Ray, Rng) {
    let filter = FilterSampler::new(Default::default());
    let s = camera_sample(cam, &filter, Sampler::Independent { seed }, x, y, i);
    (s.ray, s.rng)
}

/// Every pixel's `spp` samples by the scalar estimator (stream family `scalar_seed`)
/// and by the wide kernel (family 0), with both sides' counters; the path counts must
/// be equal.
pub fn both_estimates_counted(
    scene: &Scene,
    spp: u32,
    params: &PathParams,
    scalar_seed: u32,
    variant: Variant,
) -> (Vec<Rgb>, Vec<Rgb>, PathCounters, PathCounters) {
    let lights = LightSampler::new(scene);
    let ps = PathScene::new(scene, FlatScene::new(scene), &lights);
    let (w, h) = (scene.settings.width, scene.settings.height);
    let cam = scene.camera.rays(w, h);
    let n = (w * h * spp) as usize;
    let mut c_scalar = PathCounters::default();
    let scalar: Vec<Rgb> = (0..n)
        .map(|k| {
            let (x, y, i) = task(k, spp, w);
            let (ray, mut rng) = pixel_sample(&cam, x, y, i, scalar_seed);
            radiance_in(&ps, params, ray, &mut rng, &mut c_scalar)
        })
        .collect();
    let (out, c_wide) = wide_estimates(&ps, spp, params, variant);
    assert_eq!(c_wide.paths, c_scalar.paths);
    (scalar, out, c_scalar, c_wide)
}

/// Pixel `(x, y)` and sample `i` of task `k` (pixel-major, `spp` per pixel, rows `w`
/// wide).
fn task(k: usize, spp: u32, w: u32) -> (u32, u32, u32) {
    let (pixel, i) = (k as u32 / spp, k as u32 % spp);
    (pixel % w, pixel / w, i)
}

/// Every pixel's `spp` samples by the wide kernel in `variant` (stream family 0), with
/// its counters.
pub fn wide_estimates(
    ps: &PathScene<'_, FlatScene>,
    spp: u32,
    params: &PathParams,
    variant: Variant,
) -> (Vec<Rgb>, PathCounters) {
    let scene = ps.scene;
    let mut wide = WideScene::new(ps).expect("the scene qualifies for the wide kernel");
    wide = match variant {
        Variant::LaneByLane => wide.lane_by_lane(),
        Variant::WrongFresnel(s) => wide.with_fresnel_scale(s),
        Variant::WrongAlpha(s) => wide.with_alpha_scale(s),
        Variant::WrongBackground(s) => wide.with_background_scale(s),
        Variant::NoSphereCull => wide.without_sphere_cull(),
        Variant::Portable => wide.with_build(SimdBuild::Portable),
        Variant::Avx2 => wide.with_build(SimdBuild::Avx2),
        Variant::Avx512 => wide.with_build(SimdBuild::Avx512),
        Variant::Default => wide,
    };
    let (w, h) = (scene.settings.width, scene.settings.height);
    let cam = scene.camera.rays(w, h);
    let mut out = vec![Rgb::splat(f32::NAN); (w * h * spp) as usize];
    let mut c_wide = PathCounters::default();
    let start = |k| {
        let (x, y, i) = task(k, spp, w);
        pixel_sample(&cam, x, y, i, 0)
    };
    wide.radiance_batch(params, start, &mut out, &mut c_wide);
    (out, c_wide)
}

/// [`both_estimates_counted`] without the counters.
pub fn both_estimates(
    scene: &Scene,
    spp: u32,
    params: &PathParams,
    scalar_seed: u32,
    variant: Variant,
) -> (Vec<Rgb>, Vec<Rgb>) {
    let (scalar, wide, _, _) = both_estimates_counted(scene, spp, params, scalar_seed, variant);
    (scalar, wide)
}

/// The AVX-512 build's estimates of every pixel's `spp` samples of `scene` against the
/// AVX2 build's, bit for bit: the two differ only in the instructions chosen for the
/// same IEEE operations. (The portable build rounds its triangle tests without FMA; it
/// is checked against the scalar estimator instead.) Returns how many builds were
/// compared with AVX2: 1, or 0 on a CPU without AVX-512.
pub fn assert_builds_agree(name: &str, scene: &Scene, spp: u32) -> usize {
    if !SimdBuild::Avx512.available() {
        return 0;
    }
    let lights = LightSampler::new(scene);
    let ps = PathScene::new(scene, FlatScene::new(scene), &lights);
    let params = PathParams::default();
    let bits = |variant| {
        let (out, _) = wide_estimates(&ps, spp, &params, variant);
        out.iter()
            .map(|c| [c.r.to_bits(), c.g.to_bits(), c.b.to_bits()])
            .collect::<Vec<_>>()
    };
    let (avx2, avx512) = (bits(Variant::Avx2), bits(Variant::Avx512));
    let differ = avx2.iter().zip(&avx512).filter(|(a, b)| a != b).count();
    assert_eq!(
        differ, 0,
        "{name}: {differ} samples of the AVX-512 build differ from AVX2's"
    );
    1
}
