//! One frame of `irradia parallel` as a library call: what the ranks render
//! ([`JobInput`]), how ([`RenderJob`]), and what each rank ends with ([`RankOutcome`]).
//! [`run_rank`] is the dispatch every rank runs (threads or MPI alike): the raster
//! sorting schemes of Molnar, Cox, Ellsworth and Fuchs (1994), the ray tracer
//! image-parallel (sort-first), object-parallel by ray casting or by ray forwarding
//! (sort-last), and sort-last composited onto a tiled display.
//!
//! `input.rs` prepares the workload, `balance.rs` packs the per-rank statistics into
//! the report's "balance" and "forwarding" sections, `summary.rs` writes the report
//! (the text summary and the JSON file).

pub mod balance;
pub mod input;
pub mod summary;

pub use input::JobInput;

use crate::comm::{Comm, CommError};
use crate::composite::{CompositeOptions, Layer, Strategy, FAR};
use crate::display_tiles::{composite_to_tiles, composite_to_tiles_bounded, DisplayLayout};
use crate::job::{self, Mode};
use crate::report::Report;
use crate::sort_first::{self, TileLayout, Tiling};
use crate::{raytrace_first, raytrace_forward, raytrace_last, sort_last};
use irradia_core::{Image, Rgb};
use irradia_raster::{Pipeline, Triangle};
use std::path::{Path, PathBuf};

/// The renderer of each rank.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Renderer {
    /// The software rasterization pipeline (crates/raster).
    Raster,
    /// The Whitted ray tracer (scenes only).
    Raytrace,
}

/// Everything the ranks need for one frame.
pub struct RenderJob {
    pub mode: Mode,
    /// The compositor of sort-last.
    pub strategy: Strategy,
    /// How sort-first (and ray forwarding) cut the screen into regions.
    pub tiling: Tiling,
    pub renderer: Renderer,
    /// How sort-last ray casting shades hits on a rank's own objects.
    pub object_shading: raytrace_last::Shading,
    /// Sort-last ray tracing with ray forwarding (the full Whitted tracer).
    pub forward: bool,
    pub input: JobInput,
    /// Sort-last onto a tiled display, and the grid's column count (for file names).
    pub display: Option<(DisplayLayout, u32)>,
}

impl RenderJob {
    /// The image size.
    pub fn size(&self) -> (u32, u32) {
        self.input.size()
    }
}

/// What one rank ends with: rank 0 the image, the report and its extra sections; a
/// display rank of a tiled display its tile.
pub struct RankOutcome {
    pub image: Option<Image>,
    pub report: Option<Report>,
    /// The report's "balance" (sort-first) or "forwarding" (ray forwarding) section.
    pub balance: Option<serde_json::Value>,
    /// With a tiled display: this rank's tile (its index in the layout, the image).
    pub tile: Option<(usize, Image)>,
}

/// Renders one frame on this rank; every rank of `c` calls it.
pub fn run_rank<C: Comm>(c: &C, job: &RenderJob) -> Result<RankOutcome, CommError> {
    let n = c.size();
    let (image, balance) = match &job.input {
        JobInput::Triangles {
            tris,
            pipeline: p,
            background,
            ..
        } => {
            if let Some((layout, _)) = &job.display {
                let tile = raster_tile(c, job.strategy, layout, p, tris, *background)?;
                return tile_outcome(c, tile);
            }
            let (img, layout) = job::run_tiled(c, job.mode, p, tris, job.strategy, job.tiling)?;
            let balance = match (&img, layout) {
                (Some(_), Some(layout)) => {
                    let costs = sort_first::raster_costs(p, tris, &layout);
                    let strips = TileLayout::strips(p.width, p.height, n);
                    let strip_costs = sort_first::raster_costs(p, tris, &strips);
                    Some(balance::balance_json(
                        job.tiling,
                        &layout,
                        &costs,
                        &strips,
                        &strip_costs,
                        None,
                    ))
                }
                _ => None,
            };
            (img.as_ref().map(|l| layer_image(l, *background)), balance)
        }
        JobInput::Scene { scene, .. } => match job.mode {
            Mode::SortFirst => {
                let r = raytrace_first::render(c, scene, job.tiling, 0)?;
                c.log().begin_stage("balance");
                let balance = balance::raytrace_balance(c, scene, job.tiling, &r)?;
                c.log().end_stage();
                (r.image.as_ref().map(raytrace_first::to_image), balance)
            }
            _ if job.forward => {
                let r = raytrace_forward::render(c, scene, job.tiling, 0)?;
                c.log().begin_stage("balance");
                let forwarding = balance::forward_json(c, &r)?;
                c.log().end_stage();
                (r.image.as_ref().map(raytrace_first::to_image), forwarding)
            }
            _ if job.display.is_some() => {
                let (layout, _) = job.display.as_ref().expect("checked");
                let layer = raytrace_last::render_layer(c, scene, job.object_shading);
                let opts = CompositeOptions::default();
                let tile = composite_to_tiles(c, job.strategy, layer, layout, &opts)?;
                let tile = tile.map(|mut l| {
                    raytrace_last::fill_background(&mut l, scene.settings.background);
                    (tile_index(layout, c.rank()), raytrace_first::to_image(&l))
                });
                return tile_outcome(c, tile);
            }
            _ => {
                let img =
                    raytrace_last::render_shaded(c, scene, job.strategy, 0, job.object_shading)?;
                (img.as_ref().map(raytrace_first::to_image), None)
            }
        },
    };
    let report = Report::gather(c)?;
    Ok(RankOutcome {
        image,
        report,
        balance,
        tile: None,
    })
}

