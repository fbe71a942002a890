//! CSG by spans: set laws per ray (proptest over random solids and rays), normals of
//! subtracted faces, the coincident-surface rule, leaf numbering, union versus merge,
//! the Steinmetz solid, bounds and bad operands; and a point-membership oracle that
//! checks spans, nearest hits and normals of random CSG trees against independent
//! inside tests of their leaves.

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

// ---------------------------------------------------------------------------------
// Point-membership oracle. The laws above compare combiner calls with each other, so
// swapping union and intersection everywhere would still pass them. Here every leaf of
// a random CSG tree is also described in the test by its own implicit equation
// (|p - c| < r, slabs, distance to an axis, half-spaces ...) and placed by the same
// transforms in f64; a point is inside the tree when the Boolean formula of the tree,
// evaluated on those independent inside tests, says so. For random rays, points sampled
// along each ray must be inside the tree's combined spans exactly when the oracle says
// so (away from span ends and leaf surfaces, where rounding decides), and the nearest
// hit must be the first span boundary, lie on the leaf it names, and carry a normal
// that points out of the combined solid (into the cavity for subtracted faces).

use glam::{DAffine3, DMat3, DVec3};
use irradia_geometry::shapes::Torus;

/// One primitive, described independently of the shapes' ray code (object space).
#[derive(Clone, Debug)]
enum Prim {
    Sphere {
        c: DVec3,
        r: f64,
    },
    Cuboid {
        lo: DVec3,
        hi: DVec3,
    },
    /// Capped cone (a cylinder when the radii are equal) from `a` to `b`.
    Cone {
        a: DVec3,
        b: DVec3,
        ra: f64,
        rb: f64,
    },
    /// Ring torus around the y axis.
    Torus {
        major: f64,
        minor: f64,
    },
    /// The half-space `n · p <= d` (`n` unit).
    HalfSpace {
        n: DVec3,
        d: f64,
    },
    /// The intersection of half-spaces `n · p <= d` (`n` unit).
    Polyhedron {
        planes: Vec<(DVec3, f64)>,
    },
}

impl Prim {
    /// Signed distance to the surface (for cones and polyhedra the distance to the
    /// nearest face's infinite extension, a lower bound) and the outward normal of the
    /// nearest face, unnormalised.
    fn eval(&self, p: DVec3) -> (f64, DVec3) {
        match self {
            Prim::Sphere { c, r } => ((p - *c).length() - r, p - *c),
            Prim::Cuboid { lo, hi } => {
                // Inside: the nearest face; outside: the distance to the box.
                let below = *lo - p;
                let above = p - *hi;
                let out = below.max(above);
                let inside = out.max_element() < 0.0;
                let mut axis = 0;
                for i in 1..3 {
                    if out[i] > out[axis] {
                        axis = i;
                    }
                }
                let mut n = DVec3::ZERO;
                n[axis] = if above[axis] > below[axis] { 1.0 } else { -1.0 };
                let dist = if inside {
                    out.max_element()
                } else {
                    out.max(DVec3::ZERO).length()
                };
                (dist, n)
            }
            Prim::Cone { a, b, ra, rb } => {
                let axis = *b - *a;
                let h = axis.length();
                let u = axis / h;
                let q = p - *a;
                let s = q.dot(u);
                let radial = q - u * s;
                let rho = radial.length();
                let k = (rb - ra) / h;
                let side = (rho - (ra + k * s)) / (1.0 + k * k).sqrt();
                let e = if rho > 0.0 { radial / rho } else { DVec3::X };
                // The gradient of the nearest of the three surfaces.
                let (d0, d1) = (s.abs(), (s - h).abs());
                if side.abs() <= d0.min(d1) {
                    (side, e - u * k)
                } else if d0 < d1 {
                    (-s, -u)
                } else {
                    (s - h, u)
                }
            }
            Prim::Torus { major, minor } => {
                let rxz = (p.x * p.x + p.z * p.z).sqrt();
                let ring = if rxz > 0.0 {
                    DVec3::new(p.x, 0.0, p.z) * (major / rxz)
                } else {
                    DVec3::new(*major, 0.0, 0.0)
                };
                let q = p - ring;
                (q.length() - minor, q)
            }
            Prim::HalfSpace { n, d } => (n.dot(p) - d, *n),
            Prim::Polyhedron { planes } => {
                let (mut best, mut n) = (f64::NEG_INFINITY, DVec3::ZERO);
                for (pn, pd) in planes {
                    let f = pn.dot(p) - pd;
                    if f > best {
                        best = f;
                        n = *pn;
                    }
                }
                (best, n)
            }
        }
    }

