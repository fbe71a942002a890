//! A too-small Lipschitz bound on an implicit surface is reported after the render.

use std::process::Command;

#[test]
fn too_small_lipschitz_bound_is_warned_about() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("blob.toml");
    std::fs::write(
        &scene,
        r#"
[image]
width = 24
height = 16

[camera]
type = "perspective"
eye = [0, 0, 4]
look_at = [0, 0, 0]
up = [0, 1, 0]
fov = 40

[materials.m]
color = [0.8, 0.5, 0.3]

[[lights]]
type = "point"
position = [2, 3, 4]
intensity = 10

[[objects]]
name = "sphere with a bound ten times too small"
type = "implicit"
expr = "10*(x^2 + y^2 + z^2 - 1)"
bounds = { min = [-1.5, -1.5, -1.5], max = [1.5, 1.5, 1.5] }
lipschitz = 2
material = "m"
"#,
    )
    .unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_irradia"))
        .args(["render", scene.to_str().unwrap(), "-o"])
        .arg(dir.path().join("b.png"))
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert_eq!(
        stderr.matches("Lipschitz bound").count(),
        1,
        "one warning expected:\n{stderr}"
    );
}
