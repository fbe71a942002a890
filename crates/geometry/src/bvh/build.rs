//! Building the wide BVH: top-down binned SAH, in parallel, straight into 8-wide nodes.
//!
//! Each node starts as one set of primitives; the set with the largest surface area is
//! split in two by the surface area heuristic until the node has eight children or no
//! set is worth splitting ("collapsing" a binary SAH tree into wide nodes while it is
//! built, as Embree's BVH8 builder does). Splits are found by binning centroids into
//! 32 buckets per axis (Wald, "On fast Construction of SAH-based Bounding Volume
//! Hierarchies", RT 2007). Large sets are binned in parallel and sibling subtrees are
//! built on different threads (rayon), writing into one node array through an atomic
//! allocator.

use super::node::{ChildRef, WideNode, WIDTH};
use super::partition::{partition, Centroids};
use glam::Vec3A;
use irradia_core::Aabb;
use std::sync::atomic::{AtomicUsize, Ordering};

const BINS: usize = 32;
const _: () = assert!(BINS.is_power_of_two());
/// Sets up to this size are split by an exact sweep instead of binning.
const SWEEP_MAX: usize = 8;
/// Leaves never hold more primitives than this.
pub const MAX_LEAF: usize = 8;
/// Relative costs of visiting a node and of intersecting one block of primitives.
const TRAVERSAL_COST: f32 = 1.0;
const INTERSECT_COST: f32 = 1.0;
/// The SAH's intersection cost of `n` primitives tested in blocks of `block` (4 for
/// SIMD triangle packets, 1 otherwise), counted in blocks as Embree's builders do.
#[inline]
fn blocks(n: usize, block: usize) -> f32 {
    n.div_ceil(block) as f32
}
/// Sets at least this large are binned into two sets of bins (see `Bins::fill`).
const DUAL_BINS: usize = 128;
/// Sets larger than this are binned with several threads.
const PARALLEL_BINNING: usize = 1 << 16;
/// Subtrees larger than this are built as separate tasks.
const PARALLEL_SUBTREE: usize = 1 << 12;
/// Beyond this binary depth splits are made at the median, which bounds the depth
/// (and so the traversal stack) whatever the SAH would prefer.
pub(crate) const MAX_SAH_DEPTH: u32 = 40;

/// A primitive during the build: its box and its index in the caller's list.
#[derive(Clone, Copy, Debug)]
pub(crate) struct PrimRef {
    lo_: [f32; 3],
    pub index: u32,
    hi_: [f32; 3],
    /// 1 while the list is filled for a box left out, else 0.
    _pad: u32,
}

impl PrimRef {
    #[inline]
    fn lo(&self) -> Vec3A {
        Vec3A::from_array(self.lo_)
    }
    #[inline]
    fn hi(&self) -> Vec3A {
        Vec3A::from_array(self.hi_)
    }
    #[inline]
    pub(super) fn centroid2(&self) -> Vec3A {
        self.lo() + self.hi()
    }
}

/// Bounds of a set: of its boxes, and of its centroids (doubled, as `lo + hi`).
#[derive(Clone, Copy, Debug)]
struct SetInfo {
    lo: Vec3A,
    hi: Vec3A,
    clo: Vec3A,
    chi: Vec3A,
}

impl SetInfo {
    const EMPTY: SetInfo = SetInfo {
        lo: Vec3A::splat(f32::INFINITY),
        hi: Vec3A::splat(f32::NEG_INFINITY),
        clo: Vec3A::splat(f32::INFINITY),
        chi: Vec3A::splat(f32::NEG_INFINITY),
    };
    #[inline]
    fn add(&mut self, p: &PrimRef) {
        let (lo, hi) = (p.lo(), p.hi());
        self.lo = self.lo.min(lo);
        self.hi = self.hi.max(hi);
        let c = lo + hi;
        self.clo = self.clo.min(c);
        self.chi = self.chi.max(c);
    }
    #[inline]
    fn merge(&mut self, o: &SetInfo) {
        self.lo = self.lo.min(o.lo);
        self.hi = self.hi.max(o.hi);
        self.clo = self.clo.min(o.clo);
        self.chi = self.chi.max(o.chi);
    }
    fn aabb(&self) -> Aabb {
        Aabb::new(self.lo.into(), self.hi.into())
    }
    fn area(&self) -> f32 {
        let e = (self.hi - self.lo).max(Vec3A::ZERO);
        2.0 * (e.x * e.y + e.y * e.z + e.z * e.x)
    }
    fn of(prims: &[PrimRef]) -> SetInfo {
        let mut s = SetInfo::EMPTY;
        for p in prims {
            s.add(p);
        }
        s
    }
}

