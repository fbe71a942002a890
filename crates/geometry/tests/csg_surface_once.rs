//! CSG combines spans by their parameters alone and computes the surface only at the
//! boundary a ray reports (`csg/resolve.rs`); shadow rays get no surface at all. This
//! checks, bit for bit, that `Csg::intersect` reports the boundary that combining the
//! full spans (every surface computed, `Shape::spans`) gives: same `t`, normal
//! (including the negated normals of subtracted faces, through nested differences and
//! transforms), uv, primitive and leaf; and that `Csg::occluded` agrees with it.

use glam::{Affine3A, Quat, Vec2, Vec3};
use irradia_core::sampling::uniform_sphere;
use irradia_core::{Ray, Rng};
use irradia_geometry::csg::{Csg, CsgOperand};
use irradia_geometry::shape::Span;
use irradia_geometry::shapes::{Cuboid, Quadric, Sphere};
use irradia_geometry::Shape;
use std::sync::Arc;

fn leaf(s: impl Shape + 'static, to_parent: Affine3A) -> CsgOperand {
    CsgOperand::shape(Arc::new(s), to_parent)
}

fn turn(angle: f32, t: Vec3) -> Affine3A {
    Affine3A::from_rotation_translation(
        Quat::from_rotation_y(angle) * Quat::from_rotation_x(0.4),
        t,
    )
}

fn cylinder(axis: Vec3) -> Quadric {
    Quadric::capped_cylinder(-1.1 * axis, 1.1 * axis, 1.0).unwrap()
}

/// Trees with differences inside differences (normals negated twice), transformed
/// nodes and leaves, a CSG given as a plain shape operand, a cylinder's caps, and all
/// four operations.
fn trees() -> Vec<(&'static str, Csg)> {
    let cube = || Cuboid::new(Vec3::splat(-1.0), Vec3::splat(1.0)).unwrap();
    let box_minus_sphere = || {
        Csg::difference(vec![
            leaf(cube(), Affine3A::from_scale(Vec3::new(1.0, 0.8, 1.2))),
            leaf(Sphere::new(Vec3::ZERO, 1.3), Affine3A::IDENTITY),
        ])
        .unwrap()
    };
    let steinmetz = || {
        Csg::intersection(vec![
            leaf(cylinder(Vec3::X), Affine3A::IDENTITY),
            leaf(cylinder(Vec3::Y), turn(0.2, Vec3::ZERO)),
            leaf(cylinder(Vec3::Z), Affine3A::IDENTITY),
        ])
        .unwrap()
    };
    let merge = || {
        let mut ops = vec![leaf(Sphere::new(Vec3::ZERO, 0.7), Affine3A::IDENTITY)];
        for axis in [Vec3::X, Vec3::Y, Vec3::Z] {
            ops.push(leaf(Sphere::new(axis * 0.75, 0.45), Affine3A::IDENTITY));
        }
        Csg::merge(ops).unwrap()
    };
    // (A - B) - (C - D) with every part placed: inner subtracted faces twice negated.
    let double_difference = Csg::difference(vec![
        CsgOperand::node(box_minus_sphere(), turn(0.3, Vec3::new(0.1, 0.0, 0.0))),
        CsgOperand::node(
            Csg::difference(vec![
                leaf(Sphere::new(Vec3::ZERO, 0.9), Affine3A::IDENTITY),
                leaf(cylinder(Vec3::Y), Affine3A::from_scale(Vec3::splat(0.4))),
            ])
            .unwrap(),
            Affine3A::from_translation(Vec3::new(0.8, 0.3, -0.2)),
        ),
        leaf(
            cube(),
            turn(0.7, Vec3::new(-1.0, 0.9, 0.0)) * Affine3A::from_scale(Vec3::splat(0.35)),
        ),
    ])
    .unwrap();
    let mixed = Csg::intersection(vec![
        CsgOperand::node(merge(), Affine3A::from_scale(Vec3::splat(1.4))),
        CsgOperand::node(steinmetz(), turn(-0.5, Vec3::ZERO)),
        // A CSG node given as a plain (leaf) operand.
        CsgOperand::shape(
            Arc::new(Csg::union(vec![leaf(cube(), Affine3A::IDENTITY)]).unwrap()),
            Affine3A::from_scale(Vec3::splat(0.95)),
        ),
    ])
    .unwrap();
    let merge_minus = Csg::merge(vec![
        CsgOperand::node(double_difference.clone(), Affine3A::IDENTITY),
        CsgOperand::node(
            steinmetz(),
            Affine3A::from_translation(Vec3::new(0.0, 1.2, 0.0)),
        ),
    ])
    .unwrap();
    // A capped cylinder whose caps show (the rim cut by the ball): boundaries on clip
    // planes, whose side the parameter-only boundary carries (`span_boundary_of`).
    let capped = Csg::intersection(vec![
        leaf(cylinder(Vec3::Y), turn(0.9, Vec3::ZERO)),
        leaf(Sphere::new(Vec3::ZERO, 1.3), Affine3A::IDENTITY),
    ])
    .unwrap();
    vec![
        ("capped cylinder in a ball", capped),
        ("box minus sphere", box_minus_sphere()),
        ("steinmetz", steinmetz()),
        ("merge", merge()),
        ("double difference", double_difference),
        ("mixed", mixed),
        ("merge with differences", merge_minus),
    ]
}

