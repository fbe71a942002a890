//! irradia-parallel: parallel rendering as in the lecture's second half -- sort-first,
//! sort-middle and sort-last (Molnar, Cox, Ellsworth, Fuchs 1994), image compositing
//! (direct send, tree, binary swap, radix-k; active-pixel run lengths; depth and ordered
//! "over"), parallel submission (WireGL/Chromium), a network cost model, tiled display
//! walls, and the render and the hierarchical radiosity of one process spread over ranks
//! (`progressive`, `radiosity`). Every algorithm is generic over [`comm::Comm`], so the
//! same code runs on threads ([`comm::LocalComm`]) and under `mpirun` (`MpiComm`, cargo
//! feature `mpi`).

pub mod comm;
pub mod composite;
pub mod display_tiles;
pub mod job;
pub mod netmodel;
pub mod progressive;
pub mod radiosity;
pub mod raytrace_first;
pub mod raytrace_forward;
pub mod raytrace_last;
pub mod render_job;
pub mod report;
pub mod scale;
mod slot;
pub mod sort_common;
pub mod sort_first;
pub mod sort_last;
pub mod sort_middle;
pub mod study;
pub mod submission;
pub mod tessellate;
pub mod wall;
mod wire;
pub mod workload;
