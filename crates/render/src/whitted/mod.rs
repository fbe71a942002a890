//! The recursive (Whitted) ray tracer, as in the lecture's "Recursive Ray Tracer"
//! slides: at each hit, the local colour from the Phong model with shadow (feeler)
//! rays, plus the mirror-reflected and the refracted ray traced recursively:
//!
//! ```text
//! trace(p, d, step): if step > max return background
//!     q = intersect(p, d); if none return background
//!     return phong(q, n) + k_r trace(q, r, step+1) + k_t trace(q, t, step+1)
//! ```
//!
//! Recursion stops at `max_depth` (camera rays are depth 1; POV-Ray's
//! `max_trace_level`, and like POV-Ray a ray beyond it returns black), when a ray's
//! weight (the product of the coefficients from the camera, largest channel) falls
//! below `min_weight` (adaptive depth control, POV-Ray's `adc_bailout`), and when a ray
//! leaves the scene (it returns the background colour). The lecture's "When to stop"
//! slide lists exactly these three.
//!
//! The tracer is generic over a [`Recorder`]: rendering passes the empty one,
//! `trace-pixel` one that builds the ray tree, so both run this same code. It is also
//! generic over where its geometry answers come from ([`RayQuery`]): the scene's own
//! objects ([`SceneGeometry`]) or, for object-parallel rendering, answers forwarded
//! from the processes that own the objects (`irradia_parallel::raytrace_forward`).

pub mod geometry;
pub(crate) mod lights;
pub(crate) mod media;
mod query;
mod shading;
mod shadow;

use crate::integrator::{AovSample, Integrator};
use crate::raytree::{NoRecorder, RayKind, Recorder};
use crate::stats::Stats;
use geometry::object_transmits;
pub use geometry::SceneGeometry;
use glam::Vec3;
use irradia_core::{offset_ray_origin, Ray, Rgb, Rng};
use irradia_geometry::SceneHit;
pub use irradia_geometry::{ObjectSet, RayQuery};
use irradia_scatter::optics::{fresnel_dielectric, reflect_about, refract_through};
use irradia_scene::{Scene, ShadingModel};
use lights::PreparedLight;
use media::MediaStack;

/// The Whitted integrator over one scene, with its lights prepared, asking `G` for
/// its geometry answers (the scene's own objects unless told otherwise).
pub struct Whitted<'s, G = SceneGeometry<'s>> {
    scene: &'s Scene,
    lights: Vec<PreparedLight>,
    max_depth: u32,
    min_weight: f32,
    background: Rgb,
    ambient_light: Rgb,
    geometry: G,
    /// Whether any object lets light through: then shadow rays ask the opaque and the
    /// clear objects apart and filter the light through the clear ones.
    any_clear: bool,
    /// Whether every clear object passes light whole (each of its surfaces filters by
    /// exactly white: [`geometry::clear_passes_all`]): then a shadow ray is decided by
    /// one any-hit query over the opaque objects, with no walk through the clear ones.
    clear_passes_all: bool,
}

/// Per-sample state threaded through the recursion.
pub(crate) struct Ctx<'c, R: Recorder> {
    pub rng: &'c mut Rng,
    pub stats: &'c mut Stats,
    pub rec: &'c mut R,
    /// Deepest level reached by this sample's tree.
    pub deepest: u32,
}

impl<'s> Whitted<'s> {
    /// The tracer over `scene`'s own objects, prepared for this tracer alone.
    pub fn new(scene: &'s Scene) -> Self {
        Self::with_geometry(scene, SceneGeometry::new(scene))
    }
}

impl<'p, 's> Whitted<'s, &'p SceneGeometry<'s>> {
    /// The tracer over a prepared scene's exact structure.
    pub fn prepared(prepared: &'p crate::PreparedScene<'s>) -> Self {
        Self::with_geometry(prepared.scene(), prepared.objects())
    }
}

