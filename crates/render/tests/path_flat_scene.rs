//! The path tracer's flat scene (planar objects baked into world-space triangles) must
//! see the same geometry as the scene's generic acceleration structure: on random rays
//! through the built-in scenes, the same object is hit at the same distance with the
//! same normal and material, and shadow queries agree.

mod path_common;

use glam::Vec3;
use irradia_core::{sampling, Aabb, Ray, Rng};
use irradia_render::path::flat_scene::FlatScene;
use irradia_render::path::tracer::{AccelTracer, Tracer};

/// Compares the two tracers on `n` random rays from points inside the scene's bounds;
/// returns the number of baked objects.
fn compare(name: &str, n: u32) -> usize {
    let scene = irradia_scene::builtin::load(name).unwrap();
    let flat = FlatScene::new(&scene);
    let generic = AccelTracer { scene: &scene };
    let bounds = scene
        .accel
        .instances()
        .iter()
        .map(|i| i.bounds())
        .filter(|b| b.is_finite())
        .fold(Aabb::EMPTY, Aabb::union);
    let mut rng = Rng::new(17, 3);
    let (mut hits, mut mismatches) = (0u32, 0u32);
    for _ in 0..n {
        let u = Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32());
        let origin = bounds.min + (bounds.max - bounds.min) * u;
        let ray = Ray::new(origin, sampling::uniform_sphere(rng.next_2d()));
        let a = flat.intersect(&ray, f32::INFINITY);
        let b = generic.intersect(&ray, f32::INFINITY);
        let same = match (a, b) {
            (None, None) => true,
            (Some(a), Some(b)) => {
                hits += 1;
                let scale = 1.0 + b.hit.t;
                let same_point = a.material == b.material
                    && (a.hit.t - b.hit.t).abs() <= 1e-4 * scale
                    && (a.hit.point - b.hit.point).length() <= 1e-4 * scale;
                // Coincident faces (the short box stands on the floor: its bottom and
                // the floor are one plane) are a tie either tracer may break.
                let coincident =
                    a.instance != b.instance && a.hit.normal.dot(b.hit.normal).abs() > 1.0 - 1e-4;
                same_point
                    && (coincident
                        || (a.instance == b.instance
                            && a.hit.normal.dot(b.hit.normal) > 1.0 - 1e-4))
            }
            _ => false,
        };
        // A shadow query to a random distance along the same ray.
        let t_max = rng.next_f32() * 4.0 * bounds.extent().length();
        let occluded_same = flat.occluded(&ray, t_max) == generic.occluded(&ray, t_max);
        if !same || !occluded_same {
            if std::env::var("FLAT_DEBUG").is_ok() && mismatches < 5 {
                eprintln!("{name}: {ray:?} t_max {t_max} same {same} occl {occluded_same}\n  flat {a:?}\n  accel {b:?}");
            }
            mismatches += 1;
        }
    }
    assert!(hits > n / 4, "{name}: only {hits} of {n} rays hit anything");
    // Only rays grazing an edge (rounding-level events) may differ.
    assert!(
        mismatches * 2000 <= n,
        "{name}: {mismatches} of {n} rays differ between the flat scene and the accel"
    );
    flat.baked_objects()
}

#[test]
fn cornell_box_is_baked_whole_and_hit_the_same() {
    let scene = irradia_scene::builtin::load("cornell").unwrap();
    let flat = FlatScene::new(&scene);
    // Five walls, the light and two transformed boxes: all planar.
    assert_eq!(flat.baked_objects(), scene.objects.len());
    assert_eq!(flat.generic_objects(), 0);
    assert_eq!(flat.triangle_count(), 6 * 2 + 2 * 12);
    compare("cornell", 20_000);
}

#[test]
fn measured_cornell_box_is_hit_the_same() {
    assert!(compare("cornell-measured", 20_000) > 0);
}

#[test]
fn mixed_scenes_keep_curved_shapes_generic_and_agree() {
    // The default scene has spheres, quadrics, CSG, a mesh and an implicit surface
    // (all left to their shapes); the polyhedra scene bakes polyhedra and polygons.
    compare("default", 5_000);
    assert!(compare("polyhedra", 10_000) > 0);
}

