//! irradia-render: the integrators that turn a [`Scene`] into an image.
//!
//! - [`whitted`]: the recursive ray tracer of the lecture ("Recursive Ray Tracer"),
//!   with Phong or POV-Ray shading, shadow rays through transparent objects,
//!   reflection, refraction with nested media, and ray trees ([`raytree`]).
//! - `path` (added separately): the Monte Carlo path tracer.
//!
//! [`render`] picks the integrator named by `scene.settings.integrator` and renders
//! the image tile by tile on a rayon pool ([`film`]); [`trace_pixel`] records the ray
//! tree of one pixel with the same code.

pub mod aov;
pub mod film;
pub mod integrator;
pub mod labels;
pub mod optics;
pub mod path;
pub mod raytree;
pub mod sampler;
pub mod stats;
pub mod whitted;

pub use aov::Aov;
pub use integrator::{AovSample, Integrator};
pub use raytree::{RayKind, RayNode};
pub use stats::Stats;
pub use whitted::Whitted;

use irradia_core::{Image, ImageError, Rgb};
use irradia_scene::{Integrator as Method, Scene};
use std::sync::Arc;
use std::time::Duration;
use thiserror::Error;

#[derive(Debug, Error)]
pub enum RenderError {
    #[error(transparent)]
    Image(#[from] ImageError),
    #[error("cannot start the render threads: {0}")]
    Threads(String),
    #[error("pixel ({x}, {y}) is outside the {width}x{height} image")]
    PixelOutside {
        x: u32,
        y: u32,
        width: u32,
        height: u32,
    },
    #[error("trace-pixel records the whitted and path integrators; this scene's integrator is direct (render it with --integrator path and --max-depth 2 to trace its direct light)")]
    TraceDirect,
}

/// How to render (what to render is in the scene's settings).
#[derive(Clone)]
pub struct RenderOptions {
    /// Worker threads; `None` uses rayon's global pool (one per core).
    pub threads: Option<usize>,
    /// Side of the square tiles the image is cut into, in pixels.
    pub tile_size: u32,
    /// Extra images to produce.
    pub aovs: Vec<Aov>,
    /// Called after each tile with the number of pixels it finished (from any thread).
    pub progress: Option<Arc<dyn Fn(u64) + Send + Sync>>,
}

impl Default for RenderOptions {
    fn default() -> Self {
        Self {
            threads: None,
            tile_size: 32,
            aovs: Vec::new(),
            progress: None,
        }
    }
}

impl std::fmt::Debug for RenderOptions {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("RenderOptions")
            .field("threads", &self.threads)
            .field("tile_size", &self.tile_size)
            .field("aovs", &self.aovs)
            .finish()
    }
}

/// A rendered image with its AOVs and statistics.
#[derive(Debug)]
pub struct RenderOutput {
    /// Linear radiance.
    pub image: Image,
    /// Raw AOV images in the order they were asked for.
    pub aovs: Vec<(Aov, Image)>,
    pub stats: Stats,
    /// Wall time of the render (not counting scene loading or file writing).
    pub elapsed: Duration,
}

/// Renders `scene` with the integrator its settings name.
/// The scene's `[[labels]]` are drawn over the image ([`labels::draw_labels`]).
pub fn render(scene: &Scene, options: &RenderOptions) -> Result<RenderOutput, RenderError> {
    let mut out = match scene.settings.integrator {
        Method::Whitted => film::render_with(&Whitted::new(scene), scene, options),
        Method::Path | Method::Direct { .. } => path::output::render_output(scene, options),
    }?;
    labels::draw_labels(scene, &mut out.image);
    Ok(out)
}

/// The ray tree of sample `sample` of pixel (x, y) (x right, y down from the top left),
/// traced by the scene's integrator exactly as [`render`] traces it (Whitted: the ray
/// tree; path: the path's segments and shadow rays, [`path::trace_sample`]). Returns
/// the tree and the sample's radiance.
pub fn trace_pixel(
    scene: &Scene,
    x: u32,
    y: u32,
    sample: u32,
) -> Result<(RayNode, Rgb), RenderError> {
    let s = &scene.settings;
    if x >= s.width || y >= s.height {
        return Err(RenderError::PixelOutside {
            x,
            y,
            width: s.width,
            height: s.height,
        });
    }
    match s.integrator {
        Method::Path => return Ok(path::trace_sample::trace_sample(scene, x, y, sample)),
        Method::Direct { .. } => return Err(RenderError::TraceDirect),
        Method::Whitted => {}
    }
    let cam = scene.camera.rays(s.width, s.height);
    let spp = if s.adaptive_threshold.is_some() {
        1
    } else {
        s.spp.max(1)
    };
    let (ray, mut rng) = film::camera_sample(&cam, x, y, sample.min(spp - 1), spp);
    let mut rec = raytree::TreeRecorder::default();
    let mut stats = Stats::default();
    let mut aov = AovSample::default();
    let c = Whitted::new(scene).sample_recorded(&ray, &mut rng, &mut stats, &mut aov, &mut rec);
    let root = rec
        .roots
        .pop()
        .expect("the camera ray always opens and closes a node");
    Ok((root, c))
}
