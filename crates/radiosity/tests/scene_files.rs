//! Radiosity from scene files (`irradia radiosity SCENE.toml`): surfaces through
//! `Shape::facets`, reflectance from `color` × `diffuse`, emission from the material's
//! radiance × π.
//!
//! - the empty measured Cornell box written as a scene file gives the same surface
//!   means as the built-in one;
//! - a tessellated sphere inside a closed scene-file room is a furnace: with every
//!   surface emitting `E` and reflecting `ρ`, `B = E / (1 − ρ)` everywhere;
//! - bad input (no emitter, reflectance at or above 1, an open room where a closed one
//!   is assumed) is an input error naming the file, line and field.

use irradia_radiosity::formfactor::{Method, Params};
use irradia_radiosity::mesh::{MeshOptions, PatchSpec};
use irradia_radiosity::pipeline::{run, Config, NoProgress};
use irradia_radiosity::scene_input::{check_closed, patches_with_objects};
use irradia_radiosity::solver::{SolveOptions, SolverKind};
use irradia_radiosity::{scenes, RadiosityError};
use std::f64::consts::PI;
use std::fmt::Write;
use std::path::{Path, PathBuf};

/// Patch specs as a TOML scene: one material per spec and one polygon object per
/// planar spec (a non-planar quadrilateral, as the measured box's red wall, becomes two
/// triangles, as the mesher cuts it). Returns the text and each object's spec index.
fn scene_toml(specs: &[PatchSpec], eye: [f64; 3], look_at: [f64; 3]) -> (String, Vec<usize>) {
    let mut s = format!(
        "[camera]\neye = {eye:?}\nlook_at = {look_at:?}\nfov = 40\n\n[image]\nwidth = 64\nheight = 48\n\n"
    );
    for (i, p) in specs.iter().enumerate() {
        let e = p.emission.map(|e| e / PI);
        writeln!(
            s,
            "[materials.m{i}]\ncolor = {:?}\ndiffuse = 1.0\nemission = {e:?}\n",
            p.reflectance
        )
        .unwrap();
    }
    let mut spec_of = Vec::new();
    for (i, p) in specs.iter().enumerate() {
        let c = &p.corners;
        let planar = c.len() == 3 || {
            let n = (c[1] - c[0]).cross(c[2] - c[0]).normalize();
            (c[3] - c[0]).dot(n).abs() < 1e-6 * c[0].distance(c[2])
        };
        let polys: Vec<Vec<glam::DVec3>> = if planar {
            vec![c.clone()]
        } else {
            vec![vec![c[0], c[1], c[2]], vec![c[0], c[2], c[3]]]
        };
        for poly in polys {
            let v: Vec<[f64; 3]> = poly.iter().map(|c| c.to_array()).collect();
            writeln!(
                s,
                "[[objects]]\nname = \"{}\"\ntype = \"polygon\"\nvertices = {v:?}\nmaterial = \"m{i}\"\n",
                p.name
            )
            .unwrap();
            spec_of.push(i);
        }
    }
    (s, spec_of)
}

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

fn load(path: &Path) -> (irradia_scene::Scene, Vec<PatchSpec>, Vec<usize>) {
    let scene = irradia_scene::load_file(path).unwrap();
    let (specs, objects, warnings) = patches_with_objects(&scene, 12).unwrap();
    assert!(warnings.is_empty(), "{warnings:?}");
    (scene, specs, objects)
}

fn input_error(r: Result<impl std::fmt::Debug, RadiosityError>) -> String {
    match r {
        Err(RadiosityError::Input(m)) => m,
        other => panic!("expected an input error, got {other:?}"),
    }
}