/// The box bounds of the primitives in one bin. Bins keep no centroid bounds: the
/// partition that follows a split visits every primitive anyway and gathers the two
/// sides' centroid bounds there (as Embree's binned builders do), which halves the
/// bounds updated per primitive and axis while binning.
#[derive(Clone, Copy, Debug)]
struct BinBox {
    lo: Vec3A,
    hi: Vec3A,
}

impl BinBox {
    const EMPTY: BinBox = BinBox {
        lo: Vec3A::splat(f32::INFINITY),
        hi: Vec3A::splat(f32::NEG_INFINITY),
    };
    #[inline]
    fn merge(&mut self, o: &BinBox) {
        self.lo = self.lo.min(o.lo);
        self.hi = self.hi.max(o.hi);
    }
    fn area(&self) -> f32 {
        let e = (self.hi - self.lo).max(Vec3A::ZERO);
        2.0 * (e.x * e.y + e.y * e.z + e.z * e.x)
    }
}

/// Per-axis bins: how many centroids fall in each and the bounds of their boxes.
#[derive(Clone)]
struct Bins {
    count: [[u32; BINS]; 3],
    bounds: [[BinBox; BINS]; 3],
}

/// Maps doubled centroids to bin numbers along each axis.
#[derive(Clone, Copy)]
struct Binner {
    origin: Vec3A,
    scale: Vec3A,
    /// Bins in use (fewer for small sets, where 32 would cost more than they gain).
    bins: usize,
}

impl Binner {
    fn new(info: &SetInfo, n: usize) -> Self {
        let bins = if n < 64 {
            8
        } else if n < 1024 {
            16
        } else {
            BINS
        };
        let extent = info.chi - info.clo;
        let scale = Vec3A::select(
            extent.cmpgt(Vec3A::ZERO),
            Vec3A::splat(bins as f32 * 0.999_99) / extent,
            Vec3A::ZERO,
        );
        Self {
            origin: info.clo,
            scale,
            bins,
        }
    }
    #[inline]
    fn bins(&self, p: &PrimRef) -> [usize; 3] {
        let b = ((p.centroid2() - self.origin) * self.scale)
            .max(Vec3A::ZERO)
            .min(Vec3A::splat((self.bins - 1) as f32));
        truncate(b)
    }
}

impl Binner {
    /// Whether the bin along `axis` is below `bin`: the same arithmetic as `bins`,
    /// so partitions agree with the counts, but compared as a float (for an integer
    /// `bin >= 1`, `floor(x) < bin` exactly when `x < bin`), which spares the
    /// float-to-integer conversion in the partition's inner loop.
    #[inline(always)]
    fn below(&self, p: &PrimRef, axis: usize, bin: f32) -> bool {
        let c = p.lo_[axis] + p.hi_[axis];
        ((c - self.origin[axis]) * self.scale[axis])
            .max(0.0)
            .min((self.bins - 1) as f32)
            < bin
    }
}

/// The integer parts of three bin coordinates already clamped to `[0, BINS - 1]`, in
/// one SIMD conversion (Rust's `as` would add a saturation check per lane).
#[inline(always)]
fn truncate(b: Vec3A) -> [usize; 3] {
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::x86_64::*;
        let mut out = [0i32; 4];
        // SAFETY: SSE2 is part of the x86_64 baseline; `out` has room for 16 bytes.
        unsafe {
            let i = _mm_cvttps_epi32(b.into());
            _mm_storeu_si128(out.as_mut_ptr() as *mut __m128i, i);
        }
        [out[0] as usize, out[1] as usize, out[2] as usize]
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        [b.x as usize, b.y as usize, b.z as usize]
    }
}

