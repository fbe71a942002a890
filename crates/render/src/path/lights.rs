//! Light sampling for next-event estimation: every emitter of the scene (point, spot,
//! projector and directional lights, rectangle and sphere area lights, emissive
//! objects, the constant environment (the background plus Mitsuba's `constant`
//! emitters) and importance-sampled environment maps), chosen in proportion to its
//! power, or all equally often (`light_selection = "uniform"`, Mitsuba's way). Each emitter gives a direction, its radiance and its solid-angle density
//! (`sample`), and the density of a BSDF-sampled ray that reaches it (`pdf_object` for
//! surfaces, `pdf_environment` for rays that leave the scene), for multiple importance
//! sampling (Veach 1997, 9.2).
//!
//! Rectangle and sphere *lights* (as opposed to emissive objects) are not part of the
//! geometry, so the path tracer sees them only through light sampling; make an object
//! emissive when it should also be visible and reachable by mirrors.

use super::envmap::EnvmapSampler;
use glam::{Affine3A, Vec2, Vec3};
use irradia_core::{sampling, Rgb};
use irradia_geometry::Instance;
use irradia_scene::texture::{TextureMap, TextureQuery};
use irradia_scene::{Light, LightSelection, Projector, Scene, SpotProfile, SpotTexture};
use std::f32::consts::PI;
use std::sync::Arc;
use surface::{SurfaceSampler, WorldFacets};
use visible_sphere::VisibleSphere;

/// A light point's density: by area (turned into solid angle at the shading point) or
/// already by solid angle (a sphere's cone).
#[derive(Clone, Copy, Debug)]
enum Density {
    Area(f32),
    SolidAngle(f32),
}

/// One sampled light connection from a shading point.
#[derive(Clone, Copy, Debug)]
pub struct LightSample {
    /// Unit direction from the shading point towards the light.
    pub wi: Vec3,
    /// The point on the light (moved off its surface), or `None` for lights at infinity.
    pub target: Option<Vec3>,
    /// Incident radiance (area lights) or `intensity / r²` (delta lights).
    pub li: Rgb,
    /// Solid-angle density including the choice of this light; for delta lights the
    /// probability of choosing it.
    pub pdf: f32,
    pub delta: bool,
}

#[derive(Clone, Debug)]
enum Emitter {
    Point {
        position: Vec3,
        intensity: Rgb,
    },
    Spot {
        position: Vec3,
        direction: Vec3,
        intensity: Rgb,
        cos_inner: f32,
        cos_outer: f32,
        profile: SpotProfile,
        texture: Option<Arc<SpotTexture>>,
    },
    /// Mitsuba's `projector`: a delta-position emitter with an image for intensity.
    Projector(Arc<Projector>),
    Directional {
        direction: Vec3,
        irradiance: Rgb,
    },
    Rect {
        corner: Vec3,
        edge_u: Vec3,
        edge_v: Vec3,
        normal: Vec3,
        area: f32,
        radiance: Rgb,
    },
    Sphere {
        center: Vec3,
        radius: f32,
        radiance: Rgb,
    },
    Object {
        instance: u32,
        radiance: Rgb,
        /// Emission read at the sampled point's uv (Mitsuba's textured `area`).
        texture: Option<TextureMap>,
        area: f32,
        two_sided: bool,
        surface: SurfaceSampler,
        /// The facets in world space (for facet-sampled shapes).
        world: Option<WorldFacets>,
        /// A sphere (kept one by its transform): sampled by the cone it subtends from
        /// points outside it ([`VisibleSphere`]), by area from inside.
        cone: Option<VisibleSphere>,
    },
    Environment {
        radiance: Rgb,
        radius: f32,
    },
    /// Mitsuba's `envmap`, importance sampled by luminance.
    Envmap {
        sampler: EnvmapSampler,
        radius: f32,
    },
}

/// An emissive object's world-space facets, as the wide kernel reads them
/// ([`LightSampler::kernel_emitters`]).
#[derive(Clone, Copy, Debug)]
pub(crate) struct FacetEmitter<'a> {
    pub radiance: Rgb,
    pub two_sided: bool,
    pub triangles: &'a [[Vec3; 3]],
    pub normals: &'a [Vec3],
    pub pdf_area: &'a [f32],
    /// Cumulative area of the triangles (the table `sample` searches).
    pub cdf: &'a [f32],
    /// The probability of choosing this emitter.
    pub probability: f32,
}