    /// Distance (lower bound) from `p` to the surface.
    fn margin(&self, p: DVec3) -> f64 {
        match self {
            Prim::Polyhedron { planes } => planes
                .iter()
                .map(|(n, d)| (n.dot(p) - d).abs())
                .fold(f64::INFINITY, f64::min),
            _ => self.eval(p).0.abs(),
        }
    }

    fn inside(&self, p: DVec3) -> bool {
        match self {
            Prim::Sphere { c, r } => (p - *c).length_squared() < r * r,
            Prim::Cuboid { lo, hi } => p.cmpgt(*lo).all() && p.cmplt(*hi).all(),
            Prim::Cone { a, b, ra, rb } => {
                let axis = *b - *a;
                let h = axis.length();
                let u = axis / h;
                let q = p - *a;
                let s = q.dot(u);
                let rho = (q - u * s).length();
                s > 0.0 && s < h && rho < ra + (rb - ra) * s / h
            }
            Prim::Torus { major, minor } => {
                let rxz = (p.x * p.x + p.z * p.z).sqrt();
                (rxz - major).powi(2) + p.y * p.y < minor * minor
            }
            Prim::HalfSpace { n, d } => n.dot(p) < *d,
            Prim::Polyhedron { planes } => planes.iter().all(|(n, d)| n.dot(p) < *d),
        }
    }

    /// A box (object space) that holds the solid's part worth aiming at.
    fn aim_box(&self) -> (DVec3, DVec3) {
        match self {
            Prim::Sphere { c, r } => (*c - *r, *c + *r),
            Prim::Cuboid { lo, hi } => (*lo, *hi),
            Prim::Cone { a, b, ra, rb } => {
                let r = ra.max(*rb);
                (a.min(*b) - r, a.max(*b) + r)
            }
            Prim::Torus { major, minor } => {
                let e = DVec3::new(major + minor, *minor, major + minor);
                (-e, e)
            }
            Prim::HalfSpace { .. } => (DVec3::splat(-2.0), DVec3::splat(2.0)),
            Prim::Polyhedron { .. } => (DVec3::splat(-2.0), DVec3::splat(2.0)),
        }
    }
}

fn daffine(a: &Affine3A) -> DAffine3 {
    DAffine3 {
        matrix3: DMat3::from_cols(
            a.matrix3.x_axis.as_dvec3(),
            a.matrix3.y_axis.as_dvec3(),
            a.matrix3.z_axis.as_dvec3(),
        ),
        translation: a.translation.as_dvec3(),
    }
}

/// A leaf as the oracle sees it: the primitive and its world-to-object map (f64).
struct OracleLeaf {
    prim: Prim,
    to_object: DAffine3,
    to_world: DAffine3,
    /// Largest stretch of `to_object` (to turn object distances into world ones).
    stretch: f64,
}

impl OracleLeaf {
    fn inside(&self, p: DVec3) -> bool {
        self.prim.inside(self.to_object.transform_point3(p))
    }
    /// Lower bound on the world distance from `p` to this leaf's surface.
    fn margin(&self, p: DVec3) -> f64 {
        self.prim.margin(self.to_object.transform_point3(p)) / self.stretch
    }
    /// Outward unit normal of the leaf's surface nearest `p` (world space).
    fn normal(&self, p: DVec3) -> DVec3 {
        let g = self.prim.eval(self.to_object.transform_point3(p)).1;
        (self.to_object.matrix3.transpose() * g).normalize()
    }
}