impl<'s, G: RayQuery> Whitted<'s, G> {
    /// The tracer over `scene`'s camera, lights, materials and settings, asking
    /// `geometry` where rays hit (its object indices are `scene.objects`').
    pub fn with_geometry(scene: &'s Scene, geometry: G) -> Self {
        let s = &scene.settings;
        Self {
            scene,
            lights: scene.lights.iter().filter_map(PreparedLight::new).collect(),
            max_depth: s.max_depth.max(1),
            min_weight: s.min_weight.max(0.0),
            background: s.background,
            ambient_light: s.ambient_light,
            geometry,
            any_clear: (0..scene.objects.len()).any(|i| object_transmits(scene, i)),
            clear_passes_all: geometry::clear_passes_all(scene),
        }
    }

    /// Where the geometry answers come from.
    pub fn geometry(&self) -> &G {
        &self.geometry
    }

    /// The geometry back (e.g. to read what it recorded).
    pub fn into_geometry(self) -> G {
        self.geometry
    }

    /// What a ray travelling along `dir` sees when it leaves the scene: the background
    /// plus the radiance of the lights at infinity (Mitsuba's `constant` and `envmap`).
    #[inline]
    fn escaped(&self, dir: Vec3) -> Rgb {
        self.scene
            .lights
            .iter()
            .filter(|l| l.is_environment())
            .fold(self.background, |c, l| c + l.environment_radiance(dir))
    }

    /// Nearest hit among all objects.
    #[inline]
    pub(crate) fn intersect_all(&self, ray: &Ray, t_max: f32) -> Option<SceneHit> {
        self.geometry.closest_hit(ObjectSet::All, ray, t_max)
    }

    /// Whether any object is hit.
    #[inline]
    pub(crate) fn occluded_all(&self, ray: &Ray, t_max: f32) -> bool {
        self.geometry.any_hit(ObjectSet::All, ray, t_max)
    }

    /// Traces one camera ray with a recorder (the ray-tree hook); returns the radiance.
    pub fn sample_recorded<R: Recorder>(
        &self,
        ray: &Ray,
        rng: &mut Rng,
        stats: &mut Stats,
        aov: &mut AovSample,
        rec: &mut R,
    ) -> Rgb {
        let mut cx = Ctx {
            rng,
            stats,
            rec,
            deepest: 0,
        };
        let c = self.trace(
            ray,
            RayKind::Camera,
            1,
            Rgb::WHITE,
            &MediaStack::EMPTY,
            &mut cx,
            Some(aov),
        );
        aov.ray_depth = cx.deepest;
        c
    }

