//! A ray spawned from a hit with `offset_ray_origin(hit.point, ±normal, hit.error)`
//! never hits the same surface again at its origin: for every shape of the shapes
//! module and for CSG results, placed at scales 1e-2, 1 and 1e3 by transforms, with
//! thousands of random rays, spawning reflected rays (mirror and random directions on
//! the incident side) and transmitted rays (straight on and random directions on the
//! far side).
//!
//! "The same surface at its origin" means the same primitive of the same CSG leaf
//! (`Hit::prim`, `Hit::leaf`) closer than 1e-4 of the object's size: a legitimate
//! second hit on the same surface that close would need a grazing chord, and
//! directions are kept at least 0.01 away from tangent (a chord of a sphere at that
//! angle is 2% of its diameter). Hits on a *different* face near an edge are legitimate
//! (the offset near the origin is an absolute 1/65536, so they do happen for small
//! objects).

use glam::{Affine3A, Quat, Vec2, Vec3};
use irradia_core::sampling::uniform_sphere;
use irradia_core::{offset_ray_origin, Ray, Rng};
use irradia_geometry::csg::{Csg, CsgOperand};
use irradia_geometry::shapes::{Cuboid, Disk, Plane, Polygon, Polyhedron, Quadric, Sphere};
use irradia_geometry::{Instance, Shape};
use std::sync::Arc;

fn leaf(s: impl Shape + 'static) -> CsgOperand {
    CsgOperand::shape(Arc::new(s), Affine3A::IDENTITY)
}

/// The csg workload's three objects and a few more trees.
pub fn csg_shapes() -> Vec<(&'static str, Arc<dyn Shape>)> {
    let box_minus_sphere = Csg::difference(vec![
        leaf(Cuboid::new(Vec3::splat(-1.0), Vec3::splat(1.0)).unwrap()),
        leaf(Sphere::new(Vec3::ZERO, 1.3)),
    ])
    .unwrap();
    let steinmetz = Csg::intersection(vec![
        leaf(
            Quadric::capped_cylinder(Vec3::new(-1.1, 0.0, 0.0), Vec3::new(1.1, 0.0, 0.0), 1.0)
                .unwrap(),
        ),
        leaf(
            Quadric::capped_cylinder(Vec3::new(0.0, -1.1, 0.0), Vec3::new(0.0, 1.1, 0.0), 1.0)
                .unwrap(),
        ),
        leaf(
            Quadric::capped_cylinder(Vec3::new(0.0, 0.0, -1.1), Vec3::new(0.0, 0.0, 1.1), 1.0)
                .unwrap(),
        ),
    ])
    .unwrap();
    let seven = |merge: bool| {
        let mut ops = vec![leaf(Sphere::new(Vec3::ZERO, 0.7))];
        for axis in [Vec3::X, Vec3::Y, Vec3::Z] {
            for s in [-0.75, 0.75] {
                ops.push(leaf(Sphere::new(axis * s, 0.45)));
            }
        }
        if merge {
            Csg::merge(ops).unwrap()
        } else {
            Csg::union(ops).unwrap()
        }
    };
    let nested = Csg::difference(vec![
        CsgOperand::node(seven(true), Affine3A::from_scale(Vec3::splat(1.2))),
        CsgOperand::shape(
            Arc::new(Polyhedron::platonic(8).unwrap()),
            Affine3A::from_rotation_translation(
                Quat::from_rotation_y(0.3),
                Vec3::new(0.9, 0.4, 0.2),
            ) * Affine3A::from_scale(Vec3::splat(0.5)),
        ),
    ])
    .unwrap();
    vec![
        ("box minus sphere", Arc::new(box_minus_sphere)),
        ("steinmetz", Arc::new(steinmetz)),
        ("union of spheres", Arc::new(seven(false))),
        ("merge of spheres", Arc::new(seven(true))),
        ("nested difference", Arc::new(nested)),
    ]
}

