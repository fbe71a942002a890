//! `Accel::intersect_cast_hits` (coherent groups of eight rays traced together through
//! the top level and each instance's mesh) answers every ray bit for bit as the
//! single-ray `Accel::intersect_cast` does, on scenes of several objects: meshes side by
//! side, transformed meshes, a mesh with given normals, a sphere, and two copies of one
//! mesh in the same place (every hit a tie between instances, settled by the
//! single-ray visit order); coherent (camera) and incoherent rays, with and without a
//! finite `t_max`.

use glam::{Affine3A, Quat};
use irradia_core::{Ray, Rng, Vec3};
use irradia_geometry::generators::gyroid_mesh;
use irradia_geometry::shapes::Sphere;
use irradia_geometry::{Accel, CastHit, Instance, Shape, TriangleMesh};
use std::sync::Arc;

/// The gyroid mesh cut into `parts` slabs along x (each triangle goes to the slab of its
/// first corner), each part a mesh of its own.
fn gyroid_parts(n: u32, parts: usize) -> Vec<Arc<dyn Shape>> {
    let m = gyroid_mesh(n);
    let (lo, hi) = m
        .positions
        .iter()
        .fold((f32::INFINITY, f32::NEG_INFINITY), |(a, b), p| {
            (a.min(p.x), b.max(p.x))
        });
    let mut split = vec![Vec::new(); parts];
    for t in &m.indices {
        let x = m.positions[t[0] as usize].x;
        let s = (((x - lo) / (hi - lo) * parts as f32) as usize).min(parts - 1);
        split[s].push(*t);
    }
    split
        .into_iter()
        .filter(|ix| !ix.is_empty())
        .map(|ix| {
            Arc::new(TriangleMesh::new(m.positions.clone(), ix, None, None).unwrap())
                as Arc<dyn Shape>
        })
        .collect()
}

fn gyroid_with_normals(n: u32) -> Arc<dyn Shape> {
    let m = gyroid_mesh(n);
    let normals: Vec<Vec3> = m
        .positions
        .iter()
        .map(|p| p.normalize_or(Vec3::Z))
        .collect();
    Arc::new(TriangleMesh::new(m.positions, m.indices, Some(normals), None).unwrap())
}

fn camera(eye: Vec3, target: Vec3, w: usize, h: usize, fov_deg: f32) -> Vec<Ray> {
    let forward = (target - eye).normalize();
    let right = forward.cross(Vec3::Y).normalize();
    let up = right.cross(forward);
    let tan = (fov_deg.to_radians() * 0.5).tan();
    let aspect = w as f32 / h as f32;
    let mut rays = Vec::with_capacity(w * h);
    for y in 0..h {
        for x in 0..w {
            let sx = (2.0 * (x as f32 + 0.5) / w as f32 - 1.0) * tan * aspect;
            let sy = (1.0 - 2.0 * (y as f32 + 0.5) / h as f32) * tan;
            rays.push(Ray::new(eye, (forward + sx * right + sy * up).normalize()));
        }
    }
    rays
}

fn incoherent(n: usize, seed: u64) -> Vec<Ray> {
    let mut rng = Rng::new(seed, 7);
    let mut u = || 2.0 * rng.next_f32() - 1.0;
    (0..n)
        .map(|_| {
            Ray::new(
                Vec3::new(2.0 * u(), 2.0 * u(), 2.0 * u()),
                Vec3::new(u(), u(), u()),
            )
        })
        .collect()
}

fn bits(h: &Option<(u32, CastHit)>) -> Option<(u32, u32, [u32; 6])> {
    h.map(|(i, h)| {
        (
            i,
            h.prim,
            [h.t, h.uv.x, h.uv.y, h.normal.x, h.normal.y, h.normal.z].map(f32::to_bits),
        )
    })
}

