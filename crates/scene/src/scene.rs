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
    /// The pixel filter that weights each camera sample by its position around the
    /// pixel centre (Mitsuba's `rfilter`).
    pub filter: PixelFilter,
    /// The part of the image that is rendered (Mitsuba's `crop_offset_x/y`,
    /// `crop_width/height`); `None` renders all of it.
    pub crop: Option<CropWindow>,
    /// How next-event estimation chooses the emitter it samples.
    pub light_selection: LightSelection,
    /// The family of random streams the path tracer draws from (Mitsuba's sampler
    /// `seed`): renders with different seeds are independent estimates of the same
    /// image. The command line's `--seed` overrides it.
    pub seed: u32,
}

/// How the Monte Carlo integrators choose one emitter per light sample. Both are
/// unbiased; they differ in noise (and so in the per-pixel variance that Mitsuba's
/// test criterion measures against).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum LightSelection {
    /// In proportion to each emitter's power (Irradia's default).
    #[default]
    Power,
    /// Every emitter with the same probability (Mitsuba 3's default: each emitter's
    /// `sampling_weight` is 1).
    Uniform,
}

/// A reconstruction filter, with Mitsuba 3's definitions (plugins `box`, `tent`,
/// `gaussian`): separable, `f(x, y) = f(x) f(y)` in pixel units around the pixel centre.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PixelFilter {
    /// `f(x) = 1` for `|x| <= radius` (Mitsuba's default radius 0.5: one pixel).
    Box { radius: f32 },
    /// `f(x) = max(0, 1 - |x| / radius)` (Mitsuba's default radius 1).
    Tent { radius: f32 },
    /// `f(x) = max(0, exp(-x² / (2 stddev²)) - exp(-r² / (2 stddev²)))`, cut off at
    /// `r = 4 stddev` (Mitsuba's default stddev 0.5).
    Gaussian { stddev: f32 },
}

impl Default for PixelFilter {
    fn default() -> Self {
        PixelFilter::Box { radius: 0.5 }
    }
}

/// A rectangle of the image, in pixels from the top-left corner.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct CropWindow {
    pub x: u32,
    pub y: u32,
    pub width: u32,
    pub height: u32,
}

impl RenderSettings {
    /// The rendered rectangle: the crop window, or the whole image.
    pub fn window(&self) -> CropWindow {
        self.crop.unwrap_or(CropWindow {
            x: 0,
            y: 0,
            width: self.width,
            height: self.height,
        })
    }

    /// Why the crop window does not fit the image, if it does not.
    pub fn check_crop(&self) -> Result<(), String> {
        let Some(c) = self.crop else { return Ok(()) };
        if c.width == 0
            || c.height == 0
            || c.x as u64 + c.width as u64 > self.width as u64
            || c.y as u64 + c.height as u64 > self.height as u64
        {
            return Err(format!(
                "crop window {}x{} at ({}, {}) does not fit in the {}x{} image",
                c.width, c.height, c.x, c.y, self.width, self.height
            ));
        }
        Ok(())
    }
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
            filter: PixelFilter::default(),
            crop: None,
            light_selection: LightSelection::Power,
            seed: 0,
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
