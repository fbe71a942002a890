//! `type = "generator"` objects: each of the lecture's benchmark generators read from a
//! scene file gives the same mesh as calling the generator directly, rays hit it, and
//! bad fields are reported with the file, line and field.

use glam::{UVec3, Vec3};
use irradia_core::Ray;
use irradia_geometry::generators::{gyroid_mesh, metaballs, random_triangles as rt};
use irradia_scene::{load_file, Scene, SceneError};
use std::path::{Path, PathBuf};

const HEAD: &str = r#"[camera]
eye = [0, 0, 5]
look_at = [0, 0, 0]

[image]
width = 64
height = 48

[[lights]]
type = "point"
position = [3, 4, 5]
intensity = [30, 30, 30]
"#;

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

fn load(dir: &Path, objects: &str) -> Scene {
    let path = write(dir, "scene.toml", &format!("{HEAD}\n{objects}"));
    load_file(&path).unwrap_or_else(|e| panic!("{e}"))
}

fn triangles(s: &Scene) -> usize {
    s.accel.instances()[0].shape.facets(1).unwrap().faces.len()
}

/// Whether a ray from the eye towards the origin hits the object.
fn hit_from_front(s: &Scene) -> bool {
    let ray = Ray::new(Vec3::new(0.0, 0.0, 5.0), Vec3::new(0.0, 0.0, -1.0));
    s.accel.intersect(&ray, f32::INFINITY).is_some()
}

#[test]
fn every_generator_makes_the_mesh_the_generator_makes() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();

    let s = load(
        d,
        r#"[[objects]]
type = "generator"
generator = "random-triangles"
count = 500
seed = 7
size = { distribution = "uniform", min = 0.01, max = 0.05 }
"#,
    );
    let direct = rt::random_triangles(&rt::RandomTriangles::new(
        500,
        rt::SizeDistribution::Uniform {
            min: 0.01,
            max: 0.05,
        },
        7,
    ));
    assert_eq!(triangles(&s), 500);
    assert_eq!(direct.indices.len(), 500);
    let f = s.accel.instances()[0].shape.facets(1).unwrap();
    assert_eq!(
        f.vertices[..3],
        direct.positions[..3],
        "same seed, same triangles"
    );

    let s = load(
        d,
        "[[objects]]\ntype = \"generator\"\ngenerator = \"teapot\"\nlevel = 3\n",
    );
    let direct = irradia_geometry::shapes::bezier::tessellate(
        &irradia_geometry::shapes::bezier::teapot_patches(),
        3,
    );
    assert_eq!(triangles(&s), direct.indices.len());
    assert!(triangles(&s) > 500);
    assert!(hit_from_front(&s));

    let s = load(
        d,
        "[[objects]]\ntype = \"generator\"\ngenerator = \"gyroid\"\ngrid = 12\n",
    );
    assert_eq!(triangles(&s), gyroid_mesh(12).indices.len());
    assert!(hit_from_front(&s));

    let s = load(
        d,
        r#"[[objects]]
type = "generator"
generator = "metaballs"
grid = 24
balls = [{ center = [-0.3, 0, 0], radius = 0.3 }, { center = [0.3, 0, 0], radius = 0.3 }]
"#,
    );
    let balls = [
        metaballs::Ball {
            center: Vec3::new(-0.3, 0.0, 0.0),
            radius: 0.3,
        },
        metaballs::Ball {
            center: Vec3::new(0.3, 0.0, 0.0),
            radius: 0.3,
        },
    ];
    assert_eq!(
        triangles(&s),
        metaballs::metaballs_mesh(&balls, 24).indices.len()
    );
    assert!(hit_from_front(&s));
}

/// A 16³ u8 volume of a ball: 255 at the centre falling to 0 at radius 8 voxels.
fn ball_volume() -> Vec<u8> {
    let n = 16;
    let mut v = Vec::with_capacity(n * n * n);
    for z in 0..n {
        for y in 0..n {
            for x in 0..n {
                let p = Vec3::new(x as f32, y as f32, z as f32) - Vec3::splat(7.5);
                v.push((255.0 * (1.0 - p.length() / 8.0)).clamp(0.0, 255.0) as u8);
            }
        }
    }
    v
}

