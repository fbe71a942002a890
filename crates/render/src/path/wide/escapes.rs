//! Camera rays that certainly leave the scene, finished before they take a lane.
//!
//! A camera ray that hits nothing ends its path at once with what it sees of the
//! emitters at infinity (or black). In the bounce loop such a lane still rides
//! through a whole bounce of the vector stage (the hit, the light sample, the glossy
//! lobes, the shadow rays: all masked off) before it takes a new sample, so a scene
//! seen mostly against its environment (the speed suite's rough_balls: about 80% of
//! its camera rays miss the three spheres) runs most bounces with few useful lanes.
//! Here each group of W camera samples is tested W rays at once against a
//! conservative bound of the whole scene, before the lanes take them: the ball
//! cull of the spheres
//! ([`SphereCull`](super::sphere_cull::SphereCull)) and the slab test of the box around every
//! baked triangle (Kay and Kajiya, "Ray Tracing Complex Scenes", SIGGRAPH 1986; the
//! far distance widened by `1 + 2γ₃` as Pharr, Jakob, Humphreys, PBRT 3rd ed., 3.9.2,
//! "Conservative Ray-Bounds Intersections", so rounding never drops a ray that meets
//! the box). The rays that certainly miss everything are finished here, W at once,
//! with the very arithmetic the bounce loop applies to them ([`Background`]: the
//! environment's radiance, weight 1 from the camera), so their estimates are the
//! loop's bit for bit; the others take lanes and are traced exactly as before. This
//! is the wavefront path tracer's compaction of live paths (Laine, Karras, Aila,
//! "Megakernels Considered Harmful", HPG 2013, section 4), done at the camera.
//! (tests/path_wide_background.rs compares the kernel with and without it bit for bit,
//! and with the scalar estimator.)

use super::background::Background;
use super::kernel::mis;
use super::WideScene;
use crate::camera_batch::StartsW;
use crate::path::integrator::PathCounters;
use glam::Vec3;
use irradia_core::Rgb;
use irradia_geometry::bvh::node::gamma;
use irradia_geometry::packet::lanes::{Fw, Mw, V3};

/// Relative margin on the triangles' box (as the sphere cull's on its balls): far above
/// the rounding of a triangle test's hit point.
const MARGIN: f32 = 1e-4;

/// The box around every baked triangle, widened by [`MARGIN`].
#[derive(Clone, Debug)]
pub(crate) struct TriangleBox {
    lo: [f32; 3],
    hi: [f32; 3],
}

impl TriangleBox {
    /// The box around `corners` (`None` without triangles: no ray meets one).
    pub fn new(corners: &[[Vec3; 3]]) -> Option<Self> {
        let all = corners.iter().flatten();
        let lo = all.clone().fold(Vec3::INFINITY, |a, &p| a.min(p));
        let hi = all.fold(Vec3::NEG_INFINITY, |a, &p| a.max(p));
        if corners.is_empty() {
            return None;
        }
        let m = MARGIN * (lo.abs().max(hi.abs()).max_element() + (hi - lo).max_element());
        Some(Self {
            lo: (lo - Vec3::splat(m)).to_array(),
            hi: (hi + Vec3::splat(m)).to_array(),
        })
    }

    /// The lanes whose ray `o + t d` (`t > 0`) may meet the box (a superset of those
    /// that do; NaN keeps a lane).
    #[inline(always)]
    pub fn may_hit(&self, o: V3, d: V3) -> Mw {
        self.may_hit_within(o, d, Fw::splat(f32::INFINITY))
    }