/// The radiance of an emissive object at its sampled world point `q` (normal `n`):
/// `radiance`, or its emission texture at the point's surface coordinates, found by a
/// short ray back onto the instance along the normal (from outside, then from inside),
/// so every shape and mesh reports the uv its own hits do. The texture's mean stands in
/// if neither ray finds the surface.
fn textured(
    scene: &Scene,
    instance: u32,
    texture: &Option<TextureMap>,
    q: Vec3,
    n: Vec3,
    radiance: Rgb,
) -> Rgb {
    let Some(t) = texture else {
        return radiance;
    };
    let inst = &scene.accel.instances()[instance as usize];
    let eps = 1e-3 * (1.0 + q.abs().max_element());
    let hit = [n, -n].iter().find_map(|&side| {
        inst.intersect(&irradia_core::Ray::new(q + side * eps, -side), 2.0 * eps)
    });
    match hit {
        Some(h) => t.eval(&TextureQuery {
            uv: h.uv,
            attributes: inst.attribute_point(&h),
        }),
        None => radiance,
    }
}

/// The emitters of a scene with a discrete distribution proportional to power (or
/// uniform, [`LightSelection::Uniform`]).
#[derive(Clone, Debug, Default)]
pub struct LightSampler {
    emitters: Vec<Emitter>,
    cdf: Vec<f32>,
    probability: Vec<f32>,
    /// For each instance, the index of its emitter (emissive objects).
    by_instance: Vec<Option<u32>>,
    /// The constant environment's emitter.
    environment: Option<u32>,
    /// The environment maps' emitters.
    envmaps: Vec<u32>,
}

fn det3(m: &Affine3A) -> f32 {
    m.matrix3.determinant()
}

/// World-area density factor of an instance at object-space normal `n_obj`:
/// dA_world = |det M| |M^-T n| dA_object.
fn area_jacobian(inst: &Instance, n_obj: Vec3) -> f32 {
    let m_inv_t = inst.to_object().matrix3.transpose();
    det3(inst.to_world()).abs() * Vec3::from(m_inv_t * glam::Vec3A::from(n_obj)).length()
}

