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
//! Shadow rays are cast only where some patch may lie between the two nodes (shaft
//! culling, Haines and Wallace 1994: `hierarchical/shaft.rs`), and a round takes the
//! form factors of the links that the round before made too (a link's form factor
//! depends on its two nodes alone), so a round costs the oracle plus the new links.
//!
//! The work is cut where it is independent, so that [`solve`] and the distributed
//! solver of `irradia-parallel` (`radiosity.rs`) run the same code and agree bit for bit:
//! the links of one *pair* of patches ([`Hierarchy::link_pair`]) depend only on the
//! radiosities of the round, and the gather and push-pull of one receiving patch
//! ([`Hierarchy::iterate_patch`]) only on its own links and the radiosities of the last
//! iteration. A patch's links are those of its pairs in the order of the source patch,
//! then sorted stably by receiving node ([`Hierarchy::patch_links`]), so each node sums
//! its links in one fixed order wherever it is computed.

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
use std::time::Duration;

mod layout;
mod shaft;
pub use layout::{leaf_area_for, leaf_count};
use layout::{split_to, PatchLayout};
use shaft::{Shaft, Side};

/// Patch pairs find their candidate occluders (a test of every patch, a few ns each,
/// against the microseconds of a link's shadow rays) only up to this many patches;
/// above it every link casts its shadow rays.
const SHAFT_PATCHES: usize = 256;

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
pub(crate) struct Node {
    poly: Poly,
    patch: u32,
    area: f64,
    centroid: DVec3,
    normal: DVec3,
    /// Index of the first child (0 = leaf).
    child: u32,
    /// Number of children: 4 in the quadtrees, the grid's cells below a patch.
    children: u32,
    /// [`Poly::split_fraction`], for the shadow rays' sample points.
    split: f64,
}

/// Energy from node `src` to node `recv` with form factor `f` (node indices of the
/// [`Hierarchy`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Link {
    pub recv: u32,
    pub src: u32,
    pub f: f64,
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

/// The timing and history of a solve, for [`Hierarchy::finish`].
#[derive(Clone, Debug, Default)]
pub struct SolveRecord {
    /// Largest relative change after each iteration.
    pub history: Vec<f64>,
    pub residual: f64,
    /// Links of the last round.
    pub links: usize,
    pub link_time: Duration,
    pub solve_time: Duration,
}

/// The node tree of every patch (built once, identically on every rank) and what a
/// link needs: the visibility structure and the options.
pub struct Hierarchy<'a> {
    nodes: Vec<Node>,
    /// Descendants of patch `p` are the nodes `range[p].0..range[p].1` (its root is `p`).
    range: Vec<(u32, u32)>,
    /// Per node, what push-pull reads (16 bytes rather than a whole `Node`): the first
    /// child and the number of children, and the node's area over its parent's.
    kids: Vec<(u32, u32)>,
    weight: Vec<f64>,
    patches: &'a [Patch],
    vis: Option<Visibility>,
    /// Shaft culling of the shadow rays, with the patches' polygons (small scenes).
    shaft: Option<Shaft>,
    opts: HierarchicalOptions,
    /// Largest emission over patches and channels (the change is relative to it).
    emax: f64,
}

