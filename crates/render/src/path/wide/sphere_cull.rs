//! W rays against the scene's spheres at once: a conservative lane cull in front
//! of the exact lane-by-lane sphere pass of the kernel.
//!
//! The kernel traces spheres (the objects the flat scene leaves to their own shapes'
//! tests) lane by lane with the scalar `closest_hit`'s second half, so that hits, normals
//! and error bounds are the scalar ones bit for bit. Most rays miss every sphere; this
//! test finds, for W rays at once, the lanes whose ray may come near a sphere
//! within `(0, t_max)`, and only those lanes run the exact pass (the others cannot hit:
//! their answer is "no sphere", which is the exact answer). The hits themselves are
//! unchanged, so the kernel's samples are too.
//!
//! Shadow rays towards a one-sided light sphere leave that sphere out of the cull
//! ([`SphereCull::may_hit_but`]): it cannot block a segment to one of its points that
//! faces the origin. So their lanes run the exact pass only when another sphere may be
//! in the way, and when they do it still asks every sphere, their own included. Where
//! the exact test's rounding would have found a grazing segment blocked by its own light
//! (in exact arithmetic it is not) the sample differs from the scalar one; the kernel's
//! agreement tests allow for such rare samples.
//!
//! Each sphere is bounded by a ball (its own for an untransformed sphere, the ball
//! around its world box for a transformed one) whose radius is widened by a margin far
//! above `f32` rounding. The test is the geometric ray-sphere test (the lecture's "Ray
//! Casting a Sphere"; Haines et al., "Precision Improvements for Ray/Sphere
//! Intersection", Ray Tracing Gems, ch. 7, for the perpendicular offset `l = oc - d b`,
//! whose length is exact to a few ulps of `|oc|` where `|oc|² - b²|d|²` would cancel):
//! a lane is dropped only when the ray's line passes farther than the radius from the
//! centre, or the ball lies wholly behind the origin or beyond `t_max` along the ray.
//! Every comparison is written so that a NaN keeps the lane (conservative).

// Lane loops index several arrays by the lane on purpose.
#![allow(clippy::needless_range_loop)]

use irradia_geometry::packet::lanes::{Fw, Mw, V3, W};
use irradia_scene::Scene;

/// Relative margin on the bounding balls: a thousand times `f32`'s epsilon and more.
const MARGIN: f32 = 1e-4;

/// No sphere left out of a lane ([`SphereCull::may_hit_but`]).
pub(crate) const NONE: u32 = u32::MAX;

/// The bounding balls of the spheres, `[cx, cy, cz, r]` each.
#[derive(Clone, Debug)]
pub(crate) struct SphereCull {
    balls: Vec<[f32; 4]>,
}

impl SphereCull {
    /// The balls around the scene objects `objects` (scene indices).
    pub fn new(scene: &Scene, objects: &[u32]) -> Self {
        let balls = objects
            .iter()
            .map(|&i| {
                let inst = &scene.accel.instances()[i as usize];
                let b = inst.bounds();
                let (c, e) = (b.center(), b.extent());
                // An untransformed sphere's box is the cube around its ball; anything
                // else is bounded by the ball around its box.
                let r = if inst.is_identity() && inst.shape.kind() == "sphere" {
                    0.5 * e.max_element()
                } else {
                    0.5 * e.length()
                };
                [c.x, c.y, c.z, r * (1.0 + MARGIN)]
            })
            .collect();
        Self { balls }
    }

    /// The lanes of `active` whose ray `o + t d` may meet a sphere with `0 < t <
    /// t_max` (a superset of those that do).
    #[inline(always)]
    pub fn may_hit(&self, o: V3, d: V3, t_max: Fw, active: Mw) -> Mw {
        self.may_hit_but(o, d, t_max, active, &[NONE; W])
    }

