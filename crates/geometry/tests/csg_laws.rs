//! CSG by spans: set laws per ray (proptest over random solids and rays), normals of
//! subtracted faces, the coincident-surface rule, leaf numbering, union versus merge,
//! the Steinmetz solid, bounds and bad operands.

use glam::{Affine3A, Quat, Vec3};
use irradia_core::Ray;
use irradia_geometry::csg::{combine, combine_walk, complement, Csg, CsgOp, CsgOperand};
use irradia_geometry::shapes::{Cuboid, Plane, Polygon, Polyhedron, Quadric, ShapeError, Sphere};
use irradia_geometry::Boundary;
use irradia_geometry::{Instance, Shape, Span};
use proptest::prelude::*;
use std::sync::Arc;

fn leaf(s: impl Shape + 'static) -> CsgOperand {
    CsgOperand::shape(Arc::new(s), Affine3A::IDENTITY)
}

fn v3() -> impl Strategy<Value = Vec3> {
    (-2.0f32..2.0, -2.0f32..2.0, -2.0f32..2.0).prop_map(|(x, y, z)| Vec3::new(x, y, z))
}

/// A random placed solid: sphere, box, capped cylinder, cone or polyhedron, possibly
/// rotated and scaled.
fn solid() -> impl Strategy<Value = Instance> {
    let shape = prop_oneof![
        (v3(), 0.2f32..1.5).prop_map(|(c, r)| Arc::new(Sphere::new(c, r)) as Arc<dyn Shape>),
        (v3(), v3()).prop_filter_map("flat box", |(a, b)| {
            Cuboid::new(a, b)
                .ok()
                .filter(|_| (a - b).abs().min_element() > 0.05)
                .map(|c| Arc::new(c) as Arc<dyn Shape>)
        }),
        (v3(), v3(), 0.1f32..1.0).prop_filter_map("short cylinder", |(a, b, r)| {
            ((a - b).length() > 0.05)
                .then(|| Arc::new(Quadric::capped_cylinder(a, b, r).unwrap()) as Arc<dyn Shape>)
        }),
        (v3(), v3(), 0.0f32..1.0, 0.1f32..1.0).prop_filter_map("short cone", |(a, b, r0, r1)| {
            ((a - b).length() > 0.05)
                .then(|| Arc::new(Quadric::capped_cone(a, r0, b, r1).unwrap()) as Arc<dyn Shape>)
        }),
        prop::sample::select(vec![4u32, 6, 8, 12, 20])
            .prop_map(|f| Arc::new(Polyhedron::platonic(f).unwrap()) as Arc<dyn Shape>),
    ];
    (shape, v3(), -3.0f32..3.0, 0.5f32..1.5).prop_map(|(s, t, angle, scale)| {
        let m = Affine3A::from_scale_rotation_translation(
            Vec3::new(scale, 1.0, 1.0 / scale),
            Quat::from_axis_angle(Vec3::new(1.0, 2.0, 3.0).normalize(), angle),
            t * 0.5,
        );
        Instance::new(s, m)
    })
}

fn ray() -> impl Strategy<Value = Ray> {
    (v3(), v3()).prop_filter_map("zero direction", |(o, target)| {
        let d = target - o * 3.0;
        (d.length() > 1e-3).then(|| Ray::new(o * 3.0, d.normalize()))
    })
}

fn spans_of(i: &Instance, r: &Ray) -> Vec<Span> {
    let mut v = Vec::new();
    i.spans(r, &mut v);
    v
}

fn comb(op: CsgOp, a: &[Span], b: &[Span]) -> Vec<Span> {
    let mut v = Vec::new();
    combine(op, a, b, &mut v);
    v
}

fn ts(s: &[Span]) -> Vec<(f32, f32)> {
    s.iter().map(|s| (s.enter.t, s.exit.t)).collect()
}

fn node(op: CsgOp, a: &Instance, b: &Instance) -> Csg {
    Csg::new(op, vec![a.clone().into(), b.clone().into()]).unwrap()
}

fn well_formed(s: &[Span]) -> bool {
    s.iter().all(|x| x.enter.t <= x.exit.t) && s.windows(2).all(|w| w[0].exit.t < w[1].enter.t)
}

