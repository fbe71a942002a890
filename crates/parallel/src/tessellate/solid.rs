//! Solids that have no facets of their own (CSG trees, implicit surfaces, unbounded
//! quadrics) as triangle meshes: marching cubes (Lorensen and Cline 1987; the
//! crack-free table of `irradia_geometry::generators::marching_cubes`) over an
//! inside/outside grid, with every vertex moved onto the true surface.
//!
//! The only thing asked of the shape is its CSG spans (Roth 1982, "Ray casting for
//! modeling solids"): the intervals of a line that lie inside the solid. One ray along
//! every grid line in x, y and z (3n² rays for an n³ grid instead of n³ inside tests)
//! gives, at once,
//! - the classification of the grid points (from the x lines: inside is -1, outside
//!   +1, so marching cubes puts a vertex at the midpoint of every edge whose ends
//!   differ and winds its triangles with normals pointing out of the solid), and
//! - where each such edge really crosses the surface, with the surface's outward normal
//!   and CSG leaf there (from the line along the edge's own axis).
//!
//! So vertices lie on the surface to within the shape's own intersection precision
//! (not the linear interpolation of a sampled field), normals are the shape's normals,
//! and each triangle knows which CSG leaf it belongs to (for per-leaf materials).
//! Features thinner than a grid cell can be lost, as with any sampled surface.

use glam::{UVec3, Vec3};
use irradia_core::{Aabb, Ray};
use irradia_geometry::generators::{marching_cubes, ScalarGrid};
use irradia_geometry::{Shape, Span};
use rayon::prelude::*;

/// A tessellated surface in the shape's own (object) space.
#[derive(Clone, Debug, Default)]
pub struct SolidMesh {
    pub positions: Vec<Vec3>,
    /// Unit outward normals (the shape's, where the crossing was found; otherwise the
    /// area-weighted normal of the triangles around the vertex).
    pub normals: Vec<Vec3>,
    pub indices: Vec<[u32; 3]>,
    /// Per triangle: the CSG leaf most of its vertices lie on (0 for other shapes).
    pub leaves: Vec<u32>,
}

/// Cells along the longest axis are at most this many (a bound on memory and time:
/// about n³ grid values, 0.55 GB at 512, and 3 n² rays).
pub const MAX_CELLS: u32 = 512;

/// A crossing of the surface on a grid edge: the parameter along the edge's line (in
/// grid steps), the outward normal and the CSG leaf.
#[derive(Clone, Copy, Debug)]
struct Crossing {
    t: f32,
    normal: Vec3,
    leaf: u32,
}

/// Where a grid line is inside the solid and where it crosses the surface.
#[derive(Clone, Debug, Default)]
struct Line {
    spans: Vec<(f32, f32)>,
    crossings: Vec<Crossing>,
}

impl Line {
    fn of(spans: &[Span]) -> Self {
        let mut line = Line::default();
        for s in spans {
            line.spans.push((s.enter.t, s.exit.t));
            for b in [&s.enter, &s.exit] {
                if b.t.is_finite() {
                    line.crossings.push(Crossing {
                        t: b.t,
                        normal: b.normal,
                        leaf: b.leaf,
                    });
                }
            }
        }
        line
    }

    fn inside(&self, t: f32) -> bool {
        self.spans.iter().any(|&(a, b)| a < t && t < b)
    }

    /// The crossing on the edge `[i, i + 1]` nearest its midpoint (an edge whose ends
    /// differ crosses an odd number of times; thin slivers are rare).
    fn crossing_in(&self, i: f32) -> Option<Crossing> {
        let mid = i + 0.5;
        self.crossings
            .iter()
            .filter(|c| c.t >= i - 1e-3 && c.t <= i + 1.0 + 1e-3)
            .min_by(|a, b| (a.t - mid).abs().total_cmp(&(b.t - mid).abs()))
            .copied()
    }
}

/// The grid: `dims` points per axis from `origin`, `step` apart.
struct Grid {
    origin: Vec3,
    step: Vec3,
    dims: UVec3,
}

impl Grid {
    /// About `cells` cells along the longest side of `region`, the same step on every
    /// axis, one cell of margin all round (so a surface that touches the region's
    /// faces is still closed).
    fn new(region: &Aabb, cells: u32) -> Option<Self> {
        let ext = region.extent();
        let longest = ext.max_element();
        if longest.is_nan() || longest <= 0.0 || !region.is_finite() {
            return None;
        }
        let h = longest / cells.clamp(1, MAX_CELLS) as f32;
        let n = (ext / h).ceil().as_uvec3().max(UVec3::ONE) + UVec3::splat(2);
        let origin = region.center() - 0.5 * n.as_vec3() * h;
        Some(Self {
            origin,
            step: Vec3::splat(h),
            dims: n + UVec3::ONE,
        })
    }

    fn point(&self, i: UVec3) -> Vec3 {
        self.origin + i.as_vec3() * self.step
    }

    /// The lines along `axis` (0 x, 1 y, 2 z), ordered by the other two indices (the
    /// lower axis fastest).
    fn lines(&self, shape: &dyn Shape, axis: usize) -> Vec<Line> {
        let (a, b) = ((axis + 1) % 3, (axis + 2) % 3);
        let (lo, hi) = (a.min(b), a.max(b));
        let (nl, nh) = (self.dims[lo] as usize, self.dims[hi] as usize);
        let mut dir = Vec3::ZERO;
        dir[axis] = self.step[axis];
        (0..nl * nh)
            .into_par_iter()
            .map_init(Vec::new, |spans, k| {
                let mut i = UVec3::ZERO;
                i[lo] = (k % nl) as u32;
                i[hi] = (k / nl) as u32;
                spans.clear();
                shape.spans(&Ray::new(self.point(i), dir), spans);
                Line::of(spans)
            })
            .collect()
    }

