//! Hierarchical radiosity (Hanrahan, Salzman, Aupperle 1991, "A rapid hierarchical
//! radiosity algorithm"), with BF refinement and no n² matrix.
//!
//! Each patch is the root of a hierarchy down to the element level (the largest area
//! allowed): the patch is first cut into a grid of 16 to 64 cells (the uniform
//! substructuring of `mesh::subdivide`), and each cell is the root of a quadtree
//! (`Poly::split4`). The grid level lets the number of leaves follow the requested
//! element area closely (a pure quadtree multiplies by 4 per level); with
//! [`HierarchicalOptions::target_leaves`] the element area is searched so that the
//! number of leaves comes within 1% of the target where the patch sizes allow. Energy travels along *links* between nodes at whatever level
//! is accurate enough: a link from source `q` to receiver `p` is refined (the larger
//! node is split and its children linked instead) while its estimated transport
//! `B_q F_pq` exceeds `ε_BF` and a node can still be split. The solver then alternates
//! a gather over all links (`G_p = ρ_p Σ F_pq B_q`) with a push-pull pass over the
//! hierarchy (leaves get the gathers of all their ancestors; parents take the area
//! average of their children), and refines again with the new radiosities.
//!
//! Link form factors are the point-to-polygon closed form (`contour`) at Gauss points of
//! the receiver times the visible fraction of a few shadow rays through the BVH; the
//! refinement oracle uses the cheap disk estimate `A_q cos θ_p cos θ_q / (π r² + A_q)`.

use super::Solution;
use crate::error::{RadiosityError, Result};
use crate::formfactor::contour::point_to_polygon;
use crate::geom::Poly;
use crate::mesh::{subdivide, Element, Mesh, Patch};
use crate::visibility::Visibility;
use glam::DVec3;
use irradia_core::sampling::hash64;
use irradia_core::Rng;
use rayon::prelude::*;
use std::f64::consts::PI;

/// Parameters of the hierarchical solver.
#[derive(Clone, Copy, Debug)]
pub struct HierarchicalOptions {
    /// Leaves have at most this area (the element size).
    pub max_element_area: f64,
    /// About this many leaves: overrides `max_element_area` with the area that gives
    /// the nearest count (see [`leaf_area_for`]).
    pub target_leaves: Option<usize>,
    /// Refine a link while `B_source · F` exceeds this times the largest emission.
    pub bf_epsilon: f64,
    /// Shadow rays per link (0: no occlusion).
    pub visibility_rays: usize,
    /// Gauss points per direction on the receiver for the link form factor.
    pub gauss_points: usize,
    /// Refinement rounds (each followed by a solve).
    pub rounds: usize,
    /// Stop each solve when the largest change is below this (relative).
    pub tolerance: f64,
    pub max_iterations: usize,
    /// Refuse more leaves than this (memory guard).
    pub max_elements: usize,
    pub seed: u64,
}

impl Default for HierarchicalOptions {
    fn default() -> Self {
        Self {
            max_element_area: f64::INFINITY,
            target_leaves: None,
            bf_epsilon: 1e-4,
            visibility_rays: 4,
            gauss_points: 1,
            rounds: 3,
            tolerance: 1e-6,
            max_iterations: 1000,
            max_elements: 5_000_000,
            seed: 1,
        }
    }
}

#[derive(Clone, Copy, Debug)]
struct Node {
    poly: Poly,
    patch: u32,
    area: f64,
    centroid: DVec3,
    normal: DVec3,
    /// Index of the first child (0 = leaf).
    child: u32,
    /// Number of children: 4 in the quadtrees, the grid's cells below a patch.
    children: u32,
}

#[derive(Clone, Copy, Debug)]
struct Link {
    recv: u32,
    src: u32,
    f: f64,
}

/// The result: the leaves as a mesh, their radiosity, and statistics.
pub struct HierarchicalResult {
    pub mesh: Mesh,
    pub solution: Solution,
    pub links: usize,
    pub nodes: usize,
    /// Time spent building links (refinement oracle, form factors, shadow rays).
    pub link_time: std::time::Duration,
    /// Time spent in gathers and push-pull passes.
    pub solve_time: std::time::Duration,
}