/// Sort-last onto the tiled display: this rank's tile, background filled (raster).
fn raster_tile<C: Comm>(
    c: &C,
    strategy: Strategy,
    layout: &DisplayLayout,
    p: &Pipeline,
    tris: &[Triangle],
    background: Option<Rgb>,
) -> Result<Option<(usize, Image)>, CommError> {
    let (layer, rect) = sort_last::render_layer(c, p, tris);
    let opts = CompositeOptions::default();
    let tile = composite_to_tiles_bounded(c, strategy, layer, rect, layout, &opts)?;
    Ok(tile.map(|l| (tile_index(layout, c.rank()), layer_image(&l, background))))
}

/// The outcome of a tiled-display run: this rank's tile and (rank 0) the report.
fn tile_outcome<C: Comm>(c: &C, tile: Option<(usize, Image)>) -> Result<RankOutcome, CommError> {
    Ok(RankOutcome {
        image: None,
        report: Report::gather(c)?,
        balance: None,
        tile,
    })
}

fn tile_index(layout: &DisplayLayout, rank: usize) -> usize {
    layout
        .tiles
        .iter()
        .position(|t| t.rank == rank)
        .expect("composite_to_tiles returns a tile only to display ranks")
}

/// Where display tile `index` of a `columns`-wide grid is written, next to `output`:
/// `NAME.png` gives `NAME-ROW-COL.png`.
pub fn tile_path(output: &Path, columns: u32, index: usize) -> PathBuf {
    let (row, col) = (index / columns as usize, index % columns as usize);
    let stem = output
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "tile".into());
    let name = match output.extension() {
        Some(ext) => format!("{stem}-{row}-{col}.{}", ext.to_string_lossy()),
        None => format!("{stem}-{row}-{col}"),
    };
    output.with_file_name(name)
}

/// An RGBA8 layer as an image, with `background` where nothing opaque was drawn
/// (behind transparent surfaces, which leave the depth at the far plane: their
/// colour plus the background times what they let through, `1 - alpha`).
pub fn layer_image(l: &Layer<[u8; 4]>, background: Option<Rgb>) -> Image {
    let mut im = to_image(l);
    if let Some(bg) = background {
        for ((px, &d), c) in im.pixels_mut().iter_mut().zip(&l.depth).zip(&l.color) {
            if d == FAR {
                *px += bg * (1.0 - c[3] as f32 / 255.0);
            }
        }
    }
    im
}

/// The RGBA8 image (no transfer curve, as the rasterizer writes it) as linear colour.
pub fn to_image(l: &Layer<[u8; 4]>) -> Image {
    let px = l
        .color
        .iter()
        .map(|c| {
            Rgb::new(
                c[0] as f32 / 255.0,
                c[1] as f32 / 255.0,
                c[2] as f32 / 255.0,
            )
        })
        .collect();
    Image::from_pixels(l.width, l.height, px)
}

/// What rank 0 is doing, told stage by stage ([`crate::comm::MessageLog::on_stage`]):
/// with ray forwarding the stages alternate, a tracing pass ("render") then its queries
/// ("forward"), until no rank asks anything.
pub struct StageNarrator {
    what: String,
    forward: bool,
    forwarded: std::sync::atomic::AtomicUsize,
}

impl StageNarrator {
    pub fn new(job: &RenderJob, ranks: usize) -> Self {
        StageNarrator {
            what: format!("{} on {ranks} ranks", job.mode.name()),
            forward: job.forward,
            forwarded: std::sync::atomic::AtomicUsize::new(0),
        }
    }

    /// The job before its first stage.
    pub fn start(&self) -> String {
        self.what.clone()
    }

    /// The message for a stage that begins.
    pub fn stage(&self, stage: &str) -> String {
        use std::sync::atomic::Ordering::Relaxed;
        let what = &self.what;
        let done = self.forwarded.load(Relaxed);
        match stage {
            "render" if self.forward => format!("{what}: tracing, pass {}", done + 1),
            "forward" => {
                self.forwarded.store(done + 1, Relaxed);
                format!("{what}: forwarding the rays of pass {}", done + 1)
            }
            _ => format!("{what}: {stage}"),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tile_paths_name_row_and_column() {
        let p = tile_path(Path::new("out/wall.png"), 3, 4);
        assert_eq!(p, Path::new("out/wall-1-1.png"));
        assert_eq!(tile_path(Path::new("w"), 2, 1), Path::new("w-0-1"));
    }

    #[test]
    fn background_fills_what_nothing_covers() {
        let mut l = Layer::<[u8; 4]>::new(2, 1);
        l.color[0] = [255, 0, 0, 255];
        l.depth[0] = 0.5;
        let im = layer_image(&l, Some(Rgb::new(0.0, 0.0, 1.0)));
        assert_eq!(im.get(0, 0), Rgb::new(1.0, 0.0, 0.0));
        assert_eq!(im.get(1, 0), Rgb::new(0.0, 0.0, 1.0));
    }
}
