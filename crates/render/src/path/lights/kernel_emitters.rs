//! The emitters as the 8-wide path kernel ([`crate::path::wide`]) samples them: emissive
//! objects sampled by their world-space facets ([`FacetEmitter`]) and emissive spheres
//! sampled uniformly by area with their own sampler ([`SphereEmitter`]: a point of the
//! object-space sphere carried to world space by the instance's transform, its density
//! by the area Jacobian `|det M| |M^-T n|`, as [`LightSampler::sample`] does).

use super::{det3, Emitter, FacetEmitter, LightSampler, SurfaceSampler};
use glam::{Affine3A, Mat3, Vec2, Vec3};
use irradia_core::Rgb;
use irradia_scene::Scene;

/// An emissive sphere (not flipped) under its instance's transform.
#[derive(Clone, Copy, Debug)]
pub(crate) struct SphereEmitter {
    /// Object-space centre and radius.
    pub center: Vec3,
    pub radius: f32,
    /// The instance's object-to-world map, and the map of object normals to world
    /// normals (the inverse transpose, unnormalised).
    pub to_world: Affine3A,
    pub normal_to_world: Mat3,
    /// `|det M|` of the transform and the object-space area `4πr²`.
    pub det: f32,
    pub area: f32,
    pub radiance: Rgb,
    pub two_sided: bool,
    /// The probability of choosing this emitter.
    pub probability: f32,
}

/// One emitter of a scene the kernel can sample.
#[derive(Clone, Copy, Debug)]
pub(crate) enum KernelEmitter<'a> {
    Facets(FacetEmitter<'a>),
    Sphere(SphereEmitter),
}

impl LightSampler {
    /// Every emitter as the kernel samples it, when each is an emissive object sampled
    /// by its facets or an emissive (unflipped) sphere with its own sampler and there is
    /// no environment; `None` otherwise. Indexed like the emitters.
    pub(crate) fn kernel_emitters(&self, scene: &Scene) -> Option<Vec<KernelEmitter<'_>>> {
        if self.environment.is_some() || !self.envmaps.is_empty() {
            return None;
        }
        self.emitters
            .iter()
            .zip(&self.probability)
            .map(|(e, &probability)| match e {
                Emitter::Object {
                    radiance,
                    two_sided,
                    world: Some(w),
                    texture: None,
                    ..
                } => Some(KernelEmitter::Facets(FacetEmitter {
                    radiance: *radiance,
                    two_sided: *two_sided,
                    triangles: &w.triangles,
                    normals: &w.normals,
                    pdf_area: &w.pdf_area,
                    cdf: &w.cdf,
                    probability,
                })),
                Emitter::Object {
                    instance,
                    radiance,
                    texture: None,
                    area,
                    two_sided,
                    surface: SurfaceSampler::Exact,
                    world: None,
                } => {
                    let inst = &scene.accel.instances()[*instance as usize];
                    let shape = inst.shape.as_ref();
                    if shape.kind() != "sphere" {
                        return None;
                    }
                    // The sphere's centre and radius from its bounds (`centre ± r`),
                    // and its sampler must give outward normals (not flipped).
                    let b = shape.bounds();
                    let center = (b.min + b.max) * 0.5;
                    let radius = (b.max.x - b.min.x) * 0.5;
                    let (p, n) = shape.sample_surface(Vec2::new(0.3, 0.7))?;
                    if n.dot(p - center) <= 0.0 {
                        return None;
                    }
                    Some(KernelEmitter::Sphere(SphereEmitter {
                        center,
                        radius,
                        to_world: *inst.to_world(),
                        normal_to_world: Mat3::from(inst.to_object().matrix3.transpose()),
                        det: det3(inst.to_world()).abs(),
                        area: *area,
                        radiance: *radiance,
                        two_sided: *two_sided,
                        probability,
                    }))
                }
                _ => None,
            })
            .collect()
    }

    /// The choice `sample` makes for `(u_pick, u)` in a scene of [`KernelEmitter`]s:
    /// (emitter, probability of choosing it, and for a facet emitter its triangle and
    /// the point of the unit square to warp into it; a sphere warps `u` itself).
    #[inline]
    pub(crate) fn pick_kernel(
        &self,
        u_pick: f32,
        u: Vec2,
    ) -> Option<(usize, f32, Option<(usize, Vec2)>)> {
        let (idx, pick) = self.pick(u_pick)?;
        match &self.emitters[idx] {
            Emitter::Object { world: Some(w), .. } => {
                let (i, u) = w.pick(u)?;
                Some((idx, pick, Some((i, u))))
            }
            Emitter::Object { world: None, .. } => Some((idx, pick, None)),
            _ => None,
        }
    }
}
