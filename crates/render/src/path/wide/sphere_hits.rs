//! W rays against the scene's spheres at once, exactly: the scalar sphere test's
//! arithmetic ([`Sphere`]'s `intersect` and `occluded` under
//! [`Instance`](irradia_geometry::Instance)'s transform, as the flat scene's
//! `nearest_rest` and `occluded_rest` ask them) with the lanes in the vector and the
//! spheres in the loop (scenes have few spheres), so hits, normals and error bounds are
//! the scalar ones bit for bit.
//!
//! The quadratic is the scalar one in `f64` (lecture: "Ray Casting a Sphere"; the stable
//! pair of roots `q / a`, `c / q`, Press et al., Numerical Recipes §5.6; the
//! discriminant of Haines et al., "Precision Improvements for Ray/Sphere Intersection",
//! Ray Tracing Gems, ch. 7), the W lanes as `f64` vectors ([`Dw`]). A ray under
//! a transform is carried to object space in `f32` with `glam`'s order of sums; the hit
//! is the nearest root in `(0, t_max)` with `t_max` shrinking to each hit's `f32` `t`
//! as the scalar traversal shrinks it. Then, per sphere hit by some lane: the point
//! `c + r n` with `n` the offset from the centre (in `f64`, rounded once) normalised in
//! `f32`, the normal flipped for Mitsuba's `flip_normals`, and for a transformed sphere
//! the world point `o + t d`, the normal carried by the inverse transpose and the error
//! bound stretched by the transform (`Instance::intersect`'s arithmetic). Ties between
//! spheres at the very same `t` go to the first sphere in scene order (the scalar code:
//! its hierarchy's order); nothing else depends on the order.

// Lane loops index several arrays by the lane on purpose.
#![allow(clippy::needless_range_loop)]

use super::dw::{select, Dw, DV3};
use irradia_geometry::packet::lanes::{Fw, Mw, V3, W};
use irradia_geometry::shapes::Sphere;
use irradia_geometry::{Hit, SceneHit};
use irradia_scene::Scene;

/// A sphere's transform: world to object (columns and translation), the normal
/// matrix (columns) and the bound on its stretch, as `Instance::new` makes them.
#[derive(Clone, Debug)]
struct Placement {
    to_object: [[f32; 3]; 3],
    translation: [f32; 3],
    normal_to_world: [[f32; 3]; 3],
    max_scale: f32,
}

/// One sphere: its scene index, object-space centre and radius, flip, the error bound
/// of its object-space hits and its transform (`None`: the identity).
#[derive(Clone, Debug)]
struct Ball {
    instance: u32,
    center: [f32; 3],
    radius: f32,
    flipped: bool,
    error: f32,
    placement: Option<Placement>,
}

/// The spheres of a scene, for W rays at once.
#[derive(Clone, Debug)]
pub(crate) struct SpheresW {
    balls: Vec<Ball>,
}

/// The nearest sphere hits of W rays: in the lanes of `hit`, the scene index of
/// the sphere, `t`, the world point, the (geometric and shading) normal and the error
/// bound.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct SphereHits {
    pub hit: Mw,
    pub instance: [u32; W],
    pub t: Fw,
    pub point: V3,
    pub normal: V3,
    pub error: Fw,
}

impl SphereHits {
    /// Lane `lane`'s hit as the flat scene's `nearest_rest` reports it (no uv: the
    /// kernel's materials are untextured).
    #[inline(always)]
    pub fn scene_hit(&self, lane: usize) -> Option<SceneHit> {
        if !self.hit.get(lane) {
            return None;
        }
        let n = self.normal.lane(lane);
        let mut hit = Hit::new(self.t.0[lane], self.point.lane(lane), n, glam::Vec2::ZERO);
        hit.error = self.error.0[lane];
        Some(SceneHit {
            instance: self.instance[lane],
            hit,
        })
    }
}

/// `M v` with the columns of `m`, summed in `glam`'s order (`Mat3A::mul_vec3a`,
/// `Affine3A::transform_vector3`).
#[inline(always)]
fn mat_vec(m: &[[f32; 3]; 3], v: V3) -> V3 {
    // (No closures in the vector stage: one that is not inlined loses the loop's
    // target features.)
    splat3(m[0])
        .scale(v.x)
        .add(splat3(m[1]).scale(v.y))
        .add(splat3(m[2]).scale(v.z))
}

#[inline(always)]
fn splat3(c: [f32; 3]) -> V3 {
    V3::new(Fw::splat(c[0]), Fw::splat(c[1]), Fw::splat(c[2]))
}

#[inline(always)]
fn widen(v: V3) -> DV3 {
    DV3 {
        x: Dw::widen(v.x),
        y: Dw::widen(v.y),
        z: Dw::widen(v.z),
    }
}