    /// Traces `ray` (already counted as allowed by depth and weight) and returns the
    /// radiance it brings back.
    #[allow(clippy::too_many_arguments)]
    fn trace<R: Recorder>(
        &self,
        ray: &Ray,
        kind: RayKind,
        depth: u32,
        weight: Rgb,
        media: &MediaStack,
        cx: &mut Ctx<'_, R>,
        aov: Option<&mut AovSample>,
    ) -> Rgb {
        match kind {
            RayKind::Camera => cx.stats.camera_rays += 1,
            RayKind::Reflected => cx.stats.reflected_rays += 1,
            RayKind::Refracted => cx.stats.refracted_rays += 1,
            RayKind::Shadow => cx.stats.shadow_rays += 1,
        }
        cx.stats.reached(depth);
        cx.deepest = cx.deepest.max(depth);
        cx.rec.begin(kind, depth, ray, weight);

        let scene = self.scene;
        let Some(sh) = self.intersect_all(ray, f32::INFINITY) else {
            cx.stats.missed += 1;
            let seen = self.escaped(ray.dir);
            cx.rec.end(seen);
            return seen;
        };
        let hit = &sh.hit;
        let object = &scene.objects[sh.instance as usize];
        let mat = &scene.materials[object.material_for_leaf(hit.leaf) as usize];
        cx.rec
            .hit(sh.instance, &object.name, hit.point, hit.shading_normal);

        // Orient the normals towards the side the ray comes from.
        let entering = ray.dir.dot(hit.normal) < 0.0;
        let ng = if entering { hit.normal } else { -hit.normal };
        let ns = if hit.shading_normal.dot(ng) < 0.0 {
            -hit.shading_normal
        } else {
            hit.shading_normal
        };
        if let Some(aov) = aov {
            aov.depth = hit.t * ray.dir.length();
            aov.normal = hit.shading_normal;
            aov.object = sh.instance as i32;
        }

        let pov = mat.model == ShadingModel::PovRay;
        let colour = mat.color.eval(hit.point, hit.uv);
        let d = ray.dir.normalize();
        let view = -d;
        let filter = mat.filter_color.unwrap_or(colour) * mat.transmission;
        let mut result = self.local(hit, ng, ns, view, mat, colour, filter, depth, cx);
        cx.rec.local(result);

        // Coefficients of the reflected and transmitted rays.
        let (mut kr, mut kt) = (mat.reflection, filter);
        // (Whether the object is a closed solid is asked only of transmitting ones.)
        let (eta, far_media) = if mat.transmission > 0.0 && self.geometry.is_solid(sh.instance) {
            media.cross(sh.instance, mat.ior, entering)
        } else {
            (1.0, *media)
        };
        // `eta` is n1/n2 (the ray's medium over the next); the optics module's is the far
        // side's over the near side's, with the normal on the near side.
        if mat.fresnel && mat.transmission > 0.0 {
            let f = fresnel_dielectric(view.dot(ns).clamp(0.0, 1.0), 1.0 / eta).reflectance;
            kr = kr * f;
            kt = kt * (1.0 - f);
        }

        if !kt.is_black() {
            match refract_through(view, ns, 1.0 / eta) {
                Some(t) => {
                    let o = offset_ray_origin(hit.point, -ng, hit.error);
                    result += self.spawn(
                        Ray::new(o, t),
                        RayKind::Refracted,
                        depth,
                        kt,
                        weight,
                        &far_media,
                        cx,
                    );
                }
                None => {
                    // Total internal reflection: the light that would have left is
                    // reflected. POV-Ray adds it unfiltered (Trace::ComputeLightedTexture).
                    let k = if pov { Rgb::WHITE } else { kt };
                    let r = mirror(d, ns, ng);
                    let o = offset_ray_origin(hit.point, ng, hit.error);
                    result += self.spawn(
                        Ray::new(o, r),
                        RayKind::Reflected,
                        depth,
                        k,
                        weight,
                        media,
                        cx,
                    );
                }
            }
        }
        if !kr.is_black() {
            let r = mirror(d, ns, ng);
            let o = offset_ray_origin(hit.point, ng, hit.error);
            result += self.spawn(
                Ray::new(o, r),
                RayKind::Reflected,
                depth,
                kr,
                weight,
                media,
                cx,
            );
        }
        cx.rec.end(result);
        result
    }

    /// Spawns a secondary ray with coefficient `k` from a ray of `depth` and `weight`,
    /// unless depth or weight cut it off; returns `k * radiance`.
    #[allow(clippy::too_many_arguments)]
    #[inline]
    fn spawn<R: Recorder>(
        &self,
        ray: Ray,
        kind: RayKind,
        depth: u32,
        k: Rgb,
        weight: Rgb,
        media: &MediaStack,
        cx: &mut Ctx<'_, R>,
    ) -> Rgb {
        let w = weight * k;
        if depth + 1 > self.max_depth {
            cx.stats.cut_by_depth += 1;
            cx.rec.cut(kind, depth + 1, w, "depth");
            return Rgb::BLACK;
        }
        if w.max_component() < self.min_weight {
            cx.stats.cut_by_weight += 1;
            cx.rec.cut(kind, depth + 1, w, "weight");
            return Rgb::BLACK;
        }
        k * self.trace(&ray, kind, depth + 1, w, media, cx, None)
    }
}

/// Mirror direction about the shading normal, falling back to the geometric normal
/// when bumped shading normals would send the ray into the surface (as POV-Ray's
/// `ComputeReflection` does).
#[inline]
fn mirror(d: Vec3, ns: Vec3, ng: Vec3) -> Vec3 {
    let r = reflect_about(-d, ns);
    if r.dot(ng) > 0.0 {
        r
    } else {
        reflect_about(-d, ng)
    }
}

impl<G: RayQuery + Sync> Integrator for Whitted<'_, G> {
    #[inline]
    fn sample(&self, ray: &Ray, rng: &mut Rng, stats: &mut Stats, aov: &mut AovSample) -> Rgb {
        self.sample_recorded(ray, rng, stats, aov, &mut NoRecorder)
    }
}
