//! Display (vertex radiosity, T-vertex-free meshes, Gouraud images, PLY) and bad input
//! (item 7 of the issue): clear errors that say what to change, never a panic.

mod common;

use glam::DVec3;
use irradia_radiosity::display::{render_gouraud, write_ply, View};
use irradia_radiosity::formfactor::{self, FormFactors, Method, Params};
use irradia_radiosity::instant::{self, InstantOptions};
use irradia_radiosity::mesh::{adaptive, spec, Mesh, MeshOptions};
use irradia_radiosity::pipeline::{self, Config, NoProgress};
use irradia_radiosity::scenes;
use irradia_radiosity::solver::{SolveOptions, SolverKind, System};

#[test]
fn reflectance_at_or_above_one_is_an_error() {
    let mut s = scenes::closed_box(1.0, [0.5; 3], [1.0; 3]);
    s[2].reflectance = [0.5, 1.0, 0.5];
    let e = Mesh::build(&s, MeshOptions::default()).unwrap_err();
    assert!(e.is_input());
    let m = e.to_string();
    assert!(
        m.contains("left") && m.contains("green reflectance 1") && m.contains("below 1"),
        "{m}"
    );
}

#[test]
fn zero_area_patch_is_an_error() {
    let mut s = scenes::closed_box(1.0, [0.5; 3], [1.0; 3]);
    s.push(spec(
        "sliver",
        &[DVec3::ZERO, DVec3::X, DVec3::X * 2.0],
        [0.5; 3],
        [0.0; 3],
    ));
    let m = Mesh::build(&s, MeshOptions::default())
        .unwrap_err()
        .to_string();
    assert!(m.contains("sliver") && m.contains("zero area"), "{m}");
}

#[test]
fn too_many_elements_is_an_error_before_allocating() {
    let s = scenes::cornell_measured();
    let m = Mesh::build(
        &s,
        MeshOptions {
            max_element_area: Some(1e-6),
            max_elements: 1_000_000,
        },
    )
    .unwrap_err()
    .to_string();
    assert!(
        m.contains("--max-element-area") && m.contains("limit"),
        "{m}"
    );
    let m = FormFactors::zeros(2_000_000).unwrap_err().to_string();
    assert!(m.contains("hierarchical"), "{m}");
}

#[test]
fn open_enclosure_warns_where_closure_is_assumed() {
    let s = scenes::cornell_empty();
    let cfg = Config {
        mesh: MeshOptions {
            max_element_area: Some(200.0 * 200.0),
            ..Default::default()
        },
        method: Method::Hemicube,
        params: Params {
            hemicube_resolution: 32,
            ..Default::default()
        },
        solver: SolverKind::Southwell,
        ..Default::default()
    };
    let r = pipeline::run(&s, &cfg, &NoProgress).unwrap();
    assert!(
        r.notes.iter().any(|n| n.contains("not closed")),
        "{:?}",
        r.notes
    );
    assert!(r.diagnostics.unwrap().row_sum_mean < 0.99);
}

#[test]
fn no_emitter_is_an_error() {
    let s = scenes::closed_box(1.0, [0.5; 3], [0.0; 3]);
    let m = Mesh::build(&s, MeshOptions::default())
        .unwrap_err()
        .to_string();
    assert!(m.contains("emits"), "{m}");
}

#[test]
fn adaptive_mesh_displays_without_t_vertices() {
    let mesh = common::box_with_block(1.0 / 9.0);
    let ff = formfactor::method(
        Method::Hemicube,
        Params {
            hemicube_resolution: 32,
            ..Default::default()
        },
    )
    .compute(&mesh, None)
    .unwrap();
    let sol = SolverKind::GaussSeidel
        .matrix_solver()
        .unwrap()
        .solve(&System::new(&mesh, &ff), &SolveOptions::default())
        .unwrap();
    let (fine, split) = adaptive::refine(&mesh, &sol.b, 0.02, 0.0);
    assert!(
        split > 0 && split < mesh.len(),
        "split {split} of {}",
        mesh.len()
    );
    let b: Vec<[f64; 3]> = vec![[1.0; 3]; fine.len()];
    let d = irradia_radiosity::display::display_mesh(&fine.elements, &b, fine.scale());
    if d.t_vertices() != 0 {
        for t in &d.triangles {
            for k in 0..3 {
                let (a, b) = (
                    d.positions[t[k] as usize],
                    d.positions[t[(k + 1) % 3] as usize],
                );
                let m = 0.5 * (a + b);
                if let Some(v) = d.positions.iter().position(|p| {
                    (*p - m).length() < 1e-9
                        && d.patch[t[k] as usize]
                            == d.patch[d.positions.iter().position(|q| *q == *p).unwrap()]
                }) {
                    println!("edge {a} {b} has vertex {v} at its midpoint {m}");
                }
            }
        }
    }
    assert_eq!(d.t_vertices(), 0, "T-vertices left in the display mesh");
    // The triangles cover exactly the elements' area.
    let tri_area: f64 = d
        .triangles
        .iter()
        .map(|t| {
            0.5 * (d.positions[t[1] as usize] - d.positions[t[0] as usize])
                .cross(d.positions[t[2] as usize] - d.positions[t[0] as usize])
                .length()
        })
        .sum();
    assert!(
        (tri_area - fine.total_area()).abs() < 1e-9 * fine.total_area(),
        "{tri_area} vs {}",
        fine.total_area()
    );
}

