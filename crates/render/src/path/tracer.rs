//! What the path integrator asks of the geometry: the nearest hit along a ray (with the
//! object and material it belongs to) and whether a shadow ray is blocked.
//!
//! Two implementations: the scene's generic two-level [`Accel`] (every shape through
//! its own intersection routine and instance transform) and the path tracer's
//! [`FlatScene`](super::flat_scene::FlatScene), which bakes planar shapes into one
//! world-space triangle hierarchy. The integrator is generic over this trait, so both
//! run the same estimator.

use irradia_core::Ray;
use irradia_geometry::{Accel, Hit};
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

/// Ray queries for the path integrator.
pub trait Tracer: Sync {
    /// The nearest hit with `0 < t < t_max`.
    fn intersect(&self, ray: &Ray, t_max: f32) -> Option<PathHit>;
    /// Whether anything is hit with `0 < t < t_max`.
    fn occluded(&self, ray: &Ray, t_max: f32) -> bool;
}

/// The scene's own acceleration structure, through the generic shapes.
#[derive(Clone, Copy, Debug)]
pub struct AccelTracer<'a> {
    pub scene: &'a Scene,
}

impl Tracer for AccelTracer<'_> {
    #[inline]
    fn intersect(&self, ray: &Ray, t_max: f32) -> Option<PathHit> {
        let sh = self.scene.accel.intersect(ray, t_max)?;
        let object = &self.scene.objects[sh.instance as usize];
        Some(PathHit {
            instance: sh.instance,
            material: object.material_for_leaf(sh.hit.leaf),
            hit: sh.hit,
        })
    }

    #[inline]
    fn occluded(&self, ray: &Ray, t_max: f32) -> bool {
        self.scene.accel.occluded(ray, t_max)
    }
}

/// An [`Accel`] holding a subset of the scene's instances, with the map from its
/// instance indices back to the scene's.
#[derive(Debug)]
pub(crate) struct SubsetAccel {
    pub accel: Accel,
    pub scene_index: Vec<u32>,
    /// Each instance's material and its CSG leaves' materials (see
    /// `Object::material_for_leaf`).
    pub materials: Vec<(u32, Vec<u32>)>,
}

impl SubsetAccel {
    /// The nearest hit, with the scene's instance and material indices.
    #[inline]
    pub fn intersect(&self, ray: &Ray, t_max: f32) -> Option<PathHit> {
        let sh = self.accel.intersect(ray, t_max)?;
        let (material, leaves) = &self.materials[sh.instance as usize];
        Some(PathHit {
            instance: self.scene_index[sh.instance as usize],
            material: leaves
                .get(sh.hit.leaf as usize)
                .copied()
                .unwrap_or(*material),
            hit: sh.hit,
        })
    }
}
