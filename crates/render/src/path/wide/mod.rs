//! The wide path kernel: W (16) independent paths advanced in lockstep, one per SIMD
//! lane, in structure-of-arrays form, the way Mitsuba 3's `llvm_ad_rgb` variant runs
//! its path integrator over vector lanes (Jakob et al., "Dr.Jit: A Just-In-Time
//! Compiler for Differentiable Rendering", SIGGRAPH 2022; Mitsuba 3's `path`
//! integrator). Each step of the loop is one bounce of all live lanes, split into
//! stages as a wavefront path tracer splits its kernels (Laine, Karras, Aila,
//! "Megakernels Considered Harmful: Wavefront Path Tracing on GPUs", HPG 2013):
//!
//! 1. per lane: refill a finished lane with the next sample of the batch (camera
//!    samples are made W at a time ahead of the lanes that take them: a tile's
//!    pinhole rays in lanes, [`crate::camera_batch`]) and draw the bounce's random
//!    numbers from the lane's own stream;
//! 2. all lanes at once ([`kernel`], AVX-512 (one register of 16 `f32`) or AVX2 + FMA
//!    (two) chosen at run time ([`SimdBuild`]), or the same code in SSE): the nearest
//!    hits ([`ray_lanes`](irradia_geometry::packet::ray_lanes): W rays against every
//!    triangle of a small scene; larger scenes walk the [`FlatScene`]'s hierarchy lane by lane,
//!    with Wald et al.'s SIMD triangle packets), the hit points (triangle, material,
//!    vertex normal and light data gathered by index, or, from tables of at most W rows
//!    under AVX-512, read by lane permutes: [`gather`]), emission with MIS, the light choice and
//!    sample, the BSDF value and density, the cosine-weighted direction (with a
//!    polynomial sine and cosine), the new rays, the Russian-roulette probability and
//!    the shadow rays;
//! 3. per lane: the Russian-roulette draw and the end of finished paths.
//!
//! It is the same estimator as [`radiance_in`](super::integrator::radiance_in): NEE +
//! BSDF sampling with the power heuristic, Russian roulette from `rr_depth`, Mitsuba's
//! depth convention, the same random numbers in the same order from the same per-sample
//! stream. Every operation of a lane is the scalar code's, in the same order, except the
//! sine and cosine of the disk warp (a few ulps apart) and the order of a comparison at
//! a tie between triangles, so samples differ from the scalar ones by rounding only
//! (tests/path_wide.rs checks that every sample agrees to 1e-4 and that the
//! comparison would catch a different stream).
//!
//! **What qualifies a scene** ([`WideScene::new`]): every material is one of
//! - a solid-coloured Lambertian, the lecture's two-sided one (albedo `diffuse *
//!   color`, possibly black, i.e. no lobe) or Mitsuba's one-sided `diffuse` with a
//!   constant `reflectance`;
//! - Mitsuba's smooth `conductor` (one-sided; a delta reflection weighted by the exact
//!   conductor Fresnel reflectance, in `f64` as the scalar BSDF computes it, the W
//!   lanes at once as `f64` vectors: [`fresnel_lanes`]) or smooth `dielectric` (delta reflection or refraction chosen by the
//!   lobe number against the exact dielectric Fresnel reflectance), with constant
//!   parameters;
//!
//! - Mitsuba's `roughconductor` with isotropic GGX normals sampled by their visible
//!   ones (Mitsuba's default; the speed suite's veach_mis plates), constant parameters
//!   ([`ggx`]: value, density and sample in lanes, in `f32`, the Fresnel reflectance in
//!   `f64` lanes, [`fresnel_lanes`]); a glossy lobe as the scalar estimator treats it: a light sample
//!   weighted by the power heuristic against the BSDF's density, and emission hit
//!   after it weighted against the light sample's density;
//! - Mitsuba's `roughdielectric` with the same distribution ([`rough_dielectric`]:
//!   reflection or refraction about a visible normal, chosen by the lobe number against
//!   the dielectric Fresnel reflectance of the normal, as the scalar BSDF; two-sided,
//!   light samples on either side; Russian roulette judges `max(beta) η²` as after the
//!   smooth dielectric) and `roughplastic` ([`rough_plastic`]: the GGX coating over the
//!   diffuse base, with the scalar BSDF's precomputed transmittance table, internal
//!   reflectance (`nonlinear` or not) and specular sampling weight); glossy lobes as
//!   the rough conductor's ([`glossy`] runs each lane's one);
//!
//! each optionally emissive; no lecture mirror, gloss or glass, and no Beckmann or
//! anisotropic roughness.
//! Delta lobes follow the scalar estimator exactly: no light sample (its random
//! numbers are drawn and unused), emission hit after them counts in full (no MIS), and
//! Russian roulette judges `max(beta) eta²` with `eta` the product of the relative
//! indices crossed. Every emitter is an emissive object
//! sampled by its world-space facets (polygons, rectangles, boxes, polyhedra, emissive
//! meshes), an emissive sphere (unflipped, possibly under a transform) sampled by the
//! cone it subtends from outside where its transform keeps it a sphere, else uniformly
//! by area with its own sampler ([`sphere_light`]: the lanes whose light choice falls on
//! a sphere warp their numbers onto it), or an emitter at infinity: the
//! constant environment (a background colour and Mitsuba's `constant` emitters) and
//! Mitsuba's `envmap` ([`background`]: escaped rays gather them with MIS, light samples
//! choose them with their probability (with the other emitters, W lanes at once,
//! [`light_pick`], in scenes of few emitters) and sample them lane by lane, then
//! shade with an unbounded shadow ray in the vector stage; the maps' lookups,
//! densities and importance samples run for all lanes at once, [`envmap_lanes`]); no point,
//! spot, directional or rectangle *lights*. The Cornell box qualifies, and so do diffuse
//! scenes under an environment map. Every object must be baked into the [`FlatScene`]'s
//! triangles (polygons, rectangles, boxes, polyhedra, and triangle meshes of any size,
//! whose materials are untextured) or be a sphere (possibly placed by a transform, as
//! the Mitsuba importer builds them; no quadrics, CSG or implicit surfaces; a scene of
//! spheres only qualifies). Spheres are culled W rays at once ([`sphere_cull`]: a
//! conservative ray-ball test that only drops lanes that cannot hit one) and the lanes
//! left are traced W at once after the lanes' triangles, up to the triangle's
//! distance ([`sphere_hits`]: the scalar sphere test's `f64` quadratic, transform,
//! surface point, normal and error bound in lanes, the spheres in the loop, so the
//! hits, normals and error bounds are the scalar ones bit for bit), and so are the
//! shadow rays the triangles leave through. So the speed suite's
//! `glass_mirror.xml` (a glass and an aluminium sphere in the Cornell box) qualifies.
//! Mesh triangles shade with their interpolated vertex normals as the scalar code
//! does (`SmoothNormals`: the normals gathered by triangle index from a side table,
//! blended with the hit's barycentrics, given normals turning the geometric normal);
//! so the Stanford bunny in the Cornell box qualifies. Other scenes render with the
//! scalar `radiance_in`.