impl LightSampler {
    pub fn new(scene: &Scene) -> Self {
        let mut emitters = Vec::new();
        let bounds = scene
            .accel
            .instances()
            .iter()
            .map(|i| i.bounds())
            .filter(|b| b.is_finite())
            .fold(irradia_core::Aabb::EMPTY, |a, b| a.union(b));
        let radius = if bounds.is_empty() {
            1.0
        } else {
            0.5 * bounds.extent().length().max(1e-3)
        };
        for l in &scene.lights {
            emitters.push(match *l {
                Light::Point {
                    position,
                    intensity,
                } => Emitter::Point {
                    position,
                    intensity,
                },
                Light::Spot {
                    position,
                    direction,
                    intensity,
                    cos_inner,
                    cos_outer,
                    profile,
                    ref texture,
                } => Emitter::Spot {
                    position,
                    direction: direction.normalize(),
                    intensity,
                    cos_inner,
                    cos_outer,
                    profile,
                    texture: texture.clone(),
                },
                Light::Projector(ref p) => Emitter::Projector(p.clone()),
                // Gathered below with the background.
                Light::Constant { .. } => continue,
                Light::Envmap(ref map) => Emitter::Envmap {
                    sampler: EnvmapSampler::new(map.clone()),
                    radius,
                },
                Light::Directional {
                    direction,
                    irradiance,
                } => Emitter::Directional {
                    direction: direction.normalize(),
                    irradiance,
                },
                Light::Rect {
                    corner,
                    edge_u,
                    edge_v,
                    radiance,
                    ..
                } => {
                    let c = edge_u.cross(edge_v);
                    Emitter::Rect {
                        corner,
                        edge_u,
                        edge_v,
                        normal: c.normalize(),
                        area: c.length(),
                        radiance,
                    }
                }
                Light::Sphere {
                    center,
                    radius,
                    radiance,
                    ..
                } => Emitter::Sphere {
                    center,
                    radius,
                    radiance,
                },
            });
        }
        let mut by_instance = vec![None; scene.objects.len()];
        for (i, (obj, inst)) in scene
            .objects
            .iter()
            .zip(scene.accel.instances())
            .enumerate()
        {
            let material = &scene.materials[obj.material as usize];
            let e = material.emission;
            if e.is_black() {
                continue;
            }
            if let Some((surface, area)) = SurfaceSampler::for_shape(inst.shape.as_ref()) {
                by_instance[i] = Some(emitters.len() as u32);
                let world = match &surface {
                    SurfaceSampler::Facets { triangles, cdf } => {
                        Some(WorldFacets::new(inst, triangles, cdf, area))
                    }
                    SurfaceSampler::Exact => None,
                };
                let cone = match surface {
                    SurfaceSampler::Exact => VisibleSphere::of_instance(inst),
                    SurfaceSampler::Facets { .. } => None,
                };
                emitters.push(Emitter::Object {
                    instance: i as u32,
                    radiance: e,
                    texture: material.emission_texture.clone(),
                    area,
                    two_sided: material.emission_two_sided,
                    surface,
                    world,
                    cone,
                });
            }
        }
        let envmaps = (0..emitters.len() as u32)
            .filter(|&i| matches!(emitters[i as usize], Emitter::Envmap { .. }))
            .collect();
        let mut environment = None;
        let constant = scene
            .lights
            .iter()
            .fold(scene.settings.background, |c, l| match l {
                Light::Constant { radiance } => c + *radiance,
                _ => c,
            });
        if !constant.is_black() {
            environment = Some(emitters.len() as u32);
            emitters.push(Emitter::Environment {
                radiance: constant,
                radius,
            });
        }
        let powers: Vec<f32> = emitters
            .iter()
            .map(|e| match e {
                Emitter::Point { intensity, .. } | Emitter::Spot { intensity, .. } => {
                    4.0 * PI * intensity.mean()
                }
                Emitter::Projector(p) => p.power().mean(),
                Emitter::Envmap { sampler, radius } => {
                    PI * 4.0 * PI * radius * radius * sampler.mean_radiance()
                }
                Emitter::Directional { irradiance, .. } => PI * radius * radius * irradiance.mean(),
                Emitter::Rect { area, radiance, .. } => PI * area * radiance.mean(),
                Emitter::Sphere {
                    radius, radiance, ..
                } => PI * 4.0 * PI * radius * radius * radiance.mean(),
                Emitter::Object {
                    instance,
                    radiance,
                    area,
                    ..
                } => {
                    let s = det3(scene.accel.instances()[*instance as usize].to_world())
                        .abs()
                        .powf(2.0 / 3.0);
                    PI * area * s * radiance.mean()
                }
                Emitter::Environment { radiance, radius } => {
                    PI * 4.0 * PI * radius * radius * radiance.mean()
                }
            })
            .map(|p| if p.is_finite() && p > 0.0 { p } else { 0.0 })
            // Mitsuba's choice: every emitter that gives light, equally often.
            .map(|p| match scene.settings.light_selection {
                LightSelection::Uniform if p > 0.0 => 1.0,
                _ => p,
            })
            .collect();
        let total: f32 = powers.iter().sum();
        let probability: Vec<f32> = powers
            .iter()
            .map(|p| if total > 0.0 { p / total } else { 0.0 })
            .collect();
        let mut acc = 0.0;
        let cdf = probability
            .iter()
            .map(|p| {
                acc += p;
                acc
            })
            .collect();
        Self {
            emitters,
            cdf,
            probability,
            by_instance,
            environment,
            envmaps,
        }
    }

    pub fn is_empty(&self) -> bool {
        self.cdf.last().is_none_or(|&c| c <= 0.0)
    }

    /// The emitter `sample` chooses for `u_pick`, and the probability of choosing it.
    #[inline]
    fn pick(&self, u_pick: f32) -> Option<(usize, f32)> {
        if self.is_empty() {
            return None;
        }
        let total = *self.cdf.last()?;
        let x = u_pick * total;
        // The binary search's index; a short table (a scene's few lights) is counted
        // without branches instead, as the facets of [`WorldFacets::pick`].
        let idx = if self.cdf.len() <= 16 {
            self.cdf.iter().map(|&c| (c <= x) as usize).sum::<usize>()
        } else {
            self.cdf.partition_point(|&c| c <= x)
        }
        .min(self.emitters.len() - 1);
        let pick = self.probability[idx];
        (pick > 0.0).then_some((idx, pick))
    }

