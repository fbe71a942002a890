//! End-to-end tests of the `irradia` binary: exit codes, messages, files.

mod common;
use common::{irradia, stderr};

#[test]
fn renders_a_builtin_to_png_exr_and_pfm() {
    let dir = tempfile::tempdir().unwrap();
    for name in ["w.png", "w.exr", "w.pfm"] {
        let o = irradia(
            &[
                "render",
                "--builtin",
                "whitted",
                "--width",
                "48",
                "--height",
                "27",
                "-o",
                name,
            ],
            dir.path(),
        );
        assert!(o.status.success(), "{name}: {}", stderr(&o));
        let im = irradia_core::io::load(&dir.path().join(name)).unwrap();
        assert_eq!((im.width(), im.height()), (48, 27));
        assert!(im.mean().max_component() > 0.05);
        let err = stderr(&o);
        assert!(
            err.contains("Mrays/s") && err.contains("Reflected Rays"),
            "{err}"
        );
    }
    // Float formats are linear, PNG is sRGB: they agree after decoding.
    let png = irradia_core::io::load(&dir.path().join("w.png")).unwrap();
    let pfm = irradia_core::io::load(&dir.path().join("w.pfm")).unwrap();
    let clamped = irradia_core::Image::from_pixels(
        pfm.width(),
        pfm.height(),
        pfm.pixels().iter().map(|p| p.clamp01()).collect(),
    );
    assert!(png.rmse(&clamped) < 0.01, "{}", png.rmse(&clamped));
}

#[test]
fn no_arguments_render_the_default_scene_to_render_png() {
    let dir = tempfile::tempdir().unwrap();
    let o = irradia(
        &["render", "--width", "32", "--height", "24", "--quiet"],
        dir.path(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(dir.path().join("render.png").exists());
    assert!(
        stderr(&o).is_empty(),
        "--quiet prints nothing: {}",
        stderr(&o)
    );
}

#[test]
fn aovs_are_written_beside_the_output() {
    let dir = tempfile::tempdir().unwrap();
    let o = irradia(
        &[
            "render",
            "--builtin",
            "whitted",
            "--width",
            "32",
            "--height",
            "18",
            "-o",
            "a.pfm",
            "--aov",
            "depth,normal",
            "--aov",
            "object-id",
            "--aov",
            "ray-depth",
            "--quiet",
        ],
        dir.path(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let ids = irradia_core::io::load(&dir.path().join("a.object-id.pfm")).unwrap();
    // Raw ids: -1 for the sky at the top, object indices elsewhere.
    assert_eq!(ids.get(16, 0).r, -1.0);
    assert!(ids.pixels().iter().any(|p| p.r == 0.0));
    for aov in ["depth", "normal", "ray-depth"] {
        assert!(dir.path().join(format!("a.{aov}.pfm")).exists());
    }
}

#[test]
fn a_bad_scene_file_exits_2_naming_file_line_and_field_and_keeps_the_old_image() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("bad.toml");
    std::fs::write(
        &scene,
        "[image]\nwidth = 64\nheight = 48\n\n[camera]\neye = [0, 1, 5]\nlook_at = [0, 0, 0]\nfov = 50\n\n[[objects]]\ntype = \"sphere\"\ncenter = [0, 0, 0]\nradius = -1\n",
    )
    .unwrap();
    let out = dir.path().join("keep.png");
    std::fs::write(&out, b"precious").unwrap();
    let o = irradia(&["render", "bad.toml", "-o", "keep.png"], dir.path());
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    let err = stderr(&o);
    assert!(err.contains("bad.toml:13"), "names file and line: {err}");
    assert!(err.contains("radius"), "names the field: {err}");
    assert_eq!(err.lines().count(), 1, "one message: {err}");
    assert!(!err.contains("panicked"));
    assert_eq!(std::fs::read(&out).unwrap(), b"precious");
}

#[test]
fn a_missing_scene_file_and_an_unknown_builtin_exit_2() {
    let dir = tempfile::tempdir().unwrap();
    let o = irradia(&["render", "nowhere.toml"], dir.path());
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("nowhere.toml"));
    let o = irradia(&["render", "--builtin", "no-such-scene"], dir.path());
    assert_eq!(o.status.code(), Some(2));
    let err = stderr(&o);
    assert!(
        err.contains("no-such-scene") && err.contains("default"),
        "{err}"
    );
    assert!(!dir.path().join("render.png").exists());
}

#[test]
fn bad_options_exit_2_before_rendering() {
    let dir = tempfile::tempdir().unwrap();
    let o = irradia(
        &["render", "--builtin", "whitted", "-o", "out.jpg"],
        dir.path(),
    );
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("out.jpg"), "{}", stderr(&o));
    assert!(!stderr(&o).contains("Mrays"), "nothing was rendered");
    for bad in [
        vec!["render", "--width", "0"],
        vec!["render", "--spp", "many"],
        vec!["render", "--threads", "0"],
        vec!["render", "--aov", "colour"],
        vec!["render", "--frobnicate"],
        vec!["render", "--width", "65536", "--height", "65536"],
    ] {
        let o = irradia(&bad, dir.path());
        assert_eq!(o.status.code(), Some(2), "{bad:?}: {}", stderr(&o));
    }
    assert!(!dir.path().join("render.png").exists());
}

#[test]
fn an_unwritable_output_is_reported_and_an_existing_file_is_untouched() {
    let dir = tempfile::tempdir().unwrap();
    let o = irradia(
        &[
            "render",
            "--width",
            "8",
            "--height",
            "8",
            "-o",
            "no/such/dir/x.png",
        ],
        dir.path(),
    );
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("does not exist"), "{}", stderr(&o));
    // A folder where the image should go.
    std::fs::create_dir(dir.path().join("taken.png")).unwrap();
    let o = irradia(
        &["render", "--width", "8", "--height", "8", "-o", "taken.png"],
        dir.path(),
    );
    assert_eq!(o.status.code(), Some(2));
    assert!(dir.path().join("taken.png").is_dir());
}

