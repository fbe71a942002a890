//! `Accel::sole_mesh`: found only for a scene of one untransformed triangle mesh, and
//! then the mesh's own `intersect_cast_hit` gives bit for bit the answers of the
//! general `Accel::intersect_cast` (top-level hierarchy, then a dynamic call).

use glam::Affine3A;
use irradia_core::{Ray, Rng, Vec3};
use irradia_geometry::generators::gyroid_mesh;
use irradia_geometry::shapes::Sphere;
use irradia_geometry::{Accel, Instance, Shape, TriangleMesh};
use std::sync::Arc;

fn gyroid() -> Arc<dyn Shape> {
    let m = gyroid_mesh(24);
    Arc::new(TriangleMesh::new(m.positions, m.indices, None, None).unwrap())
}

fn random_rays(n: usize, seed: u64) -> Vec<Ray> {
    let mut rng = Rng::new(seed, 3);
    let mut u = || 2.0 * rng.next_f32() - 1.0;
    (0..n)
        .map(|_| {
            let o = Vec3::new(1.5 * u(), 1.5 * u(), 1.5 * u());
            let d = Vec3::new(u(), u(), u());
            Ray::new(o, d)
        })
        .collect()
}

#[test]
fn sole_mesh_answers_as_the_general_path() {
    let accel = Accel::build(vec![Instance::untransformed(gyroid())]);
    let mesh = accel.sole_mesh().expect("one untransformed mesh");
    let mut hits = 0;
    for (k, ray) in random_rays(20_000, 5).iter().enumerate() {
        let t_max = if k % 3 == 0 { 0.7 } else { f32::INFINITY };
        let general = accel.intersect_cast(ray, t_max);
        let fast = mesh.intersect_cast_hit(ray, t_max).map(|h| (0, h));
        assert_eq!(general, fast, "ray {k}: {ray:?}");
        hits += general.is_some() as usize;
    }
    assert!(hits > 5_000, "{hits} hits");
}

#[test]
fn no_sole_mesh_otherwise() {
    let moved = Affine3A::from_translation(Vec3::new(0.5, 0.0, 0.0));
    let sphere: Arc<dyn Shape> = Arc::new(Sphere::new(Vec3::ZERO, 1.0));
    assert!(Accel::build(vec![Instance::new(gyroid(), moved)])
        .sole_mesh()
        .is_none());
    assert!(Accel::build(vec![Instance::untransformed(sphere.clone())])
        .sole_mesh()
        .is_none());
    assert!(Accel::build(vec![
        Instance::untransformed(gyroid()),
        Instance::untransformed(sphere)
    ])
    .sole_mesh()
    .is_none());
    assert!(Accel::build(Vec::new()).sole_mesh().is_none());
}