pub(crate) mod background;
pub mod bsdf;
mod dw;
pub(crate) mod envmap_lanes;
mod escapes;
pub(crate) mod fresnel_lanes;
mod gather;
pub mod ggx;
mod glossy;
pub mod kernel;
mod lane_queries;
mod light_pick;
mod rough_dielectric;
mod rough_plastic;
pub(crate) mod sphere_cull;
pub(crate) mod sphere_hits;
pub mod sphere_light;
mod starts;

use super::flat_scene::FlatScene;
use super::integrator::{PathCounters, PathParams, PathScene};
use super::lights::{FacetEmitter, KernelEmitter};
use crate::camera_batch::CameraBatch;
use gather::Table;
use glam::Vec3;
use irradia_core::{Ray, Rgb, Rng};
use irradia_geometry::packet::{RayLaneTriangles, SimdBuild};
use irradia_scatter::microfacet::MicrofacetType;
use irradia_scatter::{bsdfs::LectureLobe, Bsdf};
use light_pick::LightPick;
use sphere_light::sph;
use starts::Starts;

/// The agreement the kernel is held to: the fraction of samples (same index in `a` and
/// `b`, e.g. the scalar estimator's and the kernel's) whose three channels agree to
/// `1e-4` relative (plus `1e-7` absolute near zero). Samples differ by rounding only, so
/// this is 1 up to a few tie-breaks; tests/path_wide.rs and the importer's
/// wide_kernel test use it.
pub fn samples_agreeing(a: &[Rgb], b: &[Rgb]) -> f64 {
    let close = |x: f32, y: f32| (x - y).abs() <= 1e-4 * x.abs().max(y.abs()) + 1e-7;
    let same = a
        .iter()
        .zip(b)
        .filter(|(p, q)| close(p.r, q.r) && close(p.g, q.g) && close(p.b, q.b))
        .count();
    same as f64 / a.len().max(1) as f64
}

/// A material as the per-lane stage reads it.
#[derive(Clone, Copy, Debug)]
pub(crate) struct WideMaterial {
    /// Whether the BSDF has its lobe (otherwise paths end at the surface).
    pub scatters: bool,
    pub emissive: bool,
    /// A smooth conductor's complex index `(eta, k)`, whose Fresnel reflectance the
    /// vector stage evaluates lane by lane (in `f64`, as the scalar BSDF does).
    pub conductor: Option<(Rgb, Rgb)>,
}

