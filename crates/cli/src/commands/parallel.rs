//! `irradia parallel`: one frame rendered sort-first, sort-middle or sort-last by N ranks
//! (threads, or MPI processes under `mpirun` with `--comm mpi`), composited, written to
//! an image, with a per-rank, per-stage JSON report. The workload is a generator (random
//! triangles, teapot, marching cubes) or a scene (file or built-in); each rank runs the
//! software rasterizer or the ray tracer.

use crate::error::CliError;
use crate::scene_arg::{load_scene, SceneArgs};
use clap::{Args, ValueEnum};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use irradia_core::{Image, Rgb};
use irradia_parallel::comm::{run_local, Comm, CommError, LocalOptions};
use irradia_parallel::composite::{CompositeOptions, Layer, Strategy};
use irradia_parallel::display_tiles::{
    composite_to_tiles, composite_to_tiles_bounded, DisplayLayout,
};
use irradia_parallel::job::{self, Mode};
use irradia_parallel::report::Report;
use irradia_parallel::sort_first::{self, imbalance, Assign, TileLayout, Tiling};
use irradia_parallel::tessellate::{solid::MAX_CELLS, Tessellation};
use irradia_parallel::workload::{scene_pipeline, scene_triangles_with, Workload};
use irradia_parallel::{raytrace_first, raytrace_forward, raytrace_last, sort_last};
use irradia_raster::{Pipeline, Triangle};
use irradia_scene::Scene;
use std::io::IsTerminal;
use std::path::PathBuf;
use std::time::Duration;

const EXAMPLES: &str = "Examples:
  irradia parallel --mode sort-last --ranks 4 --workload teapot -o teapot.png --report r.json
  irradia parallel --mode sort-first --ranks 4 --tiles-per-rank 8 --workload marching-cubes -o g.png
  irradia parallel --mode sort-first --renderer raytrace --workload builtin:whitted -o w.png
  irradia parallel --mode sort-last --renderer raytrace --workload scene.toml --compositor radix-k
  irradia parallel --mode sort-last --renderer raytrace --object-shading forward --workload builtin:default -o f.png
  mpirun -np 4 irradia parallel --comm mpi --mode sort-first --renderer raytrace --workload builtin:csg
  irradia parallel --mode sort-last --ranks 6 --display-tiles 3x2 --display-overlap 16 -o wall.png

