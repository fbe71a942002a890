//! Shadow (feeler) rays (lecture: "Shadow Rays"). Opaque objects block the light;
//! transparent ones attenuate it, as POV-Ray does: at every surface the shadow ray
//! crosses, the light is multiplied by that surface's transmitted colour
//! (`transmission * filter colour`; POV-Ray's `Trace::ComputeShadowColour`). Shadow
//! rays go straight through (no refraction: no caustics, as in POV-Ray without photons).

use super::{Ctx, ObjectSet, RayQuery, Whitted};
use crate::raytree::{Blocker, Recorder};
use glam::Vec3;
use irradia_core::{offset_ray_origin, Ray, Rgb};
use irradia_geometry::SceneHit;

/// Most transparent surfaces one shadow ray walks through before giving up (dark).
const MAX_CROSSINGS: u32 = 64;

impl<G: RayQuery> Whitted<'_, G> {
    /// Fraction of a light's colour that arrives at the origin of the shadow ray `first`
    /// from its direction (unit) over distance `dist`. Counts the shadow ray and
    /// records it.
    pub(super) fn shadow_transmittance<R: Recorder>(
        &self,
        first: &Ray,
        dist: f32,
        depth: u32,
        cx: &mut Ctx<'_, R>,
    ) -> Rgb {
        cx.stats.shadow_rays += 1;
        // Stop a hair short of the light so a light on a surface is not hidden by it.
        let t_max = if dist.is_finite() {
            dist * (1.0 - 1e-5)
        } else {
            f32::INFINITY
        };
        if self.any_clear && self.clear_passes_all && !R::RECORDS {
            // Clear objects pass the light whole: only an opaque one can block it (a
            // ray tree, which names the surfaces crossed, still walks below).
            if self.geometry.any_hit(ObjectSet::Opaque, first, t_max) {
                cx.stats.shadow_blocked += 1;
                return Rgb::BLACK;
            }
            return Rgb::WHITE;
        }
        // Most shadow rays reach their light: one any-hit query over everything
        // settles those, here; the rest (blocked, or filtered through clear objects)
        // go to a function of their own, kept out of line so that the tracer's hot
        // path stays small.
        if !self.occluded_all(first, t_max) {
            cx.rec.shadow(first, depth, None, Rgb::WHITE);
            return Rgb::WHITE;
        }
        self.shadow_through(first.origin, first.dir, t_max, depth, cx)
    }

    /// [`Self::shadow_transmittance`] of a shadow ray that something lies across: black
    /// when an object no light passes blocks it, else the light filtered through every
    /// clear surface up to `t_max`.
    #[inline(never)]
    fn shadow_through<R: Recorder>(
        &self,
        origin: Vec3,
        dir: Vec3,
        t_max: f32,
        depth: u32,
        cx: &mut Ctx<'_, R>,
    ) -> Rgb {
        let scene = self.scene;
        let first = Ray::new(origin, dir);
        let blocker = |h: SceneHit| Blocker {
            object: h.instance,
            name: &scene.objects[h.instance as usize].name,
            point: h.hit.point,
            normal: h.hit.normal,
        };
        if !self.any_clear {
            // Nothing in the scene lets light through: the any-hit query decided.
            cx.stats.shadow_blocked += 1;
            if R::RECORDS {
                let b = self.intersect_all(&first, t_max).map(blocker);
                cx.rec.shadow(&first, depth, b, Rgb::BLACK);
            }
            return Rgb::BLACK;
        }
        let geo = &self.geometry;
        if geo.any_hit(ObjectSet::Opaque, &first, t_max) {
            cx.stats.shadow_blocked += 1;
            if R::RECORDS {
                let b = geo
                    .closest_hit(ObjectSet::Opaque, &first, t_max)
                    .map(blocker);
                cx.rec.shadow(&first, depth, b, Rgb::BLACK);
            }
            return Rgb::BLACK;
        }

        // Only clear objects lie in the way: walk through them, filtering the light.
        let target = origin + dir * t_max;
        let mut ray = first;
        let mut limit = t_max;
        let mut tr = Rgb::WHITE;
        let mut first_blocker = None;
        for _ in 0..MAX_CROSSINGS {
            let Some(h) = geo.closest_hit(ObjectSet::Clear, &ray, limit) else {
                break;
            };
            let id = h.instance;
            let object = &scene.objects[id as usize];
            let mat = &scene.materials[object.material_for_leaf(h.hit.leaf) as usize];
            if first_blocker.is_none() {
                first_blocker = Some(Blocker {
                    object: id,
                    name: &object.name,
                    point: h.hit.point,
                    normal: h.hit.normal,
                });
            }
            if mat.transmission <= 0.0 {
                // An opaque leaf of a partly clear CSG object.
                tr = Rgb::BLACK;
                break;
            }
            let filter = mat
                .filter_color
                .unwrap_or_else(|| mat.color.eval(h.hit.point, h.hit.uv));
            tr *= filter * mat.transmission;
            if tr.max_component() <= 0.0 {
                tr = Rgb::BLACK;
                break;
            }
            // Continue from the far side of this surface.
            let n = if dir.dot(h.hit.normal) > 0.0 {
                h.hit.normal
            } else {
                -h.hit.normal
            };
            let o = offset_ray_origin(h.hit.point, n, h.hit.error);
            ray = Ray::new(o, dir);
            limit = if t_max.is_finite() {
                (target - o).dot(dir)
            } else {
                f32::INFINITY
            };
            if limit <= 0.0 {
                break;
            }
        }
        if tr.is_black() {
            cx.stats.shadow_blocked += 1;
        }
        cx.rec.shadow(&first, depth, first_blocker, tr);
        tr
    }
}