struct Hierarchy<'a> {
    nodes: Vec<Node>,
    patches: &'a [Patch],
    vis: Option<Visibility>,
    opts: HierarchicalOptions,
}

impl<'a> Hierarchy<'a> {
    fn build(mesh: &'a Mesh, opts: HierarchicalOptions) -> Result<Self> {
        let layout: Vec<PatchLayout> = mesh
            .patches
            .iter()
            .map(|p| PatchLayout::new(&p.poly, opts.max_element_area))
            .collect();
        let leaves = layout
            .iter()
            .fold(0usize, |s, l| s.saturating_add(l.leaves()));
        if leaves > opts.max_elements {
            return Err(RadiosityError::Input(format!(
                "--max-element-area {} would make {leaves} hierarchical leaves, more than the limit of {}; \
                 use a larger area",
                opts.max_element_area, opts.max_elements
            )));
        }
        let mut nodes = Vec::with_capacity(leaves * 4 / 3 + 65 * mesh.patches.len());
        // Roots first, so patch i is node i.
        for (i, p) in mesh.patches.iter().enumerate() {
            nodes.push(make_node(p.poly, i as u32));
        }
        for (i, l) in layout.iter().enumerate() {
            if l.grid == (1, 1) {
                split_to(&mut nodes, i, l.depth);
                continue;
            }
            let first = nodes.len() as u32;
            let cells = subdivide::subdivide(&nodes[i].poly, l.grid);
            nodes[i].child = first;
            nodes[i].children = cells.len() as u32;
            for c in cells {
                nodes.push(make_node(c, i as u32));
            }
            for c in 0..nodes[i].children {
                split_to(&mut nodes, (first + c) as usize, l.depth);
            }
        }
        Ok(Self {
            nodes,
            patches: &mesh.patches,
            vis: (opts.visibility_rays > 0).then(|| Visibility::new(mesh)),
            opts,
        })
    }

    /// The estimated transport oracle: disk approximation from centroids.
    fn estimate(&self, p: &Node, q: &Node) -> f64 {
        let d = q.centroid - p.centroid;
        let r2 = d.length_squared();
        if r2 == 0.0 {
            return 0.0;
        }
        let r = r2.sqrt();
        let cp = (p.normal.dot(d) / r).max(0.0);
        let cq = (-q.normal.dot(d) / r).max(0.0);
        (q.area * cp * cq / (PI * r2 + q.area)).min(1.0)
    }

    fn faces(p: &Node, q: &Node) -> bool {
        let front = |a: &Node, b: &Node| {
            b.poly
                .verts()
                .iter()
                .any(|v| a.normal.dot(*v - a.centroid) > 1e-12 * a.area.sqrt())
        };
        front(p, q) && front(q, p)
    }

    /// The link form factor: contour at Gauss points of the receiver, times visibility.
    fn form_factor(&self, pi: u32, qi: u32) -> f64 {
        let (p, q) = (&self.nodes[pi as usize], &self.nodes[qi as usize]);
        let pts = if self.opts.gauss_points <= 1 {
            vec![(p.centroid, p.area)]
        } else {
            p.poly.gauss_points(self.opts.gauss_points)
        };
        let mut f = 0.0;
        for (x, w) in &pts {
            // Points behind q see only its back: nothing.
            if q.normal.dot(*x - q.centroid) > 0.0 {
                f += w * point_to_polygon(*x, p.normal, q.poly.verts());
            }
        }
        f /= p.area;
        if f <= 0.0 {
            return 0.0;
        }
        if let Some(vis) = &self.vis {
            let k = self.opts.visibility_rays;
            let side = (k as f64).sqrt().ceil() as usize;
            let mut rng = Rng::new(hash64(self.opts.seed ^ ((pi as u64) << 32 | qi as u64)), 3);
            // Only pairs that face each other count: the part of q behind p's plane is
            // already cut off by the contour formula (counting it as hidden would
            // remove it twice).
            let (mut seen, mut facing) = (0, 0);
            for s in 0..k {
                let (cx, cy) = ((s % side) as f64, ((s / side) % side) as f64);
                let a = p.poly.sample(
                    (cx + rng.next_f64()) / side as f64,
                    (cy + rng.next_f64()) / side as f64,
                );
                let b = q.poly.sample(rng.next_f64(), rng.next_f64());
                if p.normal.dot(b - a) <= 0.0 || q.normal.dot(a - b) <= 0.0 {
                    continue;
                }
                facing += 1;
                if vis.visible(a, p.normal, b, q.normal) {
                    seen += 1;
                }
            }
            if facing > 0 {
                f *= seen as f64 / facing as f64;
            }
        }
        f
    }