impl Bins {
    fn new() -> Self {
        Bins {
            count: [[0; BINS]; 3],
            bounds: [[BinBox::EMPTY; BINS]; 3],
        }
    }
    fn fill(binner: &Binner, prims: &[PrimRef]) -> Self {
        if prims.len() >= PARALLEL_BINNING {
            use rayon::prelude::*;
            return prims
                .par_chunks(PARALLEL_BINNING / 4)
                .map(|c| Bins::fill(binner, c))
                .reduce_with(|mut a, b| {
                    a.merge(&b);
                    a
                })
                .unwrap_or_else(Bins::new);
        }
        let mut bins = Bins::new();
        if prims.len() < DUAL_BINS {
            for p in prims {
                bins.add(binner, p);
            }
            return bins;
        }
        // Neighbouring primitives often fall in the same bins, and each update then
        // waits for the previous one's store: two sets of bins, for the even and the
        // odd primitives, make two independent chains.
        let mut odd = Bins::new();
        let mut pairs = prims.chunks_exact(2);
        for pair in &mut pairs {
            bins.add(binner, &pair[0]);
            odd.add(binner, &pair[1]);
        }
        for p in pairs.remainder() {
            bins.add(binner, p);
        }
        bins.merge(&odd);
        bins
    }
    #[inline(always)]
    fn add(&mut self, binner: &Binner, p: &PrimRef) {
        let b = binner.bins(p);
        let (lo, hi) = (p.lo(), p.hi());
        for (axis, &bin) in b.iter().enumerate() {
            // Bin numbers are below BINS already; the mask only lets the compiler
            // drop the bounds checks.
            let k = bin & (BINS - 1);
            self.count[axis][k] += 1;
            let bb = &mut self.bounds[axis][k];
            bb.lo = bb.lo.min(lo);
            bb.hi = bb.hi.max(hi);
        }
    }
    fn merge(&mut self, o: &Bins) {
        for axis in 0..3 {
            for i in 0..BINS {
                if self.count[axis][i] == 0 && o.count[axis][i] == 0 {
                    continue;
                }
                self.count[axis][i] += o.count[axis][i];
                self.bounds[axis][i].merge(&o.bounds[axis][i]);
            }
        }
    }
}

/// A chosen split: primitives whose bin along `axis` is below `bin` go left.
struct Split {
    axis: usize,
    bin: usize,
    /// SAH cost of the split relative to the parent (`C_t + C_i Σ A_c N_c / A`).
    cost: f32,
    /// Box bounds of the two sides (their centroid bounds come from the partition).
    left: BinBox,
    right: BinBox,
}

fn best_split(bins: &Bins, nb: usize, parent_area: f32, block: usize) -> Option<Split> {
    let mut best: Option<Split> = None;
    for axis in 0..3 {
        let mut right_area = [0f32; BINS];
        let mut acc = BinBox::EMPTY;
        let mut n = 0u32;
        let mut right_count = [0u32; BINS];
        for i in (1..nb).rev() {
            acc.merge(&bins.bounds[axis][i]);
            n += bins.count[axis][i];
            right_area[i] = acc.area();
            right_count[i] = n;
        }
        let mut left = BinBox::EMPTY;
        let mut nl = 0u32;
        for i in 1..nb {
            left.merge(&bins.bounds[axis][i - 1]);
            nl += bins.count[axis][i - 1];
            let nr = right_count[i];
            if nl == 0 || nr == 0 {
                continue;
            }
            let cost = left.area() * blocks(nl as usize, block)
                + right_area[i] * blocks(nr as usize, block);
            if best.as_ref().is_none_or(|b| cost < b.cost) {
                best = Some(Split {
                    axis,
                    bin: i,
                    cost,
                    left,
                    right: BinBox::EMPTY,
                });
            }
        }
    }
    let mut s = best?;
    let mut right = BinBox::EMPTY;
    for i in s.bin..nb {
        right.merge(&bins.bounds[s.axis][i]);
    }
    s.right = right;
    s.cost = TRAVERSAL_COST + INTERSECT_COST * s.cost / parent_area.max(f32::MIN_POSITIVE);
    Some(s)
}

