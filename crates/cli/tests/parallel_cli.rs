//! `irradia parallel` with scene workloads and the ray tracer: the image-parallel ray
//! traced image equals `irradia render` bit for bit (PFM keeps the floats), scene files
//! with generator objects run through the rasterizer, and bad input exits with code 2.

mod common;
use common::{irradia, stderr};

use std::path::Path;

#[test]
fn sort_first_ray_tracing_equals_irradia_render() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let o = irradia(
        &[
            "render",
            "--builtin",
            "whitted",
            "--width",
            "48",
            "--height",
            "36",
            "-o",
            "serial.pfm",
            "--quiet",
        ],
        d,
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let o = irradia(
        &[
            "parallel",
            "--mode",
            "sort-first",
            "--renderer",
            "raytrace",
            "--workload",
            "builtin:whitted",
            "--width",
            "48",
            "--height",
            "36",
            "--ranks",
            "3",
            "--tiles-per-rank",
            "3",
            "-o",
            "par.pfm",
            "--report",
            "r.json",
            "--quiet",
        ],
        d,
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let a = irradia_core::io::load(&d.join("serial.pfm")).unwrap();
    let b = irradia_core::io::load(&d.join("par.pfm")).unwrap();
    assert_eq!(a.pixels(), b.pixels());
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(d.join("r.json")).unwrap()).unwrap();
    let bal = &report["balance"];
    assert_eq!(bal["regions"], "tiles");
    assert_eq!(bal["rays_per_rank"].as_array().unwrap().len(), 3);
    assert!(
        bal["estimated_imbalance"].as_f64().unwrap()
            <= bal["strips_estimated_imbalance"].as_f64().unwrap()
    );
}

#[test]
fn scene_workloads_run_in_every_mode_and_renderer() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../docs/examples/generators.toml");
    let scene = scene.to_str().unwrap();
    for (mode, renderer) in [
        ("sort-first", "raster"),
        ("sort-middle", "raster"),
        ("sort-last", "raster"),
        ("sort-last", "raytrace"),
    ] {
        let o = irradia(
            &[
                "parallel",
                "--mode",
                mode,
                "--renderer",
                renderer,
                "--workload",
                scene,
                "--width",
                "64",
                "--height",
                "48",
                "--ranks",
                "3",
                "-o",
                "x.png",
                "--quiet",
            ],
            d,
        );
        assert!(o.status.success(), "{mode} {renderer}: {}", stderr(&o));
        let im = irradia_core::io::load(&d.join("x.png")).unwrap();
        assert!(
            im.mean().max_component() > 0.05,
            "{mode} {renderer}: image is black"
        );
    }
}

#[test]
fn bad_parallel_input_exits_with_code_2() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(
        d.join("bad.toml"),
        "[camera]\neye = [0, 0, 5]\nlook_at = [0, 0, 0]\n\n[[objects]]\ntype = \"generator\"\ngenerator = \"sponge\"\n",
    )
    .unwrap();
    let cases: [(&[&str], &str); 7] = [
        (
            &[
                "--mode",
                "sort-middle",
                "--renderer",
                "raytrace",
                "--workload",
                "builtin:whitted",
            ],
            "sort-middle has no meaning",
        ),
        (
            &["--renderer", "raytrace", "--workload", "teapot"],
            "renders scenes",
        ),
        (&["--workload", "bad.toml"], "bad.toml:7"),
        (&["--workload", "builtin:nosuch"], "nosuch"),
        (
            &["--mode", "sort-last", "--tiles-per-rank", "4"],
            "belongs to sort-first",
        ),
        (
            &[
                "--object-shading",
                "whitted-own-objects",
                "--workload",
                "builtin:whitted",
            ],
            "belongs to sort-last ray tracing",
        ),
        (
            &[
                "--mode",
                "sort-last",
                "--renderer",
                "raytrace",
                "--workload",
                "builtin:whitted",
                "--spp",
                "4",
            ],
            "--spp belongs to sort-first",
        ),
    ];
    for (args, needle) in cases {
        let mut all = vec!["parallel"];
        all.extend_from_slice(args);
        let o = irradia(&all, d);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", stderr(&o));
        assert!(stderr(&o).contains(needle), "{args:?}: {}", stderr(&o));
    }
}