/// A span with ends on a coarse grid (so ties are common) and a distinct normal and
/// leaf per operand, to see whose boundary wins.
fn grid_span(leaf: u32) -> impl Strategy<Value = Span> {
    (0i32..6, 0i32..6).prop_map(move |(a, b)| {
        let (a, b) = (a.min(b) as f32, a.max(b) as f32);
        let mut enter = Boundary::new(
            a,
            Vec3::new(-1.0, leaf as f32, 0.0).normalize(),
            glam::Vec2::ZERO,
        );
        let mut exit = Boundary::new(
            b,
            Vec3::new(1.0, leaf as f32, 0.0).normalize(),
            glam::Vec2::ZERO,
        );
        enter.leaf = leaf;
        exit.leaf = leaf;
        Span { enter, exit }
    })
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 400, ..ProptestConfig::default() })]

    #[test]
    fn single_span_fast_path_equals_the_general_walk(a in grid_span(0), b in grid_span(1)) {
        for op in [CsgOp::Union, CsgOp::Intersection, CsgOp::Difference, CsgOp::Merge] {
            let (mut fast, mut walk) = (Vec::new(), Vec::new());
            combine(op, &[a], &[b], &mut fast);
            combine_walk(op, &[a], &[b], &mut walk);
            prop_assert_eq!(&fast, &walk, "{:?} of {:?} and {:?}", op, a, b);
        }
    }

    #[test]
    fn union_and_intersection_commute(a in solid(), b in solid(), r in ray()) {
        let (sa, sb) = (spans_of(&a, &r), spans_of(&b, &r));
        for op in [CsgOp::Union, CsgOp::Intersection, CsgOp::Merge] {
            let ab = comb(op, &sa, &sb);
            prop_assert!(well_formed(&ab));
            prop_assert_eq!(ts(&ab), ts(&comb(op, &sb, &sa)));
            // The same through CSG nodes (bounds tests and windows included).
            let mut n1 = Vec::new();
            node(op, &a, &b).spans(&r, &mut n1);
            let mut n2 = Vec::new();
            node(op, &b, &a).spans(&r, &mut n2);
            prop_assert_eq!(ts(&n1), ts(&ab));
            prop_assert_eq!(ts(&n2), ts(&ab));
        }
    }

    #[test]
    fn idempotence_and_self_difference(a in solid(), r in ray()) {
        let sa = spans_of(&a, &r);
        prop_assert_eq!(&comb(CsgOp::Intersection, &sa, &sa), &sa);
        prop_assert_eq!(&comb(CsgOp::Union, &sa, &sa), &sa);
        prop_assert!(comb(CsgOp::Difference, &sa, &sa).is_empty());
        let mut n = Vec::new();
        node(CsgOp::Difference, &a, &a).spans(&r, &mut n);
        prop_assert!(n.is_empty());
        prop_assert!(node(CsgOp::Difference, &a, &a).intersect(&r, f32::INFINITY).is_none());
    }

    #[test]
    fn difference_is_intersection_with_the_complement(a in solid(), b in solid(), r in ray()) {
        let (sa, sb) = (spans_of(&a, &r), spans_of(&b, &r));
        let mut not_b = Vec::new();
        complement(&sb, &mut not_b);
        let d = comb(CsgOp::Difference, &sa, &sb);
        prop_assert!(well_formed(&d));
        // Same boundaries, same (flipped) normals.
        prop_assert_eq!(&d, &comb(CsgOp::Intersection, &sa, &not_b));
        // De Morgan: ¬(A ∪ B) = ¬A ∩ ¬B.
        let mut not_a = Vec::new();
        complement(&sa, &mut not_a);
        let mut lhs = Vec::new();
        complement(&comb(CsgOp::Union, &sa, &sb), &mut lhs);
        prop_assert_eq!(ts(&lhs), ts(&comb(CsgOp::Intersection, &not_a, &not_b)));
    }

    #[test]
    fn associativity_and_nearest_hit(a in solid(), b in solid(), c in solid(), r in ray()) {
        let (sa, sb, sc) = (spans_of(&a, &r), spans_of(&b, &r), spans_of(&c, &r));
        // Leaf numbers as the node gives them: operand i's boundaries are leaf i.
        let numbered = |s: &[Span], leaf: u32| -> Vec<Span> {
            s.iter().map(|x| { let mut x = *x; x.enter.leaf = leaf; x.exit.leaf = leaf; x }).collect()
        };
        let (sa, sb, sc) = (numbered(&sa, 0), numbered(&sb, 1), numbered(&sc, 2));
        for op in [CsgOp::Union, CsgOp::Intersection] {
            let left = comb(op, &comb(op, &sa, &sb), &sc);
            let right = comb(op, &sa, &comb(op, &sb, &sc));
            prop_assert_eq!(ts(&left), ts(&right));
        }
        // A three-operand difference node equals A - B - C by spans, and its hit is the
        // first boundary at t > 0.
        let n = Csg::difference(vec![a.into(), b.into(), c.into()]).unwrap();
        let expect = comb(CsgOp::Difference, &comb(CsgOp::Difference, &sa, &sb), &sc);
        let mut got = Vec::new();
        n.spans(&r, &mut got);
        prop_assert_eq!(ts(&got), ts(&expect));
        let first = expect.iter().flat_map(|s| [s.enter, s.exit]).find(|e| e.t > 0.0);
        let hit = n.intersect(&r, f32::INFINITY);
        prop_assert_eq!(hit.map(|h| h.t), first.map(|e| e.t));
        prop_assert_eq!(n.occluded(&r, f32::INFINITY), first.is_some());
        if let (Some(h), Some(e)) = (hit, first) {
            prop_assert_eq!(h.normal, e.normal);
            prop_assert_eq!(h.leaf, e.leaf);
        }
    }
}

