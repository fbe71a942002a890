//! A union of spheres placed by translations tests a ray against its bounding ball
//! before its operands' boxes (`csg/ball.rs`). The ball must only drop rays that miss
//! every sphere: this checks, bit for bit, that the union's `intersect` is the nearest
//! of its spheres' own hits (the first on a tie, leaves numbered in order) and that
//! `occluded` is whether any sphere blocks, for rays grazing the spheres' silhouettes,
//! the outermost points (where the spheres touch the ball) included.

use glam::{Affine3A, Vec2, Vec3};
use irradia_core::sampling::uniform_sphere;
use irradia_core::{Ray, Rng};
use irradia_geometry::csg::{Csg, CsgOperand};
use irradia_geometry::shapes::Sphere;
use irradia_geometry::{Instance, Shape};
use std::sync::Arc;

#[test]
fn union_of_spheres_answers_as_its_spheres() {
    // The `csg` scene's seven spheres where its union stands, four given by their
    // centres and three placed by translations.
    let at = Vec3::new(2.6, 1.2, -0.3);
    let mut spheres = vec![
        (Sphere::new(at, 0.7), Vec3::ZERO),
        (
            Sphere::new(at + Vec3::new(0.75, 0.0, 0.0), 0.45),
            Vec3::ZERO,
        ),
        (
            Sphere::new(at + Vec3::new(-0.75, 0.0, 0.0), 0.45),
            Vec3::ZERO,
        ),
        (
            Sphere::new(at + Vec3::new(0.0, 0.75, 0.0), 0.45),
            Vec3::ZERO,
        ),
    ];
    for p in [
        Vec3::new(0.0, -0.75, 0.0),
        Vec3::new(0.0, 0.0, 0.75),
        Vec3::new(0.0, 0.0, -0.75),
    ] {
        spheres.push((Sphere::new(Vec3::ZERO, 0.45), at + p));
    }
    // Each operand as the node holds it.
    let parts: Vec<Instance> = spheres
        .iter()
        .map(|(s, p)| Instance::new(Arc::new(s.clone()), Affine3A::from_translation(*p)))
        .collect();
    let union = Csg::union(
        spheres
            .iter()
            .map(|(s, p)| CsgOperand::shape(Arc::new(s.clone()), Affine3A::from_translation(*p)))
            .collect(),
    )
    .unwrap();

    let mut rng = Rng::new(14, 5);
    let (mut hits, mut misses) = (0, 0);
    for i in 0..200_000 {
        // A point on a sphere's silhouette seen along `d`, nudged in or out by up to a
        // few parts in a million of the radius, or anywhere on the sphere.
        let k = i % spheres.len();
        let (s, p) = &spheres[k];
        let centre = s.center + *p;
        let d = uniform_sphere(Vec2::new(rng.next_f32(), rng.next_f32()));
        let u = uniform_sphere(Vec2::new(rng.next_f32(), rng.next_f32()));
        let u = if i % 4 == 0 {
            u
        } else {
            (u - d * u.dot(d)).normalize()
        };
        let nudge = 1.0 + (rng.next_f32() - 0.5) * 8e-6;
        let target = centre + u * (s.radius * nudge);
        let dist = 0.1 + 10.0 * rng.next_f32();
        let ray = Ray::new(target - d * dist, d * (0.5 + rng.next_f32()));
        let t_max = if i % 3 == 0 {
            dist * 1.5 * rng.next_f32()
        } else {
            f32::INFINITY
        };

        let mut want: Option<(u32, irradia_geometry::Hit)> = None;
        let mut limit = t_max;
        for (leaf, part) in parts.iter().enumerate() {
            if let Some(h) = part.intersect(&ray, limit) {
                limit = h.t;
                want = Some((leaf as u32, h));
            }
        }
        let got = union.intersect(&ray, t_max);
        let key = |h: &irradia_geometry::Hit| {
            (
                h.t.to_bits(),
                h.point.to_array().map(f32::to_bits),
                h.normal.to_array().map(f32::to_bits),
            )
        };
        assert_eq!(
            want.as_ref().map(|(leaf, h)| (*leaf, key(h))),
            got.as_ref().map(|h| (h.leaf, key(h))),
            "ray {i}: {ray:?} t_max {t_max}"
        );
        let blocked = parts.iter().any(|part| part.occluded(&ray, t_max));
        assert_eq!(
            blocked,
            union.occluded(&ray, t_max),
            "ray {i}: {ray:?} t_max {t_max}"
        );
        if want.is_some() {
            hits += 1;
        } else {
            misses += 1;
        }
    }
    assert!(
        hits > 40_000 && misses > 40_000,
        "{hits} hits, {misses} misses"
    );
}
