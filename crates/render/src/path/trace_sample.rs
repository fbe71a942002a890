//! One path-traced camera sample as a ray tree, for `irradia trace-pixel` on scenes
//! whose integrator is `path`: the path's segments, their shadow rays, what each vertex
//! adds (emission and next-event estimation, MIS-weighted) and why the path ended.
//!
//! The sample is drawn exactly as the renderer draws it (the same random stream, the
//! same [`FlatScene`] queries, the scalar estimator [`radiance_recorded`]), so its value
//! is what sample `i` of the pixel adds to the film in `irradia render` with the default
//! seed. (Scenes that qualify for the wide kernel render those samples with it; they
//! agree with the scalar estimator to rounding.)

use super::flat_scene::FlatScene;
use super::integrator::{radiance_recorded, PathCounters, PathParams, PathScene};
use super::lights::LightSampler;
use crate::filter::FilterSampler;
use crate::raytree::{RayNode, TreeRecorder};
use crate::sampler::{camera_sample, Sampler};
use irradia_core::Rgb;
use irradia_scene::Scene;

/// The tree of sample `sample` of pixel `(x, y)` (inside the image) and its radiance.
pub fn trace_sample(scene: &Scene, x: u32, y: u32, sample: u32) -> (RayNode, Rgb) {
    let s = &scene.settings;
    let params = PathParams::for_settings(s);
    let lights = LightSampler::new(scene);
    let ps = PathScene::new(scene, FlatScene::new(scene), &lights);
    let cam = scene.camera.rays(s.width, s.height);
    let filter = FilterSampler::new(s.filter);
    let cs = camera_sample(
        &cam,
        &filter,
        Sampler::Independent { seed: 0 },
        x,
        y,
        sample,
    );
    let (ray, mut rng) = (cs.ray, cs.rng);
    let mut rec = TreeRecorder::default();
    let mut counters = PathCounters::default();
    let l = radiance_recorded(&ps, &params, ray, &mut rng, &mut counters, &mut rec);
    let root = rec
        .roots
        .pop()
        .expect("the camera segment always opens and closes a node");
    (root, l)
}