/// Splits `prims` in two; the left part is moved to the front. Returns the size of the
/// left part and the two sets' bounds, or `None` when the set should stay a leaf.
fn split(
    prims: &mut [PrimRef],
    info: &SetInfo,
    depth: u32,
    block: usize,
) -> Option<(usize, SetInfo, SetInfo)> {
    let n = prims.len();
    if n <= 1 {
        return None;
    }
    if n <= MAX_LEAF && depth < MAX_SAH_DEPTH && TRAVERSAL_COST >= INTERSECT_COST * blocks(n, block)
    {
        // Any split costs at least a node visit, which is already as much as testing
        // the whole set as one leaf (sets of up to `block` primitives): a leaf.
        return None;
    }
    if n <= SWEEP_MAX && depth < MAX_SAH_DEPTH {
        return sweep_split(prims, info, block);
    }
    let sah = if depth < MAX_SAH_DEPTH && (info.chi - info.clo).max_element() > 0.0 {
        let binner = Binner::new(info, n);
        let bins = Bins::fill(&binner, prims);
        best_split(&bins, binner.bins, info.area(), block).map(|s| (s, binner))
    } else {
        None
    };
    match sah {
        Some((s, binner)) => {
            if n <= MAX_LEAF && s.cost >= INTERSECT_COST * blocks(n, block) {
                return None;
            }
            let (mid, cl, cr) = partition(prims, |p| binner.below(p, s.axis, s.bin as f32));
            debug_assert!(mid > 0 && mid < n);
            let side = |b: BinBox, c: Centroids| SetInfo {
                lo: b.lo,
                hi: b.hi,
                clo: c.lo,
                chi: c.hi,
            };
            Some((mid, side(s.left, cl), side(s.right, cr)))
        }
        None => {
            if n <= MAX_LEAF && depth < MAX_SAH_DEPTH {
                return None;
            }
            // Centroids coincide (or the tree is too deep): split at the median along
            // the longest axis of the centroid bounds.
            let axis = Aabb::new((info.clo).into(), (info.chi).into()).largest_axis();
            let mid = n / 2;
            prims.select_nth_unstable_by(mid, |a, b| {
                a.centroid2()[axis].total_cmp(&b.centroid2()[axis])
            });
            Some((mid, SetInfo::of(&prims[..mid]), SetInfo::of(&prims[mid..])))
        }
    }
}

/// Exact SAH for small sets: sort along each axis and try every split position.
fn sweep_split(
    prims: &mut [PrimRef],
    info: &SetInfo,
    block: usize,
) -> Option<(usize, SetInfo, SetInfo)> {
    let n = prims.len();
    let mut best = (f32::INFINITY, 0usize, 0usize);
    let mut right_area = [0f32; SWEEP_MAX + 1];
    for axis in 0..3 {
        prims.sort_unstable_by(|a, b| a.centroid2()[axis].total_cmp(&b.centroid2()[axis]));
        let mut acc = SetInfo::EMPTY;
        for i in (1..n).rev() {
            acc.add(&prims[i]);
            right_area[i] = acc.area();
        }
        let mut left = SetInfo::EMPTY;
        for i in 1..n {
            left.add(&prims[i - 1]);
            let cost = left.area() * blocks(i, block) + right_area[i] * blocks(n - i, block);
            if cost < best.0 {
                best = (cost, axis, i);
            }
        }
    }
    let (cost, axis, mid) = best;
    let cost = TRAVERSAL_COST + INTERSECT_COST * cost / info.area().max(f32::MIN_POSITIVE);
    if cost >= INTERSECT_COST * blocks(n, block) && n <= MAX_LEAF {
        return None;
    }
    if axis != 2 {
        prims.sort_unstable_by(|a, b| a.centroid2()[axis].total_cmp(&b.centroid2()[axis]));
    }
    Some((mid, SetInfo::of(&prims[..mid]), SetInfo::of(&prims[mid..])))
}

