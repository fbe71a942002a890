//! An unbounded plane as a finite set of cells: the part of the plane inside the view
//! frustum (out to the far plane), cut by a quadtree whose cells shrink with their
//! distance from the eye, so that every cell covers about the same number of pixels.
//!
//! - Region: the plane meets the frustum in a convex polygon, the hull of where it
//!   crosses the frustum's twelve edges. Cells that miss the polygon are dropped (cells
//!   that stick out of it are kept whole: the pipeline's clipper cuts them, and no
//!   vertex is ever made that a neighbour does not share).
//! - Detail: a cell is split while it covers more than `max_cell_px` pixels, measured
//!   at its nearest point to the eye, and, on a checkered material, while it is larger
//!   than a check and still more than a pixel and a half wide. Cells are split largest
//!   on screen first until the budget ([`MAX_PLANE_CELLS`]) is spent, so a budget cut
//!   leaves the far cells whole.
//! - No cracks: cells of different sizes meet with T-junctions, which a rasterizer can
//!   leave pinholes at; each cell is drawn as a fan from its centre through every
//!   vertex on its edges, its neighbours' corners included.
//! - Checks: when the plane is perpendicular to a coordinate axis, the cells are
//!   aligned with the world axes and the quadtree's root is a power of two of checks,
//!   anchored at a check corner, so a cell no larger than a check lies inside one check
//!   and its colour (the texture at its centre) is exact.

use glam::{DVec2, Vec3};
use std::collections::HashSet;

/// Levels of the quadtree below its root.
const MAX_LEVEL: u32 = 20;
/// At most this many cells per plane.
pub const MAX_PLANE_CELLS: usize = 1 << 17;

/// The view a plane is cut for.
#[derive(Clone, Debug)]
pub struct PlaneView {
    /// The frustum's corners in world space (corner `k` has NDC x, y, z from bits 0, 1, 2).
    pub corners: [Vec3; 8],
    /// The eye, or `None` for a parallel projection.
    pub eye: Option<Vec3>,
    /// Pixel size at unit distance (perspective) or in world units (parallel).
    pub pixel: f32,
}

/// How finely to cut.
#[derive(Clone, Copy, Debug)]
pub struct PlaneDetail {
    /// Largest cell, in pixels.
    pub max_cell_px: f32,
    /// The check size of a checkered material.
    pub checker: Option<f32>,
}

/// The cells as triangles (vertices not shared between cells), each triangle with the
/// centre and side of its cell (where and over what its colour is taken).
#[derive(Clone, Debug, Default)]
pub struct PlaneMesh {
    pub positions: Vec<Vec3>,
    pub indices: Vec<[u32; 3]>,
    pub cell_centres: Vec<Vec3>,
    pub cell_sizes: Vec<f32>,
}

/// A square cell: corner and side in quadtree units, its level.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
struct Cell {
    x: u32,
    y: u32,
    size: u32,
    level: u32,
}

