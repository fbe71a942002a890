//! OBJ and PLY files: good ones load, bad ones give errors naming file, line and field,
//! and nothing panics on truncated or garbage input.

use irradia_core::Vec3;
use irradia_geometry::io::{load_mesh, obj::parse_obj, ply::parse_ply, MeshFileError};
use irradia_geometry::Shape;
use std::path::Path;

const CUBE_OBJ: &str = "# a unit cube\no cube\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n\
f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf -4 -8 -5 -1\n";

fn tmp(name: &str, bytes: &[u8]) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("irradia-mesh-io-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let p = dir.join(name);
    std::fs::write(&p, bytes).unwrap();
    p
}

/// The unit cube as PLY (8 vertices, 6 quads) in the given format.
fn cube_ply(format: &str) -> Vec<u8> {
    let v: [[f32; 3]; 8] = [
        [0., 0., 0.],
        [1., 0., 0.],
        [1., 1., 0.],
        [0., 1., 0.],
        [0., 0., 1.],
        [1., 0., 1.],
        [1., 1., 1.],
        [0., 1., 1.],
    ];
    let f: [[i32; 4]; 6] = [
        [0, 3, 2, 1],
        [4, 5, 6, 7],
        [0, 1, 5, 4],
        [1, 2, 6, 5],
        [2, 3, 7, 6],
        [3, 0, 4, 7],
    ];
    let mut out = format!(
        "ply\nformat {format} 1.0\ncomment test\nelement vertex 8\nproperty float x\nproperty float y\nproperty float z\n\
element face 6\nproperty list uchar int vertex_indices\nend_header\n"
    )
    .into_bytes();
    let big = format == "binary_big_endian";
    let f32b = |x: f32| {
        if big {
            x.to_be_bytes()
        } else {
            x.to_le_bytes()
        }
    };
    let i32b = |x: i32| {
        if big {
            x.to_be_bytes()
        } else {
            x.to_le_bytes()
        }
    };
    if format == "ascii" {
        for p in v {
            out.extend(format!("{} {} {}\n", p[0], p[1], p[2]).bytes());
        }
        for q in f {
            out.extend(format!("4 {} {} {} {}\n", q[0], q[1], q[2], q[3]).bytes());
        }
    } else {
        for p in v {
            for x in p {
                out.extend(f32b(x));
            }
        }
        for q in f {
            out.push(4);
            for i in q {
                out.extend(i32b(i));
            }
        }
    }
    out
}

/// The cube is closed: a ray from inside hits it, at distance 0.5 from the centre.
fn check_cube(mesh: &irradia_geometry::TriangleMesh) {
    assert_eq!(mesh.triangle_count(), 12);
    for d in [Vec3::X, -Vec3::Y, Vec3::Z, Vec3::new(0.3, -0.2, 0.9)] {
        let h = mesh
            .intersect(&irradia_core::Ray::new(Vec3::splat(0.5), d), f32::INFINITY)
            .expect("closed cube");
        assert!(h.point.min_element() > -1e-6 && h.point.max_element() < 1.0 + 1e-6);
        // Normals point out of the cube (faces wound counter-clockwise from outside).
        assert!(
            h.normal.dot(h.point - Vec3::splat(0.5)) > 0.0,
            "{d}: {:?}",
            h.normal
        );
    }
}

#[test]
fn obj_cube_loads_with_polygons_and_negative_indices() {
    let p = tmp("cube.obj", CUBE_OBJ.as_bytes());
    check_cube(&load_mesh(&p).unwrap());
}

#[test]
fn obj_with_normals_and_texture_coordinates() {
    let text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nvn 0 0 1\nf 1/1/1 2/2/1 3/3/1\n";
    let m = parse_obj(text, Path::new("t.obj")).unwrap();
    assert_eq!(m.positions.len(), 3);
    assert_eq!(m.normals.as_ref().unwrap()[0], Vec3::Z);
    let mesh = m.into_mesh(Path::new("t.obj")).unwrap();
    let h = mesh
        .intersect(
            &irradia_core::Ray::new(Vec3::new(0.25, 0.5, 1.0), -Vec3::Z),
            f32::INFINITY,
        )
        .unwrap();
    assert!((h.uv - irradia_core::Vec2::new(0.25, 0.5)).length() < 1e-6);
}

