//! The ray tracer in image-parallel (sort-first) form: the whole scene is replicated on
//! every rank, each rank ray traces its screen regions with the recursive (Whitted)
//! tracer of `irradia-render`, and the regions are gathered at the display rank.
//!
//! The lecture's parallel ray tracing is this scheme: primary rays are independent, so
//! a screen split needs no communication but the final gather, and secondary and shadow
//! rays find every object because every rank holds all of them. The price is memory
//! (the scene on every rank) and balance: rays cost very different amounts across the
//! screen (a mirror sphere spawns a tree of rays, the background one), so the regions
//! can be a grid of tiles dealt out by an estimate of their cost
//! ([`crate::sort_first::Tiling`]).
//!
//! Every pixel's samples and random numbers are seeded from the pixel
//! (`irradia_render::film`), so the gathered image equals the serial `irradia render`
//! bit for bit, for any rank count and tiling.

use crate::comm::{Comm, CommError};
use crate::composite::{Layer, Operator, FAR};
use crate::sort_first::{gather_tiles, overlap, points_box, TileLayout, Tiling};
use irradia_core::{Image, Rgb};
use irradia_raster::{Pipeline, Rect, ViewParams};
use irradia_render::{driver, Whitted};
use irradia_scene::Scene;
use rayon::prelude::*;

/// A projection of the scene's camera onto its image, for screen bounds.
pub fn scene_projection(scene: &Scene) -> Pipeline {
    let (w, h) = (scene.settings.width, scene.settings.height);
    let mut p = Pipeline::new(w, h);
    p.view = ViewParams::from_camera(&scene.camera, w, h, 1e-3, 1e6);
    p
}

/// Estimated ray-tracing work per tile, in rays: one camera ray per sample, plus, for
/// every object, over the pixels of the tile its projected bounding box covers, the rays
/// a hit on it spawns: one shadow ray per light sample, and a reflected (transmitted)
/// ray with its own shadow rays when the material reflects (transmits). An unbounded
/// object, or one reaching behind the eye, covers every tile.
pub fn object_costs(scene: &Scene, tiles: &[Rect]) -> Vec<f64> {
    let p = scene_projection(scene);
    let shadow: f64 = scene
        .lights
        .iter()
        .map(|l| match l {
            irradia_scene::Light::Rect { samples, .. }
            | irradia_scene::Light::Sphere { samples, .. } => (*samples).max(1) as f64,
            _ => 1.0,
        })
        .sum();
    let boxes: Vec<_> = scene
        .accel
        .instances()
        .iter()
        .zip(&scene.objects)
        .map(|(inst, obj)| {
            let m = &scene.materials[obj.material as usize];
            let mut rays = shadow;
            if !m.reflection.is_black() {
                rays += 1.0 + shadow;
            }
            if m.transmission > 0.0 {
                rays += 2.0 * (1.0 + shadow);
            }
            let b = inst.bounds();
            if !(b.min.is_finite() && b.max.is_finite()) {
                return (None, rays);
            }
            let corners = (0..8).map(|k| {
                glam::Vec3::new(
                    if k & 1 == 0 { b.min.x } else { b.max.x },
                    if k & 2 == 0 { b.min.y } else { b.max.y },
                    if k & 4 == 0 { b.min.z } else { b.max.z },
                )
            });
            (points_box(&p, corners), rays)
        })
        .collect();
    let spp = scene.settings.spp.max(1) as f64;
    tiles
        .iter()
        .map(|r| {
            let area = (r.x1 - r.x0) as f64 * (r.y1 - r.y0) as f64;
            let covered: f64 = boxes.iter().map(|(b, rays)| rays * overlap(b, r)).sum();
            spp * (area + covered)
        })
        .collect()
}

/// The regions of `tiling` for the scene's image; every rank computes the same layout
/// from its replica of the scene, so no message is needed.
pub fn layout(scene: &Scene, ranks: usize, tiling: Tiling) -> TileLayout {
    let (w, h) = (scene.settings.width, scene.settings.height);
    let l = TileLayout::unassigned(w, h, ranks, tiling);
    let costs = object_costs(scene, &l.tiles);
    TileLayout::assigned(w, h, ranks, tiling, &costs)
}

/// What one rank did: the image (at the root) and the rays this rank traced.
pub struct RankResult {
    pub image: Option<Layer<[f32; 4]>>,
    pub rays: u64,
}

/// Renders `scene` image-parallel; the image (linear radiance in RGB, alpha 1) arrives
/// at `root`. Uses the Whitted tracer whatever the scene's `integrator` says.
pub fn render<C: Comm>(
    comm: &C,
    scene: &Scene,
    tiling: Tiling,
    root: usize,
) -> Result<RankResult, CommError> {
    comm.log().begin_stage("render");
    let layout = layout(scene, comm.size(), tiling);
    let (w, h) = (scene.settings.width, scene.settings.height);
    let whitted = Whitted::new(scene);
    let mine: Vec<Rect> = layout.mine(comm.rank()).copied().collect();
    let done: Vec<_> = mine
        .par_iter()
        .map(|r| driver::render_region(&whitted, scene, r.x0, r.y0, r.x1 - r.x0, r.y1 - r.y0))
        .collect();
    let mut layer = Layer::<[f32; 4]>::new(w, h);
    let mut rays = 0;
    for (r, (colour, stats)) in mine.iter().zip(done) {
        rays += stats.total_rays();
        let tw = (r.x1 - r.x0) as usize;
        for (j, y) in (r.y0..r.y1).enumerate() {
            let row = y as usize * w as usize + r.x0 as usize;
            for i in 0..tw {
                let c = colour[j * tw + i];
                layer.color[row + i] = [c.r, c.g, c.b, 1.0];
                layer.depth[row + i] = 0.0;
            }
        }
    }
    comm.log().begin_stage("gather");
    let image = gather_tiles(comm, &layer, &layout, root, Operator::Depth)?;
    comm.barrier()?;
    comm.log().end_stage();
    Ok(RankResult { image, rays })
}

/// The RGB of a float layer as an image (pixels no rank wrote stay black).
pub fn to_image(l: &Layer<[f32; 4]>) -> Image {
    let px = l.color.iter().map(|c| Rgb::new(c[0], c[1], c[2])).collect();
    Image::from_pixels(l.width, l.height, px)
}

/// Pixels of a float layer that no rank wrote (depth still at infinity).
pub fn unwritten(l: &Layer<[f32; 4]>) -> usize {
    l.depth.iter().filter(|&&d| d == FAR).count()
}
