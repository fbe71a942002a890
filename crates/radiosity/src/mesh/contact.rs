//! Contact lines: where an edge of one patch lies in the plane of another patch (a block
//! standing on the floor, a shelf against a wall), radiosity jumps across that line (the
//! floor under the block is dark, the floor beside it is lit: a D0 discontinuity in the
//! sense of Heckbert 1992, "Discontinuity meshing for radiosity", and Lischinski,
//! Tampieri, Greenberg 1992). An element that straddles the line averages the dark and
//! the lit part, and every element that sees only the lit part (the block's side) then
//! receives too little; an element whose single quadrature point falls on the dark side
//! is black altogether. Splitting the patch along its contact lines before meshing makes
//! every element lie on one side (a discontinuity-conforming mesh).
//!
//! The split is a binary space partition restricted to the contact segments: a piece is
//! cut by the line of a segment only where that segment actually runs through the
//! piece's interior, so the cuts do not run across the whole patch. Pieces are convex;
//! those with more than four corners are cut into quadrilaterals and a triangle.

use super::Patch;
use crate::geom::Poly;
use glam::DVec3;

/// Relative length (of the scene size) below which points coincide and pieces vanish.
const TOLERANCE: f64 = 1e-7;

/// Splits every patch along the edges of other patches that lie in its plane and cross
/// its interior. Returns the patches unchanged (same order) where nothing touches them.
pub fn split_at_contacts(patches: Vec<Patch>, scale: f64) -> Vec<Patch> {
    let tol = TOLERANCE * scale.max(1e-300);
    let mut out = Vec::with_capacity(patches.len());
    for (pi, p) in patches.iter().enumerate() {
        let segments = contact_segments(&patches, pi, tol);
        if segments.is_empty() {
            out.push(p.clone());
            continue;
        }
        let n = p.poly.normal();
        let mut pieces: Vec<Vec<DVec3>> = vec![p.poly.verts().to_vec()];
        for &(a, b) in &segments {
            let mut next = Vec::with_capacity(pieces.len() + 1);
            for piece in pieces {
                match cut(&piece, n, a, b, tol) {
                    Some((l, r)) => {
                        next.push(l);
                        next.push(r);
                    }
                    None => next.push(piece),
                }
            }
            pieces = next;
        }
        for piece in pieces {
            for poly in convex_to_polys(&piece) {
                if poly.area() > tol * tol {
                    out.push(Patch { poly, ..p.clone() });
                }
            }
        }
    }
    out
}

/// Edges of other patches lying in patch `pi`'s plane and overlapping it, clipped to it.
fn contact_segments(patches: &[Patch], pi: usize, tol: f64) -> Vec<(DVec3, DVec3)> {
    let p = &patches[pi].poly;
    let n = p.normal();
    let origin = p.v[0];
    let mut out = Vec::new();
    for (qi, q) in patches.iter().enumerate() {
        if qi == pi || q.poly.normal().dot(n).abs() > 1.0 - 1e-9 {
            continue; // coplanar neighbours meet only along shared boundaries
        }
        let vs = q.poly.verts();
        for k in 0..vs.len() {
            let (a, b) = (vs[k], vs[(k + 1) % vs.len()]);
            if n.dot(a - origin).abs() > tol || n.dot(b - origin).abs() > tol {
                continue;
            }
            if let Some(s) = clip_segment(p, n, a, b, tol) {
                out.push(s);
            }
        }
    }
    out
}

/// The part of segment `ab` (in the polygon's plane) inside the convex polygon.
fn clip_segment(p: &Poly, n: DVec3, a: DVec3, b: DVec3, tol: f64) -> Option<(DVec3, DVec3)> {
    let vs = p.verts();
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    let d = b - a;
    for k in 0..vs.len() {
        let (e0, e1) = (vs[k], vs[(k + 1) % vs.len()]);
        // Inward normal of the edge, in the plane.
        let inward = n.cross(e1 - e0).normalize_or_zero();
        let fa = inward.dot(a - e0);
        let fd = inward.dot(d);
        if fd.abs() < 1e-300 {
            if fa < -tol {
                return None;
            }
            continue;
        }
        let t = -fa / fd;
        if fd > 0.0 {
            t0 = t0.max(t);
        } else {
            t1 = t1.min(t);
        }
    }
    ((t1 - t0) * d.length() > tol).then(|| (a + d * t0, a + d * t1))
}

