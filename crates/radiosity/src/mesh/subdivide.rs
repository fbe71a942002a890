//! Uniform substructuring of a patch into elements (Cohen, Greenberg, Immel, Brock 1986,
//! "An efficient radiosity approach for realistic image synthesis"): a quadrilateral
//! becomes a k x m grid of bilinear cells, a triangle an n x n lattice of triangles, so
//! that every element has at most the requested area and the elements of one patch
//! share their corners (a conforming mesh: no T-vertices inside a patch).

use crate::geom::Poly;
use glam::DVec3;

/// Cells along each side so that every element's area stays at or below `max_area`.
pub fn grid_size(p: &Poly, max_area: f64) -> (usize, usize) {
    let area = p.area();
    if max_area.is_nan() || max_area <= 0.0 || area <= max_area {
        return (1, 1);
    }
    if p.n == 3 {
        let n = (area / max_area).sqrt().ceil() as usize;
        return (n.max(1), n.max(1));
    }
    // Side lengths along the two parameter directions; near-square cells.
    let lu = 0.5 * (p.v[0].distance(p.v[1]) + p.v[3].distance(p.v[2]));
    let lv = 0.5 * (p.v[0].distance(p.v[3]) + p.v[1].distance(p.v[2]));
    let s = max_area.sqrt();
    let mut k = (lu / s).ceil().max(1.0) as usize;
    let mut m = (lv / s).ceil().max(1.0) as usize;
    // Bilinear cells of a trapezoid differ in area: grow until all fit.
    while largest_cell(p, k, m) > max_area * (1.0 + 1e-9) {
        if lu / k as f64 >= lv / m as f64 {
            k += 1;
        } else {
            m += 1;
        }
    }
    (k, m)
}

fn largest_cell(p: &Poly, k: usize, m: usize) -> f64 {
    let mut best: f64 = 0.0;
    for &(i, j) in &[(0, 0), (k - 1, 0), (0, m - 1), (k - 1, m - 1)] {
        best = best.max(cell(p, k, m, i, j).area());
    }
    best
}

fn bilinear(p: &Poly, s: f64, t: f64) -> DVec3 {
    p.v[0] * (1.0 - s) * (1.0 - t)
        + p.v[1] * s * (1.0 - t)
        + p.v[2] * s * t
        + p.v[3] * (1.0 - s) * t
}

fn cell(p: &Poly, k: usize, m: usize, i: usize, j: usize) -> Poly {
    let (s0, s1) = (i as f64 / k as f64, (i + 1) as f64 / k as f64);
    let (t0, t1) = (j as f64 / m as f64, (j + 1) as f64 / m as f64);
    Poly::quad(
        bilinear(p, s0, t0),
        bilinear(p, s1, t0),
        bilinear(p, s1, t1),
        bilinear(p, s0, t1),
    )
}

/// The elements of one patch at the given grid size.
pub fn subdivide(p: &Poly, (k, m): (usize, usize)) -> Vec<Poly> {
    let mut out = Vec::with_capacity(k * m);
    if p.n == 3 {
        let n = k;
        let (a, b, c) = (p.v[0], p.v[1], p.v[2]);
        let at = |i: usize, j: usize| {
            a + (b - a) * (i as f64 / n as f64) + (c - a) * (j as f64 / n as f64)
        };
        for j in 0..n {
            for i in 0..n - j {
                out.push(Poly::tri(at(i, j), at(i + 1, j), at(i, j + 1)));
                if i + j + 1 < n {
                    out.push(Poly::tri(at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)));
                }
            }
        }
        return out;
    }
    for j in 0..m {
        for i in 0..k {
            out.push(cell(p, k, m, i, j));
        }
    }
    out
}

/// Number of elements `subdivide` makes.
pub fn element_count(p: &Poly, (k, m): (usize, usize)) -> usize {
    if p.n == 3 {
        k * k
    } else {
        k * m
    }
}
