//! The interleaved walks (`bvh/interleaved.rs`) against the single-ray walks they
//! interleave: for every ray the same leaves asked in the same order with the same
//! bounds, so the same answers (the path kernel's hits and shadow rays rely on it).

use irradia_core::{Aabb, Ray, Rng, Vec3};
use irradia_geometry::bvh::{Bvh, ChildRef};
use irradia_geometry::triangle::TriangleRay;

fn rand_vec(rng: &mut Rng, lo: f32, hi: f32) -> Vec3 {
    Vec3::new(
        lo + (hi - lo) * rng.next_f32(),
        lo + (hi - lo) * rng.next_f32(),
        lo + (hi - lo) * rng.next_f32(),
    )
}

fn scene(rng: &mut Rng, n: usize) -> (Vec<[Vec3; 3]>, Bvh) {
    let tris: Vec<[Vec3; 3]> = (0..n)
        .map(|i| {
            let c = rand_vec(rng, -1.0, 1.0);
            let size = if i % 13 == 0 { 0.7 } else { 0.07 };
            [0, 1, 2].map(|_| c + rand_vec(rng, -size, size))
        })
        .collect();
    let boxes: Vec<Aabb> = tris
        .iter()
        .map(|t| Aabb::from_points(t.iter().copied()))
        .collect();
    (tris, Bvh::build(&boxes))
}

fn rays(rng: &mut Rng, n: usize) -> Vec<Ray> {
    (0..n)
        .map(|_| {
            let o = rand_vec(rng, -1.5, 1.5);
            let d = (rand_vec(rng, -0.8, 0.8) - o).normalize();
            Ray::new(o, d)
        })
        .collect()
}

/// The nearest `t < t_max` among the leaf's triangles.
fn leaf_nearest(
    bvh: &Bvh,
    tris: &[[Vec3; 3]],
    leaf: ChildRef,
    ray: &Ray,
    t_max: f32,
) -> Option<f32> {
    let tr = TriangleRay::new(ray);
    let mut best = None;
    let mut t_max = t_max;
    for slot in leaf.index..leaf.index + leaf.count {
        let t = &tris[bvh.order()[slot as usize] as usize];
        if let Some(h) = tr.intersect(t[0], t[1], t[2], t_max) {
            t_max = h.t;
            best = Some(h.t);
        }
    }
    best
}

#[test]
fn interleaved_closest_walks_are_the_single_ray_walks() {
    let mut rng = Rng::new(5, 9);
    for &n in &[1usize, 7, 60, 900] {
        let (tris, bvh) = scene(&mut rng, n);
        // Fewer rays than walks in flight, as many, and several refills.
        for &count in &[1usize, 5, 16, 17, 41] {
            let rs = rays(&mut rng, count);
            // A bound per ray: most beyond the scene, some inside it.
            let t_max: Vec<f32> = (0..count)
                .map(|i| {
                    if i % 3 == 2 {
                        0.5 + rng.next_f32()
                    } else {
                        2.5
                    }
                })
                .collect();
            let mut single = Vec::new();
            for (r, &t_max) in rs.iter().zip(&t_max) {
                let mut calls = Vec::new();
                let t = bvh.closest_hit_leaves(r, t_max, |leaf, t| {
                    calls.push((leaf.index, leaf.count, t.to_bits()));
                    leaf_nearest(&bvh, &tris, leaf, r, t)
                });
                single.push((calls, t.map(f32::to_bits)));
            }
            let mut calls = vec![Vec::new(); count];
            let mut best: Vec<Option<u32>> = vec![None; count];
            bvh.closest_hit_leaves_interleaved(
                &rs,
                &t_max,
                |_| {},
                |i, leaf, t| {
                    calls[i].push((leaf.index, leaf.count, t.to_bits()));
                    let h = leaf_nearest(&bvh, &tris, leaf, &rs[i], t);
                    if let Some(h) = h {
                        best[i] = Some(h.to_bits());
                    }
                    h
                },
            );
            for i in 0..count {
                assert_eq!(
                    calls[i], single[i].0,
                    "n {n} rays {count} ray {i}: leaves differ"
                );
                assert_eq!(
                    best[i], single[i].1,
                    "n {n} rays {count} ray {i}: hit differs"
                );
            }
        }
    }
}

#[test]
fn interleaved_any_hit_walks_are_the_single_ray_walks() {
    let mut rng = Rng::new(6, 2);
    let mut blocked_total = 0;
    let mut open_total = 0;
    for &n in &[1usize, 9, 80, 1200] {
        let (tris, bvh) = scene(&mut rng, n);
        for &count in &[1usize, 3, 16, 17, 50] {
            let rs = rays(&mut rng, count);
            // Each ray its own bound: some end before what they would hit.
            let t_max: Vec<f32> = (0..count).map(|_| 0.2 + 3.0 * rng.next_f32()).collect();
            let leaf_any =
                |leaf: ChildRef, r: &Ray, t: f32| leaf_nearest(&bvh, &tris, leaf, r, t).is_some();
            let mut single = Vec::new();
            for (r, &t) in rs.iter().zip(&t_max) {
                let mut calls = Vec::new();
                let b = bvh.any_hit_leaves(r, t, |leaf, t| {
                    calls.push((leaf.index, leaf.count, t.to_bits()));
                    leaf_any(leaf, r, t)
                });
                single.push((calls, b));
            }
            let mut calls = vec![Vec::new(); count];
            let mut out = vec![false; count];
            bvh.any_hit_leaves_interleaved(&rs, &t_max, &mut out, |i, leaf, t| {
                calls[i].push((leaf.index, leaf.count, t.to_bits()));
                leaf_any(leaf, &rs[i], t)
            });
            for i in 0..count {
                assert_eq!(
                    calls[i], single[i].0,
                    "n {n} rays {count} ray {i}: leaves differ"
                );
                assert_eq!(
                    out[i], single[i].1,
                    "n {n} rays {count} ray {i}: answer differs"
                );
                if out[i] {
                    blocked_total += 1;
                } else {
                    open_total += 1;
                }
            }
        }
    }
    // Both answers occur often enough for the comparison to mean something.
    assert!(
        blocked_total > 30 && open_total > 30,
        "{blocked_total} blocked, {open_total} open"
    );
}
