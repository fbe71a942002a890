//! How the hierarchy of one patch is laid out (a grid of cells, each a quadtree) and
//! the leaf area that gives a requested number of leaves; see the parent module.

use super::{make_node, Node};
use crate::geom::Poly;
use crate::mesh::{subdivide, Patch};

/// How one patch is cut: a `grid` of cells (`mesh::subdivide`), each a quadtree of
/// `depth` levels.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct PatchLayout {
    pub(super) grid: (usize, usize),
    pub(super) depth: u32,
    cells: usize,
}

impl PatchLayout {
    /// Leaves of at most `max_area`: the quadtree depth leaves 16 to 64 grid cells
    /// (patches of fewer than 16 leaves are a plain quadtree).
    pub(super) fn new(poly: &Poly, max_area: f64) -> Self {
        let area = poly.area();
        if max_area.is_nan() || max_area <= 0.0 || area <= max_area {
            return Self {
                grid: (1, 1),
                depth: 0,
                cells: 1,
            };
        }
        let ratio = area / max_area;
        if ratio < 16.0 {
            // Small patches: a plain quadtree (1, 4 or 16 leaves).
            let mut d = 0;
            let mut a = area;
            while a > max_area {
                a /= 4.0;
                d += 1;
            }
            return Self {
                grid: (1, 1),
                depth: d,
                cells: 1,
            };
        }
        let depth = ((ratio.ln() / 4f64.ln()).floor() as i64 - 2).clamp(0, 20) as u32;
        let cell_area = max_area * 4f64.powi(depth as i32);
        let grid = subdivide::grid_size(poly, cell_area);
        Self {
            grid,
            depth,
            cells: subdivide::element_count(poly, grid),
        }
    }
    pub(super) fn leaves(&self) -> usize {
        self.cells.saturating_mul(1usize << (2 * self.depth))
    }
}

/// Number of hierarchical leaves the patches get for leaves of at most `max_area`.
pub fn leaf_count(patches: &[Patch], max_area: f64) -> usize {
    patches
        .iter()
        .map(|p| PatchLayout::new(&p.poly, max_area).leaves())
        .fold(0usize, usize::saturating_add)
}

/// The leaf area whose leaf count is nearest `target` (bisection on the logarithm of
/// the area; the count is a step function of the area, nearly monotone).
pub fn leaf_area_for(patches: &[Patch], target: usize) -> f64 {
    let total: f64 = patches.iter().map(|p| p.area()).sum();
    let target = target.max(1);
    let (mut lo, mut hi) = (
        (total / target as f64 / 16.0).ln(),
        (total / target as f64 * 4.0).ln(),
    );
    let mut best = (usize::MAX, hi.exp());
    for _ in 0..80 {
        let mid = 0.5 * (lo + hi);
        let n = leaf_count(patches, mid.exp());
        let off = n.abs_diff(target);
        if off < best.0 {
            best = (off, mid.exp());
        }
        if n > target {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    best.1
}

pub(super) fn split_to(nodes: &mut Vec<Node>, i: usize, depth: u32) {
    if depth == 0 {
        return;
    }
    let first = nodes.len() as u32;
    nodes[i].child = first;
    let (poly, patch) = (nodes[i].poly, nodes[i].patch);
    for c in poly.split4() {
        nodes.push(make_node(c, patch));
    }
    nodes[i].children = 4;
    for c in 0..4 {
        split_to(nodes, (first + c) as usize, depth - 1);
    }
}
