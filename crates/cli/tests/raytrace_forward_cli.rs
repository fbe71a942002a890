//! `irradia parallel --mode sort-last --renderer raytrace --object-shading forward`: the
//! object-parallel Whitted tracer with ray forwarding writes the image `irradia render`
//! writes (PFM keeps the floats), with shadows that local shading lacks, and reports
//! its generations; it refuses to drive a tiled display.

mod common;
use common::{irradia, stderr};

const SIZE: [&str; 4] = ["--width", "48", "--height", "36"];

fn parallel(
    shading: &str,
    out: &str,
    extra: &[&str],
    dir: &std::path::Path,
) -> std::process::Output {
    let mut args = vec![
        "parallel",
        "--mode",
        "sort-last",
        "--renderer",
        "raytrace",
        "--object-shading",
        shading,
        "--workload",
        "builtin:default",
        "--ranks",
        "3",
        "-o",
        out,
        "--report",
        "r.json",
        "--quiet",
    ];
    args.extend(SIZE);
    args.extend(extra);
    irradia(&args, dir)
}

#[test]
fn forwarded_sort_last_ray_tracing_equals_irradia_render() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let mut args = vec!["render", "-o", "serial.pfm", "--quiet"];
    args.extend(SIZE);
    let o = irradia(&args, d);
    assert!(o.status.success(), "{}", stderr(&o));

    // Tiles dealt by cost: the forwarding ranks shade screen regions as sort-first does.
    let o = parallel("forward", "fwd.pfm", &["--tiles-per-rank", "2"], d);
    assert!(o.status.success(), "{}", stderr(&o));
    let serial = irradia_core::io::load(&d.join("serial.pfm")).unwrap();
    let fwd = irradia_core::io::load(&d.join("fwd.pfm")).unwrap();
    assert_eq!(serial.pixels(), fwd.pixels());
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(d.join("r.json")).unwrap()).unwrap();
    let f = &report["balance"]["forwarding"];
    let gens = f["per_generation"].as_array().unwrap();
    assert_eq!(gens.len() as u64, f["generations"].as_u64().unwrap());
    let finished: u64 = gens
        .iter()
        .map(|g| g["pixels_finished"].as_u64().unwrap())
        .sum();
    assert_eq!(finished, 48 * 36, "every pixel finishes once");
    assert!(gens[0]["bytes"].as_u64().unwrap() > 0);

    // Local shading (no forwarding) has no shadows: the floor under the objects is
    // brighter there, so the images differ in many pixels.
    let o = parallel("local", "local.pfm", &[], d);
    assert!(o.status.success(), "{}", stderr(&o));
    let local = irradia_core::io::load(&d.join("local.pfm")).unwrap();
    let differ = local
        .pixels()
        .iter()
        .zip(serial.pixels())
        .filter(|(a, b)| a != b)
        .count();
    assert!(differ > 48 * 36 / 10, "only {differ} pixels differ");
}

#[test]
fn forwarding_cannot_drive_a_tiled_display() {
    let dir = tempfile::tempdir().unwrap();
    let mut args = vec![
        "parallel",
        "--mode",
        "sort-last",
        "--renderer",
        "raytrace",
        "--object-shading",
        "forward",
        "--workload",
        "builtin:whitted",
        "--display-tiles",
        "2x1",
        "--ranks",
        "2",
        "-o",
        "wall.png",
    ];
    args.extend(SIZE);
    let o = irradia(&args, dir.path());
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("--object-shading forward"),
        "{}",
        stderr(&o)
    );
}