#[test]
fn subtracted_faces_have_flipped_normals() {
    let d = Csg::difference(vec![
        leaf(Cuboid::new(Vec3::splat(-1.0), Vec3::splat(1.0)).unwrap()),
        leaf(Sphere::new(Vec3::ZERO, 0.8)),
    ])
    .unwrap();
    let r = Ray::new(Vec3::new(0.0, 0.0, -5.0), Vec3::Z);
    let mut s = Vec::new();
    d.spans(&r, &mut s);
    assert_eq!(ts(&s), vec![(4.0, 4.2), (5.8, 6.0)]);
    assert_eq!(s[0].enter.normal, -Vec3::Z);
    // The cavity's walls face its centre: out of the remaining solid.
    assert!(
        (s[0].exit.normal - Vec3::Z).length() < 1e-6,
        "{:?}",
        s[0].exit.normal
    );
    assert!((s[1].enter.normal + Vec3::Z).length() < 1e-6);
    assert_eq!((s[0].exit.leaf, s[1].enter.leaf, s[1].exit.leaf), (1, 1, 0));
    // From inside the cavity the first hit is the far wall, facing back at the ray.
    let h = d
        .intersect(&Ray::new(Vec3::ZERO, Vec3::Z), f32::INFINITY)
        .unwrap();
    assert!((h.t - 0.8).abs() < 1e-6 && (h.normal + Vec3::Z).length() < 1e-6 && h.leaf == 1);
}

