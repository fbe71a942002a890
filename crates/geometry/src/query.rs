//! The one ray-query interface of Irradia: every integrator (Whitted and path), the
//! radiosity solver's ray casting and the parallel renderer's ray forwarding ask the
//! geometry the same four questions through [`RayQuery`], in the spirit of
//! psychopath's single `Tracer` and of pbrt-v4's `Primitive::Intersect` /
//! `IntersectP` pair (Pharr, Jakob, Humphreys, "Physically Based Rendering", 4th ed.,
//! section 7.1): the nearest hit along a ray, whether anything is hit at all, and the
//! same two over a batch of rays (Embree's `rtcIntersect1M` / `rtcOccluded1M`
//! streams), so that an implementation can answer several rays with one SIMD pass.
//!
//! Object indices in the answers are the scene's (the index of the object and of its
//! instance in the scene's [`Accel`]), whatever subset or bake the implementation
//! holds internally.

use crate::accel::{Accel, SceneHit};
use irradia_core::Ray;

/// Which objects a query is about. The Whitted tracer asks shadow rays about the
/// objects no light passes ([`ObjectSet::Opaque`], an any-hit test suffices) and the
/// ones that filter it ([`ObjectSet::Clear`]) apart; every other query is about
/// [`ObjectSet::All`].
///
/// Opacity is a property of materials, which shapes never know: a structure built
/// without the scene's materials (a bare [`Accel`], radiosity's patches, the path
/// tracer's bake) counts every object opaque, so `Opaque` is `All` and `Clear` is
/// empty for it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ObjectSet {
    All,
    Opaque,
    Clear,
}

/// One ray of a batch and the end of its segment: the query is about `0 < t < t_max`.
#[derive(Clone, Copy, Debug)]
pub struct RaySegment {
    pub ray: Ray,
    pub t_max: f32,
}

impl RaySegment {
    #[inline]
    pub fn new(ray: Ray, t_max: f32) -> Self {
        Self { ray, t_max }
    }
}

/// Ray queries against a prepared scene.
///
/// The batched forms answer `segments[i]` in `out[i]` (the slices have equal lengths)
/// and must agree with the single-ray forms ray by ray; the default implementations
/// loop over them, and an implementation overrides them where several rays can share
/// one pass (eight rays against one triangle in SIMD lanes).
pub trait RayQuery {
    /// The nearest hit with `0 < t < t_max` among the objects of `set`.
    fn closest_hit(&self, set: ObjectSet, ray: &Ray, t_max: f32) -> Option<SceneHit>;

    /// Whether any object of `set` is hit with `0 < t < t_max`.
    fn any_hit(&self, set: ObjectSet, ray: &Ray, t_max: f32) -> bool;

    /// Whether object `object` is a closed solid (rays crossing it enter a medium).
    fn is_solid(&self, object: u32) -> bool;

    /// The nearest hit of each segment, as [`Self::closest_hit`].
    fn closest_hits(&self, set: ObjectSet, segments: &[RaySegment], out: &mut [Option<SceneHit>]) {
        assert_eq!(segments.len(), out.len(), "one answer per segment");
        for (s, o) in segments.iter().zip(out.iter_mut()) {
            *o = self.closest_hit(set, &s.ray, s.t_max);
        }
    }

    /// Whether each segment is blocked, as [`Self::any_hit`].
    fn any_hits(&self, set: ObjectSet, segments: &[RaySegment], out: &mut [bool]) {
        assert_eq!(segments.len(), out.len(), "one answer per segment");
        for (s, o) in segments.iter().zip(out.iter_mut()) {
            *o = self.any_hit(set, &s.ray, s.t_max);
        }
    }
}

/// The scene's two-level hierarchy. It knows no materials, so every object is opaque
/// (see [`ObjectSet`]).
impl RayQuery for Accel {
    #[inline]
    fn closest_hit(&self, set: ObjectSet, ray: &Ray, t_max: f32) -> Option<SceneHit> {
        match set {
            ObjectSet::All | ObjectSet::Opaque => self.intersect(ray, t_max),
            ObjectSet::Clear => None,
        }
    }

    #[inline]
    fn any_hit(&self, set: ObjectSet, ray: &Ray, t_max: f32) -> bool {
        match set {
            ObjectSet::All | ObjectSet::Opaque => self.occluded(ray, t_max),
            ObjectSet::Clear => false,
        }
    }

    #[inline]
    fn is_solid(&self, object: u32) -> bool {
        self.instances()[object as usize].shape.is_solid()
    }
}

impl<Q: RayQuery + ?Sized> RayQuery for &Q {
    #[inline]
    fn closest_hit(&self, set: ObjectSet, ray: &Ray, t_max: f32) -> Option<SceneHit> {
        (**self).closest_hit(set, ray, t_max)
    }
    #[inline]
    fn any_hit(&self, set: ObjectSet, ray: &Ray, t_max: f32) -> bool {
        (**self).any_hit(set, ray, t_max)
    }
    #[inline]
    fn is_solid(&self, object: u32) -> bool {
        (**self).is_solid(object)
    }
    #[inline]
    fn closest_hits(&self, set: ObjectSet, segments: &[RaySegment], out: &mut [Option<SceneHit>]) {
        (**self).closest_hits(set, segments, out)
    }
    #[inline]
    fn any_hits(&self, set: ObjectSet, segments: &[RaySegment], out: &mut [bool]) {
        (**self).any_hits(set, segments, out)
    }
}