/// The plane through `point` with unit `normal`, cut for `view`. Triangles wind
/// counter-clockwise seen from the side `normal` points to.
pub fn tessellate_plane(
    point: Vec3,
    normal: Vec3,
    view: &PlaneView,
    detail: PlaneDetail,
) -> PlaneMesh {
    let n = normal.normalize_or_zero();
    if n == Vec3::ZERO {
        return PlaneMesh::default();
    }
    // In-plane axes: world axes when the plane is perpendicular to one (for checks).
    let major = n.abs().max_element();
    let aligned = major > 1.0 - 1e-6;
    let (u, v) = if aligned {
        let k = (0..3).find(|&k| n[k].abs() == major).unwrap_or(1);
        let (mut u, mut v) = (Vec3::ZERO, Vec3::ZERO);
        u[(k + 1) % 3] = 1.0;
        v[(k + 2) % 3] = 1.0;
        if u.cross(v).dot(n) < 0.0 {
            std::mem::swap(&mut u, &mut v);
        }
        (u, v)
    } else {
        let u = n.any_orthonormal_vector();
        (u, n.cross(u))
    };
    // 2D coordinates about the point of the plane nearest the world origin.
    let origin = n * n.dot(point);
    let to2 = |p: Vec3| DVec2::new((p - origin).dot(u) as f64, (p - origin).dot(v) as f64);
    let hull = convex_hull(frustum_crossings(point, n, &view.corners).map(to2));
    if hull.len() < 3 {
        return PlaneMesh::default();
    }
    let (mut lo, mut hi) = (hull[0], hull[0]);
    for p in &hull {
        lo = lo.min(*p);
        hi = hi.max(*p);
    }
    let mut side = (hi - lo).max_element().max(1e-6);
    let check = detail.checker.filter(|s| *s > 0.0 && s.is_finite());
    if let (Some(s), true) = (check, aligned) {
        // Root: a power of two of checks, anchored at a check corner.
        let s = s as f64;
        lo = (lo / s).floor() * s;
        side = ((hi - lo).max_element() / s).max(1.0);
        side = s * side.log2().ceil().exp2();
    }
    let unit = side / (1u64 << MAX_LEVEL) as f64;
    let eye = view.eye.map(|e| (to2(e), (e - point).dot(n).abs() as f64));
    let cell_world = |c: &Cell| c.size as f64 * unit;
    let pixels = |c: &Cell| {
        let size = cell_world(c);
        match eye {
            Some((e2, height)) => {
                let x0 = lo + DVec2::new(c.x as f64, c.y as f64) * unit;
                let near = e2.clamp(x0, x0 + DVec2::splat(size));
                let d = ((near - e2).length_squared() + height * height).sqrt();
                size / (d.max(1e-12) * view.pixel as f64)
            }
            None => size / view.pixel as f64,
        }
    };
    let split = |c: &Cell| {
        if c.level >= MAX_LEVEL {
            return false;
        }
        let px = pixels(c);
        px > detail.max_cell_px as f64
            || check.is_some_and(|s| {
                let limit = if aligned { s as f64 } else { 0.5 * s as f64 };
                cell_world(c) > limit * (1.0 + 1e-9) && px > 1.5
            })
    };
    let meets = |c: &Cell| {
        let x0 = lo + DVec2::new(c.x as f64, c.y as f64) * unit;
        square_meets_convex(x0, cell_world(c), &hull)
    };
    // Largest on screen first, so that when the budget runs out the cells left whole
    // are the smallest on screen (the far ones).
    let root = Cell {
        x: 0,
        y: 0,
        size: 1 << MAX_LEVEL,
        level: 0,
    };
    let key = |c: &Cell| (pixels(c).max(0.0).to_bits(), c.x, c.y);
    let mut leaves = Vec::new();
    let mut queue = std::collections::BinaryHeap::new();
    if meets(&root) {
        queue.push((key(&root), root));
    }
    while let Some((_, c)) = queue.pop() {
        if split(&c) && leaves.len() + queue.len() + 4 <= MAX_PLANE_CELLS {
            let h = c.size / 2;
            for (dx, dy) in [(0, 0), (h, 0), (0, h), (h, h)] {
                let k = Cell {
                    x: c.x + dx,
                    y: c.y + dy,
                    size: h,
                    level: c.level + 1,
                };
                if meets(&k) {
                    queue.push((key(&k), k));
                }
            }
        } else {
            leaves.push(c);
        }
    }
    leaves.sort_by_key(|c| (c.y, c.x));
    let corners: HashSet<(u32, u32)> = leaves
        .iter()
        .flat_map(|c| {
            let (x1, y1) = (c.x + c.size, c.y + c.size);
            [(c.x, c.y), (x1, c.y), (x1, y1), (c.x, y1)]
        })
        .collect();
    let world = |x: f64, y: f64| {
        let q = lo + DVec2::new(x, y) * unit;
        origin + u * q.x as f32 + v * q.y as f32
    };
    let mut out = PlaneMesh::default();
    let mut ring = Vec::new();
    for c in &leaves {
        let (x1, y1) = (c.x + c.size, c.y + c.size);
        ring.clear();
        let square = [(c.x, c.y), (x1, c.y), (x1, y1), (c.x, y1)];
        for k in 0..4 {
            ring.push(square[k]);
            edge_points(square[k], square[(k + 1) % 4], &corners, &mut ring);
        }
        let half = c.size as f64 / 2.0;
        let centre = world(c.x as f64 + half, c.y as f64 + half);
        let base = out.positions.len() as u32;
        let size = cell_world(c) as f32;
        out.positions
            .extend(ring.iter().map(|&(x, y)| world(x as f64, y as f64)));
        if ring.len() == 4 {
            out.indices.push([base, base + 1, base + 2]);
            out.indices.push([base, base + 2, base + 3]);
            out.cell_centres.extend([centre, centre]);
            out.cell_sizes.extend([size, size]);
        } else {
            let mid = out.positions.len() as u32;
            out.positions.push(centre);
            let k = ring.len() as u32;
            for i in 0..k {
                out.indices.push([mid, base + i, base + (i + 1) % k]);
                out.cell_centres.push(centre);
                out.cell_sizes.push(size);
            }
        }
    }
    out
}