    /// The lanes whose ray `o + t d` may meet the box with `0 < t < t_max` (a superset
    /// of those that do; NaN keeps a lane).
    #[inline(always)]
    pub fn may_hit_within(&self, o: V3, d: V3, t_max: Fw) -> Mw {
        let axes = [(o.x, d.x), (o.y, d.y), (o.z, d.z)];
        let (mut near, mut far) = ([Fw::ZERO; 3], [Fw::ZERO; 3]);
        let mut nan = Mw::FALSE;
        for (k, (o, d)) in axes.into_iter().enumerate() {
            let inv = 1.0 / d;
            let t0 = (Fw::splat(self.lo[k]) - o) * inv;
            let t1 = (Fw::splat(self.hi[k]) - o) * inv;
            nan = nan | t0.ne(t0) | t1.ne(t1);
            let order = t0.lt(t1);
            near[k] = order.select(t0, t1);
            far[k] = order.select(t1, t0) * (1.0 + 2.0 * gamma(3));
        }
        // Misses: the far end of some slab behind the origin or before the near end of
        // another.
        let mut miss = Mw::FALSE;
        let last = t_max * (1.0 + 2.0 * gamma(3));
        for f in far {
            miss = miss | f.lt(0.0);
            for n in near {
                miss = miss | n.gt(f);
            }
        }
        for n in near {
            miss = miss | n.gt(last);
        }
        !(miss & !nan)
    }
}

/// The lanes of `active` whose camera ray `(o, d)` certainly meets nothing: outside
/// the triangles' box and every sphere's ball. None in scenes without emitters at
/// infinity (closed rooms such as the suite's Cornell boxes, where the test would
/// only cost: their renders were 2-3% slower with it), and none when the scene has
/// spheres but no cull (tests).
// Inlined into the kernel when optimised; its own frame when not (the unoptimised
// kernel's frame must fit a worker thread's stack: see `kernel.rs`).
#[cfg_attr(not(debug_assertions), inline(always))]
#[cfg_attr(debug_assertions, inline(never))]
pub(super) fn escaping(ws: &WideScene<'_, '_>, o: V3, d: V3, active: Mw) -> Mw {
    if !ws.background {
        return Mw::FALSE;
    }
    let mut may = match &ws.triangle_box {
        Some(b) => b.may_hit(o, d),
        None => Mw::FALSE,
    };
    match (&ws.cull, ws.has_rest) {
        (Some(c), _) => may = may | c.may_hit(o, d, Fw::splat(f32::INFINITY), active),
        (None, true) => return Mw::FALSE,
        (None, false) => {}
    }
    active & !may
}