#[test]
fn furnace_image_and_ply() {
    let mesh = common::furnace(2);
    let b: Vec<[f64; 3]> = vec![[std::f64::consts::PI * 0.5; 3]; mesh.len()];
    let d = irradia_radiosity::display::display_mesh(&mesh.elements, &b, mesh.scale());
    // Vertex radiosity of a uniform solution is uniform.
    assert!(d.radiosity.iter().all(|c| (c[0] - b[0][0]).abs() < 1e-12));
    let view = View {
        eye: DVec3::new(0.5, 0.5, 0.9),
        target: DVec3::new(0.5, 0.5, 0.0),
        up: DVec3::Y,
        fov_y: 60.0,
        width: 64,
        height: 48,
    };
    let img = render_gouraud(&d, &view).unwrap();
    // Inside a closed box every pixel sees a wall of radiance b/π = 0.5.
    for p in img.pixels() {
        assert!((p.r - 0.5).abs() < 1e-5, "pixel {p:?}");
    }
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("furnace.ply");
    write_ply(&d, &path).unwrap();
    let bytes = std::fs::read(&path).unwrap();
    let text = String::from_utf8_lossy(&bytes[..300]);
    assert!(text.starts_with("ply\nformat binary_little_endian 1.0"));
    assert!(text.contains(&format!("element vertex {}", d.positions.len())));
    let header_end = bytes
        .windows(11)
        .position(|w| w == b"end_header\n")
        .unwrap()
        + 11;
    let expect = d.positions.len() * (6 * 4 + 3 + 3 * 4) + d.triangles.len() * 13;
    assert_eq!(bytes.len() - header_end, expect);
}

#[test]
fn instant_radiosity_matches_the_solution_and_measures_its_clamp() {
    let mesh = common::box_with_block(1.0 / 16.0);
    let ff = formfactor::method(
        Method::Analytic,
        Params {
            visibility_samples: 16,
            ..Default::default()
        },
    )
    .compute(&mesh, None)
    .unwrap();
    let direct = SolverKind::Direct
        .matrix_solver()
        .unwrap()
        .solve(&System::new(&mesh, &ff), &SolveOptions::default())
        .unwrap();
    let total: f64 = mesh.total_area();
    let mean = |b: &[[f64; 3]]| -> f64 {
        mesh.elements
            .iter()
            .zip(b)
            .map(|(e, c)| e.area * c[0])
            .sum::<f64>()
            / total
    };
    let unclamped = instant::solve(
        &mesh,
        &InstantOptions {
            paths: 4096,
            clamp: None,
            max_bounces: 32,
        },
    );
    let clamped = instant::solve(
        &mesh,
        &InstantOptions {
            paths: 4096,
            clamp: Some(0.5),
            max_bounces: 32,
        },
    );
    let (md, mu, mc) = (mean(&direct.b), mean(&unclamped.b), mean(&clamped.b));
    let vpl_power: f64 = unclamped.vpls.iter().map(|v| v.power[0]).sum();
    let irr_area: f64 = mesh
        .elements
        .iter()
        .zip(&unclamped.b)
        .enumerate()
        .map(|(i, (e, b))| e.area * (b[0] - mesh.emission(i)[0]))
        .sum();
    println!("VPL power (red) {vpl_power:.4}; reflected power from instant b {irr_area:.4}");
    println!(
        "mean radiosity: direct {md:.4}, instant {mu:.4} ({} VPLs), clamped {mc:.4} (clamped {:.2}% of contributions, {:.2}% of the energy)",
        unclamped.vpls.len(),
        100.0 * clamped.clamped_fraction,
        100.0 * clamped.clamped_energy
    );
    assert!(
        (mu - md).abs() / md < 0.05,
        "instant radiosity mean {mu} vs {md}"
    );
    assert_eq!(unclamped.clamped_energy, 0.0);
    assert!(clamped.clamped_energy > 0.0 && clamped.clamped_energy < 0.5);
    assert!(mc < mu, "clamping removes energy");
}