/// Compares the batch with the single-ray query ray by ray; returns the hit count and
/// the instances hit.
fn check(accel: &Accel, rays: &[Ray], t_max: f32) -> (usize, Vec<u32>) {
    let mut batch = vec![None; rays.len()];
    accel.intersect_cast_hits(rays, t_max, &mut batch);
    let mut hits = 0;
    let mut objects = Vec::new();
    for (k, (r, b)) in rays.iter().zip(&batch).enumerate() {
        let single = accel.intersect_cast(r, t_max);
        assert_eq!(bits(b), bits(&single), "ray {k} {r:?} t_max {t_max}");
        if let Some((i, _)) = single {
            hits += 1;
            if !objects.contains(&i) {
                objects.push(i);
            }
        }
    }
    objects.sort();
    (hits, objects)
}

fn all_rays() -> Vec<(Vec<Ray>, f32)> {
    let cam = camera(Vec3::new(0.3, 0.4, 3.2), Vec3::ZERO, 96, 64, 60.0);
    let inc = incoherent(6000, 11);
    vec![
        (cam.clone(), f32::INFINITY),
        (cam, 3.0),
        (inc.clone(), f32::INFINITY),
        (inc, 1.0),
    ]
}

#[test]
fn parts_of_one_mesh_answer_as_single_rays() {
    let accel = Accel::build(
        gyroid_parts(24, 5)
            .into_iter()
            .map(Instance::untransformed)
            .collect(),
    );
    assert!(accel.sole_mesh().is_none());
    for (rays, t_max) in all_rays() {
        let (hits, objects) = check(&accel, &rays, t_max);
        assert!(hits > rays.len() / 10, "{hits} hits");
        if t_max.is_infinite() {
            assert_eq!(objects, vec![0, 1, 2, 3, 4], "every part is hit");
        }
    }
}

#[test]
fn transformed_and_mixed_objects_answer_as_single_rays() {
    let parts = gyroid_parts(20, 2);
    let spin = Affine3A::from_scale_rotation_translation(
        Vec3::new(0.5, 0.7, 0.6),
        Quat::from_rotation_y(0.4) * Quat::from_rotation_x(0.3),
        Vec3::new(0.2, -0.1, 0.8),
    );
    let mirrored = Affine3A::from_scale_rotation_translation(
        Vec3::new(-0.4, 0.4, 0.4),
        Quat::IDENTITY,
        Vec3::new(-0.9, 0.5, 0.6),
    );
    let sphere: Arc<dyn Shape> = Arc::new(Sphere::new(Vec3::new(0.9, 0.9, 0.9), 0.3));
    let accel = Accel::build(vec![
        Instance::untransformed(parts[0].clone()),
        Instance::new(parts[1].clone(), spin),
        Instance::new(parts[0].clone(), mirrored),
        Instance::untransformed(sphere),
        Instance::new(
            gyroid_with_normals(12),
            Affine3A::from_translation(Vec3::new(0.0, 0.0, -1.5)),
        ),
    ]);
    for (rays, t_max) in all_rays() {
        let (hits, objects) = check(&accel, &rays, t_max);
        assert!(hits > rays.len() / 10, "{hits} hits");
        assert!(objects.len() >= 3, "objects hit: {objects:?}");
    }
}

/// Two instances of one mesh in the same place: every hit is an exact tie between them,
/// which the single-ray traversal settles by its visit order; the batch must notice
/// and agree (and so must a tie between a mesh and a copy moved by a tiny offset).
#[test]
fn ties_between_instances_are_settled_as_single_rays() {
    let parts = gyroid_parts(16, 1);
    let nudge = Affine3A::from_translation(Vec3::new(0.0, 0.0, 1e-7));
    let accel = Accel::build(vec![
        Instance::untransformed(parts[0].clone()),
        Instance::untransformed(parts[0].clone()),
        Instance::new(parts[0].clone(), nudge),
    ]);
    for (rays, t_max) in all_rays() {
        let (hits, _) = check(&accel, &rays, t_max);
        assert!(hits > rays.len() / 10, "{hits} hits");
    }
}