/// Finishes the camera samples of `lanes` of `s` (sample `first + lane` in lane
/// `lane`), whose rays leave the scene: what they see of the emitters at infinity
/// (black without), computed as the bounce loop computes it for a path that has just
/// left the camera (throughput 1, no previous vertex).
// Inlined into the kernel when optimised; its own frame when not (the unoptimised
// kernel's frame must fit a worker thread's stack: see `kernel.rs`).
#[cfg_attr(not(debug_assertions), inline(always))]
#[cfg_attr(debug_assertions, inline(never))]
pub(super) fn finish(
    ws: &WideScene<'_, '_>,
    s: &StartsW,
    lanes: Mw,
    first: usize,
    out: &mut [Rgb],
    counters: &mut PathCounters,
) {
    let mut radiance = V3::ZERO;
    if let Some(env) = &ws.environment {
        let mut bg = Background {
            escaped: lanes,
            ..Background::default()
        };
        bg.escaped_radiance(env, s.dir, Mw::FALSE, ws.background_scale);
        let one = Fw::splat(1.0);
        radiance = bg.add_escaped(V3::ZERO, V3::new(one, one, one), Mw::FALSE, Fw::ZERO, mis);
    }
    for lane in lanes.lanes() {
        let l = radiance.lane(lane);
        out[first + lane] = Rgb::new(l.x, l.y, l.z);
        counters.paths += 1;
        counters.rays += 1;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use irradia_core::{Ray, Rng};
    use irradia_geometry::packet::lanes::W;
    use irradia_geometry::packet::RayLaneTriangles;
    use irradia_geometry::triangle::TriangleRay;

    /// Every ray that hits a triangle (the lanes' test and the scalar one) is kept by
    /// the box, for rays from afar, grazing the box's faces, edges and corners, from
    /// inside it and along an axis; and most rays from afar that miss are dropped.
    #[test]
    fn the_box_keeps_every_hit_and_drops_most_misses() {
        let mut rng = Rng::new(3, 7);
        let mut v = |s: f32| rng.next_centered_vec3() * s;
        // A floor-like pair and a wall (faces of the box), and random triangles.
        let mut corners = vec![
            [
                Vec3::new(-20.0, -0.6, -20.0),
                Vec3::new(20.0, -0.6, -20.0),
                Vec3::new(20.0, -0.6, 20.0),
            ],
            [
                Vec3::new(-20.0, -0.6, -20.0),
                Vec3::new(20.0, -0.6, 20.0),
                Vec3::new(-20.0, -0.6, 20.0),
            ],
            [
                Vec3::new(-20.0, -0.6, -20.0),
                Vec3::new(-20.0, 3.0, -20.0),
                Vec3::new(20.0, 3.0, -20.0),
            ],
        ];
        for _ in 0..6 {
            let c = v(10.0);
            corners.push([c + v(2.0), c + v(2.0), c + v(2.0)]);
        }
        let b = TriangleBox::new(&corners).unwrap();
        let lanes = RayLaneTriangles::new(&corners, &(0..corners.len() as u32).collect::<Vec<_>>())
            .unwrap();
        let (lo, hi) = (Vec3::from(b.lo), Vec3::from(b.hi));
        let (mut hits, mut misses, mut kept_misses, mut near_kept) = (0, 0, 0, 0u32);
        for round in 0..3000 {
            let (mut o, mut d) = (V3::ZERO, V3::ZERO);
            let mut rays = Vec::new();
            for lane in 0..W {
                // A point of the box: inside, or on a face, edge or corner.
                let mut target = (lo + hi) * 0.5 + v(1.0) * (hi - lo);
                for k in 0..3 {
                    if (round + lane + k) % 3 == 0 {
                        target[k] = if v(1.0).x < 0.0 { lo[k] } else { hi[k] };
                    }
                }
                let (origin, dir) = match round % 4 {
                    // From afar, most passing the box by.
                    0 => {
                        let from = target + v(200.0);
                        (from, target + v(400.0) - from)
                    }
                    1 => (target, v(1.0)),
                    // Along an axis (zero direction components).
                    2 => {
                        let mut dir = Vec3::ZERO;
                        dir[lane % 3] = if lane % 2 == 0 { 1.0 } else { -1.0 };
                        (target - dir * 50.0, dir)
                    }
                    _ => {
                        let from = target + v(60.0);
                        (from, target - from + v(1e-3))
                    }
                };
                o.set_lane(lane, origin);
                d.set_lane(lane, dir);
                rays.push(Ray::new(origin, dir));
            }
            let kept = b.may_hit(o, d);
            let lane_hits = lanes.nearest::<false>(o, d, Mw::TRUE);
            // Bounded just past each hit, a lane that hits is still kept; bounded
            // near its origin, a ray from afar is not.
            let past = lane_hits.t * 1.000_001;
            let kept_within = b.may_hit_within(o, d, lane_hits.hit.select(past, Fw::ZERO));
            assert_eq!(kept_within & lane_hits.hit, lane_hits.hit, "round {round}");
            if round % 4 == 0 {
                near_kept += b.may_hit_within(o, d, Fw::splat(1e-3)).lanes().count() as u32;
            }
            for (lane, ray) in rays.iter().enumerate() {
                let tr = TriangleRay::new(ray);
                let scalar = corners
                    .iter()
                    .any(|c| tr.intersect(c[0], c[1], c[2], f32::INFINITY).is_some());
                if scalar || lane_hits.hit.get(lane) {
                    hits += 1;
                    assert!(kept.get(lane), "round {round} lane {lane}: {ray:?}");
                } else if round % 4 == 0 {
                    misses += 1;
                    kept_misses += kept.get(lane) as u32;
                }
            }
        }
        println!("{hits} hits; from afar {misses} misses of which {kept_misses} kept");
        assert!(
            near_kept < 50,
            "{near_kept} rays from afar kept within 1e-3"
        );
        assert!(
            hits > 10_000 && misses > 2000,
            "{hits} hits, {misses} misses"
        );
        assert!(
            kept_misses * 2 < misses,
            "{kept_misses} of {misses} misses kept"
        );
    }
}
