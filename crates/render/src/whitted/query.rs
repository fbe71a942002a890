//! Ray queries against a set of objects: the scene's [`Accel`] in general, and a plain
//! loop over the objects' boxes when there are only a handful of them.
//!
//! For a handful of objects a linear scan beats any hierarchy: one slab test per
//! object and no traversal state. Measured on the three-object `whitted` scene at
//! 1280x720 with 2 threads (2026-11-22): 0.33-0.36 s with the scan, 0.38-0.41 s through
//! the BVH (whose traversal stack is no longer zeroed per query).

use irradia_core::{Aabb, Ray};
use irradia_geometry::{Accel, Instance, SceneHit};

/// Objects at or below this count are scanned linearly.
pub(crate) const LINEAR_MAX: usize = 8;

pub(crate) enum Query {
    Tree(Accel),
    /// The objects in scan order.
    Linear(Vec<Scanned>),
}

/// One object of a linear scan.
pub(crate) struct Scanned {
    instance: Instance,
    /// World box; `None` for unbounded objects, tested always.
    bounds: Option<Aabb>,
    /// The object index it stands for.
    id: u32,
    /// Whether it splits its hits ([`Instance::splits_surface`]).
    splits: bool,
    /// Whether the tracer reads its hits' uv (an image texture); a split hit's
    /// surface is computed without uv otherwise ([`Instance::surface_at`]).
    uv: bool,
}

impl Query {
    /// A query over `instances`, standing for objects `ids` (same order); `reads_uv`
    /// says, by object index, whose hits need their uv.
    pub fn new(instances: Vec<Instance>, ids: Vec<u32>, reads_uv: impl Fn(u32) -> bool) -> Self {
        if instances.len() > LINEAR_MAX {
            return Query::Tree(Accel::build(instances));
        }
        Query::Linear(
            instances
                .into_iter()
                .zip(ids)
                .map(|(instance, id)| {
                    let b = instance.bounds();
                    Scanned {
                        bounds: (b.is_finite() && !b.is_empty()).then_some(b),
                        splits: instance.splits_surface(),
                        uv: reads_uv(id),
                        instance,
                        id,
                    }
                })
                .collect(),
        )
    }

    /// Nearest hit with `0 < t < t_max`; `instance` is the object index. For the tree,
    /// `ids` maps the tree's instance slots to object indices (`None`: identity).
    #[inline]
    pub fn intersect(&self, ray: &Ray, t_max: f32, ids: Option<&[u32]>) -> Option<SceneHit> {
        match self {
            Query::Tree(accel) => accel.intersect(ray, t_max).map(|mut h| {
                if let Some(ids) = ids {
                    h.instance = ids[h.instance as usize];
                }
                h
            }),
            Query::Linear(list) => {
                // Objects that split their hits (`Instance::splits_surface`) give their
                // nearest parameter, and the surface is computed for the winner alone,
                // not for every object that was the nearest so far. The same objects
                // win as with whole hits: the same `t`s, compared in the same order.
                let inv = ray.dir.recip();
                let mut t_max = t_max;
                let mut best = None;
                let mut param = None;
                for o in list {
                    if o.bounds
                        .is_some_and(|b| b.hit_inv(ray.origin, inv, t_max).is_none())
                    {
                        continue;
                    }
                    if o.splits {
                        if let Some(t) = o.instance.nearest_t(ray, t_max) {
                            t_max = t as f32;
                            param = Some((o, t));
                        }
                    } else if let Some(hit) = o.instance.intersect(ray, t_max) {
                        t_max = hit.t;
                        best = Some(SceneHit {
                            instance: o.id,
                            hit,
                        });
                        param = None;
                    }
                }
                match param {
                    Some((o, t)) => Some(SceneHit {
                        instance: o.id,
                        hit: o.instance.surface_at(ray, t, o.uv),
                    }),
                    None => best,
                }
            }
        }
    }

