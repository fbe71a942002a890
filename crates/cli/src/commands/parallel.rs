//! `irradia parallel`: one frame rendered sort-first, sort-middle or sort-last by N ranks
//! (threads, or MPI processes under `mpirun` with `--comm mpi`), composited, written to
//! an image, with a per-rank, per-stage JSON report. The workload is a generator (random
//! triangles, teapot, marching cubes) or a scene (file or built-in); each rank runs the
//! software rasterizer or the ray tracer.

use crate::error::CliError;
use crate::output;
use crate::progress::Progress;
use crate::scene_arg::{load_scene, SceneArgs};
use clap::{Args, ValueEnum};
use irradia_core::Image;
use irradia_parallel::comm::{run_local, Comm, CommError, LocalOptions};
use irradia_parallel::composite::Strategy;
use irradia_parallel::display_tiles::DisplayLayout;
use irradia_parallel::job::Mode;
use irradia_parallel::raytrace_last;
use irradia_parallel::render_job::{
    self, summary, JobInput, RankOutcome, RenderJob, Renderer as JobRenderer, StageNarrator,
};
use irradia_parallel::sort_first::{Assign, Tiling};
use irradia_parallel::workload::Workload;
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
    /// Output image (.png, .exr or .pfm), written by rank 0; with --display-tiles each
    /// display's tile is written beside it as NAME-ROW-COL.png.
    #[arg(short, long, value_name = "FILE", default_value = "parallel.png")]
    pub output: PathBuf,
    /// Per-rank, per-stage report (bytes, messages, time, load imbalance) as JSON, with a
    /// "balance" section: estimated work per rank for the regions used and for strips.
    #[arg(long, value_name = "FILE.json")]
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
    /// Print nothing but errors (no progress, no summary).
    #[arg(short, long, help_heading = "General options")]
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

fn input(m: String) -> CliError {
    CliError::Input(m)
}

/// The workload named by `--workload`, as the ranks render it.
fn load_input(a: &ParallelArgs, mode: Mode) -> Result<JobInput, CliError> {
    if let Some(w) = Workload::by_name(&a.workload, a.triangles) {
        if a.renderer == Renderer::Raytrace {
            return Err(input(format!(
                "--renderer raytrace --workload {}: the ray tracer renders scenes; give a scene file or builtin:NAME (a scene file can hold a generator object: type = \"generator\", see docs/scene-format.md)",
                w.name()
            )));
        }
        let (width, height) = (a.width.unwrap_or(640), a.height.unwrap_or(480));
        check_size(width, height)?;
        return Ok(JobInput::generator(&w, width, height));
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
            a.quiet,
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
        load_scene(Some(&path), &scene_args, a.quiet)?
    };
    check_size(scene.settings.width, scene.settings.height)?;
    let name = a.workload.clone();
    if a.renderer == Renderer::Raytrace {
        if scene.settings.integrator.is_monte_carlo() && !a.quiet && is_display_process(a) {
            eprintln!("note: the parallel ray tracer is the Whitted tracer; the scene's `integrator = \"path\"` is not used (compare with `irradia render --integrator whitted`)");
        }
        return Ok(JobInput::Scene { name, scene });
    }
    let r = JobInput::rasterized(&name, &scene, a.tessellation, mode).map_err(input)?;
    if !r.skipped.is_empty() && !a.quiet && is_display_process(a) {
        eprintln!(
            "warning: {} object(s) could not be made into triangles and are left out of the raster image (open surfaces without facets, or no surface found at --tessellation {}): {}",
            r.skipped.len(),
            a.tessellation,
            r.skipped.join(", ")
        );
    }
    Ok(r.input)
}

fn check_size(width: u32, height: u32) -> Result<(), CliError> {
    if width == 0 || height == 0 || width as u64 * height as u64 > 1 << 26 {
        return Err(input(format!(
            "--width {width} --height {height}: expected 1 to 67M pixels"
        )));
    }
    Ok(())
}

