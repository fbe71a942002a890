//! `irradia wall --config FILE [SCENE] -o DIR [--comm local|mpi]`: one rank per display
//! renders its part of the wall, blended and colour-corrected, waits at the frame
//! barrier and writes `display-R-C.png`; rank 0 gathers the frames and writes
//! `photo.png` (the simulated photograph) and `photo-uncorrected.png` (the same wall
//! driven naively, for comparison). Ranks are threads (`--comm local`) or MPI processes
//! (`mpirun -np DISPLAYS irradia wall --comm mpi ...`); both write the same files.
//! `--render sort-last` splits the objects over the ranks instead and composites their
//! layers onto the displays' tiles (`--compositor`).

use super::parallel::CommKind;
use crate::error::CliError;
use crate::output;
use clap::{Args, ValueEnum};
use irradia_parallel::comm::{run_local, LocalOptions};
use irradia_parallel::composite::Strategy;
use irradia_parallel::wall::{job, WallConfig, WallRendering, WallSource};
use irradia_parallel::workload::Workload;
use std::path::{Path, PathBuf};
use std::time::Duration;

const EXAMPLES: &str = "\
Examples:
  irradia wall --config docs/examples/wall-3x2.toml -o wall-out            # teapot on a 3x2 projector wall
  irradia wall --config docs/examples/wall-3x2.toml grey -o grey-out       # the uniform calibration frame
  irradia wall --config docs/examples/wall-3x2.toml --render sort-last --compositor radix-k -o sl-out
  mpirun -np 6 irradia wall --comm mpi --config docs/examples/wall-3x2.toml -o wall-out

The wall file (TOML) gives the grid, the display size, overlap or bezel and each
projector's response (docs/parallel.md). The output folder receives display-R-C.png
for every display, photo.png (the simulated photograph) and photo-uncorrected.png.
Exit codes: 0 done, 1 failure while working, 2 bad input (wall file, option).";

