//! The scene-level acceleration structure: the top level of the two-level hierarchy
//! (over instances; meshes keep their own hierarchy over triangles inside).
//!
//! This first version tests every instance; the BVH replaces its inside without
//! changing this interface.

use crate::instance::Instance;
use crate::shape::Hit;
use irradia_core::Ray;

/// A hit in the scene: which instance, and the hit in world space.
#[derive(Clone, Copy, Debug)]
pub struct SceneHit {
    pub instance: u32,
    pub hit: Hit,
}

#[derive(Debug, Default)]
pub struct Accel {
    instances: Vec<Instance>,
}

impl Accel {
    pub fn build(instances: Vec<Instance>) -> Self {
        Self { instances }
    }

    pub fn instances(&self) -> &[Instance] {
        &self.instances
    }

    /// Nearest hit with `0 < t < t_max`.
    pub fn intersect(&self, ray: &Ray, t_max: f32) -> Option<SceneHit> {
        let mut best: Option<SceneHit> = None;
        let mut t_max = t_max;
        for (i, inst) in self.instances.iter().enumerate() {
            if !inst.bounds().is_finite() || inst.bounds().hit(ray, t_max).is_some() {
                if let Some(hit) = inst.intersect(ray, t_max) {
                    t_max = hit.t;
                    best = Some(SceneHit {
                        instance: i as u32,
                        hit,
                    });
                }
            }
        }
        best
    }

    /// Whether anything is hit with `0 < t < t_max`.
    pub fn occluded(&self, ray: &Ray, t_max: f32) -> bool {
        self.instances.iter().any(|inst| {
            (!inst.bounds().is_finite() || inst.bounds().hit(ray, t_max).is_some())
                && inst.occluded(ray, t_max)
        })
    }
}
