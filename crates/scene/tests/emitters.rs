//! The camera and light examples of docs/scene-format.md load and mean what the page
//! says; bad emitters (an environment map that is not 2:1, a missing image, a scaled
//! `to_world`, both spot falloffs at once) are refused with file, line and field.

use irradia_scene::{load_file, load_str, Light, Projection, SceneSyntax, SpotProfile};
use std::path::{Path, PathBuf};

fn data() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/emitters")
}

/// The ```toml blocks of the docs section that starts with `heading`.
fn examples(heading: &str) -> Vec<String> {
    let doc = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../docs/scene-format.md"),
    )
    .unwrap();
    let start = doc.find(heading).expect("section");
    let rest = &doc[start + heading.len()..];
    let section = &rest[..rest.find("\n## ").unwrap_or(rest.len())];
    section
        .split("```toml\n")
        .skip(1)
        .map(|b| b[..b.find("```").unwrap()].to_string())
        .collect()
}

const CAMERA: &str = "[camera]\neye = [0, 1, 5]\nlook_at = [0, 0, 0]\n\n";

fn load(text: &str) -> irradia_scene::Scene {
    let scene = if text.contains("[camera]") {
        text.to_string()
    } else {
        format!("{CAMERA}{text}")
    };
    load_str(&scene, SceneSyntax::Toml, &data().join("doc.toml"))
        .unwrap_or_else(|e| panic!("{e}\n{scene}"))
}

#[test]
fn every_camera_example_of_the_docs_loads() {
    let blocks = examples("## `[camera]`");
    assert_eq!(blocks.len(), 2, "the thin-lens and orthographic examples");
    let thin = load(&blocks[0]);
    match thin.camera.projection {
        Projection::ThinLens {
            fov_degrees,
            axis,
            aperture_radius,
            focus_distance,
        } => {
            assert_eq!(fov_degrees, 40.0);
            assert_eq!(axis, irradia_scene::FovAxis::Diagonal);
            assert_eq!((aperture_radius, focus_distance), (0.1, 6.0));
        }
        p => panic!("{p:?}"),
    }
    assert_eq!(thin.camera.near_clip, 0.5);
    let ortho = load(&blocks[1]);
    assert_eq!(
        ortho.camera.projection,
        Projection::Orthographic { height: 4.0 }
    );
}

#[test]
fn every_light_example_of_the_docs_loads() {
    let blocks = examples("## `[[lights]]`");
    assert_eq!(blocks.len(), 5, "spot, constant, envmap, projector, rect");
    let lights: Vec<Light> = blocks
        .iter()
        .map(|b| {
            let s = load(b);
            assert_eq!(s.lights.len(), 1, "{b}");
            s.lights[0].clone()
        })
        .collect();
    match &lights[0] {
        Light::Spot {
            cos_inner,
            cos_outer,
            profile,
            ..
        } => {
            assert_eq!(*profile, SpotProfile::Linear);
            assert!((cos_inner - 15f32.to_radians().cos()).abs() < 1e-6);
            assert!((cos_outer - 25f32.to_radians().cos()).abs() < 1e-6);
        }
        l => panic!("{l:?}"),
    }
    // The spot's texture frame: looking down -y with up -z, x = up × axis = -x.
    match &lights[0] {
        Light::Spot {
            texture: Some(t), ..
        } => {
            assert!(
                (t.x_axis - -glam::Vec3::X).length() < 1e-6,
                "{:?}",
                t.x_axis
            );
            assert!(
                (t.y_axis - -glam::Vec3::Z).length() < 1e-6,
                "{:?}",
                t.y_axis
            );
            assert!((t.uv_factor - 25f32.to_radians().tan()).abs() < 1e-5);
        }
        l => panic!("{l:?}"),
    }
    assert!(matches!(lights[1], Light::Constant { radiance } if radiance.g == 0.2));
    match &lights[2] {
        Light::Envmap(map) => {
            assert_eq!((map.image.width(), map.image.height()), (16, 8));
            assert_eq!(map.scale, 2.0);
            // Turned 90° about +y: the map's -z (u = 0) now looks along -x.
            let d = map.direction(glam::Vec2::new(0.0, 0.5));
            assert!((d - -glam::Vec3::X).length() < 1e-5, "{d}");
            // The bright texel (11, 2) of sky.hdr is read as HDR (above 1).
            assert!(map.image.get(11, 2).r > 30.0);
        }
        l => panic!("{l:?}"),
    }
    match &lights[3] {
        Light::Projector(p) => {
            assert_eq!((p.irradiance.width(), p.irradiance.height()), (8, 6));
            assert_eq!(p.scale, 5.0);
            assert!((p.half.x - 15f32.to_radians().tan()).abs() < 1e-6);
            assert!((p.half.y - p.half.x * 6.0 / 8.0).abs() < 1e-6);
        }
        l => panic!("{l:?}"),
    }
    assert!(matches!(lights[4], Light::Rect { .. }));
}