/// Fields of a [`WideScene::triangles`] record.
pub(crate) mod tri {
    pub const P0: usize = 0;
    pub const P1: usize = 3;
    pub const P2: usize = 6;
    pub const N: usize = 9;
    pub const LEN: usize = 12;
}
/// Fields of a [`WideScene::smooth`] record (flags are 0.0 or 1.0).
pub(crate) mod smooth {
    /// The vertex normals in world space (not renormalised; see `SmoothNormals`).
    pub const N0: usize = 0;
    pub const N1: usize = 3;
    pub const N2: usize = 6;
    /// 1 for a mesh triangle (interpolated shading normal), 0 for a flat face.
    pub const SMOOTH: usize = 9;
    /// 1 when the mesh's normals were given (they turn the geometric normal).
    pub const GIVEN: usize = 10;
    pub const LEN: usize = 12;
}
/// Fields of a [`WideScene::shading`] record (flags are 0.0 or 1.0).
pub(crate) mod mat {
    pub const ALBEDO: usize = 0;
    pub const EMISSION: usize = 3;
    pub const TWO_SIDED: usize = 6;
    /// 1 for a one-sided BSDF (Mitsuba's `diffuse` and `conductor`: nothing is
    /// scattered when the path arrives from behind the surface), 0 for the lecture's
    /// two-sided Lambert and the dielectric.
    pub const FRONT_ONLY: usize = 7;
    /// 1 for Mitsuba's smooth `conductor` (a delta reflection; the albedo is 0).
    pub const MIRROR: usize = 8;
    /// 1 for Mitsuba's smooth `dielectric` (delta reflection and refraction; the
    /// albedo is 0).
    pub const GLASS: usize = 9;
    /// The dielectric's `int_ior / ext_ior`.
    pub const ETA: usize = 10;
    /// `specular_reflectance` (conductor and dielectric) and `specular_transmittance`
    /// (dielectric).
    pub const SPEC_R: usize = 11;
    pub const SPEC_T: usize = 14;
    /// 1 for Mitsuba's `roughconductor` with isotropic GGX normals sampled by their
    /// visible ones ([`super::ggx`]; the albedo is 0).
    pub const ROUGH: usize = 17;
    /// Its roughness α.
    pub const ALPHA: usize = 18;
    /// Which glossy BSDF a `ROUGH` material is ([`super::glossy`]): the rough conductor,
    /// Mitsuba's `roughdielectric` ([`super::rough_dielectric`]: `ETA`, `SPEC_R`,
    /// `SPEC_T`) or `roughplastic` ([`super::rough_plastic`]: `ETA`, `SPEC_R`, `COAT`,
    /// `SPEC_WEIGHT`), all GGX, isotropic, visible normals, with roughness `ALPHA`.
    pub const KIND: usize = 19;
    pub const KIND_CONDUCTOR: f32 = 0.0;
    pub const KIND_DIELECTRIC: f32 = 1.0;
    pub const KIND_PLASTIC: f32 = 2.0;
    /// The rough plastic's base seen through its coating, `ρ / (1 − R_int) / η²`.
    pub const COAT: usize = 20;
    /// The rough plastic's specular sampling weight.
    pub const SPEC_WEIGHT: usize = 23;
    pub const LEN: usize = 24;
}
/// Fields of a [`WideScene::facets`] record.
pub(crate) mod facet {
    pub const A: usize = 0;
    pub const B: usize = 3;
    pub const C: usize = 6;
    pub const N: usize = 9;
    pub const RADIANCE: usize = 12;
    pub const PDF_AREA: usize = 15;
    pub const TWO_SIDED: usize = 16;
    pub const LEN: usize = 20;
}