/// Eight instances that share one square grid in z = 0, each with one more triangle
/// somewhere else, so that their boxes differ: every ray through the grid hits all
/// eight at exactly the same `t`, and which one the single-ray traversal keeps depends
/// on the order it enters their boxes, which rays of one packet (a common octant,
/// scattered origins) do not share. The batch must trace those rays alone.
#[test]
fn ties_between_instances_entered_in_different_orders() {
    let n = 8u32;
    let mut positions = Vec::new();
    for y in 0..=n {
        for x in 0..=n {
            positions.push(Vec3::new(x as f32 / n as f32, y as f32 / n as f32, 0.0));
        }
    }
    let v = |x: u32, y: u32| y * (n + 1) + x;
    let mut indices = Vec::new();
    for y in 0..n {
        for x in 0..n {
            indices.push([v(x, y), v(x + 1, y), v(x + 1, y + 1)]);
            indices.push([v(x, y), v(x + 1, y + 1), v(x, y + 1)]);
        }
    }
    let mut rng = Rng::new(3, 9);
    let mut u = move || rng.next_f32();
    let instances = (0..8)
        .map(|_| {
            let c = Vec3::new(6.0 * u() - 2.5, 6.0 * u() - 2.5, 4.0 * u() - 2.0);
            let mut p = positions.clone();
            let base = p.len() as u32;
            p.extend([
                c,
                c + Vec3::new(0.05, 0.0, 0.0),
                c + Vec3::new(0.0, 0.05, 0.0),
            ]);
            let mut ix = indices.clone();
            ix.push([base, base + 1, base + 2]);
            Instance::untransformed(Arc::new(TriangleMesh::new(p, ix, None, None).unwrap()))
        })
        .collect();
    let accel = Accel::build(instances);
    assert!(accel.casts_flat());
    let two_levels = Accel::build(
        accel
            .instances()
            .iter()
            .cloned()
            .chain([Instance::untransformed(Arc::new(Sphere::new(
                Vec3::splat(9.0),
                0.1,
            )))])
            .collect(),
    );
    assert!(!two_levels.casts_flat());
    let mut rng = Rng::new(4, 1);
    let mut u = move || rng.next_f32();
    let rays: Vec<Ray> = (0..20_000)
        .map(|_| {
            let o = Vec3::new(3.0 * u() - 1.0, 3.0 * u() - 1.0, 1.0 + 3.0 * u());
            let d = -Vec3::new(0.05 + u(), 0.05 + u(), 0.3 + u());
            Ray::new(o, d)
        })
        .collect();
    for t_max in [f32::INFINITY, 3.0] {
        let (hits, objects) = check(&accel, &rays, t_max);
        assert!(hits > 300, "{hits} hits");
        assert!(
            objects.len() > 1,
            "ties settled by more than one instance: {objects:?}"
        );
    }
}

/// Two untransformed copies of one mesh: a scene the batch traces through one flat mesh
/// of both, where every hit is an exact tie between the copies' triangles, which the
/// flat hierarchy visits in another order than the two levels. Rays outside a coherent
/// group go through the flat mesh's single-ray traversal, which must flag each tie
/// (and leave it to the two levels) as the packet traversal does; incoherent rays are
/// nearly all such rays.
#[test]
fn exact_copies_in_the_flat_mesh_answer_as_single_rays() {
    let parts = gyroid_parts(16, 2);
    let accel = Accel::build(vec![
        Instance::untransformed(parts[0].clone()),
        Instance::untransformed(parts[1].clone()),
        Instance::untransformed(parts[0].clone()),
    ]);
    assert!(
        accel.casts_flat(),
        "three untransformed meshes go through one flat mesh"
    );
    for (rays, t_max) in all_rays() {
        let (hits, objects) = check(&accel, &rays, t_max);
        assert!(hits > rays.len() / 10, "{hits} hits");
        if t_max.is_infinite() {
            assert!(objects.contains(&1), "objects hit: {objects:?}");
        }
    }
}