/// Cuts a convex piece (normal `n`) by the line through `a`, `b` when the segment `ab`
/// runs through its interior; `None` when the line misses it or only touches its boundary.
fn cut(
    piece: &[DVec3],
    n: DVec3,
    a: DVec3,
    b: DVec3,
    tol: f64,
) -> Option<(Vec<DVec3>, Vec<DVec3>)> {
    let side = n.cross(b - a).normalize_or_zero();
    let f: Vec<f64> = piece.iter().map(|v| side.dot(*v - a)).collect();
    if f.iter().all(|&x| x > -tol) || f.iter().all(|&x| x < tol) {
        return None;
    }
    // The segment must overlap the piece (not just its line).
    let poly_of = |vs: &[DVec3]| match vs.len() {
        3 | 4 => Poly::from_slice(vs),
        _ => None,
    };
    let overlaps = match poly_of(piece) {
        Some(p) => clip_segment(&p, n, a, b, tol).is_some(),
        None => convex_to_polys(piece)
            .iter()
            .any(|p| clip_segment(p, n, a, b, tol).is_some()),
    };
    if !overlaps {
        return None;
    }
    let (mut left, mut right) = (Vec::new(), Vec::new());
    for k in 0..piece.len() {
        let (p0, p1) = (piece[k], piece[(k + 1) % piece.len()]);
        let (f0, f1) = (f[k], f[(k + 1) % piece.len()]);
        if f0 >= -tol {
            left.push(p0);
        }
        if f0 <= tol {
            right.push(p0);
        }
        if (f0 > tol && f1 < -tol) || (f0 < -tol && f1 > tol) {
            let x = p0 + (p1 - p0) * (f0 / (f0 - f1));
            left.push(x);
            right.push(x);
        }
    }
    (left.len() >= 3 && right.len() >= 3).then_some((left, right))
}

/// A convex polygon as quadrilaterals and at most one triangle (a fan of quads from the
/// first corner).
fn convex_to_polys(vs: &[DVec3]) -> Vec<Poly> {
    let mut out = Vec::new();
    let mut k = 1;
    while k + 2 < vs.len() {
        out.push(Poly::quad(vs[0], vs[k], vs[k + 1], vs[k + 2]));
        k += 2;
    }
    if k + 1 < vs.len() {
        out.push(Poly::tri(vs[0], vs[k], vs[k + 1]));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn patch(name: &str, c: &[DVec3]) -> Patch {
        Patch {
            name: name.into(),
            poly: Poly::from_slice(c).unwrap(),
            reflectance: [0.5; 3],
            emission: [0.0; 3],
            source: 0,
        }
    }

    fn v(x: f64, y: f64, z: f64) -> DVec3 {
        DVec3::new(x, y, z)
    }

    #[test]
    fn a_wall_standing_on_a_floor_splits_it_and_keeps_its_area() {
        let floor = patch(
            "floor",
            &[
                v(0., 0., 0.),
                v(0., 0., 10.),
                v(10., 0., 10.),
                v(10., 0., 0.),
            ],
        );
        // A slanted wall whose bottom edge runs from (2,0,3) to (7,0,5).
        let wall = patch(
            "wall",
            &[v(2., 0., 3.), v(7., 0., 5.), v(7., 4., 5.), v(2., 4., 3.)],
        );
        let out = split_at_contacts(vec![floor.clone(), wall], 20.0);
        let floor_pieces: Vec<_> = out.iter().filter(|p| p.name == "floor").collect();
        assert!(floor_pieces.len() >= 2, "{}", floor_pieces.len());
        let area: f64 = floor_pieces.iter().map(|p| p.area()).sum();
        assert!((area - 100.0).abs() < 1e-9, "{area}");
        // No piece straddles the contact segment: every piece lies on one side of it
        // wherever the segment passes.
        let (a, b) = (v(2., 0., 3.), v(7., 0., 5.));
        let side = DVec3::Y.cross(b - a).normalize();
        for p in &floor_pieces {
            let f: Vec<f64> = p.poly.verts().iter().map(|x| side.dot(*x - a)).collect();
            let straddles = f.iter().any(|&x| x > 1e-9) && f.iter().any(|&x| x < -1e-9);
            if straddles {
                // Allowed only if the piece does not reach the segment.
                assert!(clip_segment(&p.poly, p.poly.normal(), a, b, 1e-9).is_none());
            }
        }
        // The wall itself is untouched.
        assert_eq!(out.iter().filter(|p| p.name == "wall").count(), 1);
    }

    #[test]
    fn boundary_contacts_do_not_split() {
        let floor = patch(
            "floor",
            &[
                v(0., 0., 0.),
                v(0., 0., 10.),
                v(10., 0., 10.),
                v(10., 0., 0.),
            ],
        );
        let wall = patch(
            "wall",
            &[v(0., 0., 0.), v(10., 0., 0.), v(10., 4., 0.), v(0., 4., 0.)],
        );
        let out = split_at_contacts(vec![floor, wall], 20.0);
        assert_eq!(out.len(), 2);
    }
}