    /// Index into [`Grid::lines`] of the line along `axis` through point `i`.
    fn line_index(&self, axis: usize, i: UVec3) -> usize {
        let (a, b) = ((axis + 1) % 3, (axis + 2) % 3);
        let (lo, hi) = (a.min(b), a.max(b));
        i[lo] as usize + self.dims[lo] as usize * i[hi] as usize
    }
}

/// The surface of `shape` (a solid) inside `region` (object space, finite), with about
/// `cells` grid cells along the region's longest side. `None` when the shape is not a
/// solid or the region is empty; an empty mesh when no surface lies in the region.
pub fn tessellate_solid(shape: &dyn Shape, region: &Aabb, cells: u32) -> Option<SolidMesh> {
    if !shape.is_solid() || region.is_empty() {
        return None;
    }
    let grid = Grid::new(region, cells)?;
    let lines: [Vec<Line>; 3] = [0, 1, 2].map(|axis| grid.lines(shape, axis));
    let d = grid.dims;
    let (nx, ny) = (d.x as usize, d.y as usize);
    let values: Vec<f32> = (0..nx * ny * d.z as usize)
        .into_par_iter()
        .map(|k| {
            let i = UVec3::new(
                (k % nx) as u32,
                ((k / nx) % ny) as u32,
                (k / (nx * ny)) as u32,
            );
            let line = &lines[0][grid.line_index(0, i)];
            if line.inside(i.x as f32) {
                -1.0
            } else {
                1.0
            }
        })
        .collect();
    let bounds = Aabb::new(grid.origin, grid.point(d - UVec3::ONE));
    let field = ScalarGrid {
        dims: d,
        bounds,
        values,
    };
    let step = field.spacing();
    let mc = marching_cubes(&field, 0.0);
    // Every vertex sits at the midpoint of a grid edge: find the edge, then the surface
    // crossing on it.
    let snapped: Vec<(Vec3, Vec3, u32)> = mc
        .positions
        .par_iter()
        .map(|&p| {
            let g = (p - field.bounds.min) / step;
            let axis = (0..3)
                .min_by(|&a, &b| {
                    let fa = (g[a] - g[a].floor() - 0.5).abs();
                    let fb = (g[b] - g[b].floor() - 0.5).abs();
                    fa.total_cmp(&fb)
                })
                .unwrap_or(0);
            let mut i = g.round().max(Vec3::ZERO).as_uvec3().min(d - UVec3::ONE);
            i[axis] = (g[axis].floor().max(0.0) as u32).min(d[axis].saturating_sub(2));
            let at = i[axis] as f32;
            let mut start = i;
            start[axis] = 0;
            let line = &lines[axis][grid.line_index(axis, start)];
            match line.crossing_in(at) {
                Some(c) => {
                    let mut q = grid.point(i);
                    q[axis] = grid.origin[axis] + c.t.clamp(at, at + 1.0) * grid.step[axis];
                    (q, c.normal, c.leaf)
                }
                None => (p, Vec3::ZERO, 0),
            }
        })
        .collect();
    let mut out = SolidMesh {
        positions: snapped.iter().map(|s| s.0).collect(),
        normals: snapped.iter().map(|s| s.1).collect(),
        indices: mc.indices,
        leaves: Vec::new(),
    };
    // Snapping can fold a triangle whose corners moved towards one another to nothing;
    // those are dropped.
    out.indices.retain(|t| {
        let [a, b, c] = t.map(|k| out.positions[k as usize]);
        (b - a).cross(c - a).length_squared() > 0.0
    });
    let leaf = |k: u32| snapped[k as usize].2;
    out.leaves = out
        .indices
        .iter()
        .map(|t| {
            if leaf(t[1]) == leaf(t[2]) {
                leaf(t[1])
            } else {
                leaf(t[0])
            }
        })
        .collect();
    fill_missing_normals(&mut out);
    Some(out)
}

/// Vertices whose crossing was not found get the area-weighted normal of their
/// triangles (outward, from the winding).
fn fill_missing_normals(m: &mut SolidMesh) {
    if m.normals.iter().all(|n| *n != Vec3::ZERO) {
        return;
    }
    let mut acc = vec![Vec3::ZERO; m.positions.len()];
    for t in &m.indices {
        let [a, b, c] = t.map(|k| m.positions[k as usize]);
        let n = (b - a).cross(c - a);
        for &k in t {
            acc[k as usize] += n;
        }
    }
    for (n, a) in m.normals.iter_mut().zip(acc) {
        if *n == Vec3::ZERO {
            *n = a.normalize_or_zero();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use irradia_geometry::shapes::Sphere;

    #[test]
    fn sphere_vertices_lie_on_the_sphere_with_its_normals() {
        let s = Sphere::new(Vec3::new(0.1, -0.2, 0.3), 0.8);
        let region = s.bounds();
        let m = tessellate_solid(&s, &region, 16).unwrap();
        assert!(m.indices.len() > 500, "{}", m.indices.len());
        for (p, n) in m.positions.iter().zip(&m.normals) {
            let r = *p - Vec3::new(0.1, -0.2, 0.3);
            assert!((r.length() - 0.8).abs() < 1e-4, "{p} is off the sphere");
            assert!(n.dot(r.normalize()) > 0.9999, "normal {n} at {p}");
        }
        // Winding: triangle normals point out of the sphere.
        for t in &m.indices {
            let [a, b, c] = t.map(|k| m.positions[k as usize]);
            let centre = (a + b + c) / 3.0 - Vec3::new(0.1, -0.2, 0.3);
            assert!((b - a).cross(c - a).dot(centre) > 0.0);
        }
    }
}