/// `glam`'s `Vec3::max_element` of `|v|` in every lane.
#[inline(always)]
fn max_abs(v: V3) -> Fw {
    v.x.abs().max(v.y.abs().max(v.z.abs()))
}

impl Ball {
    /// The ray in the sphere's object space (`Instance::object_ray`).
    #[inline(always)]
    fn object_ray(&self, o: V3, d: V3) -> (V3, V3) {
        match &self.placement {
            None => (o, d),
            Some(p) => (
                mat_vec(&p.to_object, o).add(splat3(p.translation)),
                mat_vec(&p.to_object, d),
            ),
        }
    }

    /// `Sphere::quadratic` in every lane: `(a, c, q, miss)`, the roots being `q / a`
    /// and `c / q` where `miss` (a negative discriminant) is false.
    #[inline(always)]
    fn quadratic(&self, o: V3, d: V3) -> (Dw, Dw, Dw, Mw) {
        let c = self.center;
        let centre = DV3 {
            x: Dw::splat(c[0] as f64),
            y: Dw::splat(c[1] as f64),
            z: Dw::splat(c[2] as f64),
        };
        let o = widen(o).sub(centre);
        let d = widen(d);
        let r = Dw::splat(self.radius as f64);
        let a = d.dot(d);
        let b = o.dot(d);
        let l = o.sub(d.scale(b / a));
        let disc = a * (r * r - l.dot(l));
        let q = -b - b.signum() * disc.sqrt();
        (a, o.dot(o) - r * r, q, disc.lt(0.0))
    }
}

impl SpheresW {
    /// The spheres among scene objects `objects` (scene indices), or `None` when one
    /// of them is not a sphere.
    pub fn new(scene: &Scene, objects: &[u32]) -> Option<Self> {
        let mut balls = Vec::new();
        for &i in objects {
            let inst = &scene.accel.instances()[i as usize];
            let s: &Sphere = inst.shape.as_sphere()?;
            let placement = (!inst.is_identity()).then(|| {
                let to = inst.to_object();
                let n = to.matrix3.transpose();
                let m = inst.to_world().matrix3;
                Placement {
                    to_object: [
                        to.matrix3.x_axis.into(),
                        to.matrix3.y_axis.into(),
                        to.matrix3.z_axis.into(),
                    ],
                    translation: to.translation.into(),
                    normal_to_world: [n.x_axis.into(), n.y_axis.into(), n.z_axis.into()],
                    // As `Instance::new`.
                    max_scale: m
                        .x_axis
                        .length()
                        .max(m.y_axis.length())
                        .max(m.z_axis.length())
                        * 3f32.sqrt(),
                }
            });
            balls.push(Ball {
                instance: i,
                center: s.center.to_array(),
                radius: s.radius,
                flipped: s.flipped(),
                // As `Sphere::intersect`.
                error: (s.center.abs().max_element() + s.radius) * 4.0 * f32::EPSILON,
                placement,
            });
        }
        Some(Self { balls })
    }

    /// The nearest sphere hit with `0 < t < t_max` of the rays `o + t d` in the lanes
    /// of `active`.
    #[inline(always)]
    pub fn nearest(&self, o: V3, d: V3, t_max: Fw, active: Mw) -> SphereHits {
        let mut out = SphereHits::default();
        let mut best = t_max;
        let mut best_t = Dw::ZERO;
        let mut which = [0usize; W];
        for (k, s) in self.balls.iter().enumerate() {
            let (oo, dd) = s.object_ray(o, d);
            let (a, c, q, miss) = s.quadratic(oo, dd);
            // `Sphere::roots`, then the nearer root in front of the origin.
            let zero = q.eq(0.0);
            let t0 = select(zero, Dw::ZERO, q / a);
            let t1 = select(zero, Dw::ZERO, c / q);
            let ordered = t0.le(t1);
            let (lo, hi) = (select(ordered, t0, t1), select(ordered, t1, t0));
            let t = select(lo.gt(0.0), lo, hi);
            let take = active & !miss & t.gt(0.0) & t.lt(Dw::widen(best));
            if !take.any() {
                continue;
            }
            best = take.select(t.narrow(), best);
            best_t = select(take, t, best_t);
            for lane in take.lanes() {
                which[lane] = k;
            }
            out.hit = out.hit | take;
        }
        if !out.hit.any() {
            return out;
        }
        out.t = out.hit.keep(best);
        // The surfaces, sphere by sphere (usually one or two are hit).
        for (k, s) in self.balls.iter().enumerate() {
            let mut mine = Mw::FALSE;
            for lane in 0..W {
                mine.set(lane, out.hit.get(lane) && which[lane] == k);
            }
            if !mine.any() {
                continue;
            }
            for lane in mine.lanes() {
                out.instance[lane] = s.instance;
            }
            let (oo, dd) = s.object_ray(o, d);
            // `Sphere::surface`: the offset from the centre in f64, rounded once, made
            // a unit vector in f32; the point projected onto the sphere.
            let p = widen(oo).add(widen(dd).scale(best_t));
            let c = s.center;
            let off = V3::new(
                (p.x - c[0] as f64).narrow(),
                (p.y - c[1] as f64).narrow(),
                (p.z - c[2] as f64).narrow(),
            );
            let n = off.normalize();
            let point = splat3(c).add(n.scale(Fw::splat(s.radius)));
            let n = if s.flipped { n.neg() } else { n };
            let (point, normal, error) = match &s.placement {
                None => (point, n, Fw::splat(s.error)),
                // `Instance::intersect`: the world point from `t`, the normal carried
                // by the inverse transpose and normalised as `Vec3A` does (divided by
                // the length), the error bound stretched.
                Some(pl) => {
                    let t = out.t;
                    let travel = d.scale(t);
                    let w = mat_vec(&pl.normal_to_world, n);
                    let len = w.dot(w).sqrt();
                    let error = s.error * pl.max_scale
                        + (max_abs(o) + max_abs(travel)) * 4.0 * f32::EPSILON;
                    (o.add(travel), w.div(len), error)
                }
            };
            out.point = V3::select(mine, point, out.point);
            out.normal = V3::select(mine, normal, out.normal);
            out.error = mine.select(error, out.error);
        }
        out
    }

