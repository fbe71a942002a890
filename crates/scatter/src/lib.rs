//! irradia-scatter: the one scattering toolkit of Irradia (in the spirit of pbrt-v4's
//! `BxDF`s and Mitsuba 3's BSDF plugins).
//!
//! - [`bsdf`]: the interface every BSDF implements ([`Scatter`]: evaluate, pdf, sample,
//!   lobe flags) and the [`Bsdf`] value an integrator holds at a surface point;
//! - [`bsdfs`]: one file per BSDF, with Mitsuba 3's parameter meanings;
//! - [`optics`]: reflection, refraction and the Fresnel equations;
//! - [`microfacet`]: the Beckmann and GGX distributions, Smith masking and sampling;
//! - [`ior`]: Mitsuba's named indices of refraction of dielectrics and conductors.
//!
//! # Conventions (one for the whole crate)
//!
//! Directions are in the local shading frame: the shading normal is +z, and both `wo`
//! (towards the viewer, where the light goes) and `wi` (towards the light, where it
//! comes from) point away from the surface. `cos θ = w.z`. Indices of refraction are
//! given as `eta = interior / exterior` (the interior is the side -z, opposite the
//! normal), as Mitsuba's `int_ior / ext_ior` and pbrt's `eta`. `eval` returns the BSDF
//! value f (without the cosine factor); `sample` returns the throughput weight
//! `f |cos θi| / pdf`, which for delta lobes is the only meaningful quantity (Veach 1997,
//! ch. 5; Pharr, Jakob and Humphreys, *PBRT* 4th ed., ch. 9).

pub mod bsdf;
pub mod bsdfs;
pub mod ior;
pub mod microfacet;
pub mod optics;
mod special;

pub use bsdf::{Bsdf, BsdfSample, LobeFlags, Scatter};