/// Appends the corners of other cells that lie strictly inside edge `a`-`b`, in order
/// from `a` (they sit at dyadic points: a point exists only if the midpoint does).
fn edge_points(
    a: (u32, u32),
    b: (u32, u32),
    corners: &HashSet<(u32, u32)>,
    out: &mut Vec<(u32, u32)>,
) {
    let len = a.0.abs_diff(b.0).max(a.1.abs_diff(b.1));
    if len < 2 {
        return;
    }
    let m = ((a.0 + b.0) / 2, (a.1 + b.1) / 2);
    if corners.contains(&m) {
        edge_points(a, m, corners, out);
        out.push(m);
        edge_points(m, b, corners, out);
    }
}

/// Where the plane crosses the twelve edges of the frustum with corners `c`.
fn frustum_crossings(point: Vec3, n: Vec3, c: &[Vec3; 8]) -> impl Iterator<Item = Vec3> + '_ {
    let dist = move |p: Vec3| (p - point).dot(n);
    (0..8usize).flat_map(move |a| {
        [1usize, 2, 4].into_iter().filter_map(move |bit| {
            let b = a | bit;
            if b == a {
                return None;
            }
            let (da, db) = (dist(c[a]), dist(c[b]));
            if (da <= 0.0) == (db <= 0.0) && da != 0.0 {
                return None;
            }
            let t = if da == db { 0.0 } else { da / (da - db) };
            Some(c[a] + (c[b] - c[a]) * t)
        })
    })
}

/// Convex hull, counter-clockwise (Andrew's monotone chain).
fn convex_hull(points: impl Iterator<Item = DVec2>) -> Vec<DVec2> {
    let mut p: Vec<DVec2> = points.filter(|q| q.is_finite()).collect();
    p.sort_by(|a, b| a.x.total_cmp(&b.x).then(a.y.total_cmp(&b.y)));
    p.dedup();
    if p.len() < 3 {
        return p;
    }
    let cross = |o: DVec2, a: DVec2, b: DVec2| (a - o).perp_dot(b - o);
    let mut hull: Vec<DVec2> = Vec::with_capacity(2 * p.len());
    for pass in 0..2 {
        let start = hull.len();
        let iter: Box<dyn Iterator<Item = &DVec2>> = if pass == 0 {
            Box::new(p.iter())
        } else {
            Box::new(p.iter().rev())
        };
        for &q in iter {
            while hull.len() >= start + 2
                && cross(hull[hull.len() - 2], hull[hull.len() - 1], q) <= 0.0
            {
                hull.pop();
            }
            hull.push(q);
        }
        hull.pop();
    }
    hull
}