    /// The lanes of `active` whose ray `o + t d` meets a sphere with `0 < t < t_max`
    /// (`Sphere::occluded`: a root in the range, decided without dividing).
    #[inline(always)]
    pub fn occluded(&self, o: V3, d: V3, t_max: Fw, active: Mw) -> Mw {
        let tm = Dw::widen(t_max);
        let mut blocked = Mw::FALSE;
        for s in &self.balls {
            let (oo, dd) = s.object_ray(o, d);
            let (a, c, q, miss) = s.quadratic(oo, dd);
            let front = q.gt(0.0) & q.lt(tm * a);
            let back = (c * q).gt(0.0) & c.abs().lt(tm * q.abs());
            blocked = blocked | (!miss & (front | back));
        }
        active & blocked
    }
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;
    use glam::{Affine3A, Quat, Vec3};
    use irradia_core::{Ray, Rgb, Rng};
    use irradia_geometry::Instance;
    use irradia_scene::{Material, Object};
    use std::sync::Arc;

    /// A unit sphere stretched, turned and moved into an ellipsoid.
    pub(in super::super) fn ellipsoid() -> Instance {
        Instance::new(
            Arc::new(Sphere::new(Vec3::ZERO, 1.0)),
            Affine3A::from_scale_rotation_translation(
                Vec3::new(0.45, 0.2, 0.3),
                Quat::from_rotation_y(0.3),
                Vec3::new(-0.4, -0.55, -0.35),
            ),
        )
    }

    /// A scene of the instances alone (one black material; the Cornell box's camera),
    /// for the lane sphere tests here and in [`super::super::sphere_cull`].
    pub(in super::super) fn scene_of(instances: Vec<Instance>) -> Scene {
        let n = instances.len();
        Scene::new(
            irradia_scene::builtin::load("cornell").unwrap().camera,
            Default::default(),
            vec![Material {
                emission: Rgb::BLACK,
                ..Material::default()
            }],
            vec![],
            (0..n)
                .map(|k| Object {
                    name: format!("s{k}"),
                    material: 0,
                    leaf_materials: vec![],
                })
                .collect(),
            instances,
        )
    }

