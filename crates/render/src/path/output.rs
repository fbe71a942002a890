//! The path tracer behind [`crate::render`]: a fixed sample budget from the scene's
//! settings, reported with the same statistics as the Whitted tracer.

use super::{render, Film, PathParams, ProgressiveOptions};
use crate::{RenderError, RenderOptions, RenderOutput, Stats};
use irradia_scene::Scene;
use std::time::Duration;

/// Path-traces `scene` at `scene.settings.spp` samples per pixel (max depth from the
/// settings, Mitsuba's convention) on the pool `options.threads` asks for.
pub fn render_output(scene: &Scene, options: &RenderOptions) -> Result<RenderOutput, RenderError> {
    let s = &scene.settings;
    let params = PathParams {
        max_depth: s.max_depth.max(1),
        ..PathParams::default()
    };
    let progressive = ProgressiveOptions {
        spp: s.spp.max(1),
        checkpoint_interval: Duration::MAX,
        ..Default::default()
    };
    let film = Film::new(s.width, s.height)?;
    let pixels = s.width as u64 * s.height as u64;
    let run = || {
        let mut done = 0u32;
        render(scene, &params, &progressive, film, |report, _| {
            if let Some(p) = &options.progress {
                // Report progress in pixels-equivalent units: a full image per pass.
                let passes = report.samples - done;
                done = report.samples;
                p(pixels * passes as u64 / s.spp.max(1) as u64);
            }
        })
    };
    let result = match options.threads {
        Some(n) => rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .map_err(|e| RenderError::Threads(e.to_string()))?
            .install(run),
        None => run(),
    }
    .map_err(|e| RenderError::Threads(e.to_string()))?;
    let c = result.counters;
    let stats = Stats {
        width: s.width,
        height: s.height,
        pixels,
        samples: c.paths,
        camera_rays: c.paths,
        reflected_rays: c.rays - c.paths,
        shadow_rays: c.shadow_rays,
        max_level: params.max_depth,
        ..Stats::default()
    };
    Ok(RenderOutput {
        image: result.film.image(),
        aovs: Vec::new(),
        stats,
        elapsed: result.elapsed,
    })
}
