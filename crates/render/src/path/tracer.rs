//! What the path integrator asks of the geometry: the one ray-query interface,
//! [`RayQuery`] (nearest hit, any hit, batched forms), plus the material of the
//! object hit, resolved for CSG leaves.
//!
//! Two implementations: the scene's generic two-level [`Accel`] ([`AccelTracer`],
//! every shape through its own intersection routine and instance transform) and the
//! path tracer's [`FlatScene`](super::flat_scene::FlatScene), which bakes planar
//! shapes into one world-space triangle hierarchy. The integrator is generic over this
//! trait, so both run the same estimator.

use irradia_core::Ray;
use irradia_geometry::{Accel, Hit, ObjectSet, RayQuery, SceneHit};
use irradia_scene::Scene;

/// A hit as the path integrator needs it.
#[derive(Clone, Copy, Debug)]
pub struct PathHit {
    /// Index of the object (and of its instance in `scene.accel`).
    pub instance: u32,
    /// Index into `scene.materials` (already resolved for CSG leaves).
    pub material: u32,
    /// The hit in world space.
    pub hit: Hit,
}

/// A [`RayQuery`] that also knows the scene's materials: the path integrator's view
/// of the geometry. Its queries are about every object ([`ObjectSet::All`]): the path
/// tracer does not filter shadow rays through transmissive objects.
pub trait Tracer: RayQuery + Sync {
    /// The material (index into `scene.materials`) of object `object` at CSG leaf
    /// `leaf` (see `Object::material_for_leaf`).
    fn material(&self, object: u32, leaf: u32) -> u32;

    /// The nearest hit with `0 < t < t_max`.
    #[inline]
    fn intersect(&self, ray: &Ray, t_max: f32) -> Option<PathHit> {
        let sh = self.closest_hit(ObjectSet::All, ray, t_max)?;
        Some(PathHit {
            instance: sh.instance,
            material: self.material(sh.instance, sh.hit.leaf),
            hit: sh.hit,
        })
    }

    /// Whether anything is hit with `0 < t < t_max`.
    #[inline]
    fn occluded(&self, ray: &Ray, t_max: f32) -> bool {
        self.any_hit(ObjectSet::All, ray, t_max)
    }
}

impl<T: Tracer + ?Sized> Tracer for &T {
    #[inline]
    fn material(&self, object: u32, leaf: u32) -> u32 {
        (**self).material(object, leaf)
    }
}

/// The scene's own acceleration structure, through the generic shapes.
#[derive(Clone, Copy, Debug)]
pub struct AccelTracer<'a> {
    pub scene: &'a Scene,
}

impl RayQuery for AccelTracer<'_> {
    #[inline]
    fn closest_hit(&self, set: ObjectSet, ray: &Ray, t_max: f32) -> Option<SceneHit> {
        self.scene.accel.closest_hit(set, ray, t_max)
    }
    #[inline]
    fn any_hit(&self, set: ObjectSet, ray: &Ray, t_max: f32) -> bool {
        self.scene.accel.any_hit(set, ray, t_max)
    }
    #[inline]
    fn is_solid(&self, object: u32) -> bool {
        self.scene.accel.is_solid(object)
    }
}

impl Tracer for AccelTracer<'_> {
    #[inline]
    fn material(&self, object: u32, leaf: u32) -> u32 {
        self.scene.objects[object as usize].material_for_leaf(leaf)
    }
}

/// An [`Accel`] holding a subset of the scene's instances, with the map from its
/// instance indices back to the scene's.
#[derive(Debug)]
pub(crate) struct SubsetAccel {
    pub accel: Accel,
    pub scene_index: Vec<u32>,
}

impl SubsetAccel {
    /// The nearest hit, with the scene's instance index.
    #[inline]
    pub fn intersect(&self, ray: &Ray, t_max: f32) -> Option<SceneHit> {
        let mut sh = self.accel.intersect(ray, t_max)?;
        sh.instance = self.scene_index[sh.instance as usize];
        Some(sh)
    }
}
