//! Meshes made from formulas: marching cubes over any scalar field, and the gyroid
//! of the triangles benchmark, the isosurface of a volume read by [`crate::io::volume`].

pub mod gyroid;
pub mod marching_cubes;
pub mod metaballs;
pub mod random_triangles;

pub use gyroid::{gyroid, gyroid_mesh};
pub use marching_cubes::{marching_cubes, volume_mesh, MeshData, ScalarGrid};