impl<'a> Hierarchy<'a> {
    /// The hierarchy of `mesh`'s patches (its elements are ignored) for `opts`, with
    /// [`HierarchicalOptions::target_leaves`] turned into a leaf area.
    pub fn new(mesh: &'a Mesh, opts: HierarchicalOptions) -> Result<Self> {
        let mut opts = opts;
        if let Some(n) = opts.target_leaves {
            opts.max_element_area = leaf_area_for(&mesh.patches, n);
        }
        Self::build(mesh, opts)
    }

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
        if mesh.patches.len() > u32::MAX as usize / 2 {
            return Err(RadiosityError::Input(format!(
                "{} patches: too many for the hierarchical solver",
                mesh.patches.len()
            )));
        }
        let mut nodes = Vec::with_capacity(leaves * 4 / 3 + 65 * mesh.patches.len());
        // Roots first, so patch i is node i.
        for (i, p) in mesh.patches.iter().enumerate() {
            nodes.push(make_node(p.poly, i as u32));
        }
        let mut range = Vec::with_capacity(layout.len());
        for (i, l) in layout.iter().enumerate() {
            let start = nodes.len() as u32;
            if l.grid == (1, 1) {
                split_to(&mut nodes, i, l.depth);
                range.push((start, nodes.len() as u32));
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
            range.push((start, nodes.len() as u32));
        }
        let emax = mesh
            .patches
            .iter()
            .flat_map(|p| p.emission.iter().copied())
            .fold(0.0, f64::max)
            .max(1e-300);
        let kids: Vec<(u32, u32)> = nodes.iter().map(|n| (n.child, n.children)).collect();
        let mut weight = vec![1.0; nodes.len()];
        for n in &nodes {
            for c in n.child..n.child + n.children {
                weight[c as usize] = nodes[c as usize].area / n.area;
            }
        }
        let vis = (opts.visibility_rays > 0).then(|| Visibility::new(mesh));
        let shaft = vis
            .as_ref()
            .filter(|_| mesh.patches.len() <= SHAFT_PATCHES)
            .map(|v| {
                let polys: Vec<Poly> = mesh.patches.iter().map(|p| p.poly).collect();
                Shaft::new(&polys, v.offset())
            });
        Ok(Self {
            nodes,
            range,
            kids,
            weight,
            patches: &mesh.patches,
            vis,
            shaft,
            opts,
            emax,
        })
    }

    /// The options in force (the leaf area found for a target count included).
    pub fn options(&self) -> &HierarchicalOptions {
        &self.opts
    }
    /// Number of patches (the roots are nodes `0..patches()`).
    pub fn patches(&self) -> usize {
        self.patches.len()
    }
    /// Number of nodes of all trees.
    pub fn nodes(&self) -> usize {
        self.nodes.len()
    }
    /// Largest emission of any patch and channel.
    pub fn emission_scale(&self) -> f64 {
        self.emax
    }
    /// Number of nodes of patch `p`'s tree (its root included).
    pub fn patch_size(&self, p: usize) -> usize {
        let (s, e) = self.range[p];
        1 + (e - s) as usize
    }
    /// Patch `p`'s nodes in their order in [`Hierarchy::iterate_patch`]'s values: the
    /// root, then the descendants.
    pub fn patch_nodes(&self, p: usize) -> impl Iterator<Item = usize> {
        let (s, e) = self.range[p];
        std::iter::once(p).chain(s as usize..e as usize)
    }
    /// Whether node `node` lies in patch `p`'s tree.
    pub fn in_patch(&self, node: u32, p: usize) -> bool {
        let (s, e) = self.range[p];
        node as usize == p || (s..e).contains(&node)
    }
    /// The radiosity every node starts from: its patch's emission.
    pub fn initial_radiosity(&self) -> Vec<[f64; 3]> {
        self.nodes
            .iter()
            .map(|n| self.patches[n.patch as usize].emission)
            .collect()
    }
    /// Every (receiver, source) pair of distinct patches, receiver-major: the order in
    /// which a patch's links are concatenated.
    pub fn pairs(&self) -> Vec<(u32, u32)> {
        let np = self.patches.len() as u32;
        (0..np)
            .flat_map(|p| (0..np).filter(move |&q| q != p).map(move |q| (p, q)))
            .collect()
    }

    /// The links from patch `q` to patch `p` for the radiosities `b`: refined while
    /// `B_q F` exceeds `ε_BF` times the largest emission (HSA 1991, section 4).
    pub fn link_pair(&self, p: u32, q: u32, b: &[[f64; 3]]) -> Vec<Link> {
        self.link_pair_reusing(p, q, b, &[])
    }

