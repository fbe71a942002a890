//! `irradia parallel --renderer raster` on a scene with a plane, a CSG object and an
//! implicit surface draws them all, names an object it cannot tessellate in a warning,
//! and refuses a bad `--tessellation` with exit code 2.

mod common;

use common::{irradia, stderr};

const SCENE: &str = r#"
[image]
width = 64
height = 48
[camera]
eye = [0, 2, 6]
look_at = [0, 0.5, 0]
fov = 50
[render]
background = [0, 0, 1]
[[lights]]
type = "point"
position = [2, 6, 4]
intensity = 60
[materials.m]
color = [0.5, 0.5, 0.5]
[materials.green]
color = [0.1, 0.8, 0.1]
[materials.red]
color = [0.9, 0.1, 0.1]
specular = 0.5
shininess = 30
[[objects]]
name = "floor"
type = "plane"
normal = [0, 1, 0]
material = "m"
[[objects]]
name = "cube minus sphere"
type = "difference"
material = "green"
children = [
  { type = "box", min = [-0.5, 0, -0.5], max = [0.5, 1, 0.5] },
  { type = "sphere", center = [0, 1, 0], radius = 0.5 },
]
transform = [{ translate = [-1, 0, 0] }]
[[objects]]
name = "blob"
type = "implicit"
expr = "x^2 + y^2 + z^2 - 0.25"
bounds = { min = [-0.6, -0.6, -0.6], max = [0.6, 0.6, 0.6] }
material = "red"
transform = [{ translate = [1, 0.5, 0] }]
[[objects]]
name = "empty csg"
type = "difference"
material = "m"
children = [
  { type = "sphere", center = [0, 2, -2], radius = 0.2 },
  { type = "sphere", center = [0, 2, -2], radius = 0.3 },
]
"#;

#[test]
fn planes_csg_and_implicit_surfaces_are_drawn_and_the_rest_is_named() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("s.toml"), SCENE).unwrap();
    let o = irradia(
        &[
            "parallel",
            "--renderer",
            "raster",
            "--workload",
            "s.toml",
            "--ranks",
            "2",
            "--tessellation",
            "24",
            "-o",
            "x.png",
        ],
        d,
    );
    let err = stderr(&o);
    assert!(o.status.success(), "{err}");
    assert!(
        err.contains("warning") && err.contains("empty csg"),
        "no warning naming the empty object: {err}"
    );
    assert!(!err.contains("floor,") && !err.contains("blob"), "{err}");
    let im = irradia_core::io::load(&d.join("x.png")).unwrap();
    // The floor fills the bottom row; the CSG object and the blob stand on it.
    let background = |x: u32, y: u32| {
        let p = im.get(x, y);
        p.b > 0.9 && p.r < 0.1
    };
    assert!((0..64).all(|x| !background(x, 47)), "floor missing");
    let p = im.get(20, 27);
    assert!(p.g > 2.0 * p.r, "the CSG object (green) is missing: {p:?}");
    let p = im.get(43, 24);
    assert!(p.r > 2.0 * p.g, "the implicit blob (red) is missing: {p:?}");
}

#[test]
fn a_bad_tessellation_exits_with_code_2() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("s.toml"), SCENE).unwrap();
    for n in ["0", "100000"] {
        let o = irradia(
            &[
                "parallel",
                "--renderer",
                "raster",
                "--workload",
                "s.toml",
                "--tessellation",
                n,
            ],
            d,
        );
        assert_eq!(o.status.code(), Some(2), "{n}: {}", stderr(&o));
        assert!(stderr(&o).contains("--tessellation"), "{}", stderr(&o));
    }
}