    /// Samples a light as seen from world point `p`.
    pub fn sample(&self, scene: &Scene, p: Vec3, u_pick: f32, u: Vec2) -> Option<LightSample> {
        let (idx, pick) = self.pick(u_pick)?;
        let on_surface = |q: Vec3,
                          n: Vec3,
                          radiance: Rgb,
                          density: Density,
                          two_sided: bool|
         -> Option<LightSample> {
            let d = q - p;
            let dist2 = d.length_squared();
            let wi = d / dist2.sqrt();
            let facing = -wi.dot(n);
            let cos_l = if two_sided { facing.abs() } else { facing };
            let (Density::Area(pdf) | Density::SolidAngle(pdf)) = density;
            if cos_l <= 0.0 || pdf <= 0.0 {
                return None;
            }
            let target = irradia_core::offset_ray_origin(q, if facing > 0.0 { n } else { -n }, 0.0);
            Some(LightSample {
                wi,
                target: Some(target),
                li: radiance,
                pdf: match density {
                    Density::Area(pdf_area) => pick * pdf_area * dist2 / cos_l,
                    Density::SolidAngle(pdf) => pick * pdf,
                },
                delta: false,
            })
        };
        match self.emitters[idx] {
            Emitter::Point {
                position,
                intensity,
            } => {
                let d = position - p;
                let dist2 = d.length_squared();
                Some(LightSample {
                    wi: d / dist2.sqrt(),
                    target: Some(position),
                    li: intensity / dist2,
                    pdf: pick,
                    delta: true,
                })
            }
            Emitter::Spot {
                position,
                direction,
                intensity,
                cos_inner,
                cos_outer,
                profile,
                ref texture,
            } => {
                let d = position - p;
                let dist2 = d.length_squared();
                let wi = d / dist2.sqrt();
                let cos = (-wi).dot(direction);
                let f = profile.falloff(cos, cos_inner, cos_outer);
                if f <= 0.0 {
                    return None;
                }
                // Mitsuba's spot texture: the image across the cone, read only inside it.
                let tint = texture.as_ref().map_or(Rgb::WHITE, |t| t.eval(-wi, cos));
                (f > 0.0).then_some(LightSample {
                    wi,
                    target: Some(position),
                    li: intensity * tint * (f / dist2),
                    pdf: pick,
                    delta: true,
                })
            }
            Emitter::Projector(ref proj) => {
                let s = proj.illuminate(p)?;
                Some(LightSample {
                    wi: s.wi,
                    target: Some(proj.position),
                    li: s.li,
                    pdf: pick,
                    delta: true,
                })
            }
            Emitter::Envmap { ref sampler, .. } => {
                let s = sampler.sample(u)?;
                Some(LightSample {
                    wi: s.wi,
                    target: None,
                    li: s.radiance,
                    pdf: pick * s.pdf,
                    delta: false,
                })
            }
            Emitter::Directional {
                direction,
                irradiance,
            } => Some(LightSample {
                wi: -direction,
                target: None,
                li: irradiance,
                pdf: pick,
                delta: true,
            }),
            Emitter::Rect {
                corner,
                edge_u,
                edge_v,
                normal,
                area,
                radiance,
            } => on_surface(
                corner + edge_u * u.x + edge_v * u.y,
                normal,
                radiance,
                Density::Area(1.0 / area),
                false,
            ),
            Emitter::Sphere {
                center,
                radius,
                radiance,
            } => match (VisibleSphere { center, radius }).sample(p, u) {
                Some((q, n, pdf)) => on_surface(q, n, radiance, Density::SolidAngle(pdf), false),
                None => {
                    let n = sampling::uniform_sphere(u);
                    let pdf_area = visible_sphere::inverse_area(radius);
                    on_surface(
                        center + n * radius,
                        n,
                        radiance,
                        Density::Area(pdf_area),
                        false,
                    )
                }
            },
            Emitter::Object {
                instance,
                radiance,
                ref texture,
                two_sided,
                world: Some(ref world),
                ..
            } => {
                let (q, n, pdf_area) = world.sample(u)?;
                let radiance = textured(scene, instance, texture, q, n, radiance);
                on_surface(q, n, radiance, Density::Area(pdf_area), two_sided)
            }
            Emitter::Object {
                instance,
                radiance,
                ref texture,
                two_sided,
                cone: Some(cone),
                ..
            } if cone.is_outside(p) => {
                let (q, n, pdf) = cone.sample(p, u)?;
                let radiance = textured(scene, instance, texture, q, n, radiance);
                on_surface(q, n, radiance, Density::SolidAngle(pdf), two_sided)
            }
            Emitter::Object {
                instance,
                radiance,
                ref texture,
                area,
                two_sided,
                ref surface,
                world: None,
                ..
            } => {
                let inst = &scene.accel.instances()[instance as usize];
                let (qo, no) = surface.sample(inst.shape.as_ref(), u)?;
                let q = inst.to_world().transform_point3(qo);
                let n = Vec3::from(inst.to_object().matrix3.transpose() * glam::Vec3A::from(no))
                    .normalize();
                let radiance = textured(scene, instance, texture, q, n, radiance);
                let pdf_area = 1.0 / (area * area_jacobian(inst, no));
                on_surface(q, n, radiance, Density::Area(pdf_area), two_sided)
            }
            Emitter::Environment { radiance, .. } => {
                let wi = sampling::uniform_sphere(u);
                Some(LightSample {
                    wi,
                    target: None,
                    li: radiance,
                    pdf: pick / (4.0 * PI),
                    delta: false,
                })
            }
        }
    }

