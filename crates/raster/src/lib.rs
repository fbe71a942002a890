//! irradia-raster: the "OpenGL pipeline" in software — the geometry units and
//! rasterizers of the lecture's "Parallel Rendering" half.
//!
//! ```text
//! Mesh / [Triangle] --Pipeline::transform_mesh / transform_and_light--> [ScreenTriangle]
//!     (geometry stage: MVP transform, Gouraud lighting or Phong attributes,
//!      homogeneous clipping with a guard band, perspective divide, viewport, culling)
//! [ScreenTriangle] --Pipeline::rasterize(region)--> Framebuffer (RGBA8 | RGBA32F | Id, f32 depth)
//!     (tile binning, fixed-point half-space edge functions with the top-left rule,
//!      perspective-correct interpolation, depth test, Gouraud or per-pixel Phong)
//! Pipeline::render_mesh / render_triangles do both.
//! ```
//!
//! ```
//! use irradia_raster::{ColorFormat, Framebuffer, Mesh, Pipeline};
//! use glam::Vec3;
//! let mesh = Mesh::new(vec![Vec3::new(-1.0, -1.0, 0.0), Vec3::new(1.0, -1.0, 0.0), Vec3::new(0.0, 1.0, 0.0)], vec![[0, 1, 2]]);
//! let pipeline = Pipeline::new(64, 48);
//! let mut fb = Framebuffer::new(64, 48, ColorFormat::Rgba8).unwrap();
//! pipeline.render_mesh(&mesh, &mut fb).unwrap();
//! assert!(fb.depth_at(32, 24) < 1.0);
//! ```

pub mod area_lights;
pub mod binning;
pub mod clip;
mod depth_bounds;
mod depth_snapshot;
pub mod fragment;
pub mod framebuffer;
pub mod geometry_stage;
pub mod interpolate;
pub mod lighting;
pub mod mesh;
pub mod pipeline;
mod prefetch;
pub mod rasterizer;
pub mod screen;
mod simd_span;
pub mod texture;
mod tiny;
pub mod transparency;
pub mod view;
mod widest;

pub use fragment::DepthFunc;
pub use framebuffer::{ColorBuffer, ColorFormat, Framebuffer, NO_ID};
pub use lighting::{Lights, Material, RasterLight, Shading};
pub use mesh::{Mesh, MeshError, Triangle, Vertex};
pub use pipeline::{Pipeline, RasterError};
pub use rasterizer::{for_each_fragment, CullMode};
pub use screen::{varying, Rect, ScreenTriangle, ScreenVertex, SCREEN_TRIANGLE_BYTES, VARYINGS};
pub use texture::Texture;
pub use view::ViewParams;
