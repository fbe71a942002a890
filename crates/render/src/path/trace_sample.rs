//! One path-traced camera sample as a ray tree, for `irradia trace-pixel` on scenes
//! whose integrator is `path`: the path's segments, their shadow rays, what each vertex
//! adds (emission and next-event estimation, MIS-weighted) and why the path ended.
//!
//! The sample is drawn exactly as the renderer draws it (the same random stream, the
//! same [`FlatScene`] queries, the scalar estimator [`radiance_recorded`]), so its value
//! is what sample `i` of the pixel adds to the film in `irradia render` with the default
//! seed. (Scenes that qualify for the 8-wide kernel render those samples with it; they
//! agree with the scalar estimator to rounding.)

use super::flat_scene::FlatScene;
use super::integrator::{radiance_recorded, PathCounters, PathParams, PathScene};
use super::lights::LightSampler;
use super::progressive::pixel_sample;
use crate::raytree::{RayNode, TreeRecorder};
use irradia_core::Rgb;
use irradia_scene::Scene;

/// The tree of sample `sample` of pixel `(x, y)` (inside the image) and its radiance.
pub fn trace_sample(scene: &Scene, x: u32, y: u32, sample: u32) -> (RayNode, Rgb) {
    let s = &scene.settings;
    let params = PathParams {
        max_depth: s.max_depth.max(1),
        ..PathParams::default()
    };
    let lights = LightSampler::new(scene);
    let ps = PathScene::new(scene, FlatScene::new(scene), &lights);
    let cam = scene.camera.rays(s.width, s.height);
    let (ray, mut rng) = pixel_sample(&cam, x, y, sample, 0);
    let mut rec = TreeRecorder::default();
    let mut counters = PathCounters::default();
    let l = radiance_recorded(&ps, &params, ray, &mut rng, &mut counters, &mut rec);
    let root = rec
        .roots
        .pop()
        .expect("the camera segment always opens and closes a node");
    (root, l)
}
