//! `irradia radiosity --solver hierarchical --comm local|mpi`: the hierarchical solve on
//! several ranks (`irradia_parallel::radiosity`), as threads of this process or MPI
//! processes, with the same [`CommArgs`](super::render_comm::CommArgs) as
//! `irradia render`. The result equals the one-process solve bit for bit.

use super::render_comm::Ranks;
use irradia_parallel::comm::{run_local, LocalOptions};
use irradia_parallel::radiosity::solve_distributed;
use irradia_radiosity::solver::hierarchical::{self, HierarchicalOptions, HierarchicalResult};
use irradia_radiosity::{Mesh, RadiosityError, Result};

impl Ranks {
    /// Solves `mesh` hierarchically on the ranks: rank 0 gets the result, the others
    /// `None`. Local ranks share this machine's cores (at least one thread each).
    pub fn solve_hierarchical(
        &self,
        mesh: &Mesh,
        opts: HierarchicalOptions,
    ) -> Result<Option<HierarchicalResult>> {
        match self {
            Ranks::One => hierarchical::solve(mesh, opts, None).map(Some),
            Ranks::Local(n, timeout) => {
                let local = LocalOptions {
                    timeout: *timeout,
                    delay: None,
                };
                let cores = std::thread::available_parallelism().map_or(1, |c| c.get());
                let threads = (cores / n).max(1);
                let mut outs = run_local(*n, local, |c| {
                    irradia_render::pool::with_threads(Some(threads), || {
                        solve_distributed(c, mesh, opts)
                    })
                    .map_err(|e| RadiosityError::Failure(e.to_string()))
                    .and_then(|r| r)
                });
                // Rank 0's error says most (it names the rank that failed).
                match outs.swap_remove(0) {
                    Ok(r) => r,
                    Err(e) => Err(RadiosityError::Failure(e.to_string())),
                }
            }
            #[cfg(feature = "mpi")]
            Ranks::Mpi(c) => match solve_distributed(c, mesh, opts) {
                // Bad options fail alike on every rank before any message: exit 2.
                Err(RadiosityError::Input(m)) => Err(RadiosityError::Input(m)),
                Err(e) => c.fail(&irradia_parallel::comm::CommError::Aborted(e.to_string())),
                ok => ok,
            },
        }
    }
}