    /// [`Hierarchy::link_pair`], taking the form factor of a link from `known` (links
    /// sorted by receiver, then source: the pair's links of an earlier round) where it
    /// is there. A link's form factor is a function of its two nodes alone, so the
    /// links are the same as [`Hierarchy::link_pair`]'s, bit for bit.
    pub fn link_pair_reusing(&self, p: u32, q: u32, b: &[[f64; 3]], known: &[Link]) -> Vec<Link> {
        let lum = |c: [f64; 3]| (c[0] + c[1] + c[2]) / 3.0;
        let ctx = Refine {
            b,
            lum: &lum,
            eps: self.opts.bf_epsilon * self.emax,
            pair: (p, q),
            cands: std::cell::OnceCell::new(),
            known,
        };
        let mut out = Vec::new();
        self.refine(p, q, &ctx, &mut out);
        out
    }

    /// Patch `p`'s links from the links of its pairs `(p, q)` given in increasing `q`:
    /// concatenated, then sorted stably by receiving node.
    pub fn patch_links(&self, per_pair: impl IntoIterator<Item = Vec<Link>>) -> Vec<Link> {
        let mut links: Vec<Link> = per_pair.into_iter().flatten().collect();
        links.sort_by_key(|l| l.recv);
        links
    }

    /// One Jacobi step on patch `p`: the gather `G = ρ Σ F B_src` at every node with
    /// links (`links`: the patch's, from [`Hierarchy::patch_links`]), then push-pull over
    /// its tree. Returns the new radiosity of its nodes in [`Hierarchy::patch_nodes`]
    /// order.
    pub fn iterate_patch(&self, p: usize, links: &[Link], b: &[[f64; 3]]) -> Vec<[f64; 3]> {
        let mut out = vec![[0.0f64; 3]; self.patch_size(p)];
        let rho = self.patches[p].reflectance;
        for run in links.chunk_by(|a, b2| a.recv == b2.recv) {
            let mut s = [0.0; 3];
            for l in run.iter() {
                let bs = b[l.src as usize];
                s[0] += l.f * bs[0];
                s[1] += l.f * bs[1];
                s[2] += l.f * bs[2];
            }
            out[self.local(p, run[0].recv as usize)] =
                [rho[0] * s[0], rho[1] * s[1], rho[2] * s[2]];
        }
        self.push_pull(p, &mut out);
        out
    }

    /// Writes patch `p`'s values (from [`Hierarchy::iterate_patch`]) into `nb` and returns
    /// their largest change from `b` (absolute, any channel).
    pub fn store_patch(
        &self,
        p: usize,
        values: &[[f64; 3]],
        b: &[[f64; 3]],
        nb: &mut [[f64; 3]],
    ) -> f64 {
        let mut change: f64 = 0.0;
        for (i, v) in self.patch_nodes(p).zip(values) {
            nb[i] = *v;
            for c in 0..3 {
                change = change.max((v[c] - b[i][c]).abs());
            }
        }
        change
    }

    /// The result: the leaves as a mesh with their radiosity from `b`.
    pub fn finish(&self, mesh: &Mesh, b: &[[f64; 3]], rec: SolveRecord) -> HierarchicalResult {
        let notes = vec![format!(
            "hierarchical: {} nodes, {} links, ε_BF = {:.1e} of the largest emission",
            self.nodes.len(),
            rec.links,
            self.opts.bf_epsilon
        )];
        let mut elements = Vec::new();
        let mut bl = Vec::new();
        for (i, n) in self.nodes.iter().enumerate() {
            if n.child == 0 {
                elements.push(Element::new(n.poly, n.patch));
                bl.push(b[i]);
            }
        }
        HierarchicalResult {
            mesh: Mesh::with_elements(mesh.patches.clone(), elements),
            solution: Solution {
                b: bl,
                history: rec.history,
                residual: rec.residual,
                display: None,
                notes,
            },
            links: rec.links,
            nodes: self.nodes.len(),
            link_time: rec.link_time,
            solve_time: rec.solve_time,
        }
    }

    /// Index of node `i` of patch `p` in the patch's values.
    fn local(&self, p: usize, i: usize) -> usize {
        if i == p {
            0
        } else {
            i - self.range[p].0 as usize + 1
        }
    }