/// Baked triangles report barycentric uv, so a polygon whose physically based material
/// has a texture stays with its own test (and its uv); an untextured one is baked.
#[test]
fn textured_polygons_keep_their_own_uv() {
    let text = |reflectance: &str| {
        format!(
            r#"
[camera]
eye = [0, 0, 5]
look_at = [0, 0, 0]

[materials.m]
type = "diffuse"
reflectance = {reflectance}

[[objects]]
type = "polygon"
vertices = [[-2, -1, 0], [2, -1, 0], [2, 1, 0], [-2, 1, 0]]
material = "m"
"#
        )
    };
    let load = |t: &str| {
        irradia_scene::load_str(
            t,
            irradia_scene::SceneSyntax::Toml,
            std::path::Path::new("t.toml"),
        )
        .unwrap()
    };
    let plain = load(&text("0.5"));
    assert_eq!(FlatScene::new(&plain).baked_objects(), 1);
    let textured = load(&text(
        r#"{ type = "checkerboard", to_uv = [{ scale = [4, 2] }] }"#,
    ));
    let flat = FlatScene::new(&textured);
    assert_eq!(flat.baked_objects(), 0);
    // The polygon's uv: u along its first edge, v across, over its extent.
    let ray = Ray::new(Vec3::new(1.0, 0.5, 5.0), -Vec3::Z);
    let hit = flat.intersect(&ray, f32::INFINITY).expect("the polygon");
    assert!(
        (hit.hit.uv - glam::Vec2::new(0.75, 0.75)).length() < 1e-5,
        "{}",
        hit.hit.uv
    );
}

/// Triangle meshes are baked with their vertex normals: on random rays at a mesh
/// ball placed by a rotation and a non-uniform scale, the flat scene reports the
/// mesh's own geometric and shading normals (given outward or inward, or computed),
/// and the shading normals are far from the geometric ones on most hits (so the
/// comparison sees them).
#[test]
fn smooth_meshes_are_baked_with_the_meshes_normals() {
    use irradia_geometry::Instance;
    use irradia_scene::{Object, Scene};
    use path_common::{uv_sphere_mesh, SphereNormals};
    for normals in [
        SphereNormals::Outward,
        SphereNormals::Inward,
        SphereNormals::Computed,
    ] {
        let to_world = glam::Affine3A::from_scale_rotation_translation(
            Vec3::new(0.45, 0.3, 0.4),
            glam::Quat::from_rotation_y(0.5),
            Vec3::new(-0.3, -0.6, 0.4),
        );
        let mesh = uv_sphere_mesh(2, 4, normals);
        let scene = Scene::new(
            path_common::camera(Vec3::new(0.0, 0.0, 4.0), Vec3::ZERO, 40.0),
            path_common::settings(8, 8, 4, irradia_core::Rgb::BLACK),
            vec![path_common::diffuse(0.5, 0.0)],
            vec![],
            vec![Object {
                name: "ball".into(),
                material: 0,
                leaf_materials: vec![],
            }],
            vec![Instance::new(std::sync::Arc::new(mesh), to_world)],
        );
        let flat = FlatScene::new(&scene);
        assert_eq!((flat.baked_objects(), flat.generic_objects()), (1, 0));
        let generic = AccelTracer { scene: &scene };
        let mut rng = Rng::new(3, 5);
        let (mut hits, mut smooth, mut mismatches) = (0, 0, 0);
        for _ in 0..4000 {
            // From a point around the ball towards a point inside it.
            let from = Vec3::new(-0.3, -0.6, 0.4) + 2.0 * sampling::uniform_sphere(rng.next_2d());
            let to = Vec3::new(-0.3, -0.6, 0.4)
                + 0.1 * (Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) - 0.5);
            let ray = Ray::new(from, to - from);
            let (Some(a), Some(b)) = (
                flat.intersect(&ray, f32::INFINITY),
                generic.intersect(&ray, f32::INFINITY),
            ) else {
                panic!("{normals:?}: the ray misses the ball");
            };
            hits += 1;
            let same = (a.hit.t - b.hit.t).abs() < 1e-4 * b.hit.t
                && a.hit.normal.dot(b.hit.normal) > 1.0 - 1e-5
                && a.hit.shading_normal.dot(b.hit.shading_normal) > 1.0 - 1e-4
                && a.hit.prim == b.hit.prim;
            if !same {
                // Rays through an edge may take either triangle (rounding).
                mismatches += 1;
                eprintln!("{normals:?}: {ray:?}\n  flat {a:?}\n  mesh {b:?}");
            }
            if a.hit.shading_normal.dot(a.hit.normal) < 0.99 {
                smooth += 1;
            }
        }
        assert!(
            mismatches <= 2,
            "{normals:?}: {mismatches} of {hits} hits differ"
        );
        assert!(
            smooth * 2 > hits,
            "{normals:?}: {smooth} of {hits} hits look smooth"
        );
    }
}