/// The tree's Boolean formula over leaf indices (depth-first, as `Hit::leaf`).
#[derive(Clone, Debug)]
enum Formula {
    Leaf(usize),
    Node(CsgOp, Vec<Formula>),
}

impl Formula {
    /// Whether the point with leaf memberships `inside` is in the tree, with every
    /// operation first renamed by `label` (the identity for the real oracle).
    fn eval(&self, inside: &[bool], label: &dyn Fn(CsgOp) -> CsgOp) -> bool {
        match self {
            Formula::Leaf(i) => inside[*i],
            Formula::Node(op, children) => {
                let mut v = children.iter().map(|c| c.eval(inside, label));
                let first = v.next().unwrap();
                let op = label(*op);
                v.fold(first, |acc, b| match op {
                    CsgOp::Union | CsgOp::Merge => acc || b,
                    CsgOp::Intersection => acc && b,
                    CsgOp::Difference => acc && !b,
                })
            }
        }
    }
}

struct Oracle {
    leaves: Vec<OracleLeaf>,
    formula: Formula,
}

impl Oracle {
    fn memberships(&self, p: DVec3) -> Vec<bool> {
        self.leaves.iter().map(|l| l.inside(p)).collect()
    }
    fn inside(&self, p: DVec3) -> bool {
        self.formula.eval(&self.memberships(p), &|op| op)
    }
    fn margin(&self, p: DVec3) -> f64 {
        self.leaves
            .iter()
            .map(|l| l.margin(p))
            .fold(f64::INFINITY, f64::min)
    }
}

fn uniform(rng: &mut irradia_core::Rng, lo: f64, hi: f64) -> f64 {
    lo + (hi - lo) * rng.next_f64()
}

fn rand_v3(rng: &mut irradia_core::Rng, r: f64) -> DVec3 {
    DVec3::new(
        uniform(rng, -r, r),
        uniform(rng, -r, r),
        uniform(rng, -r, r),
    )
}

/// A random primitive: the library's shape and the test's own description of it.
fn random_prim(rng: &mut irradia_core::Rng) -> (Arc<dyn Shape>, Prim) {
    let f = |v: DVec3| v.as_vec3();
    loop {
        match rng.below(13) {
            0 | 1 => {
                let c = rand_v3(rng, 1.0).as_vec3();
                let r = uniform(rng, 0.3, 1.3) as f32;
                let prim = Prim::Sphere {
                    c: c.as_dvec3(),
                    r: r as f64,
                };
                return (Arc::new(Sphere::new(c, r)), prim);
            }
            2 | 3 => {
                let (a, b) = (rand_v3(rng, 1.3).as_vec3(), rand_v3(rng, 1.3).as_vec3());
                if (a - b).abs().min_element() < 0.2 {
                    continue;
                }
                let (lo, hi) = (a.min(b), a.max(b));
                let prim = Prim::Cuboid {
                    lo: lo.as_dvec3(),
                    hi: hi.as_dvec3(),
                };
                return (Arc::new(Cuboid::new(a, b).unwrap()), prim);
            }
            4 | 5 => {
                let (a, b) = (f(rand_v3(rng, 1.3)), f(rand_v3(rng, 1.3)));
                let r = uniform(rng, 0.2, 0.9) as f32;
                if (a - b).length() < 0.3 {
                    continue;
                }
                let prim = Prim::Cone {
                    a: a.as_dvec3(),
                    b: b.as_dvec3(),
                    ra: r as f64,
                    rb: r as f64,
                };
                let shape = Quadric::capped_cylinder(a, b, r).unwrap();
                return (Arc::new(shape), prim);
            }
            6 | 7 => {
                let (a, b) = (f(rand_v3(rng, 1.3)), f(rand_v3(rng, 1.3)));
                let ra = if rng.below(3) == 0 {
                    0.0
                } else {
                    uniform(rng, 0.2, 1.0) as f32
                };
                let rb = uniform(rng, 0.2, 1.0) as f32;
                if (a - b).length() < 0.3 {
                    continue;
                }
                let prim = Prim::Cone {
                    a: a.as_dvec3(),
                    b: b.as_dvec3(),
                    ra: ra as f64,
                    rb: rb as f64,
                };
                let shape = Quadric::capped_cone(a, ra, b, rb).unwrap();
                return (Arc::new(shape), prim);
            }
            8 | 9 => {
                let major = uniform(rng, 0.6, 1.3) as f32;
                let minor = uniform(rng, 0.15, 0.5) as f32;
                let prim = Prim::Torus {
                    major: major as f64,
                    minor: minor as f64,
                };
                return (Arc::new(Torus::new(major, minor)), prim);
            }
            10 | 11 => {
                // An octahedron-like solid: the eight octant planes at random distances.
                let mut planes = Vec::new();
                let mut given = Vec::new();
                for i in 0..8 {
                    let s = |b: u32| if i & (1 << b) == 0 { 1.0f32 } else { -1.0 };
                    let n = Vec3::new(s(0), s(1), s(2)).normalize();
                    let d = uniform(rng, 0.4, 1.1) as f32;
                    given.push((n, d));
                    planes.push((n.as_dvec3(), d as f64));
                }
                let prim = Prim::Polyhedron { planes };
                return (Arc::new(Polyhedron::new(&given).unwrap()), prim);
            }
            _ => {
                let n = irradia_core::sampling::uniform_sphere(rng.next_2d());
                let d = uniform(rng, -0.8, 0.8) as f32;
                let prim = Prim::HalfSpace {
                    n: n.as_dvec3(),
                    d: d as f64,
                };
                return (Arc::new(Plane::new(n, d).unwrap()), prim);
            }
        }
    }
}