    /// Push-pull over patch `p`'s tree (HSA 1991, section 4): `v` holds each node's
    /// gather (indexed as [`Hierarchy::local`]) and gets its radiosity. Push: every node
    /// adds its parent's accumulated gather (children come after their parent in the
    /// node order, so one pass forward). Pull: a leaf's radiosity is `E +` its
    /// accumulated gather, an inner node's the area average of its children's, summed
    /// in child order (one pass backward).
    fn push_pull(&self, p: usize, v: &mut [[f64; 3]]) {
        let s = self.range[p].0 as usize;
        // Node of local index li (0: the root p).
        let node = |li: usize| if li == 0 { p } else { li + s - 1 };
        for li in 0..v.len() {
            let (child, children) = self.kids[node(li)];
            let acc = v[li];
            for c in 0..children as usize {
                let lc = child as usize + c - s + 1;
                let g = v[lc];
                v[lc] = [acc[0] + g[0], acc[1] + g[1], acc[2] + g[2]];
            }
        }
        let e = self.patches[p].emission;
        for li in (0..v.len()).rev() {
            let (child, children) = self.kids[node(li)];
            v[li] = if child == 0 {
                let acc = v[li];
                [e[0] + acc[0], e[1] + acc[1], e[2] + acc[2]]
            } else {
                let mut sum = [0.0; 3];
                for c in 0..children as usize {
                    let ci = child as usize + c;
                    let w = self.weight[ci];
                    let bc = v[ci - s + 1];
                    for k in 0..3 {
                        sum[k] += w * bc[k];
                    }
                }
                sum
            };
        }
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

    /// The candidate occluders of the patch pair being refined (found on first use).
    fn candidates<'c>(&self, ctx: &'c Refine) -> Option<&'c [u32]> {
        ctx.cands
            .get_or_init(|| {
                let (p, q) = ctx.pair;
                self.shaft.as_ref().map(|shaft| {
                    let (np, nq) = (&self.nodes[p as usize], &self.nodes[q as usize]);
                    shaft.candidates(&side(np), &side(nq))
                })
            })
            .as_deref()
    }

    /// The link form factor: contour at Gauss points of the receiver, times visibility
    /// (shadow rays unless the shaft between the nodes holds none of the pair's
    /// candidate occluders).
    fn form_factor(&self, pi: u32, qi: u32, ctx: &Refine) -> f64 {
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
        if let (Some(shaft), Some(c)) = (&self.shaft, self.candidates(ctx)) {
            if shaft.clear(c, &side(p), &side(q)) {
                return f;
            }
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
                let a = p.poly.sample_split(
                    p.split,
                    (cx + rng.next_f64()) / side as f64,
                    (cy + rng.next_f64()) / side as f64,
                );
                let b = q.poly.sample_split(q.split, rng.next_f64(), rng.next_f64());
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
    fn refine(&self, p: u32, q: u32, ctx: &Refine, out: &mut Vec<Link>) {
        let (np, nq) = (&self.nodes[p as usize], &self.nodes[q as usize]);
        if !Self::faces(np, nq) {
            return;
        }
        let est = self.estimate(np, nq);
        let transport =
            est.max(self.estimate(nq, np) * nq.area / np.area) * (ctx.lum)(ctx.b[q as usize]);
        let split_p = np.child != 0 && (np.area >= nq.area || nq.child == 0);
        let split_q = nq.child != 0 && !split_p;
        if transport > ctx.eps && (split_p || split_q) {
            if split_p {
                for c in 0..np.children {
                    self.refine(np.child + c, q, ctx, out);
                }
            } else {
                for c in 0..nq.children {
                    self.refine(p, nq.child + c, ctx, out);
                }
            }
            return;
        }
        let f = match ctx.known.binary_search_by(|l| (l.recv, l.src).cmp(&(p, q))) {
            Ok(i) => ctx.known[i].f,
            Err(_) => self.form_factor(p, q, ctx),
        };
        if f > 0.0 {
            out.push(Link { recv: p, src: q, f });
        }
    }
}

/// What one refinement of a patch pair reads: the radiosities, the luminance, the
/// threshold, the pair (receiver, source), its candidate occluders (found when a link
/// first needs them) and the known form factors.
struct Refine<'r> {
    b: &'r [[f64; 3]],
    lum: &'r dyn Fn([f64; 3]) -> f64,
    eps: f64,
    pair: (u32, u32),
    cands: std::cell::OnceCell<Option<Vec<u32>>>,
    known: &'r [Link],
}