Workloads: random-triangles, teapot, marching-cubes (with --triangles), a scene file
(.toml or .json, as for `irradia render`), or builtin:NAME (see `irradia scenes`).
Renderers: raster (the software pipeline, per-object materials, no shadows or
reflections; a scene's objects are cut into facets, planes into cells out to the far
plane, CSG, implicit surfaces and other solids by marching cubes at --tessellation cells
per object; objects that cannot be tessellated are left out, with a warning naming them)
or raytrace (scenes only): sort-first is the Whitted ray tracer on screen tiles (the
image equals `irradia render --integrator whitted`), sort-last ray casts each rank's
objects with local shading and no shadows, reflection or refraction (those need the
other ranks' objects), then depth-composites; with --object-shading forward, sort-last
is the full Whitted tracer over the distributed objects, the rays forwarded to the
ranks owning them (the image equals `irradia render --integrator whitted`).
Tiled displays (sort-last): --display-tiles CxR composites straight onto a grid of C x R
displays driven by ranks 0..C*R-1 (row-major from the top left); each display rank
receives only its tile and writes it as NAME-ROW-COL.png next to -o NAME.png.
Exit codes: 0 done, 1 failure while working, 2 bad input.";

#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum CommKind {
    /// Ranks as threads of this process.
    Local,
    /// MPI processes: run under `mpirun -np N irradia ... --comm mpi` (needs a build with `--features mpi`).
    Mpi,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Renderer {
    /// The software rasterization pipeline (crates/raster).
    Raster,
    /// The ray tracer: Whitted on screen tiles (sort-first) or ray casting of each rank's objects (sort-last).
    Raytrace,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum AssignArg {
    /// Tile i to rank i mod N.
    Interleaved,
    /// Largest estimated cost first to the least loaded rank (costs from screen bounds).
    Cost,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum ObjectShadingArg {
    /// Local shading without shadows or secondary rays (equals a serial ray cast).
    Local,
    /// Whitted over each rank's own objects only: shows what object-parallel ray tracing loses.
    WhittedOwnObjects,
    /// The full Whitted tracer with ray forwarding: each rank shades its screen regions and sends its shadow, reflected and refracted rays to the ranks owning the objects, in generations (equals `irradia render`).
    Forward,
}

#[derive(Args, Debug)]
#[command(after_long_help = EXAMPLES)]
pub struct ParallelArgs {
    /// Sorting scheme: sort-first, sort-middle or sort-last.
    #[arg(long, default_value = "sort-last")]
    pub mode: String,
    /// Number of ranks (threads with --comm local; ignored under MPI, which has its own).
    #[arg(long, default_value_t = 4)]
    pub ranks: usize,
    /// Compositor for sort-last: direct-send, tree, binary-swap, radix-k (k = 4) or radix-N.
    #[arg(long, default_value = "binary-swap")]
    pub compositor: String,
    /// Workload: random-triangles, teapot, marching-cubes, a scene file (.toml/.json) or builtin:NAME.
    #[arg(long, default_value = "teapot")]
    pub workload: String,
    /// Raster scene workloads: marching-cubes cells along the longest side of each CSG,
    /// implicit or other solid without facets (1 to 512); plane cells cover at most
    /// 4*height/N pixels.
    #[arg(long, default_value_t = irradia_parallel::tessellate::DEFAULT_RESOLUTION)]
    pub tessellation: u32,
    /// About how many triangles a generator workload should have.
    #[arg(long, default_value_t = 20_000)]
    pub triangles: usize,
    /// Renderer of each rank.
    #[arg(long, value_enum, default_value = "raster")]
    pub renderer: Renderer,
    /// Sort-first (and sort-last with --object-shading forward, whose ranks shade screen regions): screen regions per rank (1 = one horizontal strip each; more = a grid of tiles).
    #[arg(long, default_value_t = 1)]
    pub tiles_per_rank: usize,
    /// Sort-first with tiles: how tiles are dealt out to ranks.
    #[arg(long, value_enum, default_value = "cost")]
    pub tile_assign: AssignArg,
    /// Sort-last ray tracing: how each rank shades hits on its own objects.
    #[arg(long, value_enum, default_value = "local")]
    pub object_shading: ObjectShadingArg,
    /// Image width (default 640 for generators, the scene's own for scenes).
    #[arg(long)]
    pub width: Option<u32>,
    /// Image height (default 480 for generators, the scene's own for scenes).
    #[arg(long)]
    pub height: Option<u32>,
    /// Samples per pixel of the ray tracer in sort-first (overrides the scene's).
    #[arg(long)]
    pub spp: Option<u32>,
    /// Communicator.
    #[arg(long, value_enum, default_value = "local")]
    pub comm: CommKind,
    /// Seconds a rank waits for another before ending the job with an error naming it.
    #[arg(long, default_value_t = 30.0)]
    pub timeout: f64,
    /// Output image (PNG, EXR or PFM), written by rank 0.
    #[arg(short, long)]
    pub output: Option<PathBuf>,
    /// Per-rank, per-stage report (bytes, messages, time, load imbalance) as JSON, with a
    /// "balance" section: estimated work per rank for the regions used and for strips.
    #[arg(long)]
    pub report: Option<PathBuf>,
    /// Sort-last onto a tiled display: a grid of COLUMNSxROWS displays driven by ranks
    /// 0, 1, ... (row-major from the top left); each display rank receives only its tile of
    /// the composite and writes it (-o NAME.png gives NAME-ROW-COL.png). Needs at least
    /// COLUMNS*ROWS ranks.
    #[arg(long, value_name = "COLUMNSxROWS")]
    pub display_tiles: Option<String>,
    /// With --display-tiles: pixels by which each tile reaches into its neighbours (the
    /// overlap of edge-blended projectors).
    #[arg(long, default_value_t = 0)]
    pub display_overlap: u32,
    /// Print nothing but errors.
    #[arg(long)]
    pub quiet: bool,
}

/// Parses `--display-tiles COLUMNSxROWS`.
fn parse_grid(s: &str) -> Result<(u32, u32), CliError> {
    let bad = || {
        input(format!(
            "--display-tiles {s:?}: expected COLUMNSxROWS, e.g. 3x2 (1 to 64 each)"
        ))
    };
    let (c, r) = s.split_once(['x', 'X']).ok_or_else(bad)?;
    let (c, r): (u32, u32) = (
        c.trim().parse().map_err(|_| bad())?,
        r.trim().parse().map_err(|_| bad())?,
    );
    if !(1..=64).contains(&c) || !(1..=64).contains(&r) {
        return Err(bad());
    }
    Ok((c, r))
}

/// Where display tile `index` of a `columns`-wide grid is written, next to `output`:
/// `NAME.png` gives `NAME-ROW-COL.png`.
fn tile_path(output: &std::path::Path, columns: u32, index: usize) -> PathBuf {
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

fn input(m: String) -> CliError {
    CliError::Input(m)
}

/// What the ranks render.
enum Input {
    Triangles {
        name: String,
        tris: Vec<Triangle>,
        pipeline: Pipeline,
        /// A scene's background colour, painted where nothing was drawn.
        background: Option<Rgb>,
    },
    Scene {
        name: String,
        scene: Scene,
    },
}

/// The workload named by `--workload`.
fn load_input(a: &ParallelArgs) -> Result<Input, CliError> {
    if let Some(w) = Workload::by_name(&a.workload, a.triangles) {
        let (width, height) = (a.width.unwrap_or(640), a.height.unwrap_or(480));
        check_size(width, height)?;
        return Ok(Input::Triangles {
            name: w.name().into(),
            tris: w.triangles(),
            pipeline: w.pipeline(width, height),
            background: None,
        });
    }
    let scene_args = SceneArgs {
        width: a.width,
        height: a.height,
        spp: a.spp,
        ..SceneArgs::default()
    };
    let scene = if let Some(name) = a.workload.strip_prefix("builtin:") {
        load_scene(
            None,
            &SceneArgs {
                builtin: Some(name.to_string()),
                ..scene_args
            },
        )?
    } else {
        let path = PathBuf::from(&a.workload);
        let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("");
        if !path.exists() && !matches!(ext, "toml" | "json") {
            return Err(input(format!(
                "--workload {:?}: expected random-triangles, teapot, marching-cubes, a scene file (.toml or .json) or builtin:NAME",
                a.workload
            )));
        }
        load_scene(Some(&path), &scene_args)?
    };
    check_size(scene.settings.width, scene.settings.height)?;
    Ok(Input::Scene {
        name: a.workload.clone(),
        scene,
    })
}

fn check_size(width: u32, height: u32) -> Result<(), CliError> {
    if width == 0 || height == 0 || width as u64 * height as u64 > 1 << 26 {
        return Err(input(format!(
            "--width {width} --height {height}: expected 1 to 67M pixels"
        )));
    }
    Ok(())
}

/// Everything the ranks need for one frame.
struct Job {
    mode: Mode,
    strategy: Strategy,
    tiling: Tiling,
    renderer: Renderer,
    object_shading: raytrace_last::Shading,
    /// Sort-last ray tracing with ray forwarding (`--object-shading forward`).
    forward: bool,
    input: Input,
    /// Sort-last onto a tiled display, and the grid's column count (for file names).
    display: Option<(DisplayLayout, u32)>,
    /// Show rank 0's stage and the elapsed time while the frame runs (a terminal, no
    /// `--quiet`).
    progress: bool,
}

pub fn run(a: ParallelArgs) -> Result<(), CliError> {
    let mode = Mode::parse(&a.mode).ok_or_else(|| {
        input(format!(
            "--mode {:?}: expected sort-first, sort-middle or sort-last",
            a.mode
        ))
    })?;
    let strategy = Strategy::parse(&a.compositor).ok_or_else(|| {
        input(format!("--compositor {:?}: expected direct-send, tree, binary-swap, radix-k or radix-N (N >= 2)", a.compositor))
    })?;
    if a.ranks == 0 || a.ranks > 1024 {
        return Err(input(format!("--ranks {}: expected 1 to 1024", a.ranks)));
    }
    if a.tiles_per_rank == 0 || a.tiles_per_rank > 4096 {
        return Err(input(format!(
            "--tiles-per-rank {}: expected 1 to 4096",
            a.tiles_per_rank
        )));
    }
    if a.tiles_per_rank > 1
        && mode != Mode::SortFirst
        && a.object_shading != ObjectShadingArg::Forward
    {
        return Err(input(format!(
            "--tiles-per-rank belongs to sort-first (the mode is {})",
            mode.name()
        )));
    }
    if !(a.timeout > 0.0 && a.timeout.is_finite()) {
        return Err(input(format!(
            "--timeout {}: expected a positive number of seconds",
            a.timeout
        )));
    }
    if a.renderer == Renderer::Raytrace && mode == Mode::SortMiddle {
        return Err(input(
            "--renderer raytrace --mode sort-middle: sort-middle has no meaning for the ray tracer, which has no geometry stage whose screen-space output could be sorted to rasterizers; use sort-first (image-parallel) or sort-last (object-parallel)".into(),
        ));
    }
    if a.spp.is_some() && !(a.renderer == Renderer::Raytrace && mode == Mode::SortFirst) {
        return Err(input(
            "--spp belongs to sort-first ray tracing (sort-last ray casting sends one ray through each pixel centre; the rasterizer takes no samples)".into(),
        ));
    }
    if a.object_shading != ObjectShadingArg::Local
        && !(a.renderer == Renderer::Raytrace && mode == Mode::SortLast)
    {
        return Err(input(
            "--object-shading belongs to sort-last ray tracing (--mode sort-last --renderer raytrace)".into(),
        ));
    }
    let grid = a.display_tiles.as_deref().map(parse_grid).transpose()?;
    if grid.is_some() && a.object_shading == ObjectShadingArg::Forward {
        return Err(input(
            "--object-shading forward gathers screen regions instead of compositing layers, so it cannot drive --display-tiles; use --object-shading local".into(),
        ));
    }
    if grid.is_none() && a.display_overlap > 0 {
        return Err(input("--display-overlap belongs to --display-tiles".into()));
    }
    if grid.is_some() && mode != Mode::SortLast {
        return Err(input(format!(
            "--display-tiles composites sort-last images onto displays (the mode is {}); use --mode sort-last",
            mode.name()
        )));
    }
    if let (Some((c, r)), CommKind::Local) = (grid, a.comm) {
        if (c * r) as usize > a.ranks {
            return Err(input(format!(
                "--display-tiles {c}x{r} needs one rank per display: at least {} ranks (--ranks is {})",
                c * r,
                a.ranks
            )));
        }
    }
    let input_ = load_input(&a)?;
    let name = match &input_ {
        Input::Triangles { name, .. } | Input::Scene { name, .. } => name.clone(),
    };
    let input_ = match (a.renderer, input_) {
        (Renderer::Raytrace, Input::Triangles { name, .. }) => {
            return Err(input(format!(
                "--renderer raytrace --workload {name}: the ray tracer renders scenes; give a scene file or builtin:NAME (a scene file can hold a generator object: type = \"generator\", see docs/scene-format.md)"
            )))
        }
        (Renderer::Raster, Input::Scene { name, scene }) => {
            if a.tessellation == 0 || a.tessellation > MAX_CELLS {
                return Err(input(format!(
                    "--tessellation {}: expected 1 to {MAX_CELLS} cells",
                    a.tessellation
                )));
            }
            let opts = Tessellation {
                resolution: a.tessellation,
            };
            let st = scene_triangles_with(&scene, &opts);
            if st.triangles.is_empty() {
                return Err(input(format!(
                    "--workload {name}: none of the scene's objects could be made into triangles for the rasterizer ({} left out: open surfaces without facets, or solids with no surface at --tessellation {}); use --renderer raytrace",
                    st.skipped.join(", "),
                    a.tessellation
                )));
            }
            if !st.skipped.is_empty() && !a.quiet && is_display_process(&a) {
                eprintln!(
                    "warning: {} object(s) could not be made into triangles and are left out of the raster image (open surfaces without facets, or no surface found at --tessellation {}): {}",
                    st.skipped.len(),
                    a.tessellation,
                    st.skipped.join(", ")
                );
            }
            let pipeline = scene_pipeline(&scene);
            if mode == Mode::SortLast && st.has_transparency(&pipeline) {
                return Err(input(format!(
                    "--workload {name}: the scene has transparent (`transmission`) materials, which the rasterizer draws back to front over the opaque surfaces; sort-last depth compositing of separately drawn objects cannot order them; use --mode sort-first or sort-middle, or --renderer raytrace"
                )));
            }
            Input::Triangles {
                name,
                pipeline,
                tris: st.triangles,
                background: Some(scene.settings.background),
            }
        }
        (_, i) => i,
    };
    if let Input::Scene { scene, .. } = &input_ {
        if scene.settings.integrator.is_monte_carlo() && !a.quiet && is_display_process(&a) {
            eprintln!("note: the parallel ray tracer is the Whitted tracer; the scene's `integrator = \"path\"` is not used (compare with `irradia render --integrator whitted`)");
        }
    }
    let (width, height) = match &input_ {
        Input::Triangles { pipeline, .. } => (pipeline.width, pipeline.height),
        Input::Scene { scene, .. } => (scene.settings.width, scene.settings.height),
    };
    let display = match grid {
        Some((c, r)) => Some((
            DisplayLayout::grid(width, height, c, r, a.display_overlap)
                .map_err(|e| input(format!("--display-tiles: {e}")))?,
            c,
        )),
        None => None,
    };
    let job = Job {
        display,
        mode,
        strategy,
        tiling: Tiling {
            per_rank: a.tiles_per_rank,
            assign: match a.tile_assign {
                AssignArg::Interleaved => Assign::Interleaved,
                AssignArg::Cost => Assign::Cost,
            },
        },
        renderer: a.renderer,
        object_shading: match a.object_shading {
            ObjectShadingArg::Local => raytrace_last::Shading::Local,
            ObjectShadingArg::WhittedOwnObjects => raytrace_last::Shading::WhittedOwnObjects,
            ObjectShadingArg::Forward => raytrace_last::Shading::Local,
        },
        forward: a.object_shading == ObjectShadingArg::Forward,
        input: input_,
        progress: !a.quiet && std::io::stderr().is_terminal(),
    };
    let timeout = Duration::from_secs_f64(a.timeout);
    let frame = match a.comm {
        CommKind::Local => {
            let out = run_local(
                a.ranks,
                LocalOptions {
                    timeout,
                    delay: None,
                },
                |c| one_frame(c, &job),
            );
            let mut first = None;
            for (r, res) in out.into_iter().enumerate() {
                match res.and_then(|x| x) {
                    Ok(mut v) => {
                        write_tile(&job, &a, v.tile.take())?;
                        if r == 0 {
                            first = Some(v);
                        }
                    }
                    Err(e) => {
                        let hint = timeout_hint(&e).map(|h| format!("; {h}"));
                        let hint = hint.unwrap_or_default();
                        return Err(CliError::Failure(format!("rank {r}: {e}{hint}")));
                    }
                }
            }
            first.expect("rank 0 ran")
        }
        CommKind::Mpi => mpi_frame(&job, timeout)?,
    };
    let Frame {
        image,
        report,
        balance,
        tile,
    } = frame;
    write_tile(&job, &a, tile)?;
    let Some(report) = report else {
        return Ok(()); // not rank 0
    };
    if !a.quiet {
        let what = match &job.input {
            Input::Triangles { tris, .. } => format!("{} triangles", tris.len()),
            Input::Scene { scene, .. } => format!("{} objects", scene.objects.len()),
        };
        eprintln!(
            "{} ({:?}) of {name} ({what}) on {} ranks, {width}x{height}{}:",
            mode.name(),
            job.renderer,
            report.ranks,
            match &job.display {
                Some((l, c)) => format!(" onto {} display tiles ({c} columns)", l.tiles.len()),
                None => String::new(),
            }
        );
        for s in &report.stages {
            eprintln!(
                "  {:<13} {:>9.3} ms  {:>12} bytes sent  imbalance {:.2}",
                s.name,
                s.max_seconds * 1e3,
                s.total_bytes_sent,
                s.load_imbalance
            );
        }
        if let Some(f) = balance.as_ref().and_then(|b| b.get("forwarding")) {
            eprintln!(
                "  ray forwarding: {} generations, {} exchanges of queries",
                f["generations"], f["exchanges"]
            );
            for (i, g) in f["per_generation"]
                .as_array()
                .into_iter()
                .flatten()
                .enumerate()
            {
                eprintln!(
                    "    generation {}: {} pixels traced, {} finished, {} rays, {} queries, {} bytes sent",
                    i + 1,
                    g["pixels_traced"],
                    g["pixels_finished"],
                    g["rays"],
                    g["queries"],
                    g["bytes"]
                );
            }
        } else if let Some(b) = &balance {
            eprintln!(
                "  regions: {} ({} tiles); estimated work imbalance {:.3} (strips {:.3}){}",
                b["regions"].as_str().unwrap_or(""),
                b["tiles"],
                b["estimated_imbalance"].as_f64().unwrap_or(0.0),
                b["strips_estimated_imbalance"].as_f64().unwrap_or(0.0),
                match b.get("rays_imbalance").and_then(|v| v.as_f64()) {
                    Some(x) => format!("; rays traced imbalance {x:.3}"),
                    None => String::new(),
                }
            );
        }
    }
    if let (Some(path), Some(image)) = (&a.output, &image) {
        irradia_core::io::save(image, path).map_err(|e| CliError::Failure(e.to_string()))?;
    }
    if let Some(path) = &a.report {
        let mut json: serde_json::Value = serde_json::from_str(&report.to_json())
            .map_err(|e| CliError::Failure(e.to_string()))?;
        if let (Some(obj), Some(b)) = (json.as_object_mut(), balance) {
            obj.insert("balance".into(), b);
        }
        let text =
            serde_json::to_string_pretty(&json).map_err(|e| CliError::Failure(e.to_string()))?;
        irradia_core::io::write_atomic(path, text.as_bytes())
            .map_err(|e| CliError::Failure(format!("{}: {e}", path.display())))?;
    }
    Ok(())
}

/// Whether this process prints notes (every local run; rank 0 only is not known before
/// MPI starts, so MPI runs print nothing before the frame).
fn is_display_process(a: &ParallelArgs) -> bool {
    matches!(a.comm, CommKind::Local)
}

/// What rank 0 ends with (the others: all `None`, but for their display tile).
struct Frame {
    image: Option<Image>,
    report: Option<Report>,
    balance: Option<serde_json::Value>,
    /// With a tiled display: this rank's tile (its index in the layout, the image).
    tile: Option<(usize, Image)>,
}

/// Writes a display rank's tile next to `-o` (nothing without `-o` or a tile).
fn write_tile(job: &Job, a: &ParallelArgs, tile: Option<(usize, Image)>) -> Result<(), CliError> {
    let (Some((index, image)), Some(output), Some((layout, columns))) =
        (tile, &a.output, &job.display)
    else {
        return Ok(());
    };
    let path = tile_path(output, *columns, index);
    irradia_core::io::save(&image, &path).map_err(|e| CliError::Failure(e.to_string()))?;
    if !a.quiet {
        let t = &layout.tiles[index];
        eprintln!(
            "  display {index} (rank {}): {}x{} at ({}, {}) -> {}",
            t.rank,
            t.width,
            t.height,
            t.x,
            t.y,
            path.display()
        );
    }
    Ok(())
}

/// Sort-last onto the tiled display: this rank's tile, background filled (raster).
fn raster_tile<C: Comm>(
    c: &C,
    job: &Job,
    layout: &DisplayLayout,
    p: &Pipeline,
    tris: &[Triangle],
    background: Option<Rgb>,
) -> Result<Option<(usize, Image)>, CommError> {
    let (layer, rect) = sort_last::render_layer(c, p, tris);
    let opts = CompositeOptions::default();
    let tile = composite_to_tiles_bounded(c, job.strategy, layer, rect, layout, &opts)?;
    Ok(tile.map(|l| (tile_index(layout, c.rank()), layer_image(&l, background))))
}

/// The frame of a tiled-display run: this rank's tile and (rank 0) the report.
fn tile_frame<C: Comm>(c: &C, tile: Option<(usize, Image)>) -> Result<Frame, CommError> {
    Ok(Frame {
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

/// An RGBA8 layer as an image, with `background` where nothing opaque was drawn
/// (behind transparent surfaces, which leave the depth at the far plane: their
/// colour plus the background times what they let through, `1 - alpha`).
fn layer_image(l: &Layer<[u8; 4]>, background: Option<Rgb>) -> Image {
    let mut im = to_image(l);
    if let Some(bg) = background {
        for ((px, &d), c) in im.pixels_mut().iter_mut().zip(&l.depth).zip(&l.color) {
            if d == irradia_parallel::composite::FAR {
                *px = *px + bg * (1.0 - c[3] as f32 / 255.0);
            }
        }
    }
    im
}

fn one_frame<C: Comm>(c: &C, job: &Job) -> Result<Frame, CommError> {
    let spinner = (job.progress && c.rank() == 0).then(|| stage_spinner(c, job));
    let frame = frame_body(c, job);
    if let Some(s) = spinner {
        s.finish_and_clear();
    }
    frame
}

/// A spinner with the elapsed time and the stage rank 0 is in (its message log tells it
/// each stage as it begins); with ray forwarding, the generation.
fn stage_spinner<C: Comm>(c: &C, job: &Job) -> ProgressBar {
    let bar = ProgressBar::with_draw_target(None, ProgressDrawTarget::stderr());
    bar.set_style(
        ProgressStyle::with_template("{spinner} {elapsed:>4} {msg}").expect("a valid template"),
    );
    bar.enable_steady_tick(Duration::from_millis(120));
    let what = format!("{} on {} ranks", job.mode.name(), c.size());
    bar.set_message(what.clone());
    let shown = bar.clone();
    let forward = job.forward;
    // With forwarding, stages alternate: a tracing pass ("render"), then its queries
    // ("forward"), until no rank asks anything.
    let forwarded = std::sync::atomic::AtomicUsize::new(0);
    c.log().on_stage(move |stage| {
        let done = forwarded.load(std::sync::atomic::Ordering::Relaxed);
        let msg = match stage {
            "render" if forward => format!("{what}: tracing, pass {}", done + 1),
            "forward" => {
                forwarded.store(done + 1, std::sync::atomic::Ordering::Relaxed);
                format!("{what}: forwarding the rays of pass {}", done + 1)
            }
            _ => format!("{what}: {stage}"),
        };
        shown.set_message(msg);
    });
    bar
}

fn frame_body<C: Comm>(c: &C, job: &Job) -> Result<Frame, CommError> {
    let n = c.size();
    let (image, balance) = match &job.input {
        Input::Triangles {
            tris,
            pipeline: p,
            background,
            ..
        } if job.display.is_some() => {
            let (layout, _) = job.display.as_ref().expect("checked");
            let tile = raster_tile(c, job, layout, p, tris, *background)?;
            return tile_frame(c, tile);
        }
        Input::Triangles {
            tris,
            pipeline: p,
            background,
            ..
        } => {
            let (img, layout) = job::run_tiled(c, job.mode, p, tris, job.strategy, job.tiling)?;
            let balance = match (&img, layout) {
                (Some(_), Some(layout)) => {
                    let costs = sort_first::raster_costs(p, tris, &layout);
                    let strips = TileLayout::strips(p.width, p.height, n);
                    let strip_costs = sort_first::raster_costs(p, tris, &strips);
                    Some(balance_json(
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
            let image = img.as_ref().map(|l| layer_image(l, *background));
            (image, balance)
        }
        Input::Scene { scene, .. } => match job.mode {
            Mode::SortFirst => {
                let r = raytrace_first::render(c, scene, job.tiling, 0)?;
                c.log().begin_stage("balance");
                let rays = c.gather(0, &r.rays.to_le_bytes())?;
                c.log().end_stage();
                let balance = r.image.as_ref().map(|_| {
                    let layout = raytrace_first::layout(scene, n, job.tiling);
                    let costs = raytrace_first::object_costs(scene, &layout.tiles);
                    let (w, h) = (scene.settings.width, scene.settings.height);
                    let strips = TileLayout::strips(w, h, n);
                    let strip_costs = raytrace_first::object_costs(scene, &strips.tiles);
                    let rays: Vec<f64> = rays
                        .iter()
                        .map(|b| {
                            b.get(..8)
                                .map_or(0, |b| u64::from_le_bytes(b.try_into().expect("8 bytes")))
                                as f64
                        })
                        .collect();
                    balance_json(
                        job.tiling,
                        &layout,
                        &costs,
                        &strips,
                        &strip_costs,
                        Some(&rays),
                    )
                });
                (r.image.as_ref().map(raytrace_first::to_image), balance)
            }
            _ if job.forward => {
                let r = raytrace_forward::render(c, scene, job.tiling, 0)?;
                c.log().begin_stage("balance");
                let forwarding = forward_json(c, &r)?;
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
                return tile_frame(c, tile);
            }
            _ => {
                let img =
                    raytrace_last::render_shaded(c, scene, job.strategy, 0, job.object_shading)?;
                (img.as_ref().map(raytrace_first::to_image), None)
            }
        },
    };
    let report = Report::gather(c)?;
    Ok(Frame {
        image,
        report,
        balance,
        tile: None,
    })
}

/// The "forwarding" section of the report (root only): per generation, the pixels
/// traced and finished, the queries asked by all ranks, and the bytes and rays summed
/// over the ranks; and the ranks' cache sizes.
fn forward_json<C: Comm>(
    c: &C,
    r: &raytrace_forward::ForwardResult,
) -> Result<Option<serde_json::Value>, CommError> {
    let mine: Vec<u8> = r
        .generations
        .iter()
        .flat_map(|g| [g.traced, g.finished, g.rays, g.traffic.bytes_sent])
        .chain([r.peak_log_entries as u64])
        .flat_map(u64::to_le_bytes)
        .collect();
    let all = c.gather(0, &mine)?;
    if all.is_empty() {
        return Ok(None);
    }
    let words = |b: &[u8]| -> Vec<u64> {
        b.chunks_exact(8)
            .map(|w| u64::from_le_bytes(w.try_into().expect("8 bytes")))
            .collect()
    };
    let ranks: Vec<Vec<u64>> = all.iter().map(|b| words(b)).collect();
    let generations: Vec<serde_json::Value> = r
        .generations
        .iter()
        .enumerate()
        .map(|(i, g)| {
            let sum = |k: usize| {
                ranks
                    .iter()
                    .map(|w| w.get(4 * i + k).copied().unwrap_or(0))
                    .sum::<u64>()
            };
            serde_json::json!({
                "pixels_traced": sum(0),
                "pixels_finished": sum(1),
                "rays": sum(2),
                "queries": g.traffic.queries_total,
                "bytes": sum(3),
            })
        })
        .collect();
    Ok(Some(serde_json::json!({
        "forwarding": {
            "generations": generations.len(),
            "exchanges": r.exchanges(),
            "per_generation": generations,
            "peak_log_entries_per_rank": ranks.iter().map(|w| w.last().copied().unwrap_or(0)).collect::<Vec<_>>(),
        }
    })))
}

/// The "balance" section of the report: estimated work per rank for the regions used
/// and for one strip per rank, and (ray tracer) the rays each rank traced.
fn balance_json(
    tiling: Tiling,
    layout: &TileLayout,
    costs: &[f64],
    strips: &TileLayout,
    strip_costs: &[f64],
    rays: Option<&[f64]>,
) -> serde_json::Value {
    let n = strips.tiles.len();
    let per_rank = layout.rank_costs(costs, n);
    let strip_per_rank = strips.rank_costs(strip_costs, n);
    let mut v = serde_json::json!({
        "regions": if tiling.is_strips() { "strips" } else { "tiles" },
        "tiles": layout.tiles.len(),
        "tiles_per_rank": tiling.per_rank,
        "assign": if tiling.is_strips() { "strips" } else { tiling.assign.name() },
        "estimated_cost_per_rank": per_rank,
        "estimated_imbalance": imbalance(&per_rank),
        "strips_estimated_cost_per_rank": strip_per_rank,
        "strips_estimated_imbalance": imbalance(&strip_per_rank),
        "tile_rects": layout.tiles.iter().map(|t| [t.x0, t.y0, t.x1, t.y1]).collect::<Vec<_>>(),
        "tile_owner": layout.owner,
    });
    if let Some(r) = rays {
        v["rays_per_rank"] = serde_json::json!(r);
        v["rays_imbalance"] = serde_json::json!(imbalance(r));
    }
    v
}

#[cfg(feature = "mpi")]
fn mpi_frame(job: &Job, timeout: Duration) -> Result<Frame, CliError> {
    let comm = irradia_parallel::comm::MpiComm::init(timeout)
        .ok_or_else(|| CliError::Failure("MPI was already initialised".into()))?;
    if let Some((layout, _)) = &job.display {
        if let Err(e) = layout.validate(comm.size(), layout.width, layout.height) {
            // Every rank sees the same count and exits 2; only rank 0 says why.
            if comm.rank() != 0 {
                drop(comm);
                std::process::exit(2);
            }
            return Err(CliError::Input(format!(
                "--display-tiles: {e} (start the job with `mpirun -np {}` or more)",
                layout.tiles.len()
            )));
        }
    }
    one_frame(&comm, job).map_err(|e| -> CliError {
        if let Some(hint) = timeout_hint(&e) {
            eprintln!("irradia: rank {}: {hint}", comm.rank());
        }
        comm.fail(&e)
    })
}

/// What to do about a timeout: a rank that is still rendering looks the same as one that
/// hung, so a frame whose ranks finish their work far apart needs a longer `--timeout`.
fn timeout_hint(e: &CommError) -> Option<&'static str> {
    match e {
        CommError::Timeout { .. } => Some(
            "a rank still rendering counts as silent too: if the ranks' work is that \
             uneven (a large image, a slow scene), raise --timeout",
        ),
        _ => None,
    }
}

#[cfg(not(feature = "mpi"))]
fn mpi_frame(_: &Job, _: Duration) -> Result<Frame, CliError> {
    Err(CliError::Input(
        "--comm mpi: this irradia was built without MPI; rebuild with `cargo build --release -p irradia --features mpi`".into(),
    ))
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