/// A random placement: identity, or non-uniform scale, rotation and translation.
fn random_placement(rng: &mut irradia_core::Rng) -> Affine3A {
    if rng.below(3) == 0 {
        return Affine3A::IDENTITY;
    }
    let s = uniform(rng, 0.6, 1.5) as f32;
    let axis = irradia_core::sampling::uniform_sphere(rng.next_2d());
    let angle = uniform(rng, -3.0, 3.0) as f32;
    Affine3A::from_scale_rotation_translation(
        Vec3::new(s, 1.0, 1.0 / s),
        Quat::from_axis_angle(axis, angle),
        rand_v3(rng, 0.5).as_vec3(),
    )
}

/// A random tree of `depth` levels below a node of operation `op` (2 or 3 operands),
/// with its oracle leaves appended to `leaves` in depth-first order. `to_world` places
/// this node.
fn random_tree(
    rng: &mut irradia_core::Rng,
    op: CsgOp,
    depth: u32,
    to_world: DAffine3,
    leaves: &mut Vec<OracleLeaf>,
) -> (Csg, Formula) {
    let n = 2 + rng.below(2);
    let mut operands = Vec::new();
    let mut formulas = Vec::new();
    for _ in 0..n {
        let place = random_placement(rng);
        let child_to_world = to_world * daffine(&place);
        if depth > 0 && rng.below(2) == 0 {
            let child_op = [
                CsgOp::Union,
                CsgOp::Intersection,
                CsgOp::Difference,
                CsgOp::Merge,
            ][rng.below(4) as usize];
            let (csg, f) = random_tree(rng, child_op, depth - 1, child_to_world, leaves);
            operands.push(CsgOperand::node(csg, place));
            formulas.push(f);
        } else {
            let (shape, prim) = random_prim(rng);
            let to_object = child_to_world.inverse();
            let m = to_object.matrix3;
            let stretch =
                (m.x_axis.length_squared() + m.y_axis.length_squared() + m.z_axis.length_squared())
                    .sqrt();
            formulas.push(Formula::Leaf(leaves.len()));
            leaves.push(OracleLeaf {
                prim,
                to_object,
                to_world: child_to_world,
                stretch,
            });
            operands.push(CsgOperand::shape(shape, place));
        }
    }
    (Csg::new(op, operands).unwrap(), Formula::Node(op, formulas))
}

