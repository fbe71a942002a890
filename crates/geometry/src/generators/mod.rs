//! Meshes made from formulas: marching cubes over any scalar field, and the gyroid
//! of the triangles benchmark.

pub mod gyroid;
pub mod marching_cubes;
pub mod metaballs;
pub mod random_triangles;
pub mod volume;

pub use gyroid::{gyroid, gyroid_mesh};
pub use marching_cubes::{marching_cubes, MeshData, ScalarGrid};
