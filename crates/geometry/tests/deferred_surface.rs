//! `Shape::nearest_t` and `Shape::surface_at` (the nearest hit's parameter first, its
//! surface only for the winner of a closest-hit scan) give, bit for bit, the hit
//! `Shape::intersect` gives: for the shapes that split the work (sphere, plane), placed
//! plainly and through transforms, and for a shape that keeps the defaults; and asked
//! without uv (`surface_at(.., false)`), the same hit with uv left zero or unchanged.

use glam::{Affine3A, DVec3, Quat, Vec2, Vec3};
use irradia_core::sampling::uniform_sphere;
use irradia_core::{Ray, Rng};
use irradia_geometry::shapes::{Cuboid, Plane, Sphere};
use irradia_geometry::{Hit, Instance};
use std::sync::Arc;

fn instances() -> Vec<(&'static str, Instance)> {
    let turn = Affine3A::from_scale_rotation_translation(
        Vec3::new(1.3, 0.6, 0.9),
        Quat::from_rotation_y(0.7) * Quat::from_rotation_x(0.3),
        Vec3::new(0.2, -0.4, 0.5),
    );
    let sphere = || Arc::new(Sphere::new(Vec3::new(0.3, -0.2, 0.1), 1.1));
    let tilted = Plane::new(DVec3::new(0.3, 1.0, -0.2).normalize().as_vec3(), 0.4).unwrap();
    let floor = Plane::new(Vec3::Y, 0.0).unwrap();
    let cube = Cuboid::new(Vec3::splat(-0.8), Vec3::splat(0.8)).unwrap();
    vec![
        ("sphere", Instance::untransformed(sphere())),
        (
            "flipped sphere",
            Instance::untransformed(Arc::new(
                Sphere::new(Vec3::ZERO, 0.9).with_flipped_normals(true),
            )),
        ),
        ("placed sphere", Instance::new(sphere(), turn)),
        ("floor", Instance::untransformed(Arc::new(floor))),
        (
            "tilted plane",
            Instance::untransformed(Arc::new(tilted.clone())),
        ),
        ("placed plane", Instance::new(Arc::new(tilted), turn)),
        ("cuboid (default)", Instance::new(Arc::new(cube), turn)),
    ]
}

fn bits(h: &Hit) -> Vec<u32> {
    let v = |v: Vec3| [v.x.to_bits(), v.y.to_bits(), v.z.to_bits()];
    let mut b = vec![h.t.to_bits(), h.uv.x.to_bits(), h.uv.y.to_bits()];
    b.extend(v(h.point));
    b.extend(v(h.normal));
    b.extend(v(h.shading_normal));
    b.extend([h.prim, h.leaf, h.error.to_bits()]);
    b
}

#[test]
fn two_steps_give_the_whole_hit_bit_for_bit() {
    let mut rng = Rng::new(5, 9);
    for (name, inst) in instances() {
        let mut hits = 0;
        for i in 0..30_000 {
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
                0.5 + 5.0 * rng.next_f32()
            } else {
                f32::INFINITY
            };
            let want = inst.intersect(&ray, t_max);
            let got = inst.nearest_t(&ray, t_max).map(|t| {
                let h = inst.surface_at(&ray, t, true);
                assert_eq!(h.t.to_bits(), (t as f32).to_bits(), "{name}: t");
                // Without uv: the same hit but for uv, which is the same or zero.
                let mut lean = inst.surface_at(&ray, t, false);
                assert!(lean.uv == h.uv || lean.uv == Vec2::ZERO, "{name}: uv");
                lean.uv = h.uv;
                assert_eq!(bits(&lean), bits(&h), "{name}: hit without uv");
                h
            });
            assert_eq!(
                want.as_ref().map(bits),
                got.as_ref().map(bits),
                "{name}: ray {i}"
            );
            hits += want.is_some() as u32;
        }
        assert!(hits > 3_000, "{name}: only {hits} hits");
        // The sphere and the plane split the work; the cuboid keeps whole hits.
        assert_eq!(inst.splits_surface(), !name.contains("default"), "{name}");
    }
}

/// A union's nearest hit (POV-Ray's `union`) computes only the winning operand's
/// surface: the same hit as the nearest of the operands' whole hits, leaf included.
#[test]
fn union_reports_the_nearest_whole_hit() {
    use irradia_geometry::csg::{Csg, CsgOperand};
    use irradia_geometry::Shape;
    let turn = Affine3A::from_rotation_translation(Quat::from_rotation_z(0.6), Vec3::Y * 0.3);
    let parts: Vec<(Arc<dyn Shape>, Affine3A)> = vec![
        (Arc::new(Sphere::new(Vec3::ZERO, 0.7)), Affine3A::IDENTITY),
        (
            Arc::new(Sphere::new(Vec3::X * 0.75, 0.45)),
            Affine3A::IDENTITY,
        ),
        (Arc::new(Sphere::new(Vec3::ZERO, 0.45)), turn),
        (
            Arc::new(Cuboid::new(Vec3::splat(-0.3), Vec3::splat(0.3)).unwrap()),
            turn * Affine3A::from_translation(Vec3::Z * 0.7),
        ),
        // The first operand again: a tie, settled as the nearest of whole hits settles
        // it (the later one wins where `t` rounds up to the f32 `t_max` it is held to).
        (Arc::new(Sphere::new(Vec3::ZERO, 0.7)), Affine3A::IDENTITY),
    ];
    let union = Csg::union(
        parts
            .iter()
            .map(|(s, m)| CsgOperand::shape(s.clone(), *m))
            .collect(),
    )
    .unwrap();
    let operands: Vec<Instance> = parts
        .iter()
        .map(|(s, m)| Instance::new(s.clone(), *m))
        .collect();
    let mut rng = Rng::new(8, 1);
    let mut leaves = [0u32; 5];
    for i in 0..30_000 {
        let target =
            Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * 2.4 - Vec3::splat(1.2);
        let u = Vec2::new(rng.next_f32(), rng.next_f32());
        let o = target + uniform_sphere(u) * 4.0;
        let ray = Ray::new(o, (target - o) * 0.5);
        let t_max = if i % 3 == 0 {
            1.0 + rng.next_f32()
        } else {
            f32::INFINITY
        };
        let mut want: Option<Hit> = None;
        let mut limit = t_max;
        for (leaf, inst) in operands.iter().enumerate() {
            if let Some(mut h) = inst.intersect(&ray, limit) {
                h.leaf = leaf as u32;
                limit = h.t;
                want = Some(h);
            }
        }
        let got = union.intersect(&ray, t_max);
        assert_eq!(want.as_ref().map(bits), got.as_ref().map(bits), "ray {i}");
        if let Some(h) = got {
            leaves[h.leaf as usize] += 1;
        }
    }
    assert!(leaves[..4].iter().all(|&n| n > 100), "{leaves:?}");
}