/// Writes `text` beside the test images and loads it; the load must fail with the
/// error at `line` in `field`, its message containing `needle`.
fn refused(text: &str, field: &str, needle: &str) {
    let dir = tempfile::tempdir().unwrap();
    for f in ["sky.hdr", "not-latlong.png"] {
        std::fs::copy(data().join(f), dir.path().join(f)).unwrap();
    }
    let path = dir.path().join("bad.toml");
    let text = format!("{CAMERA}{text}");
    std::fs::write(&path, &text).unwrap();
    let err = load_file(&path).expect_err("the scene must be rejected");
    let shown = err.to_string();
    let key = field.rsplit('.').next().unwrap();
    // The field's line, below the camera header.
    let line = text
        .lines()
        .enumerate()
        .skip(CAMERA.lines().count())
        .find(|(_, l)| l.trim_start().starts_with(key))
        .unwrap()
        .0
        + 1;
    assert!(err.is_bad_input(), "{shown}");
    assert_eq!(err.line, Some(line), "{shown}");
    assert_eq!(err.field, field, "{shown}");
    assert!(
        shown.starts_with(&format!("{}:{line}:", path.display())),
        "{shown}"
    );
    assert!(
        shown.contains(needle),
        "{shown:?} should contain {needle:?}"
    );
}

#[test]
fn bad_emitters_are_refused_with_file_line_and_field() {
    refused(
        "[[lights]]\ntype = \"envmap\"\nfilename = \"not-latlong.png\"\n",
        "lights[0].filename",
        "not-latlong.png: an environment map must be a latitude-longitude image twice as wide as it is high, at least 6x3 (got 9x6)",
    );
    refused(
        "[[lights]]\ntype = \"envmap\"\nfilename = \"missing.exr\"\n",
        "lights[0].filename",
        "cannot load the environment map",
    );
    refused(
        "[[lights]]\ntype = \"envmap\"\nfilename = \"sky.hdr\"\nto_world = [{ scale = 2 }]\n",
        "lights[0].to_world",
        "must be a rotation",
    );
    refused(
        "[[lights]]\ntype = \"spot\"\nposition = [0, 1, 0]\ndirection = [0, -1, 0]\ncutoff_angle = 30\nouter_angle = 20\n",
        "lights[0].cutoff_angle",
        "not cutoff_angle with outer_angle",
    );
    refused(
        "[[lights]]\ntype = \"spot\"\nposition = [0, 1, 0]\ndirection = [0, -1, 0]\ncutoff_angle = 30\nbeam_width = 40\n",
        "lights[0].beam_width",
        "between 0 and cutoff_angle",
    );
    refused(
        "[[lights]]\ntype = \"projector\"\nposition = [0, 1, 0]\nlook_at = [0, 0, -3]\nfov = 190\n",
        "lights[0].fov",
        "between 0 and 180",
    );
    refused(
        "[[lights]]\ntype = \"projector\"\nposition = [0, 1, 0]\nlook_at = [0, 0, 0]\nfov = 30\n",
        "lights[0].look_at",
        "up must not be parallel",
    );
}

#[test]
fn bad_cameras_are_refused_with_file_line_and_field() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("c.toml");
    let text = "[camera]\ntype = \"thinlens\"\neye = [0, 0, 5]\nlook_at = [0, 0, 0]\naperture_radius = 0.1\nfocus_distance = -2\n";
    std::fs::write(&path, text).unwrap();
    let err = load_file(&path).expect_err("negative focus distance");
    assert_eq!(err.line, Some(6), "{err}");
    assert_eq!(err.field, "camera.focus_distance", "{err}");
    let text = "[camera]\neye = [0, 0, 5]\nlook_at = [0, 0, 0]\nfov_axis = \"diagnal\"\n";
    std::fs::write(&path, text).unwrap();
    let err = load_file(&path).expect_err("unknown axis");
    assert_eq!(err.field, "camera.fov_axis", "{err}");
    assert!(err.to_string().contains("diagonal"), "{err}");
}
