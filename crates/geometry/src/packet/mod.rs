//! The SIMD triangle kernels, side by side. They are three kernels, not three copies of
//! one, because each answers a different question or lays its lanes out differently:
//!
//! - [`watertight4`]: one ray against four triangles, a filter that computes lane by
//!   lane exactly the single-precision operations of the watertight test of
//!   [`crate::triangle`] (Woop, Benthin, Wald, JCGT 2013) and hands the lanes it keeps
//!   to that scalar test, so a mesh's answer is bit for bit the watertight one (no
//!   cracks along shared edges). Meshes use it for every renderer; the Whitted images
//!   depend on its exactness.
//! - [`triangle8`]: one ray against eight triangles with the Möller-Trumbore test in
//!   Embree's precomputed-normal form, AVX2 + FMA at run time (SSE otherwise). Not
//!   watertight, and about twice as fast: the path tracer's world-space bake of planar
//!   objects uses it, where a slip through an edge with a probability of the rounding
//!   error changes no estimate measurably. [`bounds8`] culls up to eight of its
//!   packets with one 8-wide slab test.
//! - [`ray_lanes`]: W (16) rays against one triangle at a time (the lanes hold rays, not
//!   triangles: Wald, Slusallek, Benthin, Wagner 2001), the same Möller-Trumbore
//!   arithmetic as [`triangle8`] in the lane types of [`lanes`], for tracing a batch of
//!   rays over a small scene in one pass over its triangles.
//!
//! [`simd_build`] says which instruction set a hot loop runs in (the CPU's features,
//! [`SimdBuild`]), for these kernels and for the path and raster loops that inline them.
//!
//! Both Möller-Trumbore kernels compute the same products and sums, so their hits agree
//! up to the rounding of a comparison at a tie (`crates/render/tests/ray_query.rs` checks it).

pub mod bounds8;
pub mod lanes;
pub mod ray_lanes;
pub mod simd_build;
pub mod triangle8;
pub mod watertight4;

pub use bounds8::PacketBounds;
pub use ray_lanes::RayLaneTriangles;
pub use simd_build::{has_avx2, has_avx512, SimdBuild};
pub use triangle8::{PacketHit, TrianglePacket, LANES};
pub use watertight4::Triangle4;