    /// [`Self::may_hit`], leaving out of each lane the sphere `own[lane]` (its place
    /// among `objects`; [`NONE`] for none): the light sphere a shadow ray ends on. A
    /// segment from a point `p` to a point `q` of a sphere that faces `p` (`p` in front
    /// of the tangent plane at `q`) lies outside the ball but for `q`, since the ball
    /// lies behind that plane; so that sphere cannot block it, and only the other
    /// spheres decide whether the lane runs the exact test (which still asks every
    /// sphere).
    #[inline(always)]
    pub fn may_hit_but(&self, o: V3, d: V3, t_max: Fw, active: Mw, own: &[u32; W]) -> Mw {
        let a = d.dot(d);
        let len = a.sqrt();
        let mut maybe = Mw::FALSE;
        for (k, s) in self.balls.iter().enumerate() {
            let c = V3::new(Fw::splat(s[0]), Fw::splat(s[1]), Fw::splat(s[2]));
            let oc = c.sub(o);
            // The parameter of the closest approach and the perpendicular offset.
            let b = oc.dot(d) / a;
            let l = oc.sub(d.scale(b));
            // The radius, widened by the rounding of `oc` and `l` (relative to |oc|).
            let r = s[3] + MARGIN * (oc.dot(oc).sqrt() + s[3]);
            let half = r / len;
            let far = l.dot(l).gt(r * r);
            let behind = (b + half).le(0.0);
            let beyond = (b - half).ge(t_max);
            let mine = Mw::from_fn(|lane| own[lane] == k as u32);
            maybe = maybe | !(far | behind | beyond | mine);
        }
        active & maybe
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::path::wide::sphere_hits::tests::{ellipsoid, scene_of};
    use glam::Vec3;
    use irradia_core::{Ray, Rng};
    use irradia_geometry::shapes::Sphere;
    use irradia_geometry::Instance;
    use std::sync::Arc;

    /// Every ray that hits a sphere (closest hit or occlusion within `t_max`, the
    /// exact tests) is kept by the cull, for rays from outside, from the surfaces
    /// (inside and out), grazing ones and short segments; and most rays from afar
    /// that miss are dropped.
    #[test]
    fn the_cull_keeps_every_hit_and_drops_most_misses() {
        let instances = vec![
            Instance::untransformed(Arc::new(Sphere::new(Vec3::new(0.4, -0.6, 0.3), 0.4))),
            Instance::untransformed(Arc::new(Sphere::new(Vec3::new(30.0, 2.0, -9.0), 1e-2))),
            ellipsoid(),
        ];
        let n = instances.len();
        let scene = scene_of(instances);
        let cull = SphereCull::new(&scene, &(0..n as u32).collect::<Vec<_>>());
        let inst = scene.accel.instances();
        let mut rng = Rng::new(11, 12);
        let mut v = |s: f32| rng.next_centered_vec3() * s;
        let (mut hits, mut kept_misses, mut misses) = (0, 0, 0);
        for round in 0..4000 {
            let (mut o, mut d, mut t_max) = (V3::ZERO, V3::ZERO, Fw::splat(f32::INFINITY));
            let mut rays = Vec::new();
            for lane in 0..W {
                let k = (round + lane) % n;
                let b = inst[k].bounds();
                let (centre, radius) = (b.center(), 0.5 * b.extent().max_element());
                let (origin, dir) = match round % 4 {
                    // From afar towards the sphere's neighbourhood.
                    0 => {
                        let from = centre + v(8.0 * radius + 4.0);
                        (from, centre + v(3.0 * radius) - from)
                    }
                    // From a point on the surface (as a bounce leaves it), any way.
                    1 => {
                        let from = centre + v(1.0).normalize() * radius * 0.9;
                        let h = inst[k].intersect(&Ray::new(from, v(1.0)), f32::INFINITY);
                        (h.map_or(from, |h| h.point), v(1.0))
                    }
                    // Grazing: past the ball's rim.
                    2 => {
                        let dir = v(1.0).normalize();
                        let side = dir.any_orthonormal_vector() * radius;
                        (
                            centre - dir * 5.0 + side * (1.0 + (rng_f(round) - 0.5) * 1e-3),
                            dir,
                        )
                    }
                    // Short segments (shadow rays with t_max = 1).
                    _ => {
                        let from = centre + v(4.0 * radius);
                        t_max.0[lane] = 1.0;
                        (from, centre + v(4.0 * radius) - from)
                    }
                };
                o.set_lane(lane, origin);
                d.set_lane(lane, dir);
                rays.push(Ray::new(origin, dir));
            }
            let kept = cull.may_hit(o, d, t_max, Mw::TRUE);
            for lane in 0..W {
                let tm = t_max.0[lane];
                let hit = inst
                    .iter()
                    .any(|i| i.intersect(&rays[lane], tm).is_some() || i.occluded(&rays[lane], tm));
                if hit {
                    hits += 1;
                    assert!(
                        kept.get(lane),
                        "round {round} lane {lane}: {:?}",
                        rays[lane]
                    );
                } else if round % 4 == 0 {
                    // Rays from afar: most that miss should be dropped. (Rays from a
                    // surface start inside its ball and grazing ones pass within the
                    // margin: those are kept by design.)
                    misses += 1;
                    kept_misses += kept.get(lane) as u32;
                }
            }
        }
        println!("{hits} hits; from afar {misses} misses of which {kept_misses} kept");
        assert!(hits > 5000 && misses > 2000, "{hits} hits, {misses} misses");
        assert!(
            kept_misses * 2 < misses,
            "{kept_misses} of {misses} misses kept"
        );
    }

    /// Shadow rays as the kernel makes them towards a point of a light sphere that
    /// faces their origin (the first hit from there, offset off the surface, with
    /// `t_max` 1), the sphere left out: every ray the exact tests of all the spheres
    /// (that one included) find blocked is kept, and most of the others are dropped.
    #[test]
    fn a_light_sphere_left_out_keeps_every_blocked_shadow_ray() {
        let instances = vec![
            Instance::untransformed(Arc::new(Sphere::new(Vec3::new(0.4, -0.6, 0.3), 0.4))),
            Instance::untransformed(Arc::new(Sphere::new(Vec3::new(-0.5, 0.5, 0.0), 0.3))),
            ellipsoid(),
            Instance::untransformed(Arc::new(Sphere::new(Vec3::new(3.0, 2.0, -1.0), 1e-2))),
        ];
        let n = instances.len();
        let scene = scene_of(instances);
        let cull = SphereCull::new(&scene, &(0..n as u32).collect::<Vec<_>>());
        let inst = scene.accel.instances();
        let mut rng = Rng::new(3, 4);
        let (mut blocked, mut open, mut dropped) = (0, 0, 0);
        for round in 0..3000 {
            let (mut o, mut d) = (V3::ZERO, V3::ZERO);
            let (mut own, mut rays) = ([NONE; W], Vec::new());
            for lane in 0..W {
                let k = (round + lane) % n;
                let b = inst[k].bounds();
                let (centre, radius) = (b.center(), 0.5 * b.extent().length());
                // From a point around the spheres towards any point of sphere `k`'s
                // box (grazing ones included), the first hit as the light point.
                let from = rng.next_centered_vec3() * 3.0;
                let aim = centre + rng.next_centered_vec3() * radius;
                let Some(h) = inst[k].intersect(&Ray::new(from, aim - from), f32::INFINITY) else {
                    continue;
                };
                if h.normal.dot(from - h.point) <= 0.0 {
                    continue; // inside the sphere: no light sample shines there
                }
                let mut q = V3::ZERO;
                let mut nq = V3::ZERO;
                q.set_lane(lane, h.point);
                nq.set_lane(lane, h.normal);
                let target = irradia_geometry::packet::lanes::offset_ray_origin(q, nq, Fw::ZERO);
                let dir = target.lane(lane) - from;
                o.set_lane(lane, from);
                d.set_lane(lane, dir);
                own[lane] = k as u32;
                rays.push((lane, Ray::new(from, dir)));
            }
            let active = Mw::from_fn(|lane| own[lane] != NONE);
            let kept = cull.may_hit_but(o, d, Fw::splat(1.0), active, &own);
            for (lane, ray) in rays {
                let hit = inst
                    .iter()
                    .any(|i| i.intersect(&ray, 1.0).is_some() || i.occluded(&ray, 1.0));
                if hit {
                    blocked += 1;
                    assert!(kept.get(lane), "round {round} lane {lane}: {ray:?}");
                } else {
                    open += 1;
                    dropped += !kept.get(lane) as u32;
                }
            }
        }
        println!("{blocked} blocked; {open} open of which {dropped} dropped");
        assert!(
            blocked > 1000 && open > 10000,
            "{blocked} blocked, {open} open"
        );
        assert!(dropped * 2 > open, "{dropped} of {open} open rays dropped");
    }

    fn rng_f(k: usize) -> f32 {
        (k as f32 * 0.618_034).fract()
    }
}
