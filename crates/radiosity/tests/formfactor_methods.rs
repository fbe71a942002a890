//! Closure (rows sum to 1 in a closed box) and reciprocity (A_i F_ij = A_j F_ji), tested
//! separately for every numerical form-factor method, and the convergence of the
//! hemicube (error falls as the resolution grows) and of ray casting (error falls as
//! rays^-1/2).

mod common;

use irradia_radiosity::formfactor::{self, FormFactors, Method, Params};
use irradia_radiosity::mesh::Mesh;

fn matrix(m: Method, mesh: &Mesh, p: Params) -> FormFactors {
    formfactor::method(m, p).compute(mesh, None).unwrap()
}

fn params() -> Params {
    Params {
        hemicube_resolution: 96,
        hemisphere_resolution: 64,
        rays: 16,
        samples: 1024,
        visibility_samples: 0,
        gauss_points: 4,
        seed: 3,
    }
}

// Reciprocity tolerances: the centroid (contour, hemisphere, hemicube) and vertex
// (raycast) methods evaluate a point, not the element, so neighbours at right angles
// differ by a few per cent between the two directions at 4 x 4 elements per wall; the
// analytic method integrates the sender and is reciprocal to quadrature accuracy;
// Monte Carlo is reciprocal by construction.

/// Worst |row sum − 1| over all rows.
fn closure_error(ff: &FormFactors) -> f64 {
    ff.row_sums()
        .iter()
        .map(|s| (s - 1.0).abs())
        .fold(0.0, f64::max)
}

fn check_closure(m: Method, tol: f64) {
    let mesh = common::furnace(4);
    let ff = matrix(m, &mesh, params());
    let e = closure_error(&ff);
    println!(
        "{}: closure error {e:.3e}; {}",
        m.name(),
        ff.diagnostics(&mesh)
    );
    assert!(
        e < tol,
        "{}: rows of a closed box sum to 1 within {tol}, worst is off by {e}",
        m.name()
    );
}

fn check_reciprocity(m: Method, tol: f64) {
    let mesh = common::furnace(4);
    let ff = matrix(m, &mesh, params());
    let d = ff.diagnostics(&mesh);
    println!("{}: {d}", m.name());
    assert!(
        d.reciprocity_relative < tol,
        "{}: reciprocity error {} above {tol}",
        m.name(),
        d.reciprocity_relative
    );
}

#[test]
fn closure_analytic() {
    check_closure(Method::Analytic, 2e-3);
}
#[test]
fn closure_contour() {
    check_closure(Method::Contour, 1e-9);
}
#[test]
fn closure_hemisphere() {
    check_closure(Method::Hemisphere, 1e-4);
}
#[test]
fn closure_hemicube() {
    check_closure(Method::Hemicube, 1e-9);
}
#[test]
fn closure_raycast() {
    check_closure(Method::RayCast, 1e-9);
}
#[test]
fn closure_montecarlo() {
    check_closure(Method::MonteCarlo, 0.15);
}

#[test]
fn reciprocity_analytic() {
    check_reciprocity(Method::Analytic, 2e-3);
}
#[test]
fn reciprocity_contour() {
    check_reciprocity(Method::Contour, 0.08);
}
#[test]
fn reciprocity_hemisphere() {
    check_reciprocity(Method::Hemisphere, 0.08);
}
#[test]
fn reciprocity_hemicube() {
    check_reciprocity(Method::Hemicube, 0.08);
}
#[test]
fn reciprocity_raycast() {
    check_reciprocity(Method::RayCast, 0.15);
}
#[test]
fn reciprocity_montecarlo() {
    check_reciprocity(Method::MonteCarlo, 1e-12);
}

/// Two perpendicular rectangles sharing an edge (the lecture's "perpendicular rectangles
/// sharing an edge"), each `per_side` x `per_side` elements: rectangle 1 (the sender,
/// `w` x `l`, z = 0, normal +z) and rectangle 2 (`h` x `l`, x = 0, normal +x).
fn perpendicular_pair(w: f64, h: f64, l: f64, per_side: usize) -> (Mesh, f64) {
    use glam::DVec3;
    use irradia_radiosity::mesh::{spec, MeshOptions};
    let v = DVec3::new;
    let r1 = [v(0., 0., 0.), v(w, 0., 0.), v(w, l, 0.), v(0., l, 0.)];
    let r2 = [v(0., 0., 0.), v(0., l, 0.), v(0., l, h), v(0., 0., h)];
    let specs = [
        spec("sender", &r1, [0.5; 3], [1.0; 3]),
        spec("receiver", &r2, [0.5; 3], [0.0; 3]),
    ];
    let area = (w * l).max(h * l) / (per_side * per_side) as f64 * 1.000001;
    let mesh = Mesh::build(
        &specs,
        MeshOptions {
            max_element_area: Some(area),
            ..Default::default()
        },
    )
    .unwrap();
    let exact = formfactor::analytic::rectangles::perpendicular_rectangles(h / l, w / l);
    (mesh, exact)
}

/// `F_{1→2}` of the two patches from an element matrix: `Σ_{i∈1, j∈2} A_i F_ij / A_1`.
fn patch_form_factor(mesh: &Mesh, ff: &FormFactors) -> f64 {
    let (mut s, mut a1) = (0.0, 0.0);
    for (i, ei) in mesh.elements.iter().enumerate() {
        if ei.patch != 0 {
            continue;
        }
        a1 += ei.area;
        for (j, ej) in mesh.elements.iter().enumerate() {
            if ej.patch == 1 {
                s += ei.area * ff.get(i, j);
            }
        }
    }
    s / a1
}

#[test]
fn edge_adjacent_elements_match_the_closed_form() {
    // The contour method's single centroid point is 5% low for elements that share an
    // edge; its rows with a near neighbour use a 3 x 3 Gauss rule over the element.
    let p = Params {
        visibility_samples: 0,
        ..params()
    };
    for (w, h, l, per_side, tol) in [
        (1.0, 1.0, 1.0, 1, 1e-4),
        (2.0, 0.5, 1.0, 1, 3e-3),
        (1.0, 1.0, 1.0, 4, 2e-3),
        (1.0, 3.0, 2.0, 3, 2e-3),
    ] {
        let (mesh, exact) = perpendicular_pair(w, h, l, per_side);
        let ff = matrix(Method::Contour, &mesh, p);
        let f = patch_form_factor(&mesh, &ff);
        println!(
            "w {w} h {h} l {l}, {per_side}² elements: contour {f:.6}, exact {exact:.6}, relative {:.2e}",
            (f - exact) / exact
        );
        assert!(
            ((f - exact) / exact).abs() < tol,
            "perpendicular rectangles sharing an edge: {f} vs {exact}"
        );
    }
}
