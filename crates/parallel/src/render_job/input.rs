//! What the ranks of one frame render: a generator's or a scene's triangles for the
//! rasterizer, or a scene for the ray tracer; and the checks that a scene can be
//! rasterized as the job asks (something tessellates; sort-last has no transparency,
//! which depth compositing of separately drawn objects cannot order).

use crate::job::Mode;
use crate::tessellate::{solid::MAX_CELLS, Tessellation};
use crate::workload::{scene_pipeline, scene_triangles_with, Workload};
use irradia_core::Rgb;
use irradia_raster::{Pipeline, Triangle};
use irradia_scene::Scene;

/// What the ranks render (built once per job, so the size of the largest variant
/// does not matter).
#[allow(clippy::large_enum_variant)]
pub enum JobInput {
    /// Triangles for the rasterizer.
    Triangles {
        name: String,
        tris: Vec<Triangle>,
        pipeline: Pipeline,
        /// A scene's background colour, painted where nothing was drawn.
        background: Option<Rgb>,
    },
    /// A scene for the ray tracer.
    Scene { name: String, scene: Scene },
}

/// A scene made into triangles, and the objects left out (by name).
pub struct Rasterized {
    pub input: JobInput,
    pub skipped: Vec<String>,
}

impl JobInput {
    /// A generator's triangles at `width` x `height`.
    pub fn generator(w: &Workload, width: u32, height: u32) -> Self {
        JobInput::Triangles {
            name: w.name().into(),
            tris: w.triangles(),
            pipeline: w.pipeline(width, height),
            background: None,
        }
    }

    /// The scene's objects as triangles for the rasterizer (solids without facets by
    /// marching cubes at `tessellation` cells per object). Errors (a message naming the
    /// workload) when nothing tessellates, or when `mode` is sort-last and the scene has
    /// transparent materials.
    pub fn rasterized(
        name: &str,
        scene: &Scene,
        tessellation: u32,
        mode: Mode,
    ) -> Result<Rasterized, String> {
        if tessellation == 0 || tessellation > MAX_CELLS {
            return Err(format!(
                "--tessellation {tessellation}: expected 1 to {MAX_CELLS} cells"
            ));
        }
        let opts = Tessellation {
            resolution: tessellation,
        };
        let st = scene_triangles_with(scene, &opts);
        if st.triangles.is_empty() {
            return Err(format!(
                "--workload {name}: none of the scene's objects could be made into triangles for the rasterizer ({} left out: open surfaces without facets, or solids with no surface at --tessellation {tessellation}); use --renderer raytrace",
                st.skipped.join(", "),
            ));
        }
        let pipeline = scene_pipeline(scene);
        if mode == Mode::SortLast && st.has_transparency(&pipeline) {
            return Err(format!(
                "--workload {name}: the scene has transparent (`transmission`) materials, which the rasterizer draws back to front over the opaque surfaces; sort-last depth compositing of separately drawn objects cannot order them; use --mode sort-first or sort-middle, or --renderer raytrace"
            ));
        }
        Ok(Rasterized {
            input: JobInput::Triangles {
                name: name.to_string(),
                pipeline,
                tris: st.triangles,
                background: Some(scene.settings.background),
            },
            skipped: st.skipped,
        })
    }

    /// The workload's name as the user gave it.
    pub fn name(&self) -> &str {
        match self {
            JobInput::Triangles { name, .. } | JobInput::Scene { name, .. } => name,
        }
    }

    /// The image size.
    pub fn size(&self) -> (u32, u32) {
        match self {
            JobInput::Triangles { pipeline, .. } => (pipeline.width, pipeline.height),
            JobInput::Scene { scene, .. } => (scene.settings.width, scene.settings.height),
        }
    }

    /// "N triangles" or "N objects".
    pub fn describe(&self) -> String {
        match self {
            JobInput::Triangles { tris, .. } => format!("{} triangles", tris.len()),
            JobInput::Scene { scene, .. } => format!("{} objects", scene.objects.len()),
        }
    }
}
