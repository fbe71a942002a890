//! `irradia render --comm local|mpi`: one image on several ranks
//! (`irradia_parallel::progressive`), as threads of this process or MPI processes.

use super::parallel::CommKind;
use crate::error::CliError;
use clap::Args;
use irradia_parallel::comm::{run_local, LocalOptions};
use irradia_parallel::progressive::render_distributed;
use irradia_render::{RenderOptions, RenderOutput};
use irradia_scene::Scene;
use std::time::Duration;

/// Options of a job spread over ranks (`irradia render`, `irradia radiosity`).
#[derive(Args, Debug, Clone)]
#[command(next_help_heading = "Distributed run")]
pub struct CommArgs {
    /// Spread the job over ranks: threads of this process (local) or MPI processes
    /// (mpi: `mpirun -np N irradia render|radiosity ... --comm mpi`, in a build with
    /// MPI). Rank 0 hands out the work (tiles; patch pairs of hierarchical radiosity) to
    /// whichever rank finishes first and writes the output, which equals the
    /// one-process run bit for bit.
    #[arg(long, value_enum, value_name = "KIND")]
    pub comm: Option<CommKind>,
    /// Number of ranks with --comm local (MPI takes its count from mpirun).
    #[arg(long, value_name = "N", default_value_t = 2,
          value_parser = clap::value_parser!(u32).range(1..=1024))]
    pub ranks: u32,
    /// Seconds a rank waits for another before it declares that rank dead and ends the
    /// job with an error naming it.
    #[arg(long, value_name = "SECONDS", default_value_t = 60.0)]
    pub comm_timeout: f64,
}

/// The ranks of a render, once started: under MPI this process is one of them.
pub enum Ranks {
    /// No --comm: this process renders alone.
    One,
    /// Threads of this process.
    Local(usize, Duration),
    #[cfg(feature = "mpi")]
    Mpi(irradia_parallel::comm::MpiComm),
}

impl CommArgs {
    /// Starts the ranks (MPI is initialised here, before anything is printed, so that
    /// only rank 0 talks). Under MPI the global thread pool gets `threads` threads here,
    /// before loading the scene uses it (afterwards it can no longer be sized).
    pub fn start(&self, threads: Option<u32>) -> Result<Ranks, CliError> {
        if !(self.comm_timeout > 0.0 && self.comm_timeout.is_finite()) {
            return Err(CliError::Input(format!(
                "--comm-timeout {}: must be a positive number of seconds",
                self.comm_timeout
            )));
        }
        let timeout = Duration::from_secs_f64(self.comm_timeout);
        match self.comm {
            None => Ok(Ranks::One),
            Some(CommKind::Local) => Ok(Ranks::Local(self.ranks as usize, timeout)),
            Some(CommKind::Mpi) => {
                if let Some(t) = threads {
                    rayon::ThreadPoolBuilder::new()
                        .num_threads(t as usize)
                        .stack_size(irradia_render::pool::WORKER_STACK)
                        .build_global()
                        .map_err(|e| CliError::Failure(format!("cannot start the threads: {e}")))?;
                }
                start_mpi(timeout)
            }
        }
    }
}

#[cfg(feature = "mpi")]
fn start_mpi(timeout: Duration) -> Result<Ranks, CliError> {
    irradia_parallel::comm::MpiComm::init(timeout)
        .map(Ranks::Mpi)
        .ok_or_else(|| CliError::Failure("MPI was already initialised".into()))
}

#[cfg(not(feature = "mpi"))]
fn start_mpi(_: Duration) -> Result<Ranks, CliError> {
    Err(CliError::Input(
        "--comm mpi: this irradia was built without MPI; build it with `bash scripts/build.sh` (MPI when OpenMPI is installed) or `cargo build --release -p irradia --features mpi`".into(),
    ))
}

impl Ranks {
    /// This process's rank (0 when it renders alone or holds the local ranks).
    pub fn rank(&self) -> usize {
        match self {
            Ranks::One | Ranks::Local(..) => 0,
            #[cfg(feature = "mpi")]
            Ranks::Mpi(c) => irradia_parallel::comm::Comm::rank(c),
        }
    }

    /// Renders on the ranks: rank 0 gets the image, the others `None`.
    pub fn render(
        &self,
        scene: &Scene,
        options: &RenderOptions,
    ) -> Result<Option<RenderOutput>, CliError> {
        match self {
            Ranks::One => Ok(Some(irradia_render::render(scene, options)?)),
            Ranks::Local(n, timeout) => {
                let local = LocalOptions {
                    timeout: *timeout,
                    delay: None,
                };
                // Each rank on a pool of its own, of --threads threads.
                let mut outs = run_local(*n, local, |c| {
                    irradia_render::pool::with_threads(options.threads, || {
                        render_distributed(c, scene, options)
                    })
                    .and_then(|r| r)
                });
                // Rank 0's error says most (it names the rank that failed).
                match outs.swap_remove(0) {
                    Ok(Ok(out)) => Ok(out),
                    Ok(Err(e)) => Err(e.into()),
                    Err(e) => Err(CliError::Failure(e.to_string())),
                }
            }
            #[cfg(feature = "mpi")]
            Ranks::Mpi(c) => {
                // The MPI calls stay on this (the main) thread; the tiles go to the
                // global pool, sized by `CommArgs::start`.
                match render_distributed(c, scene, options) {
                    Ok(out) => Ok(out),
                    Err(e) => c.fail(&irradia_parallel::comm::CommError::Aborted(e.to_string())),
                }
            }
        }
    }
}