/// A point the oracle puts inside the tree, found by aiming at random leaves.
fn point_inside(rng: &mut irradia_core::Rng, o: &Oracle) -> Option<DVec3> {
    for _ in 0..40 {
        let l = &o.leaves[rng.below(o.leaves.len() as u32) as usize];
        let (lo, hi) = l.prim.aim_box();
        let q = lo + (hi - lo) * DVec3::new(rng.next_f64(), rng.next_f64(), rng.next_f64());
        let p = l.to_world.transform_point3(q);
        if o.inside(p) && o.margin(p) > 1e-3 {
            return Some(p);
        }
    }
    None
}

#[derive(Debug, Default)]
struct OracleTally {
    rays: u32,
    hit_rays: u32,
    samples: u32,
    inside: u32,
    mismatches: u32,
    /// Mismatches of the oracle with union and intersection swapped (power check).
    swapped_mismatches: u32,
    /// ... and with a difference read as an intersection (the complement forgotten).
    no_complement_mismatches: u32,
    nearest_checked: u32,
    normals_checked: u32,
    cavity_normals: u32,
}

/// Runs the oracle over `trees` random trees per root operation; returns the tallies
/// per root operation and a list of failure messages.
fn run_membership_oracle(trees: u32) -> (Vec<(CsgOp, OracleTally)>, Vec<String>) {
    let mut rng = irradia_core::Rng::new(2024, 11);
    let mut failures = Vec::new();
    let mut tallies = Vec::new();
    let swap = |op: CsgOp| match op {
        CsgOp::Union | CsgOp::Merge => CsgOp::Intersection,
        CsgOp::Intersection => CsgOp::Union,
        d => d,
    };
    let no_complement = |op: CsgOp| match op {
        CsgOp::Difference => CsgOp::Intersection,
        o => o,
    };
    for op in [
        CsgOp::Union,
        CsgOp::Intersection,
        CsgOp::Difference,
        CsgOp::Merge,
    ] {
        let mut tally = OracleTally::default();
        for tree_no in 0..trees {
            // A tree with something inside (intersections of random solids are often
            // empty), or the last one tried.
            let (csg, oracle) = {
                let mut tries = 0;
                loop {
                    let mut leaves = Vec::new();
                    let depth = rng.below(3);
                    let (csg, formula) =
                        random_tree(&mut rng, op, depth, DAffine3::IDENTITY, &mut leaves);
                    let oracle = Oracle { leaves, formula };
                    tries += 1;
                    if tries == 20 || point_inside(&mut rng, &oracle).is_some() {
                        break (csg, oracle);
                    }
                }
            };
            for ray_no in 0..8 {
                let dir = irradia_core::sampling::uniform_sphere(rng.next_2d()).as_dvec3();
                // Mostly rays through a point inside the tree; some at random; some
                // starting inside it.
                let target = match ray_no % 4 {
                    3 => None,
                    _ => point_inside(&mut rng, &oracle),
                }
                .unwrap_or_else(|| rand_v3(&mut rng, 1.5));
                let back = if ray_no % 4 == 2 {
                    uniform(&mut rng, 0.0, 1.0)
                } else {
                    6.0
                };
                let ray = Ray::new((target - dir * back).as_vec3(), dir.as_vec3());
                let (o, d) = (ray.origin.as_dvec3(), ray.dir.as_dvec3());
                let at = |t: f64| o + d * t;
                let mut spans = Vec::new();
                csg.spans(&ray, &mut spans);
                tally.rays += 1;
                if !spans.is_empty() {
                    tally.hit_rays += 1;
                }
                if !well_formed(&spans) {
                    failures.push(format!(
                        "{op:?} tree {tree_no}: spans out of order {spans:?}"
                    ));
                    continue;
                }
                let ends: Vec<f64> = spans
                    .iter()
                    .flat_map(|s| [s.enter.t as f64, s.exit.t as f64])
                    .collect();
                // Sample points: evenly over the scene, plus some inside every span.
                let mut samples: Vec<f64> = (0..64)
                    .map(|i| -10.0 + 20.0 * (i as f64 + rng.next_f64()) / 64.0)
                    .collect();
                for s in &spans {
                    let (a, b) = ((s.enter.t as f64).max(-12.0), (s.exit.t as f64).min(12.0));
                    if a < b {
                        samples.extend((0..4).map(|_| uniform(&mut rng, a, b)));
                    }
                }
                for t in samples {
                    if ends.iter().any(|e| (e - t).abs() < 1e-3) {
                        continue;
                    }
                    let p = at(t);
                    if oracle.margin(p) < 1e-5 {
                        continue;
                    }
                    let by_spans = spans
                        .iter()
                        .any(|s| (s.enter.t as f64) < t && t < s.exit.t as f64);
                    let member = oracle.memberships(p);
                    let by_oracle = oracle.formula.eval(&member, &|o| o);
                    tally.samples += 1;
                    tally.inside += by_oracle as u32;
                    if by_spans != by_oracle {
                        tally.mismatches += 1;
                        if failures.len() < 20 {
                            failures.push(format!(
                                "{op:?} tree {tree_no} ray {ray:?}: at t = {t} the spans say \
                                 inside = {by_spans}, the oracle {by_oracle} (leaves {member:?}, \
                                 formula {:?}, spans {:?})",
                                oracle.formula,
                                ts(&spans)
                            ));
                        }
                    }
                    tally.swapped_mismatches +=
                        (oracle.formula.eval(&member, &swap) != by_spans) as u32;
                    tally.no_complement_mismatches +=
                        (oracle.formula.eval(&member, &no_complement) != by_spans) as u32;
                }
                check_nearest_hit(
                    op,
                    tree_no,
                    &csg,
                    &oracle,
                    &ray,
                    &spans,
                    &mut tally,
                    &mut failures,
                );
            }
        }
        tallies.push((op, tally));
    }
    (tallies, failures)
}