/// Whether the square `[x0, x0 + size]²` meets the convex polygon `hull` (CCW):
/// separating axes are the square's two axes and the polygon's edge normals.
fn square_meets_convex(x0: DVec2, size: f64, hull: &[DVec2]) -> bool {
    let x1 = x0 + DVec2::splat(size);
    let (mut lo, mut hi) = (hull[0], hull[0]);
    for p in hull {
        lo = lo.min(*p);
        hi = hi.max(*p);
    }
    if hi.x < x0.x || hi.y < x0.y || lo.x > x1.x || lo.y > x1.y {
        return false;
    }
    let corners = [x0, DVec2::new(x1.x, x0.y), x1, DVec2::new(x0.x, x1.y)];
    for i in 0..hull.len() {
        let (a, b) = (hull[i], hull[(i + 1) % hull.len()]);
        let outward = DVec2::new(b.y - a.y, a.x - b.x);
        if corners.iter().all(|c| (*c - a).dot(outward) > 0.0) {
            return false;
        }
    }
    true
}

#[cfg(test)]
mod tests {
    use super::*;

    fn view() -> PlaneView {
        let vp = glam::Mat4::perspective_rh(0.8, 1.5, 0.1, 500.0)
            * glam::Mat4::look_at_rh(Vec3::new(0.0, 2.0, 6.0), Vec3::ZERO, Vec3::Y);
        let inv = vp.inverse();
        let corners = std::array::from_fn(|k| {
            let ndc = glam::Vec4::new(
                if k & 1 == 0 { -1.0 } else { 1.0 },
                if k & 2 == 0 { -1.0 } else { 1.0 },
                if k & 4 == 0 { 0.0 } else { 1.0 },
                1.0,
            );
            let h = inv * ndc;
            h.truncate() / h.w
        });
        PlaneView {
            corners,
            eye: Some(Vec3::new(0.0, 2.0, 6.0)),
            pixel: 0.01,
        }
    }

    #[test]
    fn cells_are_flat_face_up_follow_the_checks_and_have_no_t_junctions() {
        let m = tessellate_plane(
            Vec3::ZERO,
            Vec3::Y,
            &view(),
            PlaneDetail {
                max_cell_px: 20.0,
                checker: Some(1.0),
            },
        );
        assert!(m.indices.len() > 100);
        let mut area = 0.0;
        for t in &m.indices {
            let [a, b, c] = t.map(|k| m.positions[k as usize]);
            assert_eq!((a.y, b.y, c.y), (0.0, 0.0, 0.0));
            let n = (b - a).cross(c - a);
            assert!(n.y >= 0.0, "triangle faces down");
            area += n.y as f64 / 2.0;
        }
        assert!(area > 100.0, "{area}");
        // No T-junction: no vertex lies at the midpoint of another triangle's edge
        // (where a smaller neighbour's corner would sit).
        let q = |p: Vec3| ((p.x * 1e3).round() as i64, (p.z * 1e3).round() as i64);
        let verts: HashSet<(i64, i64)> = m.positions.iter().map(|p| q(*p)).collect();
        let mut edges = 0;
        for t in &m.indices {
            for k in 0..3 {
                let (a, b) = (
                    m.positions[t[k] as usize],
                    m.positions[t[(k + 1) % 3] as usize],
                );
                if (a - b).length() < 0.05 {
                    continue;
                }
                edges += 1;
                let (mx, mz) = q((a + b) * 0.5);
                let hit = (-1..=1).any(|dx| (-1..=1).any(|dz| verts.contains(&(mx + dx, mz + dz))));
                assert!(!hit, "a vertex sits inside the edge {a} - {b}");
            }
        }
        assert!(edges > 100);
        // Every cell no larger than a check lies inside one check.
        for (t, c) in m.indices.iter().zip(&m.cell_centres) {
            for &k in t {
                let p = m.positions[k as usize];
                let cell = |x: f32| x.floor();
                if (p - *c).abs().max_element() < 0.5 {
                    let inside = (cell(p.x + 1e-4 * (c.x - p.x).signum()) == cell(c.x))
                        && (cell(p.z + 1e-4 * (c.z - p.z).signum()) == cell(c.z));
                    assert!(inside, "vertex {p} of the cell at {c} is in another check");
                }
            }
        }
    }
}
