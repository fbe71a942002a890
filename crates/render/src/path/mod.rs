//! The path tracer: the Monte Carlo solution of the rendering equation that every other
//! method of Irradia is checked against (lecture, "The Rendering Equation").
//!
//! - [`material_map`]: scene materials to BSDFs of `irradia_scatter` (Whitted scenes
//!   render unchanged);
//! - [`lights`]: emitters and light selection proportional to power; [`envmap`] and
//!   [`distribution`]: environment maps importance sampled by luminance, cells drawn
//!   by [`alias`] tables;
//! - [`tracer`] and [`flat_scene`]: ray queries; planar objects baked into one
//!   world-space triangle hierarchy;
//! - [`integrator`]: next-event estimation + BSDF sampling with MIS, Russian roulette;
//! - [`direct`]: direct illumination only, as Mitsuba's `direct` integrator;
//! - [`wide`]: the same estimator over W paths at once in SIMD lanes, for scenes
//!   of Lambertian surfaces and facet emitters (the Cornell box);
//! - [`path_integrator`]: the path tracer as an [`Integrator`](crate::Integrator) of the
//!   one driver (tiles, passes, budgets, checkpoints: [`crate::driver`]);
//! - [`trace_sample`]: one sample's path as a ray tree (`irradia trace-pixel`).

pub mod alias;
pub mod direct;
pub mod distribution;
pub mod envmap;
pub mod flat_scene;
pub mod integrator;
pub mod lights;
pub mod material_map;
pub mod path_integrator;
pub mod trace_sample;
pub mod tracer;
pub mod wide;

pub use integrator::{PathCounters, PathParams};
pub use path_integrator::{fingerprint, render, Kernel, PathIntegrator};