/// Node storage filled by several threads: each node index is handed out once by an
/// atomic counter and written once.
struct Arena {
    ptr: *mut WideNode,
    capacity: usize,
    next: AtomicUsize,
    /// Primitives per intersection block (see `blocks`).
    block: usize,
}

// SAFETY: every index is handed out exactly once (fetch_add), so no two threads write
// the same slot, and nothing reads the slots until the build has finished.
unsafe impl Sync for Arena {}

impl Arena {
    fn alloc(&self) -> usize {
        let i = self.next.fetch_add(1, Ordering::Relaxed);
        assert!(i < self.capacity, "BVH node arena overflow");
        i
    }
    fn write(&self, i: usize, node: WideNode) {
        assert!(i < self.capacity);
        // SAFETY: `i` is in bounds and was handed out once by `alloc`.
        unsafe { self.ptr.add(i).write(node) }
    }
}

/// A child set while a node is being split.
struct Part {
    start: usize,
    len: usize,
    info: SetInfo,
    /// Decided to stay a leaf.
    leaf: bool,
    /// Depth of the set in the binary tree the wide node collapses (what the
    /// median-split bound and so the traversal stack bound count).
    depth: u32,
}

fn build_node(
    prims: &mut [PrimRef],
    offset: usize,
    info: SetInfo,
    depth: u32,
    arena: &Arena,
) -> ChildRef {
    let mut parts: Vec<Part> = Vec::with_capacity(WIDTH);
    parts.push(Part {
        start: 0,
        len: prims.len(),
        info,
        leaf: prims.len() <= 1,
        depth,
    });
    while parts.len() < WIDTH {
        // Split the set with the largest surface area that may still be split.
        let Some(k) = (0..parts.len())
            .filter(|&k| !parts[k].leaf)
            .max_by(|&a, &b| parts[a].info.area().total_cmp(&parts[b].info.area()))
        else {
            break;
        };
        let p = &parts[k];
        let (start, len, d) = (p.start, p.len, p.depth);
        match split(&mut prims[start..start + len], &p.info, d, arena.block) {
            None => parts[k].leaf = true,
            Some((mid, l, r)) => {
                parts[k] = Part {
                    start,
                    len: mid,
                    info: l,
                    leaf: mid <= 1,
                    depth: d + 1,
                };
                parts.push(Part {
                    start: start + mid,
                    len: len - mid,
                    info: r,
                    leaf: len - mid <= 1,
                    depth: d + 1,
                });
            }
        }
    }
    parts.sort_by_key(|p| p.start);
    let leaf_ref = |p: &Part| ChildRef {
        index: (offset + p.start) as u32,
        count: p.len as u32,
    };
    if parts.len() == 1 && depth > 0 {
        // Not worth splitting after all: the parent points at the leaf directly.
        return leaf_ref(&parts[0]);
    }
    let index = arena.alloc();
    let mut node = WideNode::EMPTY;
    if parts.len() == 1 {
        // The whole set is one leaf: the root is still a node, with one child.
        node.set(0, parts[0].info.aabb(), leaf_ref(&parts[0]));
        arena.write(index, node);
        return ChildRef {
            index: index as u32,
            count: 0,
        };
    }
    // Hand each child its own disjoint slice.
    let mut refs = [ChildRef::EMPTY; WIDTH];
    let mut rest = prims;
    let mut slices: Vec<(&mut [PrimRef], &Part)> = Vec::with_capacity(WIDTH);
    let mut consumed = 0;
    for p in &parts {
        let (s, r) = rest.split_at_mut(p.start + p.len - consumed);
        consumed = p.start + p.len;
        slices.push((s, p));
        rest = r;
    }
    let build_child = |(s, p): (&mut [PrimRef], &Part)| -> ChildRef {
        if p.leaf {
            leaf_ref(p)
        } else {
            build_node(s, offset + p.start, p.info, p.depth, arena)
        }
    };
    if prims_len(&parts) >= PARALLEL_SUBTREE {
        use rayon::prelude::*;
        let out: Vec<ChildRef> = slices.into_par_iter().map(build_child).collect();
        refs[..out.len()].copy_from_slice(&out);
    } else {
        for (i, s) in slices.into_iter().enumerate() {
            refs[i] = build_child(s);
        }
    }
    for (i, p) in parts.iter().enumerate() {
        node.set(i, p.info.aabb(), refs[i]);
    }
    arena.write(index, node);
    ChildRef {
        index: index as u32,
        count: 0,
    }
}

