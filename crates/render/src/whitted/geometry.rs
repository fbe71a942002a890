//! Where the Whitted tracer's geometry answers come from.
//!
//! The recursive tracer asks the geometry exactly five kinds of question: the nearest
//! hit of a camera, reflected or refracted ray; whether a shadow ray is blocked at all;
//! whether it is blocked by an object no light passes; the next transparent surface
//! along it (to filter the light through); and whether a hit object is a closed solid
//! (for the stack of nested media). They are the questions of the one ray-query
//! interface, [`RayQuery`] (the opaque / clear split is its [`ObjectSet`] argument), so
//! that the same tracer runs over the scene's own acceleration structure ([`SceneGeometry`], the
//! default, for serial and image-parallel rendering) and over a distributed scene whose
//! objects live on other processes (`irradia_parallel::raytrace_forward`, which answers
//! from a cache of forwarded queries; Reinhard and Jansen 1997, "Rendering large scenes
//! using parallel ray tracing").

use super::query::{Query, LINEAR_MAX};
use irradia_core::{Ray, Rgb};
use irradia_geometry::{Accel, ObjectSet, RayQuery, SceneHit};
use irradia_scene::{Scene, Texture};

/// Whether any object of `scene` lets light through (a material of it, or of one of
/// its CSG leaves, transmits). Decides whether shadow rays filter through objects.
pub fn object_transmits(scene: &Scene, object: usize) -> bool {
    let transmits = |m: u32| scene.materials[m as usize].transmission > 0.0;
    let o = &scene.objects[object];
    transmits(o.material) || o.leaf_materials.iter().any(|&m| transmits(m))
}

/// Whether every object that lets light through lets it through whole: each material
/// of it (its own and its CSG leaves') has a constant filter colour (POV-Ray's `filter`
/// colour, or an untextured colour) that, times its transmission, is exactly white, as
/// POV-Ray's clear glass `rgbf <1, 1, 1, 1>`. A shadow ray's walk through such surfaces
/// (`Trace::ComputeShadowColour`: the light times each crossed surface's transmitted
/// colour) multiplies the light by exactly one at every crossing, so skipping the walk
/// gives the same colour bit for bit; only opaque objects can then block the light.
pub fn clear_passes_all(scene: &Scene) -> bool {
    let whole = |m: u32| {
        let m = &scene.materials[m as usize];
        let filter = match (m.filter_color, &m.color) {
            (Some(f), _) => f,
            (None, Texture::Solid(c)) => *c,
            _ => return false,
        };
        filter * m.transmission == Rgb::WHITE
    };
    (0..scene.objects.len())
        .filter(|&i| object_transmits(scene, i))
        .all(|i| {
            let o = &scene.objects[i];
            whole(o.material) && o.leaf_materials.iter().all(|&m| whole(m))
        })
}

/// Whether the tracer reads the uv of `object`'s hits: where a material of it (its own
/// or a CSG leaf's) is coloured by an image, the only texture looked up by uv.
pub fn object_reads_uv(scene: &Scene, object: u32) -> bool {
    let o = &scene.objects[object as usize];
    std::iter::once(&o.material)
        .chain(&o.leaf_materials)
        .any(|&m| matches!(scene.materials[m as usize].color, Texture::Image { .. }))
}

/// Two queries over the scene's objects: those no light passes (an any-hit test
/// suffices) and those that filter it. `*_ids` map tree slots back to objects.
struct ShadowSets {
    opaque: Query,
    opaque_ids: Vec<u32>,
    clear: Query,
    clear_ids: Vec<u32>,
}

impl ShadowSets {
    /// `None` when no object transmits light (then the scene's own structure serves).
    fn build(scene: &Scene) -> Option<Self> {
        let clear_object: Vec<bool> = (0..scene.objects.len())
            .map(|i| object_transmits(scene, i))
            .collect();
        if !clear_object.iter().any(|&c| c) {
            return None;
        }
        let (mut opaque, mut opaque_ids, mut clear, mut clear_ids) =
            (Vec::new(), Vec::new(), Vec::new(), Vec::new());
        for (i, inst) in scene.accel.instances().iter().enumerate() {
            if clear_object[i] {
                clear.push(inst.clone());
                clear_ids.push(i as u32);
            } else {
                opaque.push(inst.clone());
                opaque_ids.push(i as u32);
            }
        }
        Some(Self {
            opaque: Query::new(opaque, opaque_ids.clone(), |i| object_reads_uv(scene, i)),
            opaque_ids,
            clear: Query::new(clear, clear_ids.clone(), |i| object_reads_uv(scene, i)),
            clear_ids,
        })
    }
}

/// The scene's own objects: its two-level hierarchy, a linear scan when there are only
/// a handful of objects, and the opaque / clear split for shadow rays.
pub struct SceneGeometry<'s> {
    accel: &'s Accel,
    /// A linear scan over every object when there are only a handful; `None` uses the
    /// scene's own hierarchy.
    all: Option<Query>,
    /// Objects split by whether light can pass through them, for shadow rays; `None`
    /// when none does.
    shadow_sets: Option<ShadowSets>,
}

impl<'s> SceneGeometry<'s> {
    pub fn new(scene: &'s Scene) -> Self {
        Self {
            accel: &scene.accel,
            all: (scene.accel.instances().len() <= LINEAR_MAX).then(|| {
                let n = scene.accel.instances().len() as u32;
                Query::new(scene.accel.instances().to_vec(), (0..n).collect(), |i| {
                    object_reads_uv(scene, i)
                })
            }),
            shadow_sets: ShadowSets::build(scene),
        }
    }

    #[inline]
    fn intersect_all(&self, ray: &Ray, t_max: f32) -> Option<SceneHit> {
        match &self.all {
            Some(q) => q.intersect(ray, t_max, None),
            None => self.accel.intersect(ray, t_max),
        }
    }

    #[inline]
    fn occluded_all(&self, ray: &Ray, t_max: f32) -> bool {
        match &self.all {
            Some(q) => q.occluded(ray, t_max),
            None => self.accel.occluded(ray, t_max),
        }
    }
}

impl RayQuery for SceneGeometry<'_> {
    #[inline]
    fn closest_hit(&self, set: ObjectSet, ray: &Ray, t_max: f32) -> Option<SceneHit> {
        match (set, &self.shadow_sets) {
            (ObjectSet::All, _) | (ObjectSet::Opaque, None) => self.intersect_all(ray, t_max),
            (ObjectSet::Clear, None) => None,
            (ObjectSet::Opaque, Some(s)) => s.opaque.intersect(ray, t_max, Some(&s.opaque_ids)),
            (ObjectSet::Clear, Some(s)) => s.clear.intersect(ray, t_max, Some(&s.clear_ids)),
        }
    }

    #[inline]
    fn any_hit(&self, set: ObjectSet, ray: &Ray, t_max: f32) -> bool {
        match (set, &self.shadow_sets) {
            (ObjectSet::All, _) | (ObjectSet::Opaque, None) => self.occluded_all(ray, t_max),
            (ObjectSet::Clear, None) => false,
            (ObjectSet::Opaque, Some(s)) => s.opaque.occluded(ray, t_max),
            (ObjectSet::Clear, Some(s)) => s.clear.occluded(ray, t_max),
        }
    }

    #[inline]
    fn is_solid(&self, object: u32) -> bool {
        self.accel.instances()[object as usize].shape.is_solid()
    }
}