fn shapes() -> Vec<(&'static str, Arc<dyn Shape>)> {
    let clip = |q: Quadric| {
        q.clipped_by_box(Vec3::splat(-1.5), Vec3::splat(1.5))
            .unwrap()
    };
    let star: Vec<Vec3> = (0..10)
        .map(|i| {
            let a = std::f32::consts::TAU * i as f32 / 10.0;
            let r = if i % 2 == 0 { 1.0 } else { 0.4 };
            Vec3::new(r * a.cos(), r * a.sin(), 0.0)
        })
        .collect();
    let l_shape = vec![
        Vec3::new(0.0, 0.0, 0.0),
        Vec3::new(2.0, 0.0, 0.0),
        Vec3::new(2.0, 0.0, 1.0),
        Vec3::new(1.0, 0.0, 1.0),
        Vec3::new(1.0, 0.0, 2.0),
        Vec3::new(0.0, 0.0, 2.0),
    ];
    let mut v: Vec<(&'static str, Arc<dyn Shape>)> = vec![
        (
            "sphere",
            Arc::new(Sphere::new(Vec3::new(0.3, -0.2, 0.5), 1.0)),
        ),
        (
            "ellipsoid",
            Arc::new(
                Quadric::ellipsoid(Vec3::new(0.1, 0.2, -0.3), Vec3::new(1.5, 0.7, 1.0)).unwrap(),
            ),
        ),
        (
            "capped cylinder",
            Arc::new(
                Quadric::capped_cylinder(
                    Vec3::new(-1.0, -0.5, 0.2),
                    Vec3::new(0.8, 1.0, -0.4),
                    0.6,
                )
                .unwrap(),
            ),
        ),
        (
            "capped cone",
            Arc::new(
                Quadric::capped_cone(
                    Vec3::new(0.0, -1.0, 0.0),
                    1.0,
                    Vec3::new(0.3, 1.0, 0.2),
                    0.3,
                )
                .unwrap(),
            ),
        ),
        (
            "pointed cone",
            Arc::new(
                Quadric::capped_cone(
                    Vec3::new(0.0, -1.0, 0.0),
                    1.0,
                    Vec3::new(0.0, 1.0, 0.0),
                    0.0,
                )
                .unwrap(),
            ),
        ),
        ("clipped cone", Arc::new(clip(Quadric::cone(0.8).unwrap()))),
        (
            "clipped hyperboloid 1",
            Arc::new(clip(Quadric::hyperboloid_one_sheet(0.6, 0.8).unwrap())),
        ),
        (
            "clipped hyperboloid 2",
            Arc::new(clip(Quadric::hyperboloid_two_sheets(0.6, 0.4).unwrap())),
        ),
        (
            "clipped paraboloid",
            Arc::new(
                Quadric::paraboloid(1.0)
                    .unwrap()
                    .clipped_by_plane(Vec3::Y, 1.2)
                    .unwrap(),
            ),
        ),
        (
            "open tube",
            Arc::new(clip(Quadric::cylinder(0.8).unwrap()).open()),
        ),
        (
            "general quadric",
            Arc::new(
                Quadric::new([1.0, 2.0, 3.0, 0.5, -0.4, 0.3, 0.1, -0.2, 0.3, -1.5])
                    .unwrap()
                    .clipped_by_box(Vec3::splat(-3.0), Vec3::splat(3.0))
                    .unwrap(),
            ),
        ),
        (
            "plane",
            Arc::new(Plane::new(Vec3::new(0.2, 1.0, -0.3), 0.25).unwrap()),
        ),
        (
            "box",
            Arc::new(Cuboid::new(Vec3::new(-1.0, -0.5, -0.7), Vec3::new(0.8, 1.0, 0.6)).unwrap()),
        ),
        ("tetrahedron", Arc::new(Polyhedron::platonic(4).unwrap())),
        ("dodecahedron", Arc::new(Polyhedron::platonic(12).unwrap())),
        ("icosahedron", Arc::new(Polyhedron::platonic(20).unwrap())),
        ("star polygon", Arc::new(Polygon::new(star).unwrap())),
        ("L polygon", Arc::new(Polygon::new(l_shape).unwrap())),
        (
            "annulus",
            Arc::new(
                Disk::new(Vec3::new(0.1, 0.0, 0.2), Vec3::new(0.3, 1.0, 0.2), 1.0)
                    .unwrap()
                    .with_hole(0.3)
                    .unwrap(),
            ),
        ),
    ];
    v.extend(csg_shapes());
    v
}