/// Checks the options that depend on one another, before any work.
fn check_options(a: &ParallelArgs, mode: Mode) -> Result<Option<(u32, u32)>, CliError> {
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
    Ok(grid)
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
    let grid = check_options(&a, mode)?;
    output::check_image("-o", &a.output)?;
    if let Some(r) = &a.report {
        output::check_file("--report", r, &["json"])?;
    }
    let job_input = load_input(&a, mode)?;
    let (width, height) = job_input.size();
    let display = match grid {
        Some((c, r)) => Some((
            DisplayLayout::grid(width, height, c, r, a.display_overlap)
                .map_err(|e| input(format!("--display-tiles: {e}")))?,
            c,
        )),
        None => None,
    };
    let job = RenderJob {
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
        renderer: match a.renderer {
            Renderer::Raster => JobRenderer::Raster,
            Renderer::Raytrace => JobRenderer::Raytrace,
        },
        object_shading: match a.object_shading {
            ObjectShadingArg::Local => raytrace_last::Shading::Local,
            ObjectShadingArg::WhittedOwnObjects => raytrace_last::Shading::WhittedOwnObjects,
            ObjectShadingArg::Forward => raytrace_last::Shading::Local,
        },
        forward: a.object_shading == ObjectShadingArg::Forward,
        input: job_input,
    };
    let timeout = Duration::from_secs_f64(a.timeout);
    let outcome = match a.comm {
        CommKind::Local => {
            let out = run_local(
                a.ranks,
                LocalOptions {
                    timeout,
                    delay: None,
                },
                |c| one_frame(c, &job, a.quiet),
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
            first.ok_or_else(|| CliError::Failure("rank 0 returned no result".into()))?
        }
        CommKind::Mpi => mpi_frame(&job, timeout, a.quiet)?,
    };
    let RankOutcome {
        image,
        report,
        balance,
        tile,
    } = outcome;
    write_tile(&job, &a, tile)?;
    let Some(report) = report else {
        return Ok(()); // not rank 0
    };
    if !a.quiet {
        for line in summary::summary_lines(&job, &report, balance.as_ref()) {
            eprintln!("{line}");
        }
    }
    if let Some(image) = &image {
        irradia_core::io::save(image, &a.output).map_err(|e| CliError::Failure(e.to_string()))?;
        if !a.quiet {
            eprintln!("Wrote {}", a.output.display());
        }
    }
    if let Some(path) = &a.report {
        let text = summary::report_json(&report, balance.as_ref());
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

/// Writes a display rank's tile next to `-o` (nothing without a tile).
fn write_tile(
    job: &RenderJob,
    a: &ParallelArgs,
    tile: Option<(usize, Image)>,
) -> Result<(), CliError> {
    let (Some((index, image)), Some((layout, columns))) = (tile, &job.display) else {
        return Ok(());
    };
    let path = render_job::tile_path(&a.output, *columns, index);
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

/// One rank's frame; rank 0 reports the stage it is in while it runs (a bar on a
/// terminal, log lines otherwise; nothing with `--quiet`).
fn one_frame<C: Comm>(c: &C, job: &RenderJob, quiet: bool) -> Result<RankOutcome, CommError> {
    let progress = (c.rank() == 0 && !quiet).then(|| {
        let narrator = StageNarrator::new(job, c.size());
        let p = std::sync::Arc::new(Progress::new("parallel", false));
        p.message(&narrator.start());
        let shown = p.clone();
        c.log()
            .on_stage(move |stage| shown.message(&narrator.stage(stage)));
        p
    });
    let outcome = render_job::run_rank(c, job);
    if let Some(p) = progress {
        p.finish();
    }
    outcome
}

#[cfg(feature = "mpi")]
fn mpi_frame(job: &RenderJob, timeout: Duration, quiet: bool) -> Result<RankOutcome, CliError> {
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
    one_frame(&comm, job, quiet).map_err(|e| -> CliError {
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
fn mpi_frame(_: &RenderJob, _: Duration, _: bool) -> Result<RankOutcome, CliError> {
    Err(CliError::Input(
        "--comm mpi: this irradia was built without MPI; rebuild with `cargo build --release -p irradia --features mpi`".into(),
    ))
}