    /// The cumulative emitter probabilities `sample` searches with `u_pick`.
    pub(crate) fn emitter_cdf(&self) -> &[f32] {
        &self.cdf
    }

    /// The solid-angle density with which `sample` from `p` would have produced the
    /// point `q` (normal `n`, world space) on emissive instance `instance`; 0 when that
    /// instance is not sampled as a light.
    pub fn pdf_object(&self, scene: &Scene, instance: u32, p: Vec3, q: Vec3, n: Vec3) -> f32 {
        let Some(Some(idx)) = self.by_instance.get(instance as usize) else {
            return 0.0;
        };
        let Emitter::Object { area, cone, .. } = self.emitters[*idx as usize] else {
            return 0.0;
        };
        let inst = &scene.accel.instances()[instance as usize];
        let n_obj =
            Vec3::from(inst.to_world().matrix3.transpose() * glam::Vec3A::from(n)).normalize();
        let d = q - p;
        let dist2 = d.length_squared();
        let cos_l = (d.dot(n) / dist2.sqrt()).abs();
        if cos_l <= 0.0 {
            return 0.0;
        }
        // A sphere seen from outside is sampled by its cone (as `sample`).
        if let Some(pdf) = cone.and_then(|c| c.pdf(p)) {
            return self.probability[*idx as usize] * pdf;
        }
        self.probability[*idx as usize] / (area * area_jacobian(inst, n_obj)) * dist2 / cos_l
    }

    /// Whether rays that leave the scene see any light (a background, a `constant` or
    /// an `envmap`).
    pub fn has_environment(&self) -> bool {
        self.environment.is_some() || !self.envmaps.is_empty()
    }

    /// The radiance a ray travelling along `dir` sees when it leaves the scene.
    #[inline]
    pub fn environment_radiance(&self, dir: Vec3) -> Rgb {
        let mut l = match self.environment.map(|i| &self.emitters[i as usize]) {
            Some(Emitter::Environment { radiance, .. }) => *radiance,
            _ => Rgb::BLACK,
        };
        for &i in &self.envmaps {
            if let Emitter::Envmap { sampler, .. } = &self.emitters[i as usize] {
                l += sampler.map.eval(dir);
            }
        }
        l
    }

    /// [`LightSampler::environment_radiance`] of `dir` and, with `want_pdf`, its
    /// [`LightSampler::pdf_environment`] (else 0), the same values bit for bit, with each
    /// environment map's coordinates of `dir` found once for both (a ray that leaves the
    /// scene needs both for its MIS weight).
    #[inline]
    pub fn environment_radiance_pdf(&self, dir: Vec3, want_pdf: bool) -> (Rgb, f32) {
        let (mut l, mut pdf) = match self.environment {
            Some(i) => match &self.emitters[i as usize] {
                Emitter::Environment { radiance, .. } => {
                    (*radiance, self.probability[i as usize] / (4.0 * PI))
                }
                _ => (Rgb::BLACK, 0.0),
            },
            None => (Rgb::BLACK, 0.0),
        };
        for &i in &self.envmaps {
            if let Emitter::Envmap { sampler, .. } = &self.emitters[i as usize] {
                let (li, p) = sampler.radiance_pdf(dir, want_pdf);
                l += li;
                pdf += self.probability[i as usize] * p;
            }
        }
        (l, if want_pdf { pdf } else { 0.0 })
    }

    /// The solid-angle density with which `sample` produces direction `dir` towards
    /// the environment (every emitter at infinity, each weighted by its choice).
    #[inline]
    pub fn pdf_environment(&self, dir: Vec3) -> f32 {
        let mut pdf = self
            .environment
            .map_or(0.0, |i| self.probability[i as usize] / (4.0 * PI));
        for &i in &self.envmaps {
            if let Emitter::Envmap { sampler, .. } = &self.emitters[i as usize] {
                pdf += self.probability[i as usize] * sampler.pdf(dir);
            }
        }
        pdf
    }
}

mod kernel_emitters;
#[cfg(test)]
pub(crate) use kernel_emitters::cornell_with_skies;
mod surface;
#[cfg(test)]
mod tests;
mod visible_sphere;

pub(crate) use kernel_emitters::{KernelEmitter, KernelLight, SphereEmitter};
