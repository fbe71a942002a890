//! The emitters as the wide path kernel ([`crate::path::wide`]) samples them: emissive
//! objects sampled by their world-space facets ([`FacetEmitter`]) and emissive spheres
//! ([`SphereEmitter`]: by the cone they subtend from outside where the transform keeps
//! them spheres, otherwise uniformly by area with their own sampler, a point of the
//! object-space sphere carried to world space by the instance's transform, its density
//! by the area Jacobian `|det M| |M^-T n|`, as [`LightSampler::sample`] does), and the
//! emitters at infinity (the constant environment: the background plus Mitsuba's
//! `constant` emitters, and Mitsuba's `envmap`): the constant environment sampled lane
//! by lane with the scalar code's arithmetic, an environment map chosen lane by lane and
//! sampled by the kernel in lanes ([`crate::path::wide::envmap_lanes`]), so that samples
//! agree with [`LightSampler::sample`]'s bit for bit.

use super::visible_sphere::{outward_sphere, VisibleSphere};
use super::{det3, Emitter, FacetEmitter, LightSample, LightSampler, SurfaceSampler};
use crate::path::envmap::EnvmapSampler;
use glam::{Affine3A, Mat3, Vec2, Vec3};
use irradia_core::{sampling, Rgb};
use irradia_scene::Scene;
use std::f32::consts::PI;

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
    /// The world sphere, when the light is sampled by its cone from points outside
    /// it (as [`LightSampler::sample`]).
    pub cone: Option<VisibleSphere>,
    /// The scene object (instance index) the sphere is.
    pub instance: u32,
}

/// One emitter of a scene the kernel can sample.
#[derive(Clone, Copy, Debug)]
pub(crate) enum KernelEmitter<'a> {
    Facets(FacetEmitter<'a>),
    Sphere(SphereEmitter),
    /// The constant environment or an environment map, with the probability of
    /// choosing it.
    AtInfinity(f32),
}

/// The light one lane of the kernel samples.
#[derive(Clone, Copy, Debug)]
pub(crate) enum KernelLight {
    /// (emitter, probability of choosing it, and for a facet emitter its triangle and
    /// the point of the unit square to warp into it; a sphere warps `u` itself).
    Surface(usize, f32, Option<(usize, Vec2)>),
    /// The whole sample [`LightSampler::sample`] gives for the same numbers towards the
    /// constant environment.
    AtInfinity(LightSample),
    /// An environment map (its place among the maps, as [`LightSampler::environment_parts`]
    /// lists them) with the probability of choosing it: the kernel draws the direction
    /// from the map in lanes with the lane's numbers, as `sample` would.
    Envmap(usize, f32),
}

impl LightSampler {
    /// Every emitter as the kernel samples it, when each is an emissive object sampled
    /// by its facets, an emissive (unflipped) sphere with its own sampler, or an emitter
    /// at infinity; `None` otherwise. Indexed like the emitters.
    pub(crate) fn kernel_emitters(&self, scene: &Scene) -> Option<Vec<KernelEmitter<'_>>> {
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
                    cone,
                } => {
                    let inst = &scene.accel.instances()[*instance as usize];
                    let (center, radius) = outward_sphere(inst.shape.as_ref())?;
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
                        cone: *cone,
                        instance: *instance,
                    }))
                }
                Emitter::Environment { .. } | Emitter::Envmap { .. } => {
                    Some(KernelEmitter::AtInfinity(probability))
                }
                _ => None,
            })
            .collect()
    }

    /// The emitters at infinity as the kernel's lanes evaluate them
    /// ([`crate::path::wide::envmap_lanes`]): the constant environment's radiance and its
    /// share of the light density, `probability / 4π` (black and 0 without one), and
    /// every environment map with the probability of choosing it, in the order
    /// [`LightSampler::environment_radiance_pdf`] sums them.
    pub(crate) fn environment_parts(&self) -> (Rgb, f32, Vec<(&EnvmapSampler, f32)>) {
        let (radiance, pdf) = match self.environment.map(|i| (i, &self.emitters[i as usize])) {
            Some((i, Emitter::Environment { radiance, .. })) => {
                (*radiance, self.probability[i as usize] / (4.0 * PI))
            }
            _ => (Rgb::BLACK, 0.0),
        };
        let maps = self
            .envmaps
            .iter()
            .filter_map(|&i| match &self.emitters[i as usize] {
                Emitter::Envmap { sampler, .. } => Some((sampler, self.probability[i as usize])),
                _ => None,
            })
            .collect();
        (radiance, pdf, maps)
    }

    /// The choice [`LightSampler::sample`] makes for `(u_pick, u)` in a scene of
    /// [`KernelEmitter`]s: a facet or sphere emitter to be sampled by the vector stage,
    /// the whole sample of the constant environment (the same arithmetic as `sample`'s:
    /// a uniform direction on the sphere, density `pick / 4π`), or an environment map
    /// for the kernel to sample in lanes. `None` where `sample` gives none (an
    /// environment map's sample may still give none: a black map, a pole).
    #[inline]
    pub(crate) fn pick_kernel(&self, u_pick: f32, u: Vec2) -> Option<KernelLight> {
        let (idx, pick) = self.pick(u_pick)?;
        self.kernel_light(idx, pick, u)
    }

    /// [`Self::pick_kernel`]'s light once emitter `idx` is chosen with probability
    /// `pick` (the kernel's vector light choice makes the choice for W lanes at
    /// once, then the lanes at infinity ask this: [`crate::path::wide`]).
    #[inline]
    pub(crate) fn kernel_light(&self, idx: usize, pick: f32, u: Vec2) -> Option<KernelLight> {
        match &self.emitters[idx] {
            Emitter::Object { world: Some(w), .. } => {
                let (i, u) = w.pick(u)?;
                Some(KernelLight::Surface(idx, pick, Some((i, u))))
            }
            Emitter::Object { world: None, .. } => Some(KernelLight::Surface(idx, pick, None)),
            Emitter::Environment { radiance, .. } => Some(KernelLight::AtInfinity(LightSample {
                wi: sampling::uniform_sphere(u),
                target: None,
                li: *radiance,
                pdf: pick / (4.0 * PI),
                delta: false,
            })),
            Emitter::Envmap { .. } => {
                let k = self.envmaps.iter().position(|&e| e as usize == idx)?;
                Some(KernelLight::Envmap(k, pick))
            }
            _ => None,
        }
    }
}