#[test]
fn coincident_surfaces_follow_the_documented_rule() {
    let cube = |lo: Vec3, hi: Vec3| Arc::new(Cuboid::new(lo, hi).unwrap()) as Arc<dyn Shape>;
    let a = cube(Vec3::ZERO, Vec3::splat(1.0));
    let b = cube(Vec3::new(1.0, 0.0, 0.0), Vec3::new(2.0, 1.0, 1.0));
    let along_x = Ray::new(Vec3::new(-1.0, 0.5, 0.5), Vec3::X);
    // Touching face to face: the union has no inner face.
    for op in [CsgOp::Union, CsgOp::Merge] {
        let u = Csg::new(
            op,
            vec![
                Instance::untransformed(a.clone()).into(),
                Instance::untransformed(b.clone()).into(),
            ],
        )
        .unwrap();
        let mut s = Vec::new();
        u.spans(&along_x, &mut s);
        assert_eq!(ts(&s), vec![(1.0, 3.0)]);
    }
    // Their intersection is empty (only the shared face, which has no volume).
    let i = Csg::intersection(vec![
        Instance::untransformed(a.clone()).into(),
        Instance::untransformed(b.clone()).into(),
    ])
    .unwrap();
    let mut s = Vec::new();
    i.spans(&along_x, &mut s);
    assert!(s.is_empty());
    // A ∩ A and A merged with A: the left operand's surface wins (leaf 0).
    for op in [CsgOp::Intersection, CsgOp::Merge] {
        let aa = Csg::new(
            op,
            vec![
                Instance::untransformed(a.clone()).into(),
                Instance::untransformed(a.clone()).into(),
            ],
        )
        .unwrap();
        let h = aa.intersect(&along_x, f32::INFINITY).unwrap();
        assert_eq!((h.t, h.leaf), (1.0, 0), "{op:?}");
        let mut s = Vec::new();
        aa.spans(&along_x, &mut s);
        assert_eq!((s[0].enter.leaf, s[0].exit.leaf), (0, 0));
    }
    // A − B where B shares A's far face: the cut face is B's, flipped.
    let big = cube(Vec3::ZERO, Vec3::new(2.0, 1.0, 1.0));
    let d = Csg::difference(vec![
        Instance::untransformed(big).into(),
        Instance::untransformed(b.clone()).into(),
    ])
    .unwrap();
    let mut s = Vec::new();
    d.spans(&along_x, &mut s);
    assert_eq!(ts(&s), vec![(1.0, 2.0)]);
    assert_eq!((s[0].exit.leaf, s[0].exit.normal), (1, Vec3::X));
    // Rays along the shared face plane: deterministic (same answer both orders).
    let grazing = Ray::new(Vec3::new(1.0, -1.0, 0.5), Vec3::Y);
    let u1 = Csg::union(vec![
        Instance::untransformed(a.clone()).into(),
        Instance::untransformed(b.clone()).into(),
    ])
    .unwrap();
    let u2 = Csg::union(vec![
        Instance::untransformed(b).into(),
        Instance::untransformed(a).into(),
    ])
    .unwrap();
    let (mut s1, mut s2) = (Vec::new(), Vec::new());
    u1.spans(&grazing, &mut s1);
    u2.spans(&grazing, &mut s2);
    assert_eq!(ts(&s1), ts(&s2));
}

fn seven_spheres() -> Vec<CsgOperand> {
    let mut ops = vec![leaf(Sphere::new(Vec3::ZERO, 0.7))];
    for axis in [Vec3::X, Vec3::Y, Vec3::Z] {
        for s in [-0.75, 0.75] {
            ops.push(leaf(Sphere::new(axis * s, 0.45)));
        }
    }
    ops
}

#[test]
fn union_shows_inner_surfaces_and_merge_does_not() {
    let union = Csg::union(seven_spheres()).unwrap();
    let merge = Csg::merge(seven_spheres()).unwrap();
    let r = Ray::new(Vec3::ZERO, Vec3::X);
    let hu = union.intersect(&r, f32::INFINITY).unwrap();
    let hm = merge.intersect(&r, f32::INFINITY).unwrap();
    assert!((hu.t - 0.3).abs() < 1e-6 && hu.leaf == 2, "{hu:?}");
    assert!((hm.t - 1.2).abs() < 1e-6 && hm.leaf == 2, "{hm:?}");
    // Same solid: identical spans; from outside the same first hit.
    let from_outside = Ray::new(Vec3::new(-3.0, 0.1, 0.05), Vec3::X);
    let (mut su, mut sm) = (Vec::new(), Vec::new());
    union.spans(&from_outside, &mut su);
    merge.spans(&from_outside, &mut sm);
    assert_eq!(su, sm);
    assert_eq!(su.len(), 1);
    assert_eq!(
        union.intersect(&from_outside, 10.0).unwrap().t,
        merge.intersect(&from_outside, 10.0).unwrap().t
    );
    assert_eq!(union.leaf_count(), 7);
}