    /// Links receiver `p` to source `q`, refining while `b_q * F > eps`.
    fn refine(&self, p: u32, q: u32, bq: &dyn Fn(u32) -> f64, eps: f64, out: &mut Vec<Link>) {
        let (np, nq) = (&self.nodes[p as usize], &self.nodes[q as usize]);
        if !Self::faces(np, nq) {
            return;
        }
        let est = self.estimate(np, nq);
        let transport = est.max(self.estimate(nq, np) * nq.area / np.area) * bq(q);
        let split_p = np.child != 0 && (np.area >= nq.area || nq.child == 0);
        let split_q = nq.child != 0 && !split_p;
        if transport > eps && (split_p || split_q) {
            if split_p {
                for c in 0..np.children {
                    self.refine(np.child + c, q, bq, eps, out);
                }
            } else {
                for c in 0..nq.children {
                    self.refine(p, nq.child + c, bq, eps, out);
                }
            }
            return;
        }
        let f = self.form_factor(p, q);
        if f > 0.0 {
            out.push(Link { recv: p, src: q, f });
        }
    }
}

fn make_node(poly: Poly, patch: u32) -> Node {
    Node {
        poly,
        patch,
        area: poly.area(),
        centroid: poly.centroid(),
        normal: poly.normal(),
        child: 0,
        children: 0,
    }
}

/// How one patch is cut: a `grid` of cells (`mesh::subdivide`), each a quadtree of
/// `depth` levels.
#[derive(Clone, Copy, Debug, PartialEq)]
struct PatchLayout {
    grid: (usize, usize),
    depth: u32,
    cells: usize,
}