fn prims_len(parts: &[Part]) -> usize {
    parts.iter().map(|p| p.len).sum()
}

/// Builds the node array over the boxes `box_of(0..count)`. Boxes that are empty or not finite are left
/// out. Returns the nodes (root first) and the primitive order (slot -> index).
pub(crate) fn build(
    count: usize,
    box_of: impl Fn(usize) -> Aabb + Sync,
    block: usize,
) -> (Vec<WideNode>, Vec<u32>) {
    use rayon::prelude::*;
    // An indexed collect writes straight into one vector (a filtered one would gather
    // pieces and copy them); the boxes left out are then squeezed out in place.
    let mut prims: Vec<PrimRef> = (0..count)
        .into_par_iter()
        .map(|i| {
            let b = box_of(i);
            PrimRef {
                lo_: b.min.to_array(),
                hi_: b.max.to_array(),
                index: i as u32,
                _pad: u32::from(!b.is_finite() || b.is_empty()),
            }
        })
        .collect();
    if prims.iter().any(|p| p._pad != 0) {
        prims.retain(|p| p._pad == 0);
    }
    if prims.is_empty() {
        return (vec![WideNode::EMPTY], Vec::new());
    }
    let info = if prims.len() >= PARALLEL_BINNING {
        prims
            .par_chunks(PARALLEL_BINNING / 4)
            .map(SetInfo::of)
            .reduce(
                || SetInfo::EMPTY,
                |mut a, b| {
                    a.merge(&b);
                    a
                },
            )
    } else {
        SetInfo::of(&prims)
    };
    // Every inner node has at least two children and every leaf at least one
    // primitive, so there are fewer nodes than primitives (plus the root).
    let capacity = prims.len() + 1;
    let mut nodes: Vec<WideNode> = Vec::with_capacity(capacity);
    irradia_core::pages::prefer_huge_pages_raw(nodes.as_mut_ptr(), capacity);
    let arena = Arena {
        ptr: nodes.as_mut_ptr(),
        capacity,
        next: AtomicUsize::new(0),
        block: block.max(1),
    };
    let root = build_node(&mut prims, 0, info, 0, &arena);
    debug_assert_eq!(root.index, 0);
    let used = arena.next.load(Ordering::Acquire);
    // SAFETY: slots 0..used were each written exactly once by `build_node`, which has
    // returned, so all of them are initialised.
    unsafe { nodes.set_len(used) };
    // No shrink_to_fit: the unused tail was never touched, so it costs no memory,
    // and reallocating would lose the huge-page advice.
    let order = prims.par_iter().map(|p| p.index).collect();
    (nodes, order)
}

#[cfg(test)]
mod tests {
    use super::super::partition::{partition_branchless, partition_hoare};
    use super::*;
    use irradia_core::Rng;

    fn random_prims(rng: &mut Rng, n: usize) -> Vec<PrimRef> {
        (0..n)
            .map(|i| {
                let c = Vec3A::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * 10.0;
                let e = Vec3A::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * 0.3;
                PrimRef {
                    lo_: (c - e).to_array(),
                    hi_: (c + e).to_array(),
                    index: i as u32,
                    _pad: 0,
                }
            })
            .collect()
    }