#[test]
fn leaves_are_numbered_depth_first_with_paths() {
    let inner = Csg::union(vec![
        leaf(Sphere::new(Vec3::new(-1.0, 0.0, 0.0), 0.5)),
        leaf(Sphere::new(Vec3::new(1.0, 0.0, 0.0), 0.5)),
    ])
    .unwrap();
    let tree = Csg::difference(vec![
        leaf(Cuboid::new(Vec3::new(-3.0, -1.0, -1.0), Vec3::new(3.0, 1.0, 1.0)).unwrap()),
        CsgOperand::node(inner, Affine3A::from_translation(Vec3::new(0.0, 0.0, 1.0))),
        leaf(Sphere::new(Vec3::new(0.0, 0.0, 1.0), 0.5)),
    ])
    .unwrap();
    assert_eq!(tree.leaf_count(), 4);
    assert_eq!(
        tree.leaf_paths(),
        &[vec![0], vec![1, 0], vec![1, 1], vec![2]]
    );
    let down = |x: f32| {
        tree.intersect(&Ray::new(Vec3::new(x, 0.0, 5.0), -Vec3::Z), f32::INFINITY)
            .unwrap()
    };
    // Above each cavity the first hit is the cavity's floor (its leaf); elsewhere the box.
    assert_eq!(down(-1.0).leaf, 1);
    assert_eq!(down(1.0).leaf, 2);
    assert_eq!(down(0.0).leaf, 3);
    assert_eq!(down(2.5).leaf, 0);
    assert!((down(2.5).t - 4.0).abs() < 1e-6);
    // A cavity floor: a sphere centred on the top face, hit from inside the sphere.
    let h = down(-1.0);
    assert!((h.t - 4.5).abs() < 1e-5 && (h.normal - Vec3::Z).length() < 1e-5);
}