#[derive(Args, Debug)]
#[command(after_long_help = EXAMPLES)]
pub struct WallArgs {
    /// The wall file (TOML; see docs/parallel.md): grid, display size, overlap or bezel, per-projector response.
    #[arg(long)]
    pub config: PathBuf,
    /// What to show: teapot, random-triangles, marching-cubes, or grey (a uniform 50% grey calibration frame).
    #[arg(default_value = "teapot")]
    pub scene: String,
    /// Triangles for the workload.
    #[arg(long, default_value_t = 20_000)]
    pub triangles: usize,
    /// Output folder (created if missing): display-R-C.png per display, photo.png, photo-uncorrected.png.
    #[arg(short, long)]
    pub output: PathBuf,
    /// Ranks as threads of this process (`local`), or MPI processes (`mpi`): run as
    /// `mpirun -np D irradia wall --comm mpi ...` with D = columns x rows of the wall file
    /// (one rank per display; another count exits with code 2). Needs a build with `--features mpi`.
    #[arg(long, value_enum, default_value = "local")]
    pub comm: CommKind,
    /// Seconds a rank waits for another before ending the job with an error naming it.
    #[arg(long, default_value_t = 30.0)]
    pub timeout: f64,
    /// How the displays' images are made: every display renders every object through its
    /// own frustum (`per-display`), or every rank renders its share of the objects over
    /// the whole wall and the layers are composited onto the displays (`sort-last`).
    #[arg(long, value_enum, default_value = "per-display")]
    pub render: WallRenderArg,
    /// Compositor for `--render sort-last`: direct-send, tree, binary-swap, radix-k or radix-N.
    #[arg(long, default_value = "binary-swap")]
    pub compositor: String,
    /// Print nothing but errors.
    #[arg(short, long, help_heading = "General options")]
    pub quiet: bool,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum WallRenderArg {
    /// One off-axis frustum per display, all objects on every rank.
    PerDisplay,
    /// Objects split over the ranks, depth-composited onto the displays' tiles.
    SortLast,
}

pub fn run(a: WallArgs) -> Result<(), CliError> {
    let c = WallConfig::load(&a.config).map_err(CliError::Input)?;
    let src = if a.scene == "grey" || a.scene == "gray" {
        WallSource::Uniform(glam::Vec3::splat(0.5))
    } else {
        WallSource::Workload(Workload::by_name(&a.scene, a.triangles).ok_or_else(|| {
            CliError::Input(format!(
                "scene {:?}: expected teapot, random-triangles, marching-cubes or grey",
                a.scene
            ))
        })?)
    };
    if !(a.timeout.is_finite() && a.timeout > 0.0) {
        return Err(CliError::Input(format!(
            "--timeout {}: expected a positive number of seconds",
            a.timeout
        )));
    }
    let strategy = Strategy::parse(&a.compositor).ok_or_else(|| {
        CliError::Input(format!(
            "--compositor {:?}: expected direct-send, tree, binary-swap, radix-k or radix-N (N >= 2)",
            a.compositor
        ))
    })?;
    let rendering = match a.render {
        WallRenderArg::PerDisplay => WallRendering::PerDisplay,
        WallRenderArg::SortLast => WallRendering::SortLast(strategy),
    };
    let timeout = Duration::from_secs_f64(a.timeout);
    output::prepare_folder("-o", &a.output)?;
    let wrote_all = match a.comm {
        CommKind::Local => {
            let out = run_local(
                c.displays(),
                LocalOptions {
                    timeout,
                    delay: None,
                },
                |comm| job::run_with(comm, &c, &src, &a.output, rendering),
            );
            for (r, res) in out.into_iter().enumerate() {
                match res {
                    Ok(Ok(_)) => {}
                    Ok(Err(e)) => return Err(CliError::Failure(e.to_string())),
                    Err(e) => return Err(CliError::Failure(format!("rank {r}: {e}"))),
                }
            }
            true
        }
        CommKind::Mpi => mpi_run(&c, &src, &a.config, &a.output, timeout, rendering)?,
    };
    if wrote_all && !a.quiet {
        eprintln!(
            "wrote {} display images, photo.png and photo-uncorrected.png to {}",
            c.displays(),
            a.output.display()
        );
    }
    Ok(())
}

/// The wall under `mpirun`: true on rank 0 (which reports), false elsewhere.
#[cfg(feature = "mpi")]
fn mpi_run(
    c: &WallConfig,
    src: &WallSource,
    config: &Path,
    dir: &Path,
    timeout: Duration,
    rendering: WallRendering,
) -> Result<bool, CliError> {
    use irradia_parallel::comm::{Comm, CommError, MpiComm};
    let comm = MpiComm::init(timeout)
        .ok_or_else(|| CliError::Failure("MPI was already initialised".into()))?;
    if comm.size() != c.displays() {
        let msg = format!(
            "{}: the wall has {} displays ({} x {}) and needs one MPI rank per display: \
             start it with `mpirun -np {} irradia wall --comm mpi ...` (this job has {} ranks)",
            config.display(),
            c.displays(),
            c.columns,
            c.rows,
            c.displays(),
            comm.size()
        );
        // Every rank sees the same count and exits 2; only rank 0 says why.
        if comm.rank() != 0 {
            drop(comm);
            std::process::exit(2);
        }
        return Err(CliError::Input(msg));
    }
    match job::run_with(&comm, c, src, dir, rendering) {
        Ok(_) => Ok(comm.rank() == 0),
        Err(job::WallError::Comm(e)) => comm.fail(&e),
        // A rank that cannot write its image ends the job on every rank, naming itself.
        Err(e) => comm.fail(&CommError::Aborted(e.to_string())),
    }
}

#[cfg(not(feature = "mpi"))]
fn mpi_run(
    _: &WallConfig,
    _: &WallSource,
    _: &Path,
    _: &Path,
    _: Duration,
    _: WallRendering,
) -> Result<bool, CliError> {
    Err(CliError::Input(
        "--comm mpi: this irradia was built without MPI; rebuild with `cargo build --release -p irradia --features mpi`".into(),
    ))
}
