//! The one ray-query interface (`irradia_geometry::RayQuery`): its batched forms answer
//! every ray exactly as the single-ray forms do, and an any-hit query agrees with the
//! closest hit, for every implementation (the scene's `Accel`, the Whitted tracer's
//! opaque / clear split, the path tracer's flat bake with its W-rays-at-once
//! kernel, the prepared scene) over mesh scenes and CSG / quadric scenes.

use glam::Vec3;
use irradia_core::{sampling, Aabb, Ray, Rng};
use irradia_geometry::{ObjectSet, RayQuery, RaySegment, SceneHit};
use irradia_render::path::flat_scene::FlatScene;
use irradia_render::whitted::SceneGeometry;
use irradia_render::PreparedScene;
use irradia_scene::Scene;
use std::path::Path;

/// `n` random segments from points inside the scene's finite bounds, a third of them
/// unbounded, the rest ending at a random distance.
fn segments(scene: &Scene, n: usize) -> Vec<RaySegment> {
    let bounds = scene
        .accel
        .instances()
        .iter()
        .map(|i| i.bounds())
        .filter(|b| b.is_finite())
        .fold(Aabb::EMPTY, Aabb::union);
    let mut rng = Rng::new(29, 5);
    (0..n)
        .map(|i| {
            let u = Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32());
            let origin = bounds.min + (bounds.max - bounds.min) * u;
            let ray = Ray::new(origin, sampling::uniform_sphere(rng.next_2d()));
            let t_max = if i % 3 == 0 {
                f32::INFINITY
            } else {
                rng.next_f32() * bounds.extent().length()
            };
            RaySegment::new(ray, t_max)
        })
        .collect()
}

/// Bit-for-bit equality of two answers.
fn same(a: &Option<SceneHit>, b: &Option<SceneHit>) -> bool {
    match (a, b) {
        (None, None) => true,
        (Some(a), Some(b)) => {
            a.instance == b.instance
                && a.hit.t.to_bits() == b.hit.t.to_bits()
                && a.hit.point == b.hit.point
                && a.hit.normal == b.hit.normal
                && a.hit.prim == b.hit.prim
                && a.hit.leaf == b.hit.leaf
        }
        _ => false,
    }
}

/// Checks `q` on `segs` for every object set; returns how many closest hits it found.
fn check(name: &str, what: &str, q: &dyn RayQuery, segs: &[RaySegment]) -> usize {
    let mut found = 0;
    for set in [ObjectSet::All, ObjectSet::Opaque, ObjectSet::Clear] {
        let mut nearest = vec![None; segs.len()];
        let mut blocked = vec![false; segs.len()];
        q.closest_hits(set, segs, &mut nearest);
        q.any_hits(set, segs, &mut blocked);
        for (i, s) in segs.iter().enumerate() {
            let one = q.closest_hit(set, &s.ray, s.t_max);
            assert!(
                same(&one, &nearest[i]),
                "{name}/{what}/{set:?}: ray {i} {s:?}: batched {:?}, single {one:?}",
                nearest[i]
            );
            let any = q.any_hit(set, &s.ray, s.t_max);
            assert_eq!(
                any, blocked[i],
                "{name}/{what}/{set:?}: ray {i} any-hit {s:?}"
            );
            assert_eq!(
                any,
                one.is_some(),
                "{name}/{what}/{set:?}: ray {i}: any-hit {any} but closest hit {one:?}"
            );
            found += one.is_some() as usize;
        }
    }
    found
}

/// Every implementation over `scene`; returns the hits of the flat bake.
fn check_scene(name: &str, scene: &Scene) -> usize {
    // Not a multiple of W (16) nor of eight: the batches end with a partial group of lanes.
    let segs = segments(scene, 1003);
    let flat = FlatScene::new(scene);
    let prepared = PreparedScene::new(scene);
    let hits = [
        check(name, "accel", &scene.accel, &segs),
        check(name, "whitted", &SceneGeometry::new(scene), &segs),
        check(name, "flat", &flat, &segs),
        check(name, "prepared", &prepared, &segs),
    ];
    for h in hits {
        assert!(
            h > segs.len() / 4,
            "{name}: only {h} hits: the rays test little"
        );
    }
    hits[2]
}

#[test]
fn batched_and_single_ray_queries_agree_on_mesh_scenes() {
    // Two tetrahedra (OBJ and PLY) and the teapot, meshes through their own
    // hierarchies of watertight four-triangle packets; the Cornell box, baked whole by
    // the path tracer and small enough for its W-rays-at-once kernel.
    let meshes =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../scene/tests/data/meshes/scene.toml");
    let scene = irradia_scene::load_file(&meshes).unwrap();
    check_scene("meshes", &scene);
    let cornell = irradia_scene::builtin::load("cornell").unwrap();
    assert_eq!(FlatScene::new(&cornell).generic_objects(), 0);
    check_scene("cornell", &cornell);
    check_scene("teapot", &irradia_scene::builtin::load("teapot").unwrap());
}

#[test]
fn batched_and_single_ray_queries_agree_on_csg_and_quadric_scenes() {
    // The default scene has glass (so the opaque / clear split is not trivial), CSG
    // with a material per leaf, quadrics, a mesh and an implicit surface.
    for name in ["default", "csg", "quadrics", "whitted"] {
        check_scene(name, &irradia_scene::builtin::load(name).unwrap());
    }
}
