//! The path integrator: a Monte Carlo estimator of the rendering equation
//! (Kajiya 1986, "The Rendering Equation"), with next-event estimation of direct light
//! and BSDF sampling combined by multiple importance sampling with the power heuristic
//! (Veach and Guibas 1995), and Russian roulette (Arvo and Kirk 1990).
//!
//! Path depth follows Mitsuba's convention: a path of `k` segments from the camera has
//! depth `k`; `max_depth = 1` shows only emitters seen directly, `2` adds direct light.

use super::lights::LightSampler;
use super::material_map::{
    desc_anisotropic, is_uniform, material_bsdf, material_bsdf_query, Tangents,
};
use super::tracer::{AccelTracer, PathHit, Tracer};
use crate::raytree::{Blocker, NoRecorder, RayKind, Recorder};
use glam::{Vec2, Vec3};
use irradia_core::{offset_ray_origin, Frame, Ray, Rgb, Rng};
use irradia_scatter::{Bsdf, LobeFlags, Scatter};
use irradia_scene::texture::TextureQuery;
use irradia_scene::{Material, Scene};
use std::borrow::Cow;

/// Parameters of the estimator.
#[derive(Clone, Copy, Debug)]
pub struct PathParams {
    /// Longest path, in segments (Mitsuba's `max_depth`).
    pub max_depth: u32,
    /// Depth from which Russian roulette may end paths (Mitsuba's `rr_depth`).
    pub rr_depth: u32,
}

impl Default for PathParams {
    fn default() -> Self {
        Self {
            max_depth: 8,
            rr_depth: 5,
        }
    }
}

impl PathParams {
    /// The parameters a scene's settings ask for (the one place they are built):
    /// `max_depth` from the settings (Mitsuba's convention, at least 1), Mitsuba's
    /// default `rr_depth`.
    pub fn for_settings(s: &irradia_scene::RenderSettings) -> Self {
        Self {
            max_depth: s.max_depth.max(1),
            ..Self::default()
        }
    }
}

/// Power heuristic with β = 2.
#[inline]
pub(crate) fn mis(a: f32, b: f32) -> f32 {
    let (a2, b2) = (a * a, b * b);
    if a2 + b2 > 0.0 {
        a2 / (a2 + b2)
    } else {
        0.0
    }
}

/// Counts of rays cast, for statistics.
#[derive(Clone, Copy, Debug, Default)]
pub struct PathCounters {
    pub paths: u64,
    pub rays: u64,
    pub shadow_rays: u64,
}

impl PathCounters {
    pub fn add(&mut self, o: &PathCounters) {
        self.paths += o.paths;
        self.rays += o.rays;
        self.shadow_rays += o.shadow_rays;
    }
}

/// Everything a path sample reads, prepared once per render: the scene, the ray
/// queries, the lights and the BSDF of every material whose colour is the same
/// everywhere (so it is not rebuilt at every hit).
pub struct PathScene<'a, T: Tracer> {
    pub scene: &'a Scene,
    pub tracer: T,
    pub lights: &'a LightSampler,
    /// Per material: its BSDF when it does not vary over surfaces (solid colour);
    /// `None`, or an empty table, means it is built at each hit.
    pub bsdfs: Vec<Option<Bsdf>>,
    /// Per material: whether its BSDF needs the surface's tangent frame (anisotropic
    /// roughness, normal and bump maps); an empty table means it is found at each hit.
    pub oriented: Vec<bool>,
}

impl<'a, T: Tracer> PathScene<'a, T> {
    /// Prepares `scene` for sampling with the ray queries of `tracer`.
    pub fn new(scene: &'a Scene, tracer: T, lights: &'a LightSampler) -> Self {
        let bsdfs = scene
            .materials
            .iter()
            .map(|m| {
                is_uniform(m)
                    .then(|| material_bsdf(m, Vec3::ZERO, Vec2::ZERO, &Tangents::default()))
            })
            .collect();
        let oriented = scene.materials.iter().map(needs_tangent_frame).collect();
        Self {
            scene,
            tracer,
            lights,
            bsdfs,
            oriented,
        }
    }
}