/// The first boundary with `0 < t < t_max` of the spans with every surface computed.
fn reference(csg: &Csg, ray: &Ray, t_max: f32) -> Option<irradia_geometry::shape::Boundary> {
    let mut spans: Vec<Span> = Vec::new();
    csg.spans(ray, &mut spans);
    spans
        .iter()
        .flat_map(|s| [s.enter, s.exit])
        .find(|e| e.t > 0.0 && e.t < t_max)
}

#[test]
fn the_reported_boundary_is_the_full_combinations() {
    let mut rng = Rng::new(11, 3);
    for (name, csg) in trees() {
        let (mut hits, mut negated) = (0, 0);
        for i in 0..20_000 {
            // Rays from outside towards random points of the box, and from inside it.
            let target =
                Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * 3.0 - Vec3::splat(1.5);
            let u = Vec2::new(rng.next_f32(), rng.next_f32());
            let (origin, dir) = if i % 4 == 0 {
                (target, uniform_sphere(u))
            } else {
                let o = target + uniform_sphere(u) * 6.0;
                (o, (target - o) * 0.37)
            };
            let ray = Ray::new(origin, dir);
            let t_max = if i % 3 == 0 {
                1.0 + 20.0 * rng.next_f32()
            } else {
                f32::INFINITY
            };
            let want = reference(&csg, &ray, t_max);
            let got = csg.intersect(&ray, t_max);
            assert_eq!(
                csg.occluded(&ray, t_max),
                want.is_some(),
                "{name}: occluded, ray {ray:?}"
            );
            let (Some(w), Some(g)) = (want, got) else {
                assert_eq!(
                    want.is_some(),
                    got.is_some(),
                    "{name}: hit or not, ray {ray:?}"
                );
                continue;
            };
            hits += 1;
            let bits = |v: Vec3| v.to_array().map(f32::to_bits);
            assert_eq!(g.t.to_bits(), w.t.to_bits(), "{name}: t, ray {ray:?}");
            assert_eq!(
                bits(g.normal),
                bits(w.normal),
                "{name}: normal, ray {ray:?}"
            );
            assert_eq!(g.uv.x.to_bits(), w.uv.x.to_bits(), "{name}: u, ray {ray:?}");
            assert_eq!(g.uv.y.to_bits(), w.uv.y.to_bits(), "{name}: v, ray {ray:?}");
            assert_eq!(
                (g.prim, g.leaf),
                (w.prim, w.leaf),
                "{name}: prim, leaf, ray {ray:?}"
            );
            // A normal against the ray's way out of a solid it is leaving, or into one
            // it enters from inside a subtracted part: counts subtracted faces met.
            if g.normal.dot(dir) > 0.0 && g.t > 0.0 {
                negated += 1;
            }
        }
        assert!(hits > 2_000, "{name}: only {hits} hits");
        assert!(negated > 100, "{name}: {negated} exits");
    }
}