#[test]
fn trace_pixel_prints_text_json_and_dot() {
    let dir = tempfile::tempdir().unwrap();
    let args = [
        "trace-pixel",
        "--builtin",
        "whitted",
        "--width",
        "64",
        "--height",
        "36",
    ];
    let run = |extra: &[&str]| {
        let mut a: Vec<&str> = args.to_vec();
        a.extend_from_slice(extra);
        let o = irradia(&a, dir.path());
        assert!(o.status.success(), "{}", stderr(&o));
        String::from_utf8(o.stdout).unwrap()
    };
    // A pixel on the glass sphere (left of centre): refracted rays.
    let json = run(&["20", "20", "--format", "json"]);
    let v: serde_json::Value = serde_json::from_str(&json).expect("valid JSON");
    assert_eq!(v["tree"]["kind"], "camera");
    assert!(v["rays"].as_u64().unwrap() >= 2);
    let dot = run(&["20", "20", "--format", "dot"]);
    assert!(dot.starts_with("digraph raytree {"));
    assert!(dot.trim_end().ends_with('}'));
    assert_eq!(
        dot.matches("->").count() + 1,
        v["rays"].as_u64().unwrap() as usize
    );
    let text = run(&["20", "20"]);
    assert!(text.contains("camera ray, depth 1"), "{text}");

    let o = irradia(
        &["trace-pixel", "--builtin", "whitted", "5000", "1"],
        dir.path(),
    );
    assert_eq!(o.status.code(), Some(2));
    let o = irradia(
        &["trace-pixel", "--builtin", "whitted", "x", "1"],
        dir.path(),
    );
    assert_eq!(o.status.code(), Some(2));
}

#[test]
fn scenes_lists_the_builtins_and_help_has_examples() {
    let dir = tempfile::tempdir().unwrap();
    let o = irradia(&["scenes"], dir.path());
    assert!(o.status.success());
    let list = String::from_utf8(o.stdout).unwrap();
    assert!(
        list.contains("default") && list.contains("whitted"),
        "{list}"
    );
    let o = irradia(&["render", "--help"], dir.path());
    let help = String::from_utf8(o.stdout).unwrap();
    for opt in [
        "--output",
        "--builtin",
        "--width",
        "--height",
        "--spp",
        "--max-depth",
        "--threads",
        "--quiet",
        "--aov",
        "Examples:",
    ] {
        assert!(help.contains(opt), "render --help mentions {opt}");
    }
}
