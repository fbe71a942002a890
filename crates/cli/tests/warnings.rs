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

/// A bare model's importer notes (the camera and lights it added) print without
/// `--quiet` and not with it; a warning (a feature not rendered) prints either way.
#[test]
fn quiet_silences_the_importers_notes_but_not_its_warnings() {
    let dir = tempfile::tempdir().unwrap();
    let obj = dir.path().join("tri.obj");
    // `l` (a line element) is a warning: lines are not rendered.
    std::fs::write(&obj, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nl 1 2\n").unwrap();
    for quiet in [false, true] {
        let mut cmd = Command::new(env!("CARGO_BIN_EXE_irradia"));
        cmd.args([
            "render",
            obj.to_str().unwrap(),
            "--width",
            "16",
            "--height",
            "12",
        ])
        .args(["--spp", "1", "-o"])
        .arg(dir.path().join("t.png"));
        if quiet {
            cmd.arg("--quiet");
        }
        let out = cmd.output().unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(out.status.success(), "{stderr}");
        assert_eq!(stderr.contains("no camera"), !quiet, "{stderr}");
        assert!(stderr.contains("warning"), "{stderr}");
    }
}