/// The nearest hit is the first span boundary at t > 0; it lies on the leaf it names,
/// and its normal is that leaf's normal, pointing out of the combined solid.
#[allow(clippy::too_many_arguments)]
fn check_nearest_hit(
    op: CsgOp,
    tree_no: u32,
    csg: &Csg,
    oracle: &Oracle,
    ray: &Ray,
    spans: &[Span],
    tally: &mut OracleTally,
    failures: &mut Vec<String>,
) {
    let (o, d) = (ray.origin.as_dvec3(), ray.dir.as_dvec3());
    let mut fail = |m: String| {
        if failures.len() < 40 {
            failures.push(format!("{op:?} tree {tree_no} ray {ray:?}: {m}"));
        }
    };
    let hit = csg.intersect(ray, f32::INFINITY);
    if csg.occluded(ray, f32::INFINITY) != hit.is_some() {
        fail(format!("occluded disagrees with intersect {hit:?}"));
    }
    let first = spans
        .iter()
        .flat_map(|s| [(s.enter, true), (s.exit, false)])
        .find(|(b, _)| b.t > 0.0 && b.t < f32::INFINITY);
    let origin_outside = !oracle.inside(o) && oracle.margin(o) > 1e-4;
    // A union reports the nearest surface of any operand (inner ones too), which is the
    // first span entry only when the ray starts outside.
    if op == CsgOp::Union && !origin_outside {
        return;
    }
    let (h, (b, entering)) = match (hit, first) {
        (None, None) => return,
        (Some(h), Some(f)) => (h, f),
        (h, f) => {
            fail(format!("hit {h:?} but first span boundary {f:?}"));
            return;
        }
    };
    tally.nearest_checked += 1;
    let t_ok = if op == CsgOp::Union {
        (h.t - b.t).abs() <= 1e-4 * b.t.max(1.0)
    } else {
        h.t == b.t && h.normal == b.normal && h.leaf == b.leaf
    };
    if !t_ok {
        fail(format!("hit {h:?} is not the first span boundary {b:?}"));
        return;
    }
    if origin_outside && !entering {
        fail(format!("from outside, the first boundary {b:?} is an exit"));
    }
    let p = o + d * h.t as f64;
    let Some(leaf) = oracle.leaves.get(h.leaf as usize) else {
        fail(format!("leaf {} out of range", h.leaf));
        return;
    };
    if leaf.margin(p) > 1e-4 {
        fail(format!(
            "hit point {p:?} is {} from the surface of its leaf {}",
            leaf.margin(p),
            h.leaf
        ));
        return;
    }
    // Away from edges (other leaves' surfaces), compare the normal with the leaf's
    // own and with the inside test on both sides of the surface.
    let clear = oracle
        .leaves
        .iter()
        .enumerate()
        .all(|(i, l)| i == h.leaf as usize || l.margin(p) > 1e-2);
    if !clear {
        return;
    }
    let n = h.normal.as_dvec3();
    let g = leaf.normal(p);
    let cavity = n.dot(g) < 0.0;
    let expect = if cavity { -g } else { g };
    if (n - expect).length() > 1e-3 {
        fail(format!(
            "normal {n:?} is not ±{g:?}, the normal of leaf {}",
            h.leaf
        ));
        return;
    }
    let delta = 2e-3;
    // Where the leaf is thinner than that (near a cone's apex), both sides are outside.
    if leaf.margin(p - n * delta) < 0.5 * delta || leaf.margin(p + n * delta) < 0.5 * delta {
        return;
    }
    let (behind, in_front) = (oracle.inside(p - n * delta), oracle.inside(p + n * delta));
    if !behind || in_front {
        fail(format!(
            "normal {n:?} at {p:?} does not point out of the solid (inside behind: {behind}, \
             in front: {in_front}; cavity face: {cavity}; leaf {:?})",
            leaf.prim
        ));
        return;
    }
    tally.normals_checked += 1;
    tally.cavity_normals += cavity as u32;
}