impl PatchLayout {
    /// Leaves of at most `max_area`: the quadtree depth leaves 16 to 64 grid cells
    /// (patches of fewer than 16 leaves are a plain quadtree).
    fn new(poly: &Poly, max_area: f64) -> Self {
        let area = poly.area();
        if !(max_area > 0.0) || area <= max_area {
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
    fn leaves(&self) -> usize {
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

fn split_to(nodes: &mut Vec<Node>, i: usize, depth: u32) {
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

/// Solves the mesh's patches hierarchically. `mesh` supplies the patches (its elements
/// are ignored); the result's mesh has the leaves as elements.
pub fn solve(
    mesh: &Mesh,
    opts: HierarchicalOptions,
    progress: Option<&(dyn Fn(&str) + Sync)>,
) -> Result<HierarchicalResult> {
    let mut opts = opts;
    if let Some(n) = opts.target_leaves {
        opts.max_element_area = leaf_area_for(&mesh.patches, n);
    }
    let h = Hierarchy::build(mesh, opts)?;
    let nn = h.nodes.len();
    let np = h.patches.len();
    let emax = h
        .patches
        .iter()
        .flat_map(|p| p.emission.iter().copied())
        .fold(0.0, f64::max)
        .max(1e-300);
    let eps = opts.bf_epsilon * emax;
    let lum = |c: [f64; 3]| (c[0] + c[1] + c[2]) / 3.0;
    // Radiosity per node (area average over its leaves).
    let mut b: Vec<[f64; 3]> = h
        .nodes
        .iter()
        .map(|n| h.patches[n.patch as usize].emission)
        .collect();
    let mut links: Vec<Link> = Vec::new();
    let mut history = Vec::new();
    let mut notes = Vec::new();
    let mut residual = f64::INFINITY;
    let mut link_time = std::time::Duration::ZERO;
    let mut solve_time = std::time::Duration::ZERO;
    for round in 0..opts.rounds.max(1) {
        let t_link = std::time::Instant::now();
        if let Some(p) = progress {
            p(&format!(
                "hierarchical: refining links (round {})",
                round + 1
            ));
        }
        let bq = |q: u32| lum(b[q as usize]);
        // Refine from the patch pairs each round (re-linking from the top with the new
        // radiosities is the BF refinement of HSA 1991 section 4).
        let pairs: Vec<(u32, u32)> = (0..np as u32)
            .flat_map(|p| (0..np as u32).filter(move |&q| q != p).map(move |q| (p, q)))
            .collect();
        links = pairs
            .par_iter()
            .flat_map_iter(|&(p, q)| {
                let mut out = Vec::new();
                h.refine(p, q, &bq, eps, &mut out);
                out
            })
            .collect();
        links.sort_unstable_by_key(|l| l.recv);
        link_time += t_link.elapsed();
        let t_solve = std::time::Instant::now();
        if let Some(p) = progress {
            p(&format!("hierarchical: solving with {} links", links.len()));
        }
        // Jacobi gather + push-pull until the change is small.
        for _ in 0..opts.max_iterations {
            let mut gathered = vec![[0.0f64; 3]; nn];
            // Links are sorted by receiver: gather in parallel over receiver runs.
            let chunks: Vec<&[Link]> = links.chunk_by(|a, b2| a.recv == b2.recv).collect();
            let sums: Vec<(u32, [f64; 3])> = chunks
                .par_iter()
                .map(|run| {
                    let mut s = [0.0; 3];
                    for l in run.iter() {
                        let bs = b[l.src as usize];
                        s[0] += l.f * bs[0];
                        s[1] += l.f * bs[1];
                        s[2] += l.f * bs[2];
                    }
                    (run[0].recv, s)
                })
                .collect();
            for (r, s) in sums {
                let rho = h.patches[h.nodes[r as usize].patch as usize].reflectance;
                gathered[r as usize] = [rho[0] * s[0], rho[1] * s[1], rho[2] * s[2]];
            }
            let mut nb = vec![[0.0f64; 3]; nn];
            for root in 0..np {
                push_pull(&h.nodes, h.patches, root, [0.0; 3], &gathered, &mut nb);
            }
            let change = nb
                .iter()
                .zip(&b)
                .flat_map(|(x, y)| (0..3).map(move |c| (x[c] - y[c]).abs()))
                .fold(0.0, f64::max)
                / emax;
            b = nb;
            history.push(change);
            residual = change;
            if change < opts.tolerance {
                break;
            }
        }
        solve_time += t_solve.elapsed();
    }
    notes.push(format!(
        "hierarchical: {} nodes, {} links, ε_BF = {:.1e} of the largest emission",
        nn,
        links.len(),
        opts.bf_epsilon
    ));
    let mut elements = Vec::new();
    let mut bl = Vec::new();
    for (i, n) in h.nodes.iter().enumerate() {
        if n.child == 0 {
            elements.push(Element::new(n.poly, n.patch));
            bl.push(b[i]);
        }
    }
    Ok(HierarchicalResult {
        mesh: Mesh::with_elements(mesh.patches.clone(), elements),
        solution: Solution {
            b: bl,
            history,
            residual,
            display: None,
            notes,
        },
        links: links.len(),
        nodes: nn,
        link_time,
        solve_time,
    })
}

/// Leaves: `E + Σ gathers down the path`; inner nodes: area average of children.
fn push_pull(
    nodes: &[Node],
    patches: &[Patch],
    i: usize,
    down: [f64; 3],
    g: &[[f64; 3]],
    out: &mut [[f64; 3]],
) -> [f64; 3] {
    let n = &nodes[i];
    let acc = [down[0] + g[i][0], down[1] + g[i][1], down[2] + g[i][2]];
    let r = if n.child == 0 {
        let e = patches[n.patch as usize].emission;
        [e[0] + acc[0], e[1] + acc[1], e[2] + acc[2]]
    } else {
        let mut s = [0.0; 3];
        for c in 0..n.children {
            let ci = (n.child + c) as usize;
            let bc = push_pull(nodes, patches, ci, acc, g, out);
            let w = nodes[ci].area / n.area;
            for k in 0..3 {
                s[k] += w * bc[k];
            }
        }
        s
    };
    out[i] = r;
    r
}