/// A prepared scene that qualifies for the wide kernel, with flat tables the vector
/// stage gathers from by index (one record per triangle, material and emitter facet).
pub struct WideScene<'s, 'a> {
    pub(crate) ps: &'s PathScene<'a, FlatScene>,
    /// Per baked triangle: corners and unit normal ([`tri`]).
    pub(crate) triangles: Table<{ tri::LEN }>,
    /// Per baked triangle: its material and instance.
    pub(crate) triangle_owner: Vec<(u32, u32)>,
    /// Per baked triangle: its vertex normals ([`smooth`]), when some triangle has
    /// them (a mesh); `None` when every triangle shades with its geometric normal.
    pub(crate) smooth: Option<Table<{ smooth::LEN }>>,
    pub(crate) materials: Vec<WideMaterial>,
    /// Per material: albedo, emission, sidedness ([`mat`]).
    pub(crate) shading: Table<{ mat::LEN }>,
    /// Every emitter's world-space triangles ([`facet`]); one zero record when there
    /// are none, so that an index of 0 is always valid.
    pub(crate) facets: Table<{ facet::LEN }>,
    /// Index of each emitter's first facet in `facets`.
    pub(crate) facet_start: Vec<u32>,
    /// The light choice's tables, when it is small enough to make in the vector
    /// stage; otherwise each lane makes it with `LightSampler::pick_kernel`.
    pub(crate) pick: Option<LightPick>,
    /// The triangles for tracing W rays at once (small scenes); otherwise each
    /// lane walks the flat scene's hierarchy.
    pub(crate) rays: Option<RayLaneTriangles>,
    /// In a larger scene, the triangles the flat scene tests before its hierarchy
    /// (its large triangles: the walls of a room around a mesh), for testing them W
    /// rays at once before each lane walks the tree ([`lane_queries`]).
    pub(crate) first: Option<RayLaneTriangles>,
    /// With [`Self::first`]: the box around the other triangles (the tree's), so that
    /// only the lanes whose ray may meet it walk the tree.
    pub(crate) tree_box: Option<escapes::TriangleBox>,
    /// Whether some objects (spheres) are not baked: each lane then also asks the
    /// flat scene's own test of those after the triangles.
    pub(crate) has_rest: bool,
    /// The spheres' lane cull ([`sphere_cull`]): only lanes whose ray may meet one run
    /// the exact lane-by-lane test; `None` without spheres or when disabled (tests).
    pub(crate) cull: Option<sphere_cull::SphereCull>,
    /// Per emitter: the place among the spheres' cull of the one-sided emissive sphere
    /// it is, [`sphere_cull::NONE`] for any other emitter: its light samples that can
    /// shine face the shading point, so that sphere cannot block their shadow rays
    /// ([`sphere_cull::SphereCull::may_hit_but`]). (A two-sided one shines from its far
    /// side too, through itself.)
    pub(crate) light_ball: Vec<u32>,
    /// The box around every baked triangle (none without triangles), for finding the
    /// camera rays that certainly leave the scene ([`escapes`]).
    pub(crate) triangle_box: Option<escapes::TriangleBox>,
    /// The spheres' exact lane test ([`sphere_hits`]), when there are spheres.
    pub(crate) spheres: Option<sphere_hits::SpheresW>,
    /// A factor on the smooth conductor's and dielectric's Fresnel reflectance: 1
    /// (exact: the product is the reflectance itself) except in the test that shows
    /// a wrong reflectance is caught.
    pub(crate) fresnel_scale: f32,
    /// Whether rays that leave the scene see emitters at infinity (a background, a
    /// `constant`, an `envmap`; see [`background`]).
    pub(crate) background: bool,
    /// A factor on the radiance of the emitters at infinity: 1 except in the test
    /// that shows a wrong environment is caught.
    pub(crate) background_scale: f32,
    /// The emitters at infinity in the lanes' form ([`envmap_lanes`]), when there are any.
    pub(crate) environment: Option<envmap_lanes::EnvironmentW>,
    /// Whether some material is glossy (a rough conductor, dielectric or plastic: the
    /// vector stage skips their lobes otherwise).
    pub(crate) has_rough: bool,
    /// A factor on the glossy BSDFs' α: 1 except in the test that shows a wrong
    /// roughness is caught.
    pub(crate) alpha_scale: f32,
    /// The rough plastics' transmittance tables `T(μ)` ([`rough_plastic`]):
    /// [`rough_plastic::ROWS`] rows per material (zeros but for plastics); empty
    /// without a rough plastic.
    pub(crate) transmittance: Table<1>,
    /// Per emitter: its sphere record ([`sph`]) when some emitter is an emissive
    /// sphere sampled by its own sampler; `None` when every emitter is facets.
    pub(crate) sphere_lights: Option<Table<{ sph::LEN }>>,
    /// The build of the kernel that runs: the widest this CPU has
    /// ([`SimdBuild::best`], or the one [`KERNEL_VAR`] names) unless a test asks for another.
    pub(crate) build: SimdBuild,
}

/// The environment variable that forces a build of the kernel ([`SimdBuild::chosen`]):
/// `avx512`, `avx2` or `portable`, for A/B timings of the builds (the samples are the
/// same between AVX2 and AVX-512, which differ only in the instructions LLVM picks for
/// the same IEEE operations; the portable build rounds its triangle tests without
/// FMA). `scalar` forces the scalar estimator instead (`path_integrator`).
pub const KERNEL_VAR: &str = "IRRADIA_PATH_KERNEL";

/// At most this many emitters, and facets per emitter, for the vector light choice.
const VECTOR_PICK_MAX: usize = 16;

