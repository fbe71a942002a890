//! The measured Cornell box (reference/cornell-box.md): from the light, the form factors
//! to the empty box's floor, back wall and side walls plus the open front sum to 1; the
//! same closure through the numerical methods; and the solved box is plausible.
//!
//! The comparison with the path tracer is tests/path_agreement.rs.

use glam::DVec3;
use irradia_radiosity::formfactor::contour::point_to_polygon;
use irradia_radiosity::formfactor::{self, Method, Params};
use irradia_radiosity::geom::Poly;
use irradia_radiosity::mesh::{Mesh, MeshOptions};
use irradia_radiosity::scenes;

fn area_to_polygon(from: &Poly, to: &[DVec3], gauss: usize) -> f64 {
    let n = from.normal();
    from.gauss_points(gauss)
        .iter()
        .map(|(x, w)| w * point_to_polygon(*x, n, to))
        .sum::<f64>()
        / from.area()
}

#[test]
fn light_form_factors_sum_to_one() {
    let specs = scenes::cornell_empty();
    let light = specs.iter().find(|s| s.name == "light").unwrap();
    let lp = Poly::from_slice(&light.corners).unwrap();
    let mut total = 0.0;
    for name in ["floor", "back wall", "green wall", "red wall"] {
        let s = specs.iter().find(|s| s.name == name).unwrap();
        // The red wall is not planar: cut it as the mesher does (two triangles).
        let parts: Vec<Vec<DVec3>> = if name == "red wall" {
            vec![
                vec![s.corners[0], s.corners[1], s.corners[2]],
                vec![s.corners[0], s.corners[2], s.corners[3]],
            ]
        } else {
            vec![s.corners.clone()]
        };
        let f: f64 = parts.iter().map(|c| area_to_polygon(&lp, c, 8)).sum();
        println!("light -> {name}: {f:.6}");
        total += f;
    }
    let front = area_to_polygon(&lp, &scenes::cornell_front_opening(), 8);
    println!("light -> open front: {front:.6}");
    total += front;
    for s in specs.iter().filter(|s| s.name.starts_with("ceiling")) {
        assert!(
            area_to_polygon(&lp, &s.corners, 4).abs() < 1e-12,
            "the light cannot see the ceiling it lies in"
        );
    }
    println!("sum: {total:.12}");
    assert!(
        (total - 1.0).abs() < 1e-9,
        "light form factors sum to {total}"
    );
}

#[test]
fn light_rows_plus_front_sum_to_one_numerically() {
    let specs = scenes::cornell_empty();
    let mesh = Mesh::build(
        &specs,
        MeshOptions {
            max_element_area: Some(140.0 * 140.0),
            ..Default::default()
        },
    )
    .unwrap();
    let front = scenes::cornell_front_opening();
    for m in [Method::Hemicube, Method::Hemisphere, Method::Analytic] {
        let ff = formfactor::method(
            m,
            Params {
                hemicube_resolution: 256,
                hemisphere_resolution: 128,
                visibility_samples: 0,
                ..Default::default()
            },
        )
        .compute(&mesh, None)
        .unwrap();
        for (i, e) in mesh.elements.iter().enumerate() {
            if mesh.patches[e.patch as usize].name != "light" {
                continue;
            }
            let row: f64 = ff.row(i).iter().sum();
            let f_front = area_to_polygon(&e.poly, &front, 6);
            println!(
                "{}: light element {i}: row {row:.5} + front {f_front:.5} = {:.5}",
                m.name(),
                row + f_front
            );
            assert!(
                (row + f_front - 1.0).abs() < 3e-3,
                "{}: {row} + {f_front}",
                m.name()
            );
        }
    }
}

#[test]
fn solved_box_is_plausible() {
    let specs = scenes::cornell_measured();
    let cfg = irradia_radiosity::pipeline::Config {
        mesh: MeshOptions {
            max_element_area: Some(100.0 * 100.0),
            ..Default::default()
        },
        method: Method::Hemicube,
        params: Params {
            hemicube_resolution: 64,
            ..Default::default()
        },
        ..Default::default()
    };
    let r =
        irradia_radiosity::pipeline::run(&specs, &cfg, &irradia_radiosity::pipeline::NoProgress)
            .unwrap();
    assert!(
        r.solution.residual < 1e-5,
        "residual {}",
        r.solution.residual
    );
    let means = r.surface_means(specs.len());
    let get = |n: &str| means[specs.iter().position(|s| s.name == n).unwrap()];
    let (red, green, floor) = (get("red wall"), get("green wall"), get("floor"));
    println!("red wall {red:?}\ngreen wall {green:?}\nfloor {floor:?}");
    assert!(red[0] > 3.0 * red[1], "the red wall is red");
    assert!(green[1] > 2.0 * green[0], "the green wall is green");
    assert!(floor.iter().all(|&v| v > 0.0));
    // The floor is lit directly: brighter than the ceiling, which is lit only indirectly.
    let ceil = get("ceiling front");
    assert!(floor[0] > ceil[0]);
}

// The acceptance test (mean radiosity of each surface within 2% of the path
// tracer) lives in tests/path_agreement.rs, written with the path tracer.
