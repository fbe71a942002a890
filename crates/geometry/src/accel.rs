//! The scene-level acceleration structure: the top level of the two-level hierarchy
//! (a [`Bvh`] over the world boxes of the instances; meshes keep their own hierarchy
//! over triangles inside), plus a plain list for unbounded shapes (planes, unclipped
//! quadrics), which no box can hold and every ray tests.

use crate::bvh::Bvh;
use crate::instance::Instance;
use crate::mesh::TriangleMesh;
use crate::shape::{CastHit, Hit};
use irradia_core::Ray;

/// A hit in the scene: which instance, and the hit in world space.
#[derive(Clone, Copy, Debug)]
pub struct SceneHit {
    pub instance: u32,
    pub hit: Hit,
}

#[derive(Debug)]
pub struct Accel {
    instances: Vec<Instance>,
    /// Over the instances with finite bounds (leaf slots map to instance indices).
    bvh: Bvh,
    /// Instances whose bounds are not finite.
    unbounded: Vec<u32>,
    /// The instances flattened into one mesh for batches of cast rays, where they can
    /// be (built on first use: `flat_meshes.rs`).
    pub(crate) flat: std::sync::OnceLock<Option<crate::flat_meshes::FlatMeshes>>,
}

impl Default for Accel {
    fn default() -> Self {
        Self::build(Vec::new())
    }
}

impl Accel {
    /// Builds the top-level hierarchy over `instances` (in parallel when large).
    pub fn build(instances: Vec<Instance>) -> Self {
        let boxes: Vec<_> = instances.iter().map(|i| i.bounds()).collect();
        let bvh = Bvh::build(&boxes);
        let unbounded = boxes
            .iter()
            .enumerate()
            .filter(|(_, b)| !b.is_finite() && !b.is_empty())
            .map(|(i, _)| i as u32)
            .collect();
        Self {
            instances,
            bvh,
            unbounded,
            flat: std::sync::OnceLock::new(),
        }
    }

    pub fn instances(&self) -> &[Instance] {
        &self.instances
    }

    /// How many instances have no finite bounds (every ray tests them).
    pub fn unbounded_count(&self) -> usize {
        self.unbounded.len()
    }

    /// The hierarchy over the bounded instances.
    pub fn bvh(&self) -> &Bvh {
        &self.bvh
    }

    /// Nearest hit with `0 < t < t_max`.
    pub fn intersect(&self, ray: &Ray, t_max: f32) -> Option<SceneHit> {
        let mut best: Option<SceneHit> = None;
        let mut t_max = t_max;
        for &i in &self.unbounded {
            if let Some(hit) = self.instances[i as usize].intersect(ray, t_max) {
                t_max = hit.t;
                best = Some(SceneHit { instance: i, hit });
            }
        }
        self.bvh.closest_hit(ray, t_max, |slot, t_max| {
            let i = self.bvh.order()[slot as usize];
            let hit = self.instances[i as usize].intersect(ray, t_max)?;
            best = Some(SceneHit { instance: i, hit });
            Some(hit.t)
        });
        best
    }

    /// [`Self::intersect`] as ray casting reports it: the instance and
    /// [`Instance::intersect_cast`]'s hit (the same `t`, primitive, uv and normal).
    pub fn intersect_cast(&self, ray: &Ray, t_max: f32) -> Option<(u32, CastHit)> {
        let mut best: Option<(u32, CastHit)> = None;
        let mut t_max = t_max;
        for &i in &self.unbounded {
            if let Some(hit) = self.instances[i as usize].intersect_cast(ray, t_max) {
                t_max = hit.t;
                best = Some((i, hit));
            }
        }
        self.bvh.closest_hit(ray, t_max, |slot, t_max| {
            let i = self.bvh.order()[slot as usize];
            let hit = self.instances[i as usize].intersect_cast(ray, t_max)?;
            best = Some((i, hit));
            Some(hit.t)
        });
        best
    }

    /// The scene's one triangle mesh, when the scene is exactly one untransformed mesh:
    /// then [`Self::intersect_cast`]'s answer to every ray is instance 0 and the mesh's
    /// [`TriangleMesh::intersect_cast_hit`] (the same routine the general path reaches
    /// through the top-level hierarchy and a dynamic call), so a caller tracing many
    /// rays may ask the mesh directly.
    pub fn sole_mesh(&self) -> Option<&TriangleMesh> {
        match self.instances.as_slice() {
            [only] if only.is_identity() => only.shape.as_triangle_mesh(),
            _ => None,
        }
    }

    /// Whether anything is hit with `0 < t < t_max`.
    pub fn occluded(&self, ray: &Ray, t_max: f32) -> bool {
        self.unbounded
            .iter()
            .any(|&i| self.instances[i as usize].occluded(ray, t_max))
            || self.bvh.any_hit(ray, t_max, |slot, t_max| {
                self.instances[self.bvh.order()[slot as usize] as usize].occluded(ray, t_max)
            })
    }
}