#[test]
fn empty_cornell_box_from_a_scene_file_matches_the_builtin() {
    let dir = tempfile::tempdir().unwrap();
    let builtin = scenes::cornell_empty();
    let (text, spec_of) = scene_toml(&builtin, [278.0, 273.0, -800.0], [278.0, 273.0, 0.0]);
    let path = write(dir.path(), "cornell.toml", &text);
    let (_, from_file, objects) = load(&path);
    assert_eq!(from_file.len(), spec_of.len());
    let cfg = Config {
        mesh: MeshOptions {
            max_element_area: Some(60.0 * 60.0),
            ..Default::default()
        },
        method: Method::Contour,
        params: Params {
            visibility_samples: 0,
            ..Default::default()
        },
        ..Default::default()
    };
    let a = run(&builtin, &cfg, &NoProgress).unwrap();
    let b = run(&from_file, &cfg, &NoProgress).unwrap();
    assert_eq!(a.mesh.len(), b.mesh.len());
    let ma = a.surface_means(builtin.len());
    // The scene file's surfaces, gathered back to the built-in's (area-weighted).
    let mut mb = vec![[0.0; 3]; builtin.len()];
    let mut area = vec![0.0; builtin.len()];
    for (e, bv) in b.mesh.elements.iter().zip(&b.solution.b) {
        let k = spec_of[objects[b.mesh.patches[e.patch as usize].source as usize]];
        for c in 0..3 {
            mb[k][c] += e.area * bv[c];
        }
        area[k] += e.area;
    }
    for (m, a) in mb.iter_mut().zip(&area) {
        *m = m.map(|x| x / a);
    }
    for (s, (x, y)) in builtin.iter().zip(ma.iter().zip(&mb)) {
        for c in 0..3 {
            // The scene stores f32 coordinates, colours and radiance (1e-4 measured).
            let rel = (x[c] - y[c]).abs() / x[c].abs().max(1e-12);
            assert!(rel < 5e-4, "{}: built-in {x:?}, scene file {y:?}", s.name);
        }
    }
}

/// A closed 1 m room of six polygons facing in, and a tessellated sphere standing in
/// it; one material that emits `E = 1` and reflects `rho` (leave out wall `skip`).
fn furnace_scene(rho: f64, skip: Option<usize>) -> String {
    let walls = scenes::closed_box(1.0, [rho; 3], [1.0; 3]);
    let mut s = format!(
        "[camera]\neye = [0.5, 0.5, 0.05]\nlook_at = [0.5, 0.5, 1]\nfov = 60\n\n\
         [materials.glow]\ncolor = [{rho}, {rho}, {rho}]\ndiffuse = 1.0\nemission = [{e}, {e}, {e}]\n\n\
         [[objects]]\nname = \"ball\"\ntype = \"sphere\"\ncenter = [0.5, 0.35, 0.5]\nradius = 0.25\nmaterial = \"glow\"\n\n",
        e = 1.0 / PI
    );
    for (i, w) in walls.iter().enumerate() {
        if Some(i) == skip {
            continue;
        }
        let v: Vec<[f64; 3]> = w.corners.iter().map(|c| c.to_array()).collect();
        writeln!(
            s,
            "[[objects]]\nname = \"{}\"\ntype = \"polygon\"\nvertices = {v:?}\nmaterial = \"glow\"\n",
            w.name
        )
        .unwrap();
    }
    s
}

