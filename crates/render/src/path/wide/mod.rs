//! The 8-wide path kernel: eight independent paths advanced in lockstep, one per SIMD
//! lane, in structure-of-arrays form, the way Mitsuba 3's `llvm_ad_rgb` variant runs
//! its path integrator over vector lanes (Jakob et al., "Dr.Jit: A Just-In-Time
//! Compiler for Differentiable Rendering", SIGGRAPH 2022; Mitsuba 3's `path`
//! integrator). Each step of the loop is one bounce of all live lanes, split into
//! stages as a wavefront path tracer splits its kernels (Laine, Karras, Aila,
//! "Megakernels Considered Harmful: Wavefront Path Tracing on GPUs", HPG 2013):
//!
//! 1. per lane: refill a finished lane with the next sample of the batch, find the
//!    nearest hit (the scene's own [`Tracer`], so hits are the scalar estimator's, bit
//!    for bit; Wald et al.'s SIMD triangle packets inside it) and draw the bounce's
//!    random numbers from the lane's own stream;
//! 2. all lanes at once ([`kernel`], 8-wide AVX2 + FMA chosen at run time, or the same
//!    code in SSE): emission with MIS, the light sample, the BSDF value and density,
//!    the cosine-weighted direction (with a polynomial sine and cosine), the new ray
//!    and the Russian-roulette probability;
//! 3. per lane: the shadow ray, the Russian-roulette draw, the end of paths.
//!
//! It is the same estimator as [`radiance_in`](super::integrator::radiance_in): NEE +
//! BSDF sampling with the power heuristic, Russian roulette from `rr_depth`, Mitsuba's
//! depth convention, the same random numbers in the same order from the same per-sample
//! stream. Every operation of a lane is the scalar code's, in the same order, except the
//! sine and cosine of the disk warp (a few ulps apart), so most samples come out
//! bit-identical and the rest differ by rounding (tests/path_wide.rs checks both).
//!
//! **What qualifies a scene** ([`WideScene::new`]): every material is a solid-coloured
//! Lambertian (albedo `diffuse * color`, possibly black, i.e. no lobe), optionally
//! emissive; no mirror, gloss or glass; every emitter is an emissive object sampled by
//! its world-space facets (polygons, boxes, polyhedra, emissive meshes); no point, spot,
//! directional, rectangle or sphere lights and a black background (no environment). The
//! Cornell box qualifies. Any geometry does (the hits come from the scalar tracer).
//! Other scenes render with the scalar `radiance_in`.

pub mod kernel;
pub mod lanes;

use super::bsdf::Lobe;
use super::integrator::{PathCounters, PathParams, PathScene};
use super::lights::FacetEmitter;
use super::tracer::Tracer;
use glam::Vec3;
use irradia_core::{Ray, Rgb, Rng};

/// A material as the kernel reads it.
#[derive(Clone, Copy, Debug)]
pub(crate) struct WideMaterial {
    /// Lambertian albedo (only meaningful when `scatters`).
    pub albedo: [f32; 3],
    /// Whether the BSDF has its lobe (otherwise paths end at the surface).
    pub scatters: bool,
    pub emission: [f32; 3],
    pub emissive: bool,
    pub two_sided: bool,
}

/// One world-space emitter triangle with what a light sample reads.
#[derive(Clone, Copy, Debug)]
pub(crate) struct LightFacet {
    pub corners: [[f32; 3]; 3],
    pub normal: [f32; 3],
    pub pdf_area: f32,
    pub radiance: [f32; 3],
    pub two_sided: bool,
}

/// A prepared scene that qualifies for the 8-wide kernel.
pub struct WideScene<'s, 'a, T: Tracer> {
    pub(crate) ps: &'s PathScene<'a, T>,
    pub(crate) materials: Vec<WideMaterial>,
    pub(crate) facets: Vec<LightFacet>,
    /// Index of each emitter's first facet in `facets`.
    pub(crate) facet_start: Vec<usize>,
}

impl<'s, 'a, T: Tracer> WideScene<'s, 'a, T> {
    /// The kernel's view of `ps`, or `None` when the scene does not qualify (see the
    /// module documentation).
    pub fn new(ps: &'s PathScene<'a, T>) -> Option<Self> {
        let scene = ps.scene;
        if !scene.settings.background.is_black() || scene.materials.is_empty() {
            return None;
        }
        let materials = scene
            .materials
            .iter()
            .enumerate()
            .map(|(i, m)| {
                let bsdf = ps.bsdfs.get(i).copied().flatten()?;
                let mut lobes = bsdf.lobes();
                let albedo = match (lobes.next(), lobes.next()) {
                    (None, _) => None,
                    (Some(Lobe::Lambert { albedo }), None) => Some(*albedo),
                    _ => return None,
                };
                Some(WideMaterial {
                    albedo: albedo.map_or([0.0; 3], |a| [a.r, a.g, a.b]),
                    scatters: albedo.is_some(),
                    emission: [m.emission.r, m.emission.g, m.emission.b],
                    emissive: !m.emission.is_black(),
                    two_sided: m.emission_two_sided,
                })
            })
            .collect::<Option<Vec<_>>>()?;
        let emitters: Vec<FacetEmitter<'_>> = ps.lights.facet_emitters()?;
        let mut facets = Vec::new();
        let mut facet_start = Vec::new();
        for e in &emitters {
            facet_start.push(facets.len());
            for (k, t) in e.triangles.iter().enumerate() {
                facets.push(LightFacet {
                    corners: t.map(|v: Vec3| v.to_array()),
                    normal: e.normals[k].to_array(),
                    pdf_area: e.pdf_area[k],
                    radiance: [e.radiance.r, e.radiance.g, e.radiance.b],
                    two_sided: e.two_sided,
                });
            }
        }
        Some(Self {
            ps,
            materials,
            facets,
            facet_start,
        })
    }

    /// Radiance samples `0..out.len()`: sample `k` starts from `start(k)` (its camera
    /// ray and its random stream, already advanced past the pixel jitter) and its
    /// estimate is written to `out[k]`. Equivalent to calling `radiance_in` on each.
    pub fn radiance_batch(
        &self,
        params: &PathParams,
        start: impl FnMut(usize) -> (Ray, Rng),
        out: &mut [Rgb],
        counters: &mut PathCounters,
    ) {
        #[cfg(target_arch = "x86_64")]
        if super::triangle_packet::has_avx2() {
            // SAFETY: the CPU supports AVX2 and FMA.
            unsafe { kernel::run_avx2(self, params, start, out, counters) };
            return;
        }
        kernel::run_portable(self, params, start, out, counters);
    }
}
