//! irradia-radiosity: the "Radiosity" half of the lecture as a lighting-simulation tool.
//!
//! Data flows one way: patches (`scenes`, or your own `PatchSpec`s) -> `mesh::Mesh`
//! (patches cut into elements) -> form factors (`formfactor`, one method per file) ->
//! solver (`solver`, one per file; `solver::hierarchical` needs no matrix) -> display
//! (`display`: vertex radiosity, Gouraud images through the rasterizer, PLY;
//! `two_pass`: the ray-traced two-pass image with mirrors and glass, whose scenes are
//! `two_pass_scene`). `instant` is Keller's instant
//! radiosity; `convergence` writes residual histories and charts; `pipeline` runs the
//! meshing, form factors and solve with timings; `job` chooses the scene, draws the
//! image and writes the report, as the `irradia radiosity` command does.

pub mod convergence;
pub mod display;
pub mod error;
pub mod formfactor;
pub mod geom;
pub mod instant;
pub mod job;
pub mod mesh;
pub mod options;
pub mod pipeline;
pub mod scene_input;
pub mod scenes;
pub mod solver;
pub mod two_pass;
pub mod two_pass_scene;
pub mod visibility;

pub use error::{RadiosityError, Result};
pub use mesh::{Mesh, MeshOptions, PatchSpec};