    /// Whether anything is hit with `0 < t < t_max`.
    #[inline]
    pub fn occluded(&self, ray: &Ray, t_max: f32) -> bool {
        match self {
            Query::Tree(accel) => accel.occluded(ray, t_max),
            Query::Linear(list) => {
                let inv = ray.dir.recip();
                list.iter().any(|o| {
                    o.bounds
                        .is_none_or(|b| b.hit_inv(ray.origin, inv, t_max).is_some())
                        && o.instance.occluded(ray, t_max)
                })
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{Affine3A, Quat, Vec2, Vec3};
    use irradia_core::sampling::uniform_sphere;
    use irradia_core::Rng;
    use irradia_geometry::shapes::{Cuboid, Plane, Sphere};
    use std::sync::Arc;

    /// The nearest hit of the list by whole hits, every object's surface computed: what
    /// the linear scan gave before it deferred surfaces.
    fn whole_hits(list: &[Instance], ray: &Ray, t_max: f32) -> Option<SceneHit> {
        let inv = ray.dir.recip();
        let mut t_max = t_max;
        let mut best = None;
        for (id, inst) in list.iter().enumerate() {
            let b = inst.bounds();
            let bounded = b.is_finite() && !b.is_empty();
            if bounded && b.hit_inv(ray.origin, inv, t_max).is_none() {
                continue;
            }
            if let Some(hit) = inst.intersect(ray, t_max) {
                t_max = hit.t;
                best = Some(SceneHit {
                    instance: id as u32,
                    hit,
                });
            }
        }
        best
    }

    #[test]
    fn deferred_surfaces_pick_the_same_hit_bit_for_bit() {
        let turn = Affine3A::from_rotation_translation(Quat::from_rotation_y(0.5), Vec3::X);
        let list = vec![
            Instance::untransformed(Arc::new(Plane::new(Vec3::Y, -1.0).unwrap())),
            Instance::untransformed(Arc::new(Sphere::new(Vec3::new(0.5, 0.0, 0.0), 1.0))),
            // Two coincident spheres: a tie, settled as the whole-hit scan settles it
            // (the second wins where `t` rounds up to the f32 `t_max` it is held to).
            Instance::untransformed(Arc::new(Sphere::new(Vec3::new(-0.8, 0.2, 0.3), 0.7))),
            Instance::untransformed(Arc::new(Sphere::new(Vec3::new(-0.8, 0.2, 0.3), 0.7))),
            Instance::new(Arc::new(Sphere::new(Vec3::ZERO, 0.6)), turn),
            Instance::new(
                Arc::new(Cuboid::new(Vec3::splat(-0.4), Vec3::splat(0.4)).unwrap()),
                turn * Affine3A::from_translation(Vec3::new(0.0, 0.5, -1.0)),
            ),
            Instance::untransformed(Arc::new(Plane::new(Vec3::Z, 2.0).unwrap())),
        ];
        let n = list.len() as u32;
        let query = Query::new(list.clone(), (0..n).collect(), |_| true);
        let mut rng = Rng::new(3, 7);
        let (mut hits, mut winners) = (0, vec![0u32; list.len()]);
        for i in 0..40_000 {
            let target =
                Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * 4.0 - Vec3::splat(2.0);
            let u = Vec2::new(rng.next_f32(), rng.next_f32());
            let o = target + uniform_sphere(u) * 5.0;
            let ray = Ray::new(o, (target - o) * 0.3);
            let t_max = if i % 3 == 0 {
                2.0 + 2.0 * rng.next_f32()
            } else {
                f32::INFINITY
            };
            let want = whole_hits(&list, &ray, t_max);
            let got = query.intersect(&ray, t_max, None);
            assert_eq!(format!("{want:?}"), format!("{got:?}"), "ray {i}");
            if let Some(h) = want {
                hits += 1;
                winners[h.instance as usize] += 1;
            }
        }
        assert!(hits > 20_000, "{hits} hits");
        // Every object wins somewhere, both of the coincident pair included.
        for (i, &w) in winners.iter().enumerate() {
            assert!(w > 0, "object {i} never won");
        }
    }
}