/// The Cornell box with an environment map and the constant environment beside its
/// light: emitters of all three kinds (for the light-choice tests here and in
/// `wide/light_pick.rs`).
#[cfg(test)]
pub(crate) fn cornell_with_skies() -> Scene {
    use irradia_core::{Image, Rgb};
    use irradia_scene::{EnvMap, Light};
    use std::sync::Arc;
    let mut scene = irradia_scene::builtin::load("cornell").unwrap();
    let mut image = Image::filled(16, 8, Rgb::splat(0.2)).unwrap();
    image.set(5, 2, Rgb::new(8.0, 4.0, 1.0));
    image.set(11, 6, Rgb::new(0.5, 3.0, 6.0));
    let map = EnvMap {
        image: Arc::new(image),
        scale: 1.5,
        to_world: glam::Mat3::from_rotation_x(0.4),
        path: Default::default(),
    };
    scene.lights.push(Light::Envmap(Arc::new(map)));
    scene.lights.push(Light::Constant {
        radiance: Rgb::new(0.1, 0.2, 0.3),
    });
    Scene::new(
        scene.camera,
        scene.settings.clone(),
        scene.materials.clone(),
        scene.lights.clone(),
        scene.objects.clone(),
        scene.accel.instances().to_vec(),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;
    use irradia_core::Rng;

    /// `pick_kernel` gives exactly `sample`'s light samples for emitters at infinity,
    /// and `sample`'s choice of emitter and facet for facets, in a scene with both.
    #[test]
    fn wide_choice_equals_the_scalar_sample() {
        let scene = cornell_with_skies();
        let lights = LightSampler::new(&scene);
        let kinds = lights
            .kernel_emitters(&scene)
            .expect("facets and emitters at infinity");
        let at_infinity = kinds
            .iter()
            .filter(|k| matches!(k, KernelEmitter::AtInfinity(_)))
            .count();
        assert_eq!(at_infinity, 2);
        let mut rng = Rng::new(3, 4);
        let (mut facets, mut far) = (0, 0);
        let p = Vec3::new(0.1, 0.2, 0.3);
        for _ in 0..2000 {
            let (up, u) = (rng.next_f32(), rng.next_2d());
            match lights.pick_kernel(up, u) {
                Some(KernelLight::Surface(e, pick, Some((t, w)))) => {
                    facets += 1;
                    // The facet `sample` itself chooses for the same numbers.
                    let (idx, p) = lights.pick(up).unwrap();
                    assert_eq!((e, pick), (idx, p));
                    let Emitter::Object {
                        world: Some(wd), ..
                    } = &lights.emitters[e]
                    else {
                        panic!("a facet emitter");
                    };
                    assert_eq!(wd.pick(u), Some((t, w)));
                }
                Some(KernelLight::Surface(_, _, None)) => panic!("no sphere emitter here"),
                Some(KernelLight::Envmap(k, pick)) => {
                    // The map's own sample, as the kernel draws it in lanes.
                    far += 1;
                    let idx = lights.envmaps[k] as usize;
                    assert_eq!(lights.pick(up), Some((idx, pick)));
                    let Emitter::Envmap { sampler, .. } = &lights.emitters[idx] else {
                        panic!("an environment map");
                    };
                    match (sampler.sample(u), lights.sample(&scene, p, up, u)) {
                        (Some(s), Some(want)) => {
                            assert_eq!(s.wi, want.wi);
                            assert_eq!(s.radiance, want.li);
                            assert_eq!((pick * s.pdf).to_bits(), want.pdf.to_bits());
                        }
                        (None, None) => {}
                        (s, want) => panic!("{s:?} against {want:?}"),
                    }
                }
                Some(KernelLight::AtInfinity(ls)) => {
                    far += 1;
                    let want = lights.sample(&scene, p, up, u).unwrap();
                    assert_eq!(ls.wi, want.wi);
                    assert_eq!(ls.li, want.li);
                    assert_eq!(ls.pdf.to_bits(), want.pdf.to_bits());
                    assert!(ls.target.is_none() && want.target.is_none());
                }
                None => assert!(lights.sample(&scene, p, up, u).is_none()),
            }
        }
        assert!(
            facets > 100 && far > 100,
            "{facets} facets, {far} at infinity"
        );
    }
}