#[test]
fn spans_agree_with_an_independent_point_membership_oracle() {
    let start = std::time::Instant::now();
    let (tallies, failures) = run_membership_oracle(200);
    for (op, t) in &tallies {
        eprintln!("{op:?}: {t:?}");
    }
    eprintln!("oracle run: {:?}", start.elapsed());
    assert!(
        failures.is_empty(),
        "{} failures:\n{}",
        failures.len(),
        failures.join("\n")
    );
    for (op, t) in &tallies {
        // Not vacuous: the rays hit, points are found inside and outside, hits and
        // normals were checked (subtracted faces included where there are any).
        assert!(
            t.hit_rays as f64 >= 0.3 * t.rays as f64,
            "{op:?}: only {} of {} rays hit",
            t.hit_rays,
            t.rays
        );
        assert!(
            t.inside >= 1000 && t.samples - t.inside >= 1000,
            "{op:?}: {t:?}"
        );
        assert!(t.nearest_checked >= t.rays / 4, "{op:?}: {t:?}");
        assert!(t.normals_checked >= t.rays / 8, "{op:?}: {t:?}");
        if *op == CsgOp::Difference {
            assert!(
                t.cavity_normals >= 50,
                "too few subtracted faces seen: {t:?}"
            );
        }
        assert_eq!(t.mismatches, 0);
        // Power: the oracle tells union from intersection and a difference from an
        // intersection; a combiner that confused them would disagree this often.
        assert!(
            t.swapped_mismatches as f64 > 0.02 * t.samples as f64 || *op == CsgOp::Difference,
            "{op:?}: swapping union and intersection changes only {} of {} samples",
            t.swapped_mismatches,
            t.samples
        );
    }
    let total = |f: fn(&OracleTally) -> u32| tallies.iter().map(|(_, t)| f(t)).sum::<u32>();
    let samples = total(|t| t.samples);
    assert!(total(|t| t.swapped_mismatches) as f64 > 0.05 * samples as f64);
    assert!(total(|t| t.no_complement_mismatches) as f64 > 0.02 * samples as f64);
}