#[test]
fn tessellated_sphere_in_a_closed_scene_file_room_is_a_furnace() {
    let dir = tempfile::tempdir().unwrap();
    let rho = 0.5;
    let path = write(dir.path(), "furnace.toml", &furnace_scene(rho, None));
    let (scene, specs, objects) = load(&path);
    // The sphere's facets and the walls close the room.
    check_closed(&specs, Some((&scene, &objects))).unwrap();
    let sphere_faces = objects.iter().filter(|&&o| o == 0).count();
    assert!(sphere_faces > 50, "{sphere_faces} facets");
    let expected = 1.0 / (1.0 - rho);
    // The hemicube: every pixel of a closed room sees exactly one element, so each
    // row of form factors sums to 1 with the sphere's occlusion included.
    let cfg = Config {
        mesh: MeshOptions {
            max_element_area: Some(1.0 / 36.0 * 1.000001),
            ..Default::default()
        },
        method: Method::Hemicube,
        params: Params {
            hemicube_resolution: 64,
            ..Default::default()
        },
        solver: SolverKind::GaussSeidel,
        solve: SolveOptions {
            tolerance: 1e-9,
            max_iterations: 10_000,
        },
        ..Default::default()
    };
    let r = run(&specs, &cfg, &NoProgress).unwrap();
    let (mut worst, mut energy_in, mut energy_out) = (0.0f64, 0.0, 0.0);
    for (e, b) in r.mesh.elements.iter().zip(&r.solution.b) {
        worst = worst.max((b[0] - expected).abs() / expected);
        energy_in += e.area * 1.0;
        energy_out += e.area * (1.0 - rho) * b[0];
    }
    let balance = (energy_out - energy_in).abs() / energy_in;
    println!(
        "{} elements: worst |B − E/(1−ρ)| / (E/(1−ρ)) = {worst:.2e}, energy balance {balance:.2e}",
        r.mesh.len()
    );
    // Emitted power equals absorbed power (energy conservation) and every element
    // reaches the furnace value; the remainder is the link form factors' quadrature
    // and shadow-ray error next to the sphere.
    assert!(balance < 1e-3, "absorbed/emitted power off by {balance}");
    assert!(worst < 1e-2, "furnace error {worst}");
}

#[test]
fn no_emitter_names_the_file_and_field() {
    let dir = tempfile::tempdir().unwrap();
    let text = furnace_scene(0.5, None).replace(
        &format!("emission = [{e}, {e}, {e}]", e = 1.0 / PI),
        "emission = [0, 0, 0]",
    );
    let path = write(dir.path(), "dark.toml", &text);
    let scene = irradia_scene::load_file(&path).unwrap();
    let m = input_error(patches_with_objects(&scene, 24));
    println!("{m}");
    assert!(m.starts_with(&format!("{}:", path.display())), "{m}");
    assert!(m.contains("materials") && m.contains("emission"), "{m}");
}

#[test]
fn reflectance_at_or_above_one_names_file_line_and_field() {
    let dir = tempfile::tempdir().unwrap();
    let text =
        furnace_scene(0.5, None).replace("color = [0.5, 0.5, 0.5]", "color = [1.0, 0.5, 0.5]");
    let path = write(dir.path(), "bright.toml", &text);
    let scene = irradia_scene::load_file(&path).unwrap();
    let m = input_error(patches_with_objects(&scene, 24));
    println!("{m}");
    let line = text
        .lines()
        .position(|l| l.starts_with("color = [1.0"))
        .unwrap()
        + 1;
    assert!(
        m.starts_with(&format!("{}:{line}:", path.display())),
        "expected line {line}: {m}"
    );
    assert!(
        m.contains("materials.glow.color") && m.contains("red"),
        "{m}"
    );
}

#[test]
fn open_room_where_a_closed_one_is_assumed_names_the_object() {
    let dir = tempfile::tempdir().unwrap();
    // Without the ceiling (wall 1): the walls' top edges are open.
    let text = furnace_scene(0.5, Some(1));
    let path = write(dir.path(), "open.toml", &text);
    let (scene, specs, objects) = load(&path);
    let m = input_error(check_closed(&specs, Some((&scene, &objects))));
    println!("{m}");
    assert!(m.starts_with(&format!("{}:", path.display())), "{m}");
    assert!(m.contains("objects[") && m.contains("open"), "{m}");
    // The line is that of an [[objects]] entry of a wall.
    let line: usize = m.split(':').nth(1).unwrap().parse().unwrap();
    let at = text.lines().nth(line - 1).unwrap();
    assert!(
        at.contains("objects") || at.starts_with("name"),
        "line {line}: {at}"
    );
}