fn side(n: &Node) -> Side<'_> {
    Side {
        poly: &n.poly,
        normal: n.normal,
        centroid: n.centroid,
    }
}

pub(crate) fn make_node(poly: Poly, patch: u32) -> Node {
    Node {
        poly,
        patch,
        area: poly.area(),
        centroid: poly.centroid(),
        normal: poly.normal(),
        child: 0,
        children: 0,
        split: poly.split_fraction(),
    }
}

/// Solves the mesh's patches hierarchically. `mesh` supplies the patches (its elements
/// are ignored); the result's mesh has the leaves as elements.
pub fn solve(
    mesh: &Mesh,
    opts: HierarchicalOptions,
    progress: Option<&(dyn Fn(&str) + Sync)>,
) -> Result<HierarchicalResult> {
    let h = Hierarchy::new(mesh, opts)?;
    let (nn, np) = (h.nodes(), h.patches());
    let opts = *h.options();
    let mut b = h.initial_radiosity();
    let pairs = h.pairs();
    let mut known: Vec<Vec<Link>> = vec![Vec::new(); pairs.len()];
    let mut rec = SolveRecord {
        residual: f64::INFINITY,
        ..Default::default()
    };
    for round in 0..opts.rounds.max(1) {
        let t_link = std::time::Instant::now();
        if let Some(p) = progress {
            p(&format!(
                "hierarchical: refining links (round {})",
                round + 1
            ));
        }
        // Refine from the patch pairs each round (re-linking from the top with the new
        // radiosities is the BF refinement of HSA 1991 section 4); the form factors of
        // links the last round had too are taken from it.
        let per_pair: Vec<Vec<Link>> = pairs
            .par_iter()
            .zip(known.par_iter())
            .map(|(&(p, q), k)| h.link_pair_reusing(p, q, &b, k))
            .collect();
        let m = np.saturating_sub(1);
        let links: Vec<Vec<Link>> = (0..np)
            .map(|p| h.patch_links(per_pair[p * m..(p + 1) * m].iter().cloned()))
            .collect();
        if round + 1 < opts.rounds {
            known = per_pair;
            known
                .par_iter_mut()
                .for_each(|k| k.sort_unstable_by_key(|l| (l.recv, l.src)));
        }
        rec.links = links.iter().map(Vec::len).sum();
        rec.link_time += t_link.elapsed();
        let t_solve = std::time::Instant::now();
        if let Some(p) = progress {
            p(&format!("hierarchical: solving with {} links", rec.links));
        }
        // Jacobi gather + push-pull until the change is small. Every node belongs to
        // one patch, so `store_patch` overwrites all of `nb`: the two buffers swap
        // (a fresh 32 MB vector per sweep at 1M elements was page faults and memset).
        let mut nb = vec![[0.0f64; 3]; nn];
        for _ in 0..opts.max_iterations {
            let values: Vec<Vec<[f64; 3]>> = (0..np)
                .into_par_iter()
                .map(|p| h.iterate_patch(p, &links[p], &b))
                .collect();
            let mut change: f64 = 0.0;
            for (p, v) in values.iter().enumerate() {
                change = change.max(h.store_patch(p, v, &b, &mut nb));
            }
            let change = change / h.emission_scale();
            std::mem::swap(&mut b, &mut nb);
            rec.history.push(change);
            rec.residual = change;
            if change < opts.tolerance {
                break;
            }
        }
        rec.solve_time += t_solve.elapsed();
    }
    Ok(h.finish(mesh, &b, rec))
}