/// Whether `material`'s BSDF is not symmetric about the normal, so that it needs the
/// surface's tangent frame.
fn needs_tangent_frame(material: &irradia_scene::Material) -> bool {
    material.bsdf.as_deref().is_some_and(desc_anisotropic)
}

/// The BSDF at a hit and its local shading frame, or `None` when the surface does not
/// scatter. For BSDFs that are not symmetric about the normal, the frame's +x is
/// `dp/du` where the shape reports it (Mitsuba's shading frame, which orients
/// anisotropic roughness and normal maps); its +z is the shading
/// normal kept on the side of the geometric normal (out of solids), never turned
/// towards the viewer: Mitsuba's one-sided BSDFs
/// see light from inside as arriving on their back (`wo.z < 0`), and the lecture
/// mixture, which scatters on both sides, renders as before.
///
/// A material whose BSDF is the same everywhere lends the prepared one (no copy of the
/// BSDF, no reference count touched by every hit of every thread).
pub(crate) fn surface_at<'p, T: Tracer>(
    ps: &'p PathScene<'_, T>,
    sh: &PathHit,
) -> Option<(Cow<'p, Bsdf>, Frame)> {
    let hit = &sh.hit;
    let ns = if hit.shading_normal.dot(hit.normal) < 0.0 {
        -hit.shading_normal
    } else {
        hit.shading_normal
    };
    // Mitsuba's shading frame: +x along dp/du where the shape has a parameterisation.
    // Only a BSDF that is not symmetric about the normal (anisotropic roughness, normal
    // and bump maps) sees the difference; the others keep the cheaper frame about the
    // normal alone (and their random streams, so their images are unchanged).
    let material = &ps.scene.materials[sh.material as usize];
    let oriented = match ps.oriented.get(sh.material as usize) {
        Some(&o) => o,
        None => needs_tangent_frame(material),
    };
    let (frame, tangents) = if oriented {
        let (dpdu, dpdv) = match ps.scene.accel.instances().get(sh.instance as usize) {
            Some(inst) => inst.uv_derivatives(hit),
            None => (Vec3::ZERO, Vec3::ZERO),
        };
        let frame = Frame::from_normal_tangent(ns, dpdu);
        let tangents = Tangents {
            dpdu: frame.to_local(dpdu),
            dpdv: frame.to_local(dpdv),
            ng: frame.to_local(hit.normal),
        };
        (frame, tangents)
    } else {
        (Frame::from_normal(ns), Tangents::default())
    };
    let bsdf = match ps.bsdfs.get(sh.material as usize) {
        Some(Some(b)) => Cow::Borrowed(b),
        _ => {
            let q = texture_query(ps.scene, sh);
            Cow::Owned(material_bsdf_query(material, hit.point, &q, &tangents))
        }
    };
    if bsdf.flags() == LobeFlags::NONE {
        return None;
    }
    Some((bsdf, frame))
}

/// What a texture lookup at `sh` reads: the hit's uv and where it lies on the
/// attributes of the mesh hit (for `mesh_attribute` textures).
pub(crate) fn texture_query<'s>(scene: &'s Scene, sh: &PathHit) -> TextureQuery<'s> {
    let instance = scene.accel.instances().get(sh.instance as usize);
    TextureQuery {
        uv: sh.hit.uv,
        attributes: instance.and_then(|inst| inst.attribute_point(&sh.hit)),
    }
}

/// The radiance `material` emits at `sh` (on its emitting side): its emission
/// texture there, or the constant.
#[inline]
pub(crate) fn emission_at(scene: &Scene, material: &Material, sh: &PathHit) -> Rgb {
    if material.emission_texture.is_none() {
        return material.emission;
    }
    material.emission_query(&texture_query(scene, sh))
}