    fn same(a: &SetInfo, b: &SetInfo) -> bool {
        a.lo == b.lo && a.hi == b.hi && a.clo == b.clo && a.chi == b.chi
    }

    #[test]
    fn partition_counts_and_gathers_the_centroid_bounds_of_each_side() {
        let mut rng = Rng::new(7, 1);
        for n in [1, 2, 3, 4, 10, 11, 100, 101, 1000, 1001] {
            let mut prims = random_prims(&mut rng, n);
            let cut = 10.0 * rng.next_f32();
            let left = |p: &PrimRef| p.centroid2().x < cut;
            let want = prims.iter().filter(|p| left(p)).count();
            let (mid, cl, cr) = if n % 2 == 0 {
                partition_hoare(&mut prims, left)
            } else {
                partition_branchless(&mut prims, left)
            };
            assert_eq!(mid, want);
            assert!(prims[..mid].iter().all(left) && !prims[mid..].iter().any(left));
            let (l, r) = (SetInfo::of(&prims[..mid]), SetInfo::of(&prims[mid..]));
            assert_eq!((cl.lo, cl.hi), (l.clo, l.chi));
            assert_eq!((cr.lo, cr.hi), (r.clo, r.chi));
        }
    }

    #[test]
    fn binned_splits_report_the_exact_bounds_of_both_sides() {
        let mut rng = Rng::new(7, 2);
        for n in [9, 40, 200, 3000] {
            for block in [1, 8] {
                let mut prims = random_prims(&mut rng, n);
                let info = SetInfo::of(&prims);
                let (mid, l, r) = split(&mut prims, &info, 0, block).expect("a split");
                assert!(mid > 0 && mid < n);
                assert!(same(&l, &SetInfo::of(&prims[..mid])), "n {n} block {block}");
                assert!(same(&r, &SetInfo::of(&prims[mid..])), "n {n} block {block}");
                // The two sides are the two sides of one bin boundary.
                let binner = Binner::new(&info, n);
                let axis = (0..3)
                    .find(|&a| {
                        (1..binner.bins).any(|b| {
                            prims[..mid].iter().all(|p| binner.bins(p)[a] < b)
                                && prims[mid..].iter().all(|p| binner.bins(p)[a] >= b)
                        })
                    })
                    .is_some();
                assert!(axis, "n {n} block {block}");
            }
        }
    }

    #[test]
    fn sets_no_larger_than_a_block_stay_leaves_and_larger_ones_are_split() {
        let mut rng = Rng::new(7, 3);
        for n in 2..=MAX_LEAF {
            let mut prims = random_prims(&mut rng, n);
            let info = SetInfo::of(&prims);
            assert!(split(&mut prims, &info, 0, 8).is_none(), "n {n}");
            // Past the SAH depth limit sets are split at the median whatever their size.
            let (mid, _, _) = split(&mut prims, &info, MAX_SAH_DEPTH, 8).expect("median");
            assert_eq!(mid, n / 2);
        }
        // Far-apart pairs are worth splitting when each primitive is its own block.
        let mut prims = random_prims(&mut rng, 2);
        prims[1].lo_ = [1e3; 3];
        prims[1].hi_ = [1e3 + 1.0; 3];
        let info = SetInfo::of(&prims);
        assert!(split(&mut prims, &info, 0, 1).is_some());
    }

    #[test]
    fn the_bin_test_of_the_partition_agrees_with_the_bin_numbers() {
        let mut rng = Rng::new(7, 4);
        let prims = random_prims(&mut rng, 2000);
        let info = SetInfo::of(&prims);
        for n in [20, 500, 2000] {
            let binner = Binner::new(&info, n);
            for p in &prims {
                let b = binner.bins(p);
                for (axis, &got) in b.iter().enumerate() {
                    for bin in 1..binner.bins {
                        assert_eq!(binner.below(p, axis, bin as f32), got < bin);
                    }
                }
            }
        }
    }
}