    /// Every lane's nearest hit (which sphere, `t`, point, normal, error bound) and
    /// occlusion equal the scalar tests' (`Instance::intersect` and `occluded`, nearest
    /// over the spheres as the scalar traversal takes it) bit for bit, for rays from
    /// afar, from the surfaces (inside and out), grazing ones and short segments,
    /// against plain, flipped, transformed and far-off spheres.
    #[test]
    fn lane_hits_equal_the_scalar_sphere_tests_bit_for_bit() {
        let instances = vec![
            Instance::untransformed(Arc::new(Sphere::new(Vec3::new(0.4, -0.6, 0.3), 0.4))),
            Instance::untransformed(Arc::new(
                Sphere::new(Vec3::new(-0.3, 0.5, 0.2), 0.35).with_flipped_normals(true),
            )),
            Instance::untransformed(Arc::new(Sphere::new(Vec3::new(30.0, 2.0, -9.0), 1e-2))),
            ellipsoid(),
            Instance::new(
                Arc::new(Sphere::new(Vec3::new(0.1, 0.2, -0.1), 0.5).with_flipped_normals(true)),
                Affine3A::from_scale_rotation_translation(
                    Vec3::splat(0.7),
                    Quat::from_rotation_x(1.1),
                    Vec3::new(0.6, 0.4, -0.5),
                ),
            ),
        ];
        let n = instances.len();
        let scene = scene_of(instances);
        let objects: Vec<u32> = (0..n as u32).collect();
        let spheres = SpheresW::new(&scene, &objects).unwrap();
        let inst = scene.accel.instances();
        let mut rng = Rng::new(3, 4);
        let mut v = |s: f32| rng.next_centered_vec3() * s;
        let (mut hits, mut blocked, mut flipped, mut placed) = (0, 0, 0, 0);
        for round in 0..6000 {
            let (mut o, mut d) = (V3::ZERO, V3::ZERO);
            let mut t_max = Fw::splat(f32::INFINITY);
            let mut rays = Vec::new();
            for lane in 0..W {
                let k = (round + lane) % n;
                let b = inst[k].bounds();
                let (centre, radius) = (b.center(), 0.5 * b.extent().max_element());
                let (origin, dir) = match round % 4 {
                    0 => {
                        let from = centre + v(8.0 * radius + 4.0);
                        (from, centre + v(3.0 * radius) - from)
                    }
                    // From a point of the surface (inside and out), as a bounce leaves.
                    1 => {
                        let from = centre + v(1.0).normalize() * radius * 0.9;
                        let h = inst[k].intersect(&Ray::new(from, v(1.0)), f32::INFINITY);
                        (h.map_or(from, |h| h.point), v(1.0))
                    }
                    // Grazing the bounding ball's rim.
                    2 => {
                        let dir = v(1.0).normalize();
                        let side = dir.any_orthonormal_vector() * radius;
                        let jitter = 1.0 + (v(1.0).x) * 2e-3;
                        (centre - dir * 5.0 + side * jitter, dir)
                    }
                    // Segments (shadow rays with t_max = 1, and a finite bound).
                    _ => {
                        let from = centre + v(4.0 * radius);
                        t_max.0[lane] = if lane % 2 == 0 { 1.0 } else { 0.5 };
                        (from, centre + v(4.0 * radius) - from)
                    }
                };
                o.set_lane(lane, origin);
                d.set_lane(lane, dir);
                rays.push(Ray::new(origin, dir));
            }
            let active = Mw::from_fn(|lane| lane != 3 || round % 5 != 0);
            let got = spheres.nearest(o, d, t_max, active);
            let occ = spheres.occluded(o, d, t_max, active);
            for lane in 0..W {
                let ray = &rays[lane];
                // The scalar nearest: each sphere asked up to the best `t` so far.
                let mut want: Option<(usize, Hit)> = None;
                let mut tm = t_max.0[lane];
                for (k, i) in inst.iter().enumerate() {
                    if let Some(h) = i.intersect(ray, tm) {
                        tm = h.t;
                        want = Some((k, h));
                    }
                }
                let want_occ = inst.iter().any(|i| i.occluded(ray, t_max.0[lane]));
                if !active.get(lane) {
                    assert!(!got.hit.get(lane) && !occ.get(lane));
                    continue;
                }
                assert_eq!(
                    occ.get(lane),
                    want_occ,
                    "round {round} lane {lane}: {ray:?}"
                );
                blocked += want_occ as u32;
                let g = got.scene_hit(lane);
                match (want, g) {
                    (None, None) => {}
                    (Some((k, w)), Some(g)) => {
                        hits += 1;
                        flipped += (k == 1 || k == 4) as u32;
                        placed += (k >= 3) as u32;
                        assert_eq!(g.instance, k as u32);
                        let h = g.hit;
                        let same = |a: Vec3, b: Vec3| {
                            a.to_array().map(f32::to_bits) == b.to_array().map(f32::to_bits)
                        };
                        assert_eq!(h.t.to_bits(), w.t.to_bits(), "round {round} lane {lane}");
                        assert!(same(h.point, w.point), "{:?} {:?}", h.point, w.point);
                        assert!(same(h.normal, w.normal), "{:?} {:?}", h.normal, w.normal);
                        assert!(same(h.shading_normal, w.shading_normal));
                        assert_eq!(h.error.to_bits(), w.error.to_bits());
                    }
                    (w, g) => {
                        panic!("round {round} lane {lane}: {ray:?}: scalar {w:?}, lanes {g:?}")
                    }
                }
            }
        }
        println!("{hits} hits ({flipped} flipped, {placed} transformed), {blocked} blocked");
        assert!(hits > 8000 && flipped > 1000 && placed > 1000 && blocked > 4000);
    }

    /// A shape that is not a sphere is refused.
    #[test]
    fn only_spheres_are_taken() {
        let scene = scene_of(vec![Instance::untransformed(Arc::new(
            irradia_geometry::shapes::Cube::new(false),
        ))]);
        assert!(SpheresW::new(&scene, &[0]).is_none());
    }
}
