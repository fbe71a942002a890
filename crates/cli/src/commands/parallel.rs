//! `irradia parallel`: one frame rendered sort-first, sort-middle or sort-last by N ranks
//! (threads, or MPI processes under `mpirun` with `--comm mpi`), composited, written to
//! an image, with a per-rank, per-stage JSON report.

use crate::error::CliError;
use clap::{Args, ValueEnum};
use irradia_core::{Image, Rgb};
use irradia_parallel::comm::{run_local, Comm, CommError, LocalOptions};
use irradia_parallel::composite::{Layer, Strategy};
use irradia_parallel::job::{self, Mode};
use irradia_parallel::report::Report;
use irradia_parallel::workload::Workload;
use std::path::PathBuf;
use std::time::Duration;

#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum CommKind {
    /// Ranks as threads of this process.
    Local,
    /// MPI processes: run as `mpirun -np N irradia parallel --comm mpi ...` (needs a build with `--features mpi`).
    Mpi,
}

#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum Renderer {
    Raster,
    Raytrace,
}

#[derive(Args, Debug)]
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
    /// Workload: random-triangles, teapot or marching-cubes.
    #[arg(long, default_value = "teapot")]
    pub workload: String,
    /// About how many triangles the workload should have.
    #[arg(long, default_value_t = 20_000)]
    pub triangles: usize,
    /// Renderer of each rank (only `raster` is available so far).
    #[arg(long, value_enum, default_value = "raster")]
    pub renderer: Renderer,
    #[arg(long, default_value_t = 640)]
    pub width: u32,
    #[arg(long, default_value_t = 480)]
    pub height: u32,
    /// Communicator.
    #[arg(long, value_enum, default_value = "local")]
    pub comm: CommKind,
    /// Seconds a rank waits for another before ending the job with an error naming it.
    #[arg(long, default_value_t = 30.0)]
    pub timeout: f64,
    /// Output image (PNG, EXR or PFM), written by rank 0.
    #[arg(short, long)]
    pub output: Option<PathBuf>,
    /// Per-rank, per-stage report (bytes, messages, time, load imbalance) as JSON.
    #[arg(long)]
    pub report: Option<PathBuf>,
    /// Print nothing but errors.
    #[arg(long)]
    pub quiet: bool,
}

fn input(m: String) -> CliError {
    CliError::Input(m)
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
    let workload = Workload::by_name(&a.workload, a.triangles).ok_or_else(|| {
        input(format!(
            "--workload {:?}: expected random-triangles, teapot or marching-cubes (scene files are not supported by `irradia parallel` yet)",
            a.workload
        ))
    })?;
    if matches!(a.renderer, Renderer::Raytrace) {
        return Err(input("--renderer raytrace: the ray-traced parallel modes are not implemented yet; use --renderer raster".into()));
    }
    if a.ranks == 0 || a.ranks > 1024 {
        return Err(input(format!("--ranks {}: expected 1 to 1024", a.ranks)));
    }
    if a.width == 0 || a.height == 0 || a.width as u64 * a.height as u64 > 1 << 26 {
        return Err(input(format!(
            "--width {} --height {}: expected 1 to 67M pixels",
            a.width, a.height
        )));
    }
    if !(a.timeout > 0.0 && a.timeout.is_finite()) {
        return Err(input(format!(
            "--timeout {}: expected a positive number of seconds",
            a.timeout
        )));
    }
    let tris = workload.triangles();
    let p = workload.pipeline(a.width, a.height);
    let timeout = Duration::from_secs_f64(a.timeout);
    let (image, report) = match a.comm {
        CommKind::Local => {
            let out = run_local(
                a.ranks,
                LocalOptions {
                    timeout,
                    delay: None,
                },
                |c| one_frame(c, mode, &p, &tris, strategy),
            );
            let mut first = None;
            for (r, res) in out.into_iter().enumerate() {
                match res.and_then(|x| x) {
                    Ok(v) if r == 0 => first = Some(v),
                    Ok(_) => {}
                    Err(e) => return Err(CliError::Failure(format!("rank {r}: {e}"))),
                }
            }
            first.expect("rank 0 ran")
        }
        CommKind::Mpi => mpi_frame(mode, &p, &tris, strategy, timeout)?,
    };
    let (Some(image), Some(report)) = (image, report) else {
        return Ok(()); // not rank 0
    };
    if !a.quiet {
        eprintln!(
            "{} of {} ({} triangles) on {} ranks, {}x{}:",
            mode.name(),
            workload.name(),
            tris.len(),
            report.ranks,
            a.width,
            a.height
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
    }
    if let Some(path) = &a.output {
        irradia_core::io::save(&to_image(&image), path)
            .map_err(|e| CliError::Failure(e.to_string()))?;
    }
    if let Some(path) = &a.report {
        irradia_core::io::write_atomic(path, report.to_json().as_bytes())
            .map_err(|e| CliError::Failure(format!("{}: {e}", path.display())))?;
    }
    Ok(())
}

type Frame = (Option<Layer<[u8; 4]>>, Option<Report>);

fn one_frame<C: Comm>(
    c: &C,
    mode: Mode,
    p: &irradia_raster::Pipeline,
    tris: &[irradia_raster::Triangle],
    strategy: Strategy,
) -> Result<Frame, CommError> {
    let img = job::run(c, mode, p, tris, strategy)?;
    let report = Report::gather(c)?;
    Ok((img, report))
}

#[cfg(feature = "mpi")]
fn mpi_frame(
    mode: Mode,
    p: &irradia_raster::Pipeline,
    tris: &[irradia_raster::Triangle],
    strategy: Strategy,
    timeout: Duration,
) -> Result<Frame, CliError> {
    let comm = irradia_parallel::comm::MpiComm::init(timeout)
        .ok_or_else(|| CliError::Failure("MPI was already initialised".into()))?;
    one_frame(&comm, mode, p, tris, strategy).map_err(|e| -> CliError { comm.fail(&e) })
}

#[cfg(not(feature = "mpi"))]
fn mpi_frame(
    _: Mode,
    _: &irradia_raster::Pipeline,
    _: &[irradia_raster::Triangle],
    _: Strategy,
    _: Duration,
) -> Result<Frame, CliError> {
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