/// Ray-triangle intersection in f64: (t, barycentric weights of a, b, c).
fn ray_triangle(o: DVec3, d: DVec3, a: DVec3, b: DVec3, c: DVec3) -> Option<(f64, [f64; 3])> {
    let (e1, e2) = (b - a, c - a);
    let p = d.cross(e2);
    let det = e1.dot(p);
    if det.abs() < 1e-300 {
        return None;
    }
    let s = o - a;
    let u = s.dot(p) / det;
    let q = s.cross(e1);
    let v = d.dot(q) / det;
    let t = e2.dot(q) / det;
    (t > 0.0).then_some((t, [1.0 - u - v, u, v]))
}

#[test]
fn gouraud_image_is_linear_interpolation_at_pixel_centres() {
    // A quad leaning steeply away from the camera, with four different vertex colours:
    // perspective-correct Gouraud interpolation must give, at every pixel centre, the
    // colour linearly interpolated at the surface point the pixel's ray hits.
    let corners = [
        DVec3::new(-1.0, -0.8, -1.5),
        DVec3::new(1.2, -0.9, -1.5),
        DVec3::new(0.9, 0.7, -6.0),
        DVec3::new(-1.1, 0.8, -6.0),
    ];
    let colours = [
        [0.9, 0.1, 0.2],
        [0.1, 0.8, 0.3],
        [0.2, 0.3, 1.0],
        [1.0, 1.0, 0.1],
    ];
    let pi = std::f64::consts::PI;
    let d = irradia_radiosity::mesh::weld::DisplayMesh {
        positions: corners.to_vec(),
        normals: vec![DVec3::Z; 4],
        radiosity: colours.iter().map(|c| c.map(|v| v * pi)).collect(),
        triangles: vec![[0, 1, 2], [0, 2, 3]],
        patch: vec![0; 4],
    };
    let view = View {
        eye: DVec3::ZERO,
        target: DVec3::new(0.0, 0.0, -1.0),
        up: DVec3::Y,
        fov_y: 50.0,
        width: 64,
        height: 48,
    };
    let img = render_gouraud(&d, &view).unwrap();
    let (mut inside, mut outside, mut worst, mut affine_gap) = (0, 0, 0.0f64, 0.0f64);
    for j in 0..view.height {
        for i in 0..view.width {
            let dir = view.ray_direction(i as f64 + 0.5, j as f64 + 0.5);
            let px = img.get(i, j);
            let got = [px.r as f64, px.g as f64, px.b as f64];
            let mut hit = None;
            let mut near_edge = false;
            for t in &d.triangles {
                let [a, b, c] = t.map(|k| d.positions[k as usize]);
                if let Some((_, l)) = ray_triangle(view.eye, dir, a, b, c) {
                    let m = l.iter().copied().fold(f64::INFINITY, f64::min);
                    if m > 1e-3 {
                        hit = Some((t, l));
                    } else if m > -1e-3 {
                        near_edge = true;
                    }
                }
            }
            match hit {
                Some((t, l)) => {
                    inside += 1;
                    let want: [f64; 3] = std::array::from_fn(|ch| {
                        (0..3).map(|k| l[k] * colours[t[k] as usize][ch]).sum()
                    });
                    for ch in 0..3 {
                        worst = worst.max((got[ch] - want[ch]).abs());
                    }
                    // What screen-space (affine) interpolation would give instead: the
                    // weights of the projected triangle.
                    let proj = |p: DVec3| DVec3::new(p.x / -p.z, p.y / -p.z, 0.0);
                    let [a, b, c] = t.map(|k| proj(d.positions[k as usize]));
                    let q = proj(view.eye + dir);
                    let (_, la) = ray_triangle(q + DVec3::Z, -DVec3::Z, a, b, c).expect("inside");
                    let aff: f64 = (0..3).map(|k| la[k] * colours[t[k] as usize][0]).sum();
                    affine_gap = affine_gap.max((aff - want[0]).abs());
                }
                None if !near_edge => {
                    outside += 1;
                    assert_eq!(got, [0.0; 3], "pixel ({i}, {j}) sees nothing");
                }
                None => {}
            }
        }
    }
    println!(
        "{inside} pixels inside, {outside} outside; worst error {worst:.2e}; affine interpolation would be off by up to {affine_gap:.3}"
    );
    assert!(inside > 600 && outside > 300, "{inside} {outside}");
    // The rasterizer snaps vertices to 1/256 pixel and interpolates in f32: about 1e-4
    // here (measured 1.6e-4), three orders of magnitude below the affine error.
    assert!(worst < 5e-4, "Gouraud colour off by {worst}");
    assert!(
        affine_gap > 0.05,
        "the test cannot tell perspective from affine"
    );
}