#[test]
fn ply_cube_loads_in_every_encoding() {
    for format in ["ascii", "binary_little_endian", "binary_big_endian"] {
        let p = tmp(&format!("cube-{format}.ply"), &cube_ply(format));
        check_cube(&load_mesh(&p).unwrap_or_else(|e| panic!("{format}: {e}")));
    }
}

fn obj_err(text: &str) -> MeshFileError {
    parse_obj(text, Path::new("bad.obj")).unwrap_err()
}

#[test]
fn obj_errors_name_line_and_field() {
    let e = obj_err("v 0 0 0\nv 1 x 0\n");
    assert_eq!((e.line, e.field.as_deref()), (Some(2), Some("v: y")));
    assert!(e.to_string().starts_with("bad.obj:2: v: y:"), "{e}");
    let e = obj_err("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n");
    assert_eq!(e.line, Some(4));
    assert!(e.message.contains("out of range"), "{e}");
    let e = obj_err("v 0 0 0\nv 1 0 0\nf 1 2\n");
    assert!(e.message.contains("at least 3"), "{e}");
    let e = obj_err("v 0 0\n");
    assert!(e.message.contains("expected 3 numbers"), "{e}");
    let e = obj_err("v 0 0 nan\n");
    assert!(e.message.contains("not finite"), "{e}");
    let e = obj_err("v 0 0 0\nf 0 1 1\n");
    assert!(e.message.contains("out of range"), "{e}");
    // No faces at all: the mesh is refused (naming the file).
    let p = tmp("empty.obj", b"v 0 0 0\n");
    let e = load_mesh(&p).unwrap_err();
    assert!(
        e.to_string().contains("empty.obj") && e.message.contains("no triangles"),
        "{e}"
    );
}

#[test]
fn missing_file_and_unknown_extension() {
    let e = load_mesh(Path::new("/nonexistent/mesh.ply")).unwrap_err();
    assert_eq!(e.to_string(), "/nonexistent/mesh.ply: no such file");
    let p = tmp("mesh.stl", b"solid");
    assert!(load_mesh(&p).unwrap_err().message.contains(".obj or .ply"));
}

#[test]
fn ply_header_claiming_more_than_the_file_holds() {
    // Binary: cut the body short; the count check fires before reading.
    let mut bytes = cube_ply("binary_little_endian");
    bytes.truncate(bytes.len() - 30);
    let e = parse_ply(&bytes, Path::new("short.ply")).unwrap_err();
    assert!(e.message.contains("header declares 6 face"), "{e}");
    assert!(e.field.as_deref().unwrap().contains("face"), "{e}");
    // A header that claims a billion vertices is refused without allocating them.
    let text = String::from_utf8_lossy(&cube_ply("binary_little_endian"))
        .replace("element vertex 8", "element vertex 1000000000");
    let e = parse_ply(text.as_bytes(), Path::new("huge.ply")).unwrap_err();
    assert!(e.message.contains("1000000000 vertex"), "{e}");
    // ASCII: the lines run out.
    let ascii = cube_ply("ascii");
    let cut = &ascii[..ascii.len() - 20];
    let e = parse_ply(cut, Path::new("short.ply")).unwrap_err();
    assert!(
        e.message.contains("ends early") || e.message.contains("missing value"),
        "{e}"
    );
    assert!(e.line.is_some());
}

#[test]
fn ply_errors_name_line_and_field() {
    let good = String::from_utf8(cube_ply("ascii")).unwrap();
    let e = parse_ply(
        good.replacen("1 0 0\n", "1 zz 0\n", 1).as_bytes(),
        Path::new("a.ply"),
    )
    .unwrap_err();
    assert_eq!(e.line, Some(12));
    assert_eq!(e.field.as_deref(), Some("vertex 1: y"));
    let e = parse_ply(
        good.replacen("4 0 3 2 1", "4 0 3 2 9", 1).as_bytes(),
        Path::new("a.ply"),
    )
    .unwrap_err();
    assert!(
        e.message.contains("out of range")
            && e.field.as_deref() == Some("face 0: vertex_indices [3]"),
        "{e}"
    );
    let e = parse_ply(
        good.replace("format ascii", "format weird").as_bytes(),
        Path::new("a.ply"),
    )
    .unwrap_err();
    assert_eq!(e.line, Some(2));
    let e = parse_ply(
        good.replace("property float y\n", "").as_bytes(),
        Path::new("a.ply"),
    )
    .unwrap_err();
    assert!(
        e.message.contains("x, y and z") || e.message.contains("more than"),
        "{e}"
    );
    let e = parse_ply(
        b"ply\nformat ascii 1.0\nelement vertex 1\n",
        Path::new("a.ply"),
    )
    .unwrap_err();
    assert!(e.message.contains("end_header"), "{e}");
    let e = parse_ply(b"solid cube\n", Path::new("a.ply")).unwrap_err();
    assert!(e.message.contains("not a PLY"), "{e}");
}