/// One sample of the radiance arriving along `ray` (a camera ray), traced through the
/// scene's generic acceleration structure.
pub fn radiance(
    scene: &Scene,
    lights: &LightSampler,
    params: &PathParams,
    ray: Ray,
    rng: &mut Rng,
    counters: &mut PathCounters,
) -> Rgb {
    let ps = PathScene {
        scene,
        tracer: AccelTracer { scene },
        lights,
        bsdfs: Vec::new(),
        oriented: Vec::new(),
    };
    radiance_in(&ps, params, ray, rng, counters)
}

/// One sample of the radiance arriving along `ray`, in a prepared scene (with the
/// [`FlatScene`](super::flat_scene::FlatScene) as its tracer in renders).
#[inline]
pub fn radiance_in<T: Tracer>(
    ps: &PathScene<'_, T>,
    params: &PathParams,
    ray: Ray,
    rng: &mut Rng,
    counters: &mut PathCounters,
) -> Rgb {
    radiance_recorded(ps, params, ray, rng, counters, &mut NoRecorder)
}

/// [`radiance_in`] reporting the path to `rec` as a ray tree (`irradia trace-pixel`):
/// each segment is a node (kind `camera`, then `reflected` or `refracted`) whose
/// children are its shadow ray and the next segment; a node's `local` is the radiance
/// added at its hit (emission and next-event estimation, MIS-weighted), its `radiance`
/// what the rest of the path returns, and a path ended by Russian roulette or the depth
/// limit ends in a cut child. With [`NoRecorder`] this is `radiance_in`, instruction for
/// instruction (every recording call compiles away).
pub fn radiance_recorded<T: Tracer, R: Recorder>(
    ps: &PathScene<'_, T>,
    params: &PathParams,
    mut ray: Ray,
    rng: &mut Rng,
    counters: &mut PathCounters,
    rec: &mut R,
) -> Rgb {
    let (scene, tracer, lights) = (ps.scene, &ps.tracer, ps.lights);
    counters.paths += 1;
    let mut l = Rgb::BLACK;
    let mut beta = Rgb::WHITE;
    // The product of the relative indices of refraction crossed so far: radiance
    // loses a factor eta^2 entering glass and gets it back leaving, so Russian
    // roulette judges `beta * eta^2` (as Mitsuba's `path` does) and does not end
    // paths for being inside a denser medium.
    let mut eta = 1.0f32;
    // Recording only: per open segment, its weight and `l` when it began.
    let mut open: Vec<(Rgb, Rgb)> = Vec::new();
    let mut kind = RayKind::Camera;
    // The previous scattering vertex and its BSDF density, for MIS on emitter hits.
    let mut prev: Option<(Vec3, f32)> = None;
    for depth in 1..=params.max_depth {
        counters.rays += 1;
        if R::RECORDS {
            rec.begin(kind, depth - 1, &ray, beta);
            open.push((beta, l));
        }
        let Some(sh) = tracer.intersect(&ray, f32::INFINITY) else {
            if lights.has_environment() {
                let (le, pdf_light) = lights.environment_radiance_pdf(ray.dir, prev.is_some());
                let w = match prev {
                    Some((_, pdf)) => mis(pdf, pdf_light),
                    None => 1.0,
                };
                l += beta * le * w;
            }
            break;
        };
        let hit = sh.hit;
        let material = &scene.materials[sh.material as usize];
        let wo_world = -ray.dir.normalize();
        let n = hit.normal;
        if R::RECORDS {
            let name = &scene.objects[sh.instance as usize].name;
            rec.hit(sh.instance, name, hit.point, n);
        }

        if !material.emission.is_black() && (material.emission_two_sided || n.dot(wo_world) > 0.0) {
            let w = match prev {
                Some((p, pdf)) => mis(pdf, lights.pdf_object(scene, sh.instance, p, hit.point, n)),
                None => 1.0,
            };
            l += beta * emission_at(scene, material, &sh) * w;
        }
        if depth == params.max_depth {
            if R::RECORDS {
                rec.cut(RayKind::Reflected, depth, beta, "depth");
            }
            break;
        }
        let Some((bsdf, frame)) = surface_at(ps, &sh) else {
            break;
        };
        let wo = frame.to_local(wo_world);

        // Next-event estimation.
        if bsdf.flags().has_smooth() {
            if let Some(ls) = lights.sample(scene, hit.point, rng.next_f32(), rng.next_2d()) {
                let wi = frame.to_local(ls.wi);
                let f = bsdf.eval(wo, wi);
                if !f.is_black() && ls.wi.dot(n) * wi.z > 0.0 {
                    let side = if ls.wi.dot(n) > 0.0 { n } else { -n };
                    let origin = offset_ray_origin(hit.point, side, hit.error);
                    counters.shadow_rays += 1;
                    let (shadow, t_max) = match ls.target {
                        Some(t) => (Ray::new(origin, t - origin), 1.0),
                        None => (Ray::new(origin, ls.wi), f32::INFINITY),
                    };
                    let visible = !tracer.occluded(&shadow, t_max);
                    if visible {
                        let w = if ls.delta {
                            1.0
                        } else {
                            mis(ls.pdf, bsdf.pdf(wo, wi))
                        };
                        l += beta * f * ls.li * (wi.z.abs() * w / ls.pdf);
                    }
                    if R::RECORDS {
                        let blocker = (!visible)
                            .then(|| tracer.intersect(&shadow, t_max))
                            .flatten();
                        let blocker = blocker.as_ref().map(|b| Blocker {
                            object: b.instance,
                            name: &scene.objects[b.instance as usize].name,
                            point: b.hit.point,
                            normal: b.hit.normal,
                        });
                        let through = if visible { Rgb::WHITE } else { Rgb::BLACK };
                        rec.shadow(&shadow, depth - 1, blocker, through);
                    }
                }
            }
        } else {
            // Keep the random stream aligned whatever the material.
            rng.next_f32();
            rng.next_2d();
        }

        // Continue the path by sampling the BSDF.
        let Some(s) = bsdf.sample(wo, rng.next_f32(), rng.next_2d()) else {
            break;
        };
        let wi_world = frame.to_world(s.wi);
        // Reject directions on the wrong side of the geometric surface (shading-normal
        // light leaks).
        if wi_world.dot(n) * s.wi.z <= 0.0 {
            break;
        }
        beta *= s.weight;
        eta *= s.eta;
        if beta.is_black() || !beta.is_finite() {
            break;
        }
        prev = if s.is_delta() {
            None
        } else {
            Some((hit.point, s.pdf))
        };
        let side = if wi_world.dot(n) > 0.0 { n } else { -n };
        ray = Ray::new(offset_ray_origin(hit.point, side, hit.error), wi_world);

        kind = if s.wi.z < 0.0 {
            RayKind::Refracted
        } else {
            RayKind::Reflected
        };
        if depth + 1 >= params.rr_depth {
            let q = (beta.max_component() * (eta * eta)).min(0.95);
            if rng.next_f32() >= q {
                if R::RECORDS {
                    rec.cut(kind, depth, beta, "roulette");
                }
                break;
            }
            beta = beta / q;
        }
    }
    if R::RECORDS {
        close_segments(rec, &open, l);
    }
    l
}

/// Closes the recorded segments (weight, pixel radiance when each began), innermost
/// first: each gets the radiance added at its own hit (`local`) and returns what it and
/// every later segment added (`end`), both divided by its weight; `total` is the sample.
fn close_segments<R: Recorder>(rec: &mut R, open: &[(Rgb, Rgb)], total: Rgb) {
    let unweight = |v: Rgb, w: Rgb| {
        let d = |a: f32, b: f32| if b > 0.0 { a / b } else { 0.0 };
        Rgb::new(d(v.r, w.r), d(v.g, w.g), d(v.b, w.b))
    };
    let mut next_start = total;
    for &(weight, start) in open.iter().rev() {
        rec.local(unweight(next_start - start, weight));
        rec.end(unweight(total - start, weight));
        next_start = start;
    }
}