impl<'s, 'a> WideScene<'s, 'a> {
    /// The kernel's view of `ps`, or `None` when the scene does not qualify (see the
    /// module documentation).
    pub fn new(ps: &'s PathScene<'a, FlatScene>) -> Option<Self> {
        let scene = ps.scene;
        if scene.materials.is_empty() {
            return None;
        }
        // Emission read from a texture at the hit's uv: the scalar kernel's work.
        if scene.materials.iter().any(|m| m.emission_texture.is_some()) {
            return None;
        }
        let mut materials = Vec::new();
        let mut shading = Vec::new();
        let mut plastic_tables = Vec::new();
        let flag = |b: bool| if b { 1.0 } else { 0.0 };
        for (i, m) in scene.materials.iter().enumerate() {
            let mut row = [0.0; mat::LEN];
            let mut conductor = None;
            // The lecture's Lambert (two-sided) or Mitsuba's `diffuse` (one-sided), both
            // with a constant albedo (a textured one has no BSDF here); Mitsuba's
            // smooth `conductor` (one-sided) and `dielectric`.
            let (albedo, front_only, scatters) = match ps.bsdfs.get(i) {
                Some(Some(Bsdf::LectureMix(bsdf))) => {
                    let mut lobes = bsdf.lobes();
                    match (lobes.next(), lobes.next()) {
                        (None, _) => (Rgb::BLACK, false, false),
                        (Some(LectureLobe::Lambert { albedo }), None) => (*albedo, false, true),
                        _ => return None,
                    }
                }
                Some(Some(Bsdf::Diffuse(d))) => (d.reflectance, true, true),
                Some(Some(Bsdf::Conductor(c))) => {
                    row[mat::MIRROR] = 1.0;
                    let r = c.specular_reflectance;
                    row[mat::SPEC_R..mat::SPEC_R + 3].copy_from_slice(&[r.r, r.g, r.b]);
                    conductor = Some((c.eta, c.k));
                    (Rgb::BLACK, true, true)
                }
                // GGX, isotropic, visible normals (the speed suite's plates).
                Some(Some(Bsdf::RoughConductor(c)))
                    if c.distribution.kind == MicrofacetType::Ggx
                        && !c.distribution.is_anisotropic()
                        && c.distribution.sample_visible =>
                {
                    row[mat::ROUGH] = 1.0;
                    row[mat::ALPHA] = c.distribution.alpha_u;
                    let r = c.specular_reflectance;
                    row[mat::SPEC_R..mat::SPEC_R + 3].copy_from_slice(&[r.r, r.g, r.b]);
                    conductor = Some((c.eta, c.k));
                    (Rgb::BLACK, true, true)
                }
                // Mitsuba's `roughdielectric` and `roughplastic`, GGX, isotropic, visible
                // normals (the speed suite's rough_balls).
                Some(Some(Bsdf::RoughDielectric(d)))
                    if d.distribution.kind == MicrofacetType::Ggx
                        && !d.distribution.is_anisotropic()
                        && d.distribution.sample_visible =>
                {
                    row[mat::ROUGH] = 1.0;
                    row[mat::KIND] = mat::KIND_DIELECTRIC;
                    row[mat::ALPHA] = d.distribution.alpha_u;
                    row[mat::ETA] = d.eta;
                    let (r, t) = (d.specular_reflectance, d.specular_transmittance);
                    row[mat::SPEC_R..mat::SPEC_R + 3].copy_from_slice(&[r.r, r.g, r.b]);
                    row[mat::SPEC_T..mat::SPEC_T + 3].copy_from_slice(&[t.r, t.g, t.b]);
                    (Rgb::BLACK, false, true)
                }
                Some(Some(Bsdf::RoughPlastic(p)))
                    if p.distribution.kind == MicrofacetType::Ggx
                        && !p.distribution.is_anisotropic()
                        && p.distribution.sample_visible =>
                {
                    plastic_tables.push((i, rough_plastic::record(p, &mut row)));
                    (Rgb::BLACK, true, true)
                }
                Some(Some(Bsdf::Dielectric(d))) => {
                    row[mat::GLASS] = 1.0;
                    row[mat::ETA] = d.eta;
                    let (r, t) = (d.specular_reflectance, d.specular_transmittance);
                    row[mat::SPEC_R..mat::SPEC_R + 3].copy_from_slice(&[r.r, r.g, r.b]);
                    row[mat::SPEC_T..mat::SPEC_T + 3].copy_from_slice(&[t.r, t.g, t.b]);
                    (Rgb::BLACK, false, true)
                }
                _ => return None,
            };
            materials.push(WideMaterial {
                scatters,
                emissive: !m.emission.is_black(),
                conductor,
            });
            let (a, e) = (albedo, m.emission);
            row[..8].copy_from_slice(&[
                a.r,
                a.g,
                a.b,
                e.r,
                e.g,
                e.b,
                flag(m.emission_two_sided),
                flag(front_only),
            ]);
            shading.push(row);
        }
        // Objects the flat scene does not bake are traced lane by lane with their own
        // shapes' tests (the scalar code's, so hits agree): spheres only, whole objects
        // (no CSG leaves).
        for &i in ps.tracer.rest_objects() {
            let instance = &scene.accel.instances()[i as usize];
            let object = &scene.objects[i as usize];
            if instance.shape.kind() != "sphere" || !object.leaf_materials.is_empty() {
                return None;
            }
        }
        let has_rest = !ps.tracer.rest_objects().is_empty();
        let spheres = match has_rest {
            true => Some(sphere_hits::SpheresW::new(scene, ps.tracer.rest_objects())?),
            false => None,
        };
        let mut triangles = Vec::new();
        let mut triangle_owner = Vec::new();
        // Nothing baked (spheres only): no triangles to trace, one zero record.
        let baked = ps.tracer.baked_triangles().unwrap_or_default();
        let corners: Vec<_> = baked.iter().map(|t| t.0).collect();
        let rays = RayLaneTriangles::new(&corners, &ps.tracer.packet_order());
        let first_order = ps.tracer.first_order();
        let first = RayLaneTriangles::new(&corners, &first_order);
        let tree_box = first.as_ref().and_then(|_| {
            let mut in_first = vec![false; corners.len()];
            first_order
                .iter()
                .for_each(|&t| in_first[t as usize] = true);
            let tree: Vec<_> = (corners.iter().zip(in_first))
                .filter_map(|(c, f)| (!f).then_some(*c))
                .collect();
            escapes::TriangleBox::new(&tree)
        });
        let triangle_box = escapes::TriangleBox::new(&corners);
        let any_smooth = baked.iter().any(|t| t.4.is_some());
        let mut smooth_table = Vec::new();
        for (c, n, instance, material, vertex_normals) in baked {
            let mut r = [0.0; tri::LEN];
            for (k, v) in [c[0], c[1], c[2], n].iter().enumerate() {
                r[3 * k..3 * k + 3].copy_from_slice(&v.to_array());
            }
            triangles.push(r);
            triangle_owner.push((material, instance));
            if any_smooth {
                let mut r = [0.0; smooth::LEN];
                if let Some(s) = vertex_normals {
                    for (k, v) in s.normals.iter().enumerate() {
                        r[3 * k..3 * k + 3].copy_from_slice(&v.to_array());
                    }
                    r[smooth::SMOOTH] = 1.0;
                    r[smooth::GIVEN] = if s.given { 1.0 } else { 0.0 };
                }
                smooth_table.push(r);
            }
        }
        if triangles.is_empty() {
            triangles.push([0.0; tri::LEN]);
        }
        let smooth = any_smooth.then(|| Table::new(smooth_table));
        let kernel_emitters = ps.lights.kernel_emitters(scene)?;
        let at_infinity = kernel_emitters
            .iter()
            .any(|e| matches!(e, KernelEmitter::AtInfinity(_)));
        // A sphere emitter and an emitter at infinity have one placeholder facet (a zero
        // record, the whole of its emitter's area table), so the light choice's tables
        // stay aligned; the vector stage samples a sphere itself ([`sphere_light`]), and
        // the lanes sample emitters at infinity ([`background`]).
        const WHOLE: &[f32] = &[1.0];
        const NO_TRIANGLE: &[[Vec3; 3]] = &[[Vec3::ZERO; 3]];
        const NO_NORMAL: &[Vec3] = &[Vec3::ZERO];
        const NO_DENSITY: &[f32] = &[0.0];
        let placeholder = |probability| FacetEmitter {
            radiance: Rgb::BLACK,
            two_sided: false,
            triangles: NO_TRIANGLE,
            normals: NO_NORMAL,
            pdf_area: NO_DENSITY,
            cdf: WHOLE,
            probability,
        };
        let mut sphere_table = vec![[0.0; sph::LEN]; kernel_emitters.len().max(1)];
        let mut emitters = Vec::new();
        for (i, e) in kernel_emitters.iter().enumerate() {
            emitters.push(match e {
                KernelEmitter::Facets(f) => *f,
                KernelEmitter::Sphere(s) => {
                    sphere_table[i] = sphere_light::record(s);
                    placeholder(s.probability)
                }
                KernelEmitter::AtInfinity(probability) => placeholder(*probability),
            });
        }
        let any_sphere = kernel_emitters
            .iter()
            .any(|e| matches!(e, KernelEmitter::Sphere(_)));
        let sphere_lights = any_sphere.then(|| Table::new(sphere_table));
        let rest = ps.tracer.rest_objects();
        let light_ball = kernel_emitters
            .iter()
            .map(|e| match e {
                KernelEmitter::Sphere(s) if !s.two_sided => rest
                    .iter()
                    .position(|&i| i == s.instance)
                    .map_or(sphere_cull::NONE, |k| k as u32),
                _ => sphere_cull::NONE,
            })
            .collect();
        let mut facets = Vec::new();
        let mut facet_start = Vec::new();
        for e in &emitters {
            facet_start.push(facets.len() as u32);
            for (k, t) in e.triangles.iter().enumerate() {
                let mut r = [0.0; facet::LEN];
                for (j, v) in [t[0], t[1], t[2], e.normals[k]].iter().enumerate() {
                    r[3 * j..3 * j + 3].copy_from_slice(&v.to_array());
                }
                r[facet::RADIANCE..facet::RADIANCE + 3].copy_from_slice(&[
                    e.radiance.r,
                    e.radiance.g,
                    e.radiance.b,
                ]);
                r[facet::PDF_AREA] = e.pdf_area[k];
                r[facet::TWO_SIDED] = if e.two_sided { 1.0 } else { 0.0 };
                facets.push(r);
            }
        }
        let emitter_cdf = ps.lights.emitter_cdf();
        // The vector light choice: emitters at infinity by their placeholder facet, then
        // those lanes sample them lane by lane (`light_pick::far_lights`).
        let small = emitters.len() <= VECTOR_PICK_MAX
            && emitters
                .iter()
                .all(|e| !e.cdf.is_empty() && e.cdf.len() <= VECTOR_PICK_MAX);
        let pick =
            (small && !ps.lights.is_empty() && emitter_cdf.len() == emitters.len()).then(|| {
                LightPick {
                    emitter_cdf: emitter_cdf.to_vec(),
                    probability: Table::new(emitters.iter().map(|e| [e.probability]).collect()),
                    total: Table::new(emitters.iter().map(|e| [*e.cdf.last().unwrap()]).collect()),
                    start: facet_start.clone(),
                    len: emitters.iter().map(|e| e.cdf.len() as u32).collect(),
                    facet_cdf: Table::new(
                        emitters
                            .iter()
                            .flat_map(|e| e.cdf.iter().map(|&c| [c]))
                            .collect(),
                    ),
                    max_len: emitters.iter().map(|e| e.cdf.len()).max().unwrap_or(0),
                    far: Table::new(
                        kernel_emitters
                            .iter()
                            .map(|e| [f32::from(matches!(e, KernelEmitter::AtInfinity(_)) as u8)])
                            .collect(),
                    ),
                    any_far: at_infinity,
                }
            });
        if facets.is_empty() {
            facets.push([0.0; facet::LEN]);
        }
        let has_rough = shading.iter().any(|r| r[mat::ROUGH] != 0.0);
        let mut transmittance = Vec::new();
        if !plastic_tables.is_empty() {
            transmittance = vec![[0.0]; shading.len() * rough_plastic::ROWS];
            for (i, t) in plastic_tables {
                let rows = &mut transmittance[i * rough_plastic::ROWS..][..rough_plastic::ROWS];
                for (r, v) in rows.iter_mut().zip(t) {
                    *r = [v];
                }
            }
        }
        let mut ws = Self {
            ps,
            triangles: Table::new(triangles),
            triangle_owner,
            smooth,
            materials,
            shading: Table::new(shading),
            facets: Table::new(facets),
            facet_start,
            pick,
            rays,
            first,
            tree_box,
            has_rest,
            cull: has_rest.then(|| sphere_cull::SphereCull::new(scene, ps.tracer.rest_objects())),
            light_ball,
            triangle_box,
            spheres,
            fresnel_scale: 1.0,
            background: ps.lights.has_environment(),
            background_scale: 1.0,
            environment: ps
                .lights
                .has_environment()
                .then(|| envmap_lanes::EnvironmentW::new(ps.lights)),
            has_rough,
            alpha_scale: 1.0,
            transmittance: Table::new(transmittance),
            sphere_lights,
            build: SimdBuild::Portable,
        };
        ws.set_build(SimdBuild::chosen(KERNEL_VAR));
        Some(ws)
    }

