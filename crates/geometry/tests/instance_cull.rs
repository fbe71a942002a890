//! A turned (rotated) instance tests a ray against its shape's own box in object space
//! before asking the shape (`Instance::may_meet`). The test must only drop rays that
//! miss: this checks, bit for bit, that `intersect`, `nearest_t` and `occluded` of such
//! instances answer as the shape asked directly with the ray carried into object space
//! (what they did before the test), for rays aimed at the corners, edges and faces of
//! the own box, where a cube minus a sphere keeps all its surface, and for windows
//! `t_max` that end just before, inside and past the solid.

use glam::{Affine3A, Quat, Vec2, Vec3};
use irradia_core::sampling::uniform_sphere;
use irradia_core::{Ray, Rng};
use irradia_geometry::csg::{Csg, CsgOperand};
use irradia_geometry::shapes::{Cuboid, Quadric, Sphere};
use irradia_geometry::{Instance, Shape};
use std::sync::Arc;

fn leaf(s: impl Shape + 'static) -> CsgOperand {
    CsgOperand::shape(Arc::new(s), Affine3A::IDENTITY)
}

/// The `csg` scene's solids and two plain shapes, each with its own box.
fn shapes() -> Vec<(&'static str, Arc<dyn Shape>)> {
    let cube = || Cuboid::new(Vec3::splat(-1.0), Vec3::splat(1.0)).unwrap();
    let cylinder = |axis: Vec3| Quadric::capped_cylinder(-1.1 * axis, 1.1 * axis, 1.0).unwrap();
    vec![
        (
            "cube minus sphere",
            Arc::new(
                Csg::difference(vec![leaf(cube()), leaf(Sphere::new(Vec3::ZERO, 1.3))]).unwrap(),
            ),
        ),
        (
            "Steinmetz solid",
            Arc::new(
                Csg::intersection(vec![
                    leaf(cylinder(Vec3::X)),
                    leaf(cylinder(Vec3::Y)),
                    leaf(cylinder(Vec3::Z)),
                ])
                .unwrap(),
            ),
        ),
        ("cube", Arc::new(cube())),
        (
            "sphere",
            Arc::new(Sphere::new(Vec3::new(0.2, -0.1, 0.3), 0.9)),
        ),
    ]
}

/// The ray carried into object space as `Instance` carries it.
fn object_ray(i: &Instance, r: &Ray) -> Ray {
    Ray::new(
        i.to_object().transform_point3(r.origin),
        i.to_object().transform_vector3(r.dir),
    )
}

#[test]
fn turned_instances_drop_only_rays_that_miss() {
    let places = [
        Affine3A::from_scale_rotation_translation(
            Vec3::splat(0.9),
            Quat::from_rotation_y(-30f32.to_radians()),
            Vec3::new(-2.6, 0.9, -0.5),
        ),
        Affine3A::from_rotation_translation(
            Quat::from_rotation_y(-35f32.to_radians()) * Quat::from_rotation_x(-25f32.to_radians()),
            Vec3::new(0.0, 1.1, -1.0),
        ),
        Affine3A::from_scale_rotation_translation(
            Vec3::new(1.5, 0.5, 1.0),
            Quat::from_rotation_z(0.7),
            Vec3::new(3.0, -1.0, 2.0),
        ),
    ];
    let mut rng = Rng::new(14, 3);
    for (name, shape) in shapes() {
        let own = shape.bounds();
        for (k, m) in places.iter().enumerate() {
            let inst = Instance::new(shape.clone(), *m);
            let (mut hits, mut culled) = (0, 0);
            for i in 0..30_000 {
                // A target on the own box: a corner, an edge or a face, nudged by up to
                // a few ulps either way, or anywhere near the box.
                let mut p = own.min
                    + (own.max - own.min)
                        * Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32());
                let snap = i % 4;
                for axis in 0..snap.min(3) {
                    let a = (axis + i / 4) % 3;
                    p[a] = if rng.next_f32() < 0.5 {
                        own.min[a]
                    } else {
                        own.max[a]
                    };
                    p[a] += (rng.next_f32() - 0.5) * 8.0 * f32::EPSILON * p[a].abs().max(1.0);
                }
                let target = m.transform_point3(p);
                let d = uniform_sphere(Vec2::new(rng.next_f32(), rng.next_f32()));
                let dist = 0.05 + 8.0 * rng.next_f32();
                let ray = Ray::new(target - d * dist, d * (0.5 + rng.next_f32()));
                let t_max = match i % 3 {
                    0 => f32::INFINITY,
                    1 => dist * 2.0 * rng.next_f32(),
                    _ => dist * (0.999 + 0.002 * rng.next_f32()),
                };
                let oray = object_ray(&inst, &ray);
                let want = shape.intersect(&oray, t_max);
                let got = inst.intersect(&ray, t_max);
                assert_eq!(
                    want.map(|h| (h.t.to_bits(), h.prim, h.leaf)),
                    got.map(|h| (h.t.to_bits(), h.prim, h.leaf)),
                    "{name}, place {k}, ray {i}: {ray:?} t_max {t_max}"
                );
                assert_eq!(
                    shape.nearest_t(&oray, t_max).map(f64::to_bits),
                    inst.nearest_t(&ray, t_max).map(f64::to_bits),
                    "{name}, place {k}, ray {i}"
                );
                assert_eq!(
                    shape.occluded(&oray, t_max),
                    inst.occluded(&ray, t_max),
                    "{name}, place {k}, ray {i}"
                );
                if want.is_some() {
                    hits += 1;
                } else if !own.is_empty() {
                    culled += 1;
                }
            }
            assert!(
                hits > 3_000 && culled > 3_000,
                "{name}, place {k}: {hits} hits, {culled} misses"
            );
        }
    }
}