fn dir_around(rng: &mut Rng, n: Vec3) -> Vec3 {
    loop {
        let d = uniform_sphere(Vec2::new(rng.next_f32(), rng.next_f32()));
        let c = d.dot(n);
        if c.abs() > 0.01 {
            return if c > 0.0 { d } else { -d };
        }
    }
}

/// Fires `rays` random rays at the placed shape and checks every spawned ray.
fn check(name: &str, inst: &Instance, size: f32, rays: u32, seed: u64) -> u32 {
    let mut rng = Rng::new(seed, 7);
    let b = inst.bounds();
    let (lo, hi) = if b.is_finite() {
        (b.min, b.max)
    } else {
        let c = inst.to_world().transform_point3(Vec3::ZERO);
        (c - Vec3::splat(size), c + Vec3::splat(size))
    };
    let mut hits = 0;
    for _ in 0..rays {
        let target = lo + (hi - lo) * Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32());
        let d = uniform_sphere(Vec2::new(rng.next_f32(), rng.next_f32()));
        let ray = Ray::new(target - d * 3.0 * size, d);
        let Some(h) = inst.intersect(&ray, f32::INFINITY) else {
            continue;
        };
        hits += 1;
        assert!(
            h.normal.is_finite() && (h.normal.length() - 1.0).abs() < 1e-3,
            "{name}: normal {:?}",
            h.normal
        );
        let n = h.normal;
        let side = if d.dot(n) < 0.0 { n } else { -n };
        let reflected = d - 2.0 * d.dot(n) * n;
        let mut spawned = vec![(side, reflected), (side, dir_around(&mut rng, side))];
        if d.dot(side).abs() > 0.01 {
            spawned.push((-side, d));
        }
        spawned.push((-side, dir_around(&mut rng, -side)));
        for (push, dir) in spawned {
            if dir.dot(push) <= 0.0 {
                continue; // a grazing mirror direction rounded to the wrong side
            }
            let o = offset_ray_origin(h.point, push, h.error);
            if let Some(h2) = inst.intersect(&Ray::new(o, dir), f32::INFINITY) {
                let dist = (h2.point - o).length();
                let same_surface = h2.prim == h.prim && h2.leaf == h.leaf;
                assert!(
                    !same_surface || dist > 1e-4 * size,
                    "{name} (size {size}): a spawned ray re-hit at distance {dist:e} \
                     (hit {:?} normal {:?} error {:e}, spawned {:?} dir {:?})",
                    h.point,
                    h.normal,
                    h.error,
                    o,
                    dir
                );
            }
        }
    }
    hits
}

#[test]
fn spawned_rays_never_rehit_at_their_origin() {
    for (k, (name, shape)) in shapes().into_iter().enumerate() {
        let mut total = 0;
        for (j, scale) in [1.0f32, 1e-2, 1e3].into_iter().enumerate() {
            let placements = [
                Affine3A::IDENTITY,
                Affine3A::from_scale_rotation_translation(
                    Vec3::new(scale, scale * 0.8, scale * 1.3),
                    Quat::from_euler(glam::EulerRot::XYZ, 0.4, -0.7, 0.2),
                    Vec3::new(2.0, -1.0, 3.5) * scale,
                ),
            ];
            for (i, m) in placements.into_iter().enumerate() {
                if i == 0 && j > 0 {
                    continue;
                }
                let inst = Instance::new(shape.clone(), m);
                total += check(name, &inst, 3.0 * scale, 400, (k * 10 + j * 2 + i) as u64);
            }
        }
        assert!(
            total > 100,
            "{name}: only {total} hits; the test would prove little"
        );
    }
}