    /// Runs `build`, whose tables of at most W rows it reads by lane permutes
    /// (AVX-512) or by gathers ([`gather`]).
    fn set_build(&mut self, build: SimdBuild) {
        self.build = build;
        self.triangles.set_build(build);
        self.shading.set_build(build);
        self.facets.set_build(build);
        self.transmittance.set_build(build);
        for t in self.smooth.iter_mut() {
            t.set_build(build);
        }
        for t in self.sphere_lights.iter_mut() {
            t.set_build(build);
        }
        if let Some(p) = &mut self.pick {
            for t in [
                &mut p.probability,
                &mut p.total,
                &mut p.facet_cdf,
                &mut p.far,
            ] {
                t.set_build(build);
            }
        }
    }

    /// Whether the scene has baked triangles (a scene of spheres only has none).
    pub(crate) fn has_triangles(&self) -> bool {
        self.triangle_box.is_some()
    }

    /// The same kernel in another build (for tests: the builds agree bit for bit).
    ///
    /// # Panics
    /// If this CPU cannot run `build` ([`SimdBuild::available`]).
    #[doc(hidden)]
    pub fn with_build(mut self, build: SimdBuild) -> Self {
        assert!(build.available(), "this CPU cannot run the {build:?} build");
        self.set_build(build);
        self
    }

