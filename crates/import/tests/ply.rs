//! PLY as a bare model: quads and polygons, triangle strips (igea.ply's layout),
//! normals, uv, vertex colours, the three encodings; framing; errors; round trips.

mod common;
use common::*;
use irradia_import::{import, Options};
use std::path::Path;

const FILES: &[&str] = &[
    "ply/polygons_ascii.ply",
    "ply/strips_be.ply",
    "ply/quad_le.ply",
];

#[test]
fn every_ply_test_file_round_trips() {
    for f in FILES {
        assert_round_trip(&data(f));
    }
}

#[test]
fn polygons_are_fanned_and_colours_read() {
    let m = irradia_geometry::io::ply::read_ply(&data("ply/polygons_ascii.ply")).unwrap();
    assert_eq!(
        m.indices.len(),
        2 + 3,
        "a quad and a pentagon fan into 5 triangles"
    );
    let c = m.attributes.get("vertex_color").expect("vertex colours");
    assert_eq!(c.channels(), 3);
    assert_eq!(c.row(0).unwrap(), &[1.0, 0.0, 0.0]);
    assert!(
        (c.row(8).unwrap()[0] - irradia_core::color::srgb_to_linear(128.0 / 255.0)).abs() < 1e-6
    );
    assert!(m.normals.is_some() && m.uvs.is_some());
    let imp = imported(&data("ply/polygons_ascii.ply"));
    let mat = imp
        .tree
        .get("materials")
        .unwrap()
        .get("vertex_colors")
        .unwrap();
    assert_eq!(
        mat.get("reflectance").unwrap().get("type").unwrap().value,
        irradia_scene::file::tree::Value::Str("mesh_attribute".into())
    );
}

#[test]
fn triangle_strips_as_igea_stores_them() {
    // One `tristrips` element, a list of int with -1 between strips, big-endian, and
    // per-vertex confidence and intensity (skipped).
    let m = irradia_geometry::io::ply::read_ply(&data("ply/strips_be.ply")).unwrap();
    assert_eq!(
        m.indices.len(),
        5 * 5 * 2,
        "a 6x6 grid of strips: 50 triangles"
    );
    let imp = imported(&data("ply/strips_be.ply"));
    imp.scene().unwrap();
}

#[test]
fn binary_little_endian_doubles_and_float_colours() {
    let m = irradia_geometry::io::ply::read_ply(&data("ply/quad_le.ply")).unwrap();
    assert_eq!(m.indices.len(), 2);
    assert_eq!(
        m.attributes.get("vertex_color").unwrap().row(1).unwrap(),
        &[0.0, 1.0, 0.0],
        "float colours are linear"
    );
    assert_eq!(m.uvs.as_ref().unwrap()[2].to_array(), [1.0, 1.0]);
}

#[test]
fn a_bare_ply_is_framed_and_lit() {
    for f in FILES {
        let imp = imported(&data(f));
        let m = irradia_geometry::io::ply::read_ply(&data(f)).unwrap();
        let (mut lo, mut hi) = ([f32::MAX; 3], [f32::MIN; 3]);
        for p in &m.positions {
            for k in 0..3 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        assert_frames(&imp.tree, lo, hi, 640.0, 480.0);
        assert_frames(&imp.tree, lo, hi, 480.0, 640.0);
        assert_eq!(imp.notes.len(), 2, "{:?}", imp.notes);
        assert!(imp.tree.get("lights").is_some());
    }
}

#[test]
fn errors_name_the_file_and_element() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("bad.ply");
    let text = std::fs::read_to_string(data("ply/polygons_ascii.ply"))
        .unwrap()
        .replace("4 0 1 2 3", "4 0 1 2 30");
    std::fs::write(&p, text).unwrap();
    let e = import(&p, &Options::default()).unwrap_err();
    assert!(e.is_bad_input());
    let s = e.to_string();
    assert!(
        s.contains("bad.ply") && s.contains("face 0") && s.contains("out of range"),
        "{s}"
    );
    // Only vertices: no triangles is an error naming the file.
    let p = dir.path().join("points.ply");
    std::fs::write(&p, "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\nend_header\n0 0 0\n").unwrap();
    let e = import(&p, &Options::default()).unwrap_err();
    assert!(
        e.to_string().contains("points.ply") && e.to_string().contains("no faces"),
        "{e}"
    );
    let _ = Path::new("");
}

/// Findings of `cargo fuzz run ply`, kept as regression tests: each ends quickly in an
/// error or a scene, never a panic or a hang.
#[test]
fn fuzz_findings_end_quickly() {
    for entry in std::fs::read_dir(data("ply/fuzz")).unwrap() {
        let p = entry.unwrap().path();
        let bytes = std::fs::read(&p).unwrap();
        let t = std::time::Instant::now();
        let _ = irradia_import::ply::parse_bytes(&bytes, &p);
        assert!(t.elapsed().as_secs_f64() < 1.0, "{}", p.display());
    }
}

/// The real igea.ply (a Stanford-style scan stored as one `tristrips` element, the file
/// the importer once read as "the mesh has no triangles"): every triangle of the
/// strips, wound consistently (each directed edge once, with its opposite: a closed
/// surface), facing outwards (positive volume), as an independent numpy decoding found.
#[test]
fn the_real_igea_scan_reads_as_a_closed_consistent_surface() {
    let path = data("ply/igea.ply.gz");
    let m = irradia_geometry::io::read_mesh_file(&path, 0).unwrap();
    assert_eq!(m.positions.len(), 134_345);
    assert_eq!(m.indices.len(), 268_686);
    let mut edges = std::collections::HashSet::new();
    let mut volume = 0.0f64;
    for t in &m.indices {
        for k in 0..3 {
            assert!(
                edges.insert((t[k], t[(k + 1) % 3])),
                "directed edge {:?} twice: inconsistent winding",
                (t[k], t[(k + 1) % 3])
            );
        }
        let p = |i: u32| m.positions[i as usize].as_dvec3();
        volume += p(t[0]).dot(p(t[1]).cross(p(t[2]))) / 6.0;
    }
    let open = edges
        .iter()
        .filter(|&&(a, b)| !edges.contains(&(b, a)))
        .count();
    assert_eq!(open, 0, "every edge has its twin: a closed surface");
    assert!((volume - 2.7852e-4).abs() < 1e-8, "volume {volume}");
    // The scene path: `irradia render igea.ply.gz` reads it as a bare model.
    let imp = imported(&path);
    assert_eq!(imp.notes.len(), 2, "{:?}", imp.notes);
    imp.scene().unwrap();
}
