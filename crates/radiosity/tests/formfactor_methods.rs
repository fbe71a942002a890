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