    /// The same kernel with its per-lane variants only: each lane walks the flat
    /// scene's hierarchy and chooses its light with `LightSampler::pick_kernel` (what
    /// scenes of more than 64 triangles or 16 emitters use); for tests.
    #[doc(hidden)]
    pub fn lane_by_lane(mut self) -> Self {
        self.rays = None;
        self.first = None;
        self.tree_box = None;
        self.pick = None;
        self
    }

    /// The same kernel with a wrong Fresnel reflectance (the smooth conductor's and
    /// dielectric's, times `scale`); for the test that shows the comparison with the
    /// scalar estimator catches it.
    #[doc(hidden)]
    pub fn with_fresnel_scale(mut self, scale: f32) -> Self {
        self.fresnel_scale = scale;
        self
    }

    /// The same kernel without the spheres' lane cull (every lane runs the exact
    /// sphere test); for tests and measurements.
    #[doc(hidden)]
    pub fn without_sphere_cull(mut self) -> Self {
        self.cull = None;
        self
    }

    /// The same kernel with the emitters at infinity `scale` times too bright (escaped
    /// rays and light samples); for the test that shows the comparison with the
    /// scalar estimator catches it.
    #[doc(hidden)]
    pub fn with_background_scale(mut self, scale: f32) -> Self {
        self.background_scale = scale;
        self
    }