#[test]
fn truncated_and_garbage_files_never_panic() {
    let mut rng = irradia_core::Rng::new(5, 5);
    for format in ["ascii", "binary_little_endian", "binary_big_endian"] {
        let good = cube_ply(format);
        for cut in 0..good.len() {
            let _ = parse_ply(&good[..cut], Path::new("cut.ply"));
        }
        for _ in 0..300 {
            let mut b = good.clone();
            for _ in 0..4 {
                let i = rng.below(b.len() as u32) as usize;
                b[i] = rng.next_u32() as u8;
            }
            if let Ok(m) = parse_ply(&b, Path::new("garbage.ply")) {
                let _ = m.into_mesh(Path::new("garbage.ply"));
            }
        }
    }
    for cut in 0..CUBE_OBJ.len() {
        let _ = parse_obj(&CUBE_OBJ[..cut], Path::new("cut.obj"));
    }
    for _ in 0..300 {
        let mut b = CUBE_OBJ.as_bytes().to_vec();
        for _ in 0..4 {
            let i = rng.below(b.len() as u32) as usize;
            b[i] = rng.next_u32() as u8;
        }
        if let Ok(m) = parse_obj(&String::from_utf8_lossy(&b), Path::new("garbage.obj")) {
            let _ = m.into_mesh(Path::new("garbage.obj"));
        }
    }
}

/// The unit cube as Stanford-style triangle strips (igea.ply's `tristrips` element):
/// each face `a b c d` as the strip `a b d c`, the strips separated by -1, one of them
/// ending in a repeated vertex (a join, dropped).
fn cube_tristrips_ply(format: &str) -> Vec<u8> {
    let ascii = String::from_utf8(cube_ply("ascii")).unwrap();
    let vertices: Vec<&str> = ascii.lines().skip(10).take(8).collect();
    let faces: [[i32; 4]; 6] = [
        [0, 3, 2, 1],
        [4, 5, 6, 7],
        [0, 1, 5, 4],
        [1, 2, 6, 5],
        [2, 3, 7, 6],
        [3, 0, 4, 7],
    ];
    let mut strip: Vec<i32> = Vec::new();
    for (k, f) in faces.iter().enumerate() {
        if k > 0 {
            strip.push(-1);
        }
        strip.extend([f[0], f[1], f[3], f[2]]);
    }
    let last = *strip.last().unwrap();
    strip.push(last); // a join: its triangle repeats a vertex
    let mut out = format!(
        "ply\nformat {format} 1.0\nelement vertex 8\nproperty float x\nproperty float y\nproperty float z\n\
element tristrips 1\nproperty list int int vertex_indices\nend_header\n"
    )
    .into_bytes();
    if format == "ascii" {
        for v in vertices {
            out.extend(format!("{v}\n").bytes());
        }
        let list: Vec<String> = strip.iter().map(|i| i.to_string()).collect();
        out.extend(format!("{} {}\n", strip.len(), list.join(" ")).bytes());
    } else {
        for v in vertices {
            for x in v.split_whitespace() {
                out.extend(x.parse::<f32>().unwrap().to_le_bytes());
            }
        }
        out.extend((strip.len() as i32).to_le_bytes());
        for i in &strip {
            out.extend(i.to_le_bytes());
        }
    }
    out
}

#[test]
fn ply_triangle_strips_load_with_alternating_winding() {
    for format in ["ascii", "binary_little_endian"] {
        let p = tmp(&format!("strips-{format}.ply"), &cube_tristrips_ply(format));
        check_cube(&load_mesh(&p).unwrap_or_else(|e| panic!("{format}: {e}")));
    }
    // An index past the vertices is named like a face's.
    let bad = String::from_utf8(cube_tristrips_ply("ascii"))
        .unwrap()
        .replacen(" 0 3 1 2 ", " 0 3 1 9 ", 1);
    let e = parse_ply(bad.as_bytes(), Path::new("s.ply")).unwrap_err();
    assert!(
        e.message.contains("out of range")
            && e.field.as_deref().unwrap().starts_with("tristrips 0"),
        "{e}"
    );
}
