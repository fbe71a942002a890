//! The prepared scene: the ray-query structures of one scene, built once per render
//! and shared by every integrator that traces it (pbrt-v4 builds its aggregate once in
//! `BasicScene::CreateAggregate` and hands it to whichever integrator the scene names).
//!
//! Two structures answer the one [`RayQuery`] interface, each built on first use so
//! that a render pays only for what its integrator asks:
//! - [`PreparedScene::objects`]: the scene's own two-level hierarchy with the opaque /
//!   clear split of its objects for shadow rays ([`SceneGeometry`]; the Whitted tracer,
//!   the parallel ray forwarding);
//! - [`PreparedScene::flat`]: the world-space triangle bake of every planar object in
//!   SIMD packets, the rest in a smaller hierarchy ([`FlatScene`]; the path tracer).

use crate::path::flat_scene::FlatScene;
use crate::whitted::SceneGeometry;
use irradia_geometry::RayQuery;
use irradia_scene::Scene;
use std::sync::OnceLock;

/// One scene's ray-query structures.
pub struct PreparedScene<'s> {
    scene: &'s Scene,
    objects: OnceLock<SceneGeometry<'s>>,
    flat: OnceLock<FlatScene>,
}

impl<'s> PreparedScene<'s> {
    /// Prepares `scene`; the structures are built when first asked for.
    pub fn new(scene: &'s Scene) -> Self {
        Self {
            scene,
            objects: OnceLock::new(),
            flat: OnceLock::new(),
        }
    }

    pub fn scene(&self) -> &'s Scene {
        self.scene
    }

    /// The scene's objects through their own shapes, split by whether light passes
    /// them (exact hits: what the Whitted images are made of).
    pub fn objects(&self) -> &SceneGeometry<'s> {
        self.objects.get_or_init(|| SceneGeometry::new(self.scene))
    }

    /// The planar objects baked into world-space triangles, the rest through their
    /// shapes (hits equal to the shapes' up to rounding).
    pub fn flat(&self) -> &FlatScene {
        self.flat.get_or_init(|| FlatScene::new(self.scene))
    }
}

/// A prepared scene answers through its exact structure ([`Self::objects`]).
impl RayQuery for PreparedScene<'_> {
    #[inline]
    fn closest_hit(
        &self,
        set: irradia_geometry::ObjectSet,
        ray: &irradia_core::Ray,
        t_max: f32,
    ) -> Option<irradia_geometry::SceneHit> {
        self.objects().closest_hit(set, ray, t_max)
    }
    #[inline]
    fn any_hit(
        &self,
        set: irradia_geometry::ObjectSet,
        ray: &irradia_core::Ray,
        t_max: f32,
    ) -> bool {
        self.objects().any_hit(set, ray, t_max)
    }
    #[inline]
    fn is_solid(&self, object: u32) -> bool {
        self.objects().is_solid(object)
    }
}