    /// The same kernel with a wrong roughness (the rough conductor's α times
    /// `scale`); for the test that shows the comparison with the scalar estimator
    /// catches it.
    #[doc(hidden)]
    pub fn with_alpha_scale(mut self, scale: f32) -> Self {
        self.alpha_scale = scale;
        self
    }

    /// Whether the kernel traces its W rays at once against every triangle (small
    /// scenes) rather than lane by lane through the hierarchy; for tests.
    #[doc(hidden)]
    pub fn traces_all_lanes_at_once(&self) -> bool {
        self.rays.is_some()
    }

    /// Radiance samples `0..out.len()`: sample `k` starts from `start(k)` (its camera
    /// ray and its random stream, already advanced past the pixel jitter) and its
    /// estimate is written to `out[k]`. Equivalent to calling `radiance_in` on each.
    ///
    /// `start` is called through a `dyn` reference (once per path), so the kernel is
    /// compiled once, in this crate, not again in every crate that calls it.
    pub fn radiance_batch(
        &self,
        params: &PathParams,
        mut start: impl FnMut(usize) -> (Ray, Rng),
        out: &mut [Rgb],
        counters: &mut PathCounters,
    ) {
        self.run(params, &mut Starts::Each(&mut start), out, counters);
    }

    /// The radiance of a tile's camera samples ([`CameraBatch`]): sample `k` is
    /// `batch.sample(k)`, its estimate goes to `out[k]` (`out.len() == batch.len()`) and
    /// its filter weight to `weights[k]` (`weights` is `batch.len()` long, or empty when
    /// the caller needs none: [`CameraBatch::unit_weights`]). The same as
    /// [`Self::radiance_batch`] over `batch.sample`, but the kernel makes the camera
    /// samples W at once, in its own vector width.
    pub fn radiance_camera_batch(
        &self,
        params: &PathParams,
        batch: &CameraBatch<'_>,
        out: &mut [Rgb],
        weights: &mut [f32],
        counters: &mut PathCounters,
    ) {
        assert_eq!(out.len(), batch.len());
        assert!(weights.is_empty() || weights.len() == batch.len());
        self.run(
            params,
            &mut Starts::Camera { batch, weights },
            out,
            counters,
        );
    }

    fn run(
        &self,
        params: &PathParams,
        starts: &mut Starts<'_, '_>,
        out: &mut [Rgb],
        counters: &mut PathCounters,
    ) {
        match self.build {
            // SAFETY: `build` is only ever a build this CPU runs (`chosen`, or
            // `with_build`'s check).
            #[cfg(target_arch = "x86_64")]
            SimdBuild::Avx512 => unsafe { kernel::run_avx512(self, params, starts, out, counters) },
            #[cfg(target_arch = "x86_64")]
            SimdBuild::Avx2 => unsafe { kernel::run_avx2(self, params, starts, out, counters) },
            _ => kernel::run_portable(self, params, starts, out, counters),
        }
    }
}
