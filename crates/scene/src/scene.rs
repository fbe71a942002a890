//! The validated scene: camera, image and render settings, materials, lights, objects,
//! and the acceleration structure built over the objects.

use crate::camera::Camera;
use crate::label::Label;
use crate::light::Light;
use crate::material::Material;
use irradia_core::Rgb;
use irradia_geometry::{Accel, Instance};
use std::path::PathBuf;

/// Which integrator renders the scene.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Integrator {
    /// The recursive (Whitted) ray tracer with Phong shading.
    #[default]
    Whitted,
    /// The Monte Carlo path tracer (solves the rendering equation).
    Path,
    /// Direct illumination only, as Mitsuba 3's `direct` plugin: per camera hit,
    /// `emitter_samples` light samples and `bsdf_samples` BSDF samples combined by
    /// multiple importance sampling (both default 1).
    Direct {
        emitter_samples: u32,
        bsdf_samples: u32,
    },
}

impl Integrator {
    /// Whether a Monte Carlo estimator renders the scene (path or direct), so that
    /// progressive budgets and the path tracer's film apply.
    pub fn is_monte_carlo(self) -> bool {
        matches!(self, Integrator::Path | Integrator::Direct { .. })
    }
}

#[derive(Clone, Debug, PartialEq)]
pub struct RenderSettings {
    pub width: u32,
    pub height: u32,
    /// Recursion limit: camera rays have depth 1 (POV-Ray's max_trace_level).
    pub max_depth: u32,
    /// Rays whose remaining weight falls below this are not traced (POV-Ray's
    /// adc_bailout); 0 disables the cut.
    pub min_weight: f32,
    /// Samples per pixel (stratified).
    pub spp: u32,
    /// Adaptive supersampling threshold (colour difference that triggers refinement);
    /// `None` for plain stratified sampling.
    pub adaptive_threshold: Option<f32>,
    /// Radiance of rays that leave the scene.
    pub background: Rgb,
    /// Ambient light multiplied by each material's ambient coefficient.
    pub ambient_light: Rgb,
    pub integrator: Integrator,
}

impl Default for RenderSettings {
    fn default() -> Self {
        Self {
            width: 640,
            height: 480,
            max_depth: 5,
            min_weight: 1.0 / 255.0,
            spp: 1,
            adaptive_threshold: None,
            background: Rgb::BLACK,
            ambient_light: Rgb::WHITE,
            integrator: Integrator::Whitted,
        }
    }
}

/// A placed object: its instance in `Scene::accel` has the same index.
#[derive(Clone, Debug)]
pub struct Object {
    pub name: String,
    /// Material of the object (index into `Scene::materials`).
    pub material: u32,
    /// For CSG objects: the material of each leaf (by `Hit::leaf`); empty means every
    /// leaf uses `material`.
    pub leaf_materials: Vec<u32>,
}

impl Object {
    /// The material index for a hit on CSG leaf `leaf`.
    #[inline]
    pub fn material_for_leaf(&self, leaf: u32) -> u32 {
        self.leaf_materials
            .get(leaf as usize)
            .copied()
            .unwrap_or(self.material)
    }
}

#[derive(Debug)]
pub struct Scene {
    pub camera: Camera,
    pub settings: RenderSettings,
    pub materials: Vec<Material>,
    pub lights: Vec<Light>,
    pub objects: Vec<Object>,
    pub accel: Accel,
    /// The file the scene came from, if any (for messages).
    pub source: Option<PathBuf>,
    /// Captions drawn over the rendered image.
    pub labels: Vec<Label>,
}

impl Scene {
    /// Assembles a scene from its parts; builds the acceleration structure over
    /// `instances`, which must be parallel to `objects`.
    pub fn new(
        camera: Camera,
        settings: RenderSettings,
        materials: Vec<Material>,
        lights: Vec<Light>,
        objects: Vec<Object>,
        instances: Vec<Instance>,
    ) -> Self {
        assert_eq!(objects.len(), instances.len(), "one instance per object");
        Self {
            camera,
            settings,
            materials,
            lights,
            objects,
            accel: Accel::build(instances),
            source: None,
            labels: Vec::new(),
        }
    }
}