#[test]
fn raw_and_nrrd_volumes_give_the_same_isosurface() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("ball.raw"), ball_volume()).unwrap();
    let mut nrrd =
        b"NRRD0004\ntype: uchar\ndimension: 3\nsizes: 16 16 16\nencoding: raw\n\n".to_vec();
    nrrd.extend(ball_volume());
    std::fs::write(d.join("ball.nrrd"), nrrd).unwrap();
    let raw = load(
        d,
        r#"[[objects]]
type = "generator"
generator = "volume"
path = "ball.raw"
dims = [16, 16, 16]
voxel = "u8"
iso = 128
transform = [{ translate = [-7.5, -7.5, -7.5] }]
"#,
    );
    let from_nrrd = load(
        d,
        "[[objects]]\ntype = \"generator\"\ngenerator = \"volume\"\npath = \"ball.nrrd\"\niso = 128\n",
    );
    assert!(triangles(&raw) > 100);
    assert_eq!(triangles(&raw), triangles(&from_nrrd));
    assert!(hit_from_front(&raw), "the ball is centred on the view axis");
    let direct = irradia_geometry::generators::volume_mesh(
        &irradia_geometry::io::volume::read_raw(
            &d.join("ball.raw"),
            &irradia_geometry::io::volume::RawSpec::new(
                UVec3::splat(16),
                irradia_geometry::io::volume::VoxelType::U8,
            ),
        )
        .unwrap(),
        128.0,
    );
    assert_eq!(triangles(&raw), direct.indices.len());
}

fn fails(objects: &str) -> (SceneError, PathBuf, String, tempfile::TempDir) {
    let dir = tempfile::tempdir().unwrap();
    let text = format!("{HEAD}\n{objects}");
    let path = write(dir.path(), "bad.toml", &text);
    let err = load_file(&path).expect_err("the scene must be rejected");
    (err, path, text, dir)
}

fn check(objects: &str, needle_line: &str, field: &str, message: &str) {
    let (err, path, text, _dir) = fails(objects);
    let shown = err.to_string();
    let line = text.lines().position(|l| l.contains(needle_line)).unwrap() + 1;
    assert!(err.is_bad_input(), "{shown}");
    assert_eq!(err.file.as_deref(), Some(path.as_path()), "{shown}");
    assert_eq!(err.line, Some(line), "{shown}");
    assert_eq!(err.field, field, "{shown}");
    assert!(
        shown.contains(message),
        "{shown:?} should contain {message:?}"
    );
}

#[test]
fn bad_generator_fields_name_the_file_line_and_field() {
    let g = "[[objects]]\ntype = \"generator\"\n";
    check(
        &format!("{g}generator = \"sponge\"\n"),
        "sponge",
        "objects[0].generator",
        "random-triangles",
    );
    check(
        &format!("{g}generator = \"random-triangles\"\ncount = 0\n"),
        "count",
        "objects[0].count",
        "between 1 and",
    );
    check(
        &format!("{g}generator = \"random-triangles\"\nsize = {{ distribution = \"gamma\", area = 1 }}\n"),
        "size",
        "objects[0].size.distribution",
        "gamma",
    );
    check(
        &format!("{g}generator = \"teapot\"\nlevel = 999\n"),
        "level",
        "objects[0].level",
        "between 1 and 256",
    );
    check(
        &format!("{g}generator = \"gyroid\"\ngrid = 10\ncount = 3\n"),
        "count",
        "objects[0].count",
        "",
    );
    check(
        &format!("{g}generator = \"volume\"\npath = \"missing.raw\"\ndims = [4, 4, 4]\nvoxel = \"u8\"\niso = 1\n"),
        "missing.raw",
        "objects[0].path",
        "cannot read the volume",
    );
    check(
        &format!(
            "{g}generator = \"volume\"\npath = \"v.raw\"\ndims = [4, 4]\nvoxel = \"u8\"\niso = 1\n"
        ),
        "dims",
        "objects[0].dims",
        "[nx, ny, nz]",
    );
    check(
        &format!("{g}generator = \"volume\"\npath = \"v.raw\"\ndims = [4, 4, 4]\nvoxel = \"u12\"\niso = 1\n"),
        "u12",
        "objects[0].voxel",
        "u8",
    );
}