#[test]
fn steinmetz_hits_lie_inside_all_three_cylinders() {
    let s = Csg::intersection(vec![
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
    let b = s.bounds();
    assert!(
        b.min.cmpge(Vec3::splat(-1.0 - 1e-5)).all() && b.max.cmple(Vec3::splat(1.0 + 1e-5)).all(),
        "{b:?}"
    );
    let mut rng = irradia_core::Rng::new(9, 9);
    let mut hits = 0;
    for _ in 0..20000 {
        let d =
            irradia_core::sampling::uniform_sphere(glam::Vec2::new(rng.next_f32(), rng.next_f32()));
        let target = Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * 2.0 - 1.0;
        let r = Ray::new(target - 4.0 * d, d);
        let Some(h) = s.intersect(&r, f32::INFINITY) else {
            continue;
        };
        hits += 1;
        let p = h.point;
        let tol = 1e-5;
        let rho = [
            p.y * p.y + p.z * p.z,
            p.x * p.x + p.z * p.z,
            p.x * p.x + p.y * p.y,
        ];
        assert!(
            rho.iter().all(|&q| q <= 1.0 + tol),
            "{p:?} outside a cylinder"
        );
        // On the surface of the cylinder whose leaf it reports.
        assert!(
            (rho[h.leaf as usize] - 1.0).abs() < tol,
            "{p:?} not on cylinder {}",
            h.leaf
        );
        // The normal is that cylinder's radial direction.
        let mut radial = p;
        radial[h.leaf as usize] = 0.0;
        assert!((h.normal - radial.normalize()).length() < 1e-4);
        assert!(s.occluded(&r, f32::INFINITY));
    }
    assert!(hits > 5000);
}

#[test]
fn half_spaces_cut_solids() {
    // A sphere cut by the plane y = 0 (keep below): the cap faces up.
    let hemi = Csg::intersection(vec![
        leaf(Sphere::new(Vec3::ZERO, 1.0)),
        leaf(Plane::new(Vec3::Y, 0.0).unwrap()),
    ])
    .unwrap();
    let h = hemi
        .intersect(&Ray::new(Vec3::new(0.2, 5.0, 0.1), -Vec3::Y), f32::INFINITY)
        .unwrap();
    assert!((h.t - 5.0).abs() < 1e-6 && h.normal == Vec3::Y && h.leaf == 1);
    assert!(hemi.bounds().max.y <= 1e-6 && hemi.bounds().min.y >= -1.0 - 1e-5);
}

#[test]
fn bounds_follow_the_operation() {
    let a = Instance::untransformed(Arc::new(Sphere::new(Vec3::ZERO, 1.0)));
    let b = Instance::untransformed(Arc::new(Sphere::new(Vec3::new(1.5, 0.0, 0.0), 1.0)));
    let u = node(CsgOp::Union, &a, &b).bounds();
    let i = node(CsgOp::Intersection, &a, &b).bounds();
    let d = node(CsgOp::Difference, &a, &b).bounds();
    assert_eq!((u.min.x, u.max.x), (-1.0, 2.5));
    assert_eq!((i.min.x, i.max.x), (0.5, 1.0));
    assert_eq!((d.min.x, d.max.x), (-1.0, 1.0));
}

#[test]
fn bad_operands_are_errors() {
    assert_eq!(
        Csg::union(vec![]).unwrap_err(),
        ShapeError::NoOperands { op: "union" }
    );
    let square =
        Polygon::new(vec![Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::Y]).unwrap();
    let err = Csg::difference(vec![leaf(Sphere::new(Vec3::ZERO, 1.0)), leaf(square)]).unwrap_err();
    assert_eq!(err, ShapeError::NotSolid { kind: "polygon" });
    assert!(err.to_string().contains("closed solid"));
    let tube = Quadric::cylinder(1.0)
        .unwrap()
        .clipped_by_box(Vec3::splat(-1.0), Vec3::splat(1.0))
        .unwrap()
        .open();
    assert!(Csg::merge(vec![leaf(tube)]).is_err());
}

#[test]
fn degenerate_rays_neither_panic_nor_hang() {
    let shapes: Vec<Arc<dyn Shape>> = vec![
        Arc::new(Csg::merge(seven_spheres()).unwrap()),
        Arc::new(Csg::union(seven_spheres()).unwrap()),
        Arc::new(
            Csg::difference(vec![
                leaf(Cuboid::new(Vec3::splat(-1.0), Vec3::splat(1.0)).unwrap()),
                leaf(Sphere::new(Vec3::ZERO, 1.3)),
                leaf(Plane::new(Vec3::new(1.0, 1.0, 0.0), 0.5).unwrap()),
                leaf(Polyhedron::platonic(12).unwrap()),
                leaf(Quadric::capped_cone(Vec3::ZERO, 0.5, Vec3::Y, 0.2).unwrap()),
            ])
            .unwrap(),
        ),
        Arc::new(
            Polygon::new(vec![
                Vec3::ZERO,
                Vec3::X,
                Vec3::new(1.0, 1.0, 0.0),
                Vec3::new(0.5, 0.2, 0.0),
                Vec3::Y,
            ])
            .unwrap(),
        ),
        Arc::new(irradia_geometry::shapes::Disk::new(Vec3::ZERO, Vec3::Z, 1.0).unwrap()),
        Arc::new(
            Quadric::cylinder(1.0)
                .unwrap()
                .clipped_by_box(Vec3::splat(-1.0), Vec3::splat(1.0))
                .unwrap()
                .open(),
        ),
        Arc::new(Quadric::hyperboloid_two_sheets(1.0, 1.0).unwrap()),
        Arc::new(Quadric::new([1.0, -1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0]).unwrap()),
    ];
    let rays = [
        Ray::new(Vec3::ZERO, Vec3::ZERO),
        Ray::new(Vec3::new(3.0, 0.0, 0.0), Vec3::ZERO),
        Ray::new(Vec3::new(f32::NAN, 0.0, 0.0), Vec3::X),
        Ray::new(Vec3::ZERO, Vec3::new(f32::NAN, 1.0, 0.0)),
        Ray::new(Vec3::ZERO, Vec3::new(f32::INFINITY, 1.0, 0.0)),
    ];
    for s in &shapes {
        for r in &rays {
            let _ = s.intersect(r, f32::INFINITY);
            let _ = s.occluded(r, f32::INFINITY);
            let mut v = Vec::new();
            s.spans(r, &mut v);
        }
    }
}
