//! Ordered depth-first traversal of the wide BVH: children whose box the ray enters
//! are visited nearest first, and a node is skipped when it starts beyond the nearest
//! hit found so far. Shadow rays use an any-hit traversal that stops at the first hit.

use super::build::MAX_SAH_DEPTH;
use super::node::{ChildRef, NodeRay, WIDTH};
use super::Bvh;
use irradia_core::Ray;
use std::mem::MaybeUninit;

/// Stack depth: at most `WIDTH - 1` entries per level, and the builder bounds the
/// binary depth, and so the number of wide levels (median splits beyond binary depth
/// `MAX_SAH_DEPTH`, which halve the set: at most 32 more levels for 32-bit counts).
pub(super) const STACK: usize = (WIDTH - 1) * (MAX_SAH_DEPTH as usize + 33);

#[derive(Clone, Copy)]
pub(super) struct Entry {
    pub(super) node: ChildRef,
    pub(super) t_near: f32,
}

impl Bvh {
    /// The children of `node` that `mask` says a ray enters (at distances `t_near`),
    /// each prefetched (a leaf by `leaf_prefetch`, a node by [`Bvh::prefetch`]), sorted
    /// far to near: the nearest is `hits[n - 1]`, the rest are pushed in order.
    #[inline(always)]
    pub(super) fn entered_far_to_near(
        &self,
        node: &super::node::WideNode,
        mut mask: u32,
        t_near: &[f32; WIDTH],
        leaf_prefetch: impl Fn(ChildRef),
    ) -> ([Entry; WIDTH], usize) {
        let mut hits = [Entry {
            node: ChildRef::EMPTY,
            t_near: 0.0,
        }; WIDTH];
        let mut n = 0;
        while mask != 0 {
            let i = mask.trailing_zeros() as usize;
            mask &= mask - 1;
            let c = node.child_ref(i);
            if c.is_leaf() {
                leaf_prefetch(c);
            } else {
                self.prefetch(c);
            }
            let e = Entry {
                node: c,
                t_near: t_near[i],
            };
            // Insertion sort, descending by distance.
            let mut j = n;
            while j > 0 && hits[j - 1].t_near < e.t_near {
                hits[j] = hits[j - 1];
                j -= 1;
            }
            hits[j] = e;
            n += 1;
        }
        (hits, n)
    }

    /// Starts fetching an inner node's four cache lines (a leaf's data is the caller's).
    #[inline(always)]
    pub(super) fn prefetch(&self, c: ChildRef) {
        #[cfg(target_arch = "x86_64")]
        if !c.is_leaf() {
            if let Some(n) = self.nodes.get(c.index as usize) {
                use std::arch::x86_64::{_mm_prefetch, _MM_HINT_T0};
                let p = n as *const _ as *const i8;
                // SAFETY: prefetching is a hint; `p .. p + 256` is the node.
                unsafe {
                    _mm_prefetch(p, _MM_HINT_T0);
                    _mm_prefetch(p.add(64), _MM_HINT_T0);
                    _mm_prefetch(p.add(128), _MM_HINT_T0);
                    _mm_prefetch(p.add(192), _MM_HINT_T0);
                }
            }
        }
        #[cfg(not(target_arch = "x86_64"))]
        let _ = c;
    }

    /// Finds the nearest hit with `0 < t < t_max`. `hit(slot, t_max)` intersects the
    /// primitive in `slot` and returns `Some(t)` for a hit with `t < t_max` (the
    /// closure records whatever else it needs). Returns the nearest `t` found.
    #[inline]
    pub fn closest_hit<F>(&self, ray: &Ray, t_max: f32, mut hit: F) -> Option<f32>
    where
        F: FnMut(u32, f32) -> Option<f32>,
    {
        self.closest_hit_leaves(ray, t_max, |leaf, mut t_max| {
            let mut found = None;
            for slot in leaf.index..leaf.index + leaf.count {
                if let Some(t) = hit(slot, t_max) {
                    if t < t_max {
                        t_max = t;
                        found = Some(t);
                    }
                }
            }
            found
        })
    }

    /// Like [`Bvh::closest_hit`], but the closure gets a whole leaf (`index` and
    /// `count`; see [`Bvh::map_leaves`]) and returns the nearest `t < t_max` in it.
    #[inline]
    pub fn closest_hit_leaves<F>(&self, ray: &Ray, t_max: f32, hit: F) -> Option<f32>
    where
        F: FnMut(ChildRef, f32) -> Option<f32>,
    {
        self.closest_hit_leaves_prefetch(ray, t_max, |_| {}, hit)
    }

    /// Like [`Bvh::closest_hit_leaves`]; `prefetch(leaf)` is called as soon as a leaf's
    /// box is entered, so the caller can start loading the leaf's data before it is
    /// needed.
    #[inline]
    pub fn closest_hit_leaves_prefetch<P, F>(
        &self,
        ray: &Ray,
        t_max: f32,
        prefetch: P,
        hit: F,
    ) -> Option<f32>
    where
        P: Fn(ChildRef),
        F: FnMut(ChildRef, f32) -> Option<f32>,
    {
        #[cfg(target_arch = "x86_64")]
        if crate::packet::has_avx2() {
            // SAFETY: the CPU has AVX2.
            return unsafe { self.closest_avx2(ray, t_max, prefetch, hit) };
        }
        self.closest::<false, P, F>(ray, t_max, prefetch, hit)
    }

    /// The traversal compiled for AVX2, so the 8-wide box test is inlined into it.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    unsafe fn closest_avx2<P, F>(&self, ray: &Ray, t_max: f32, prefetch: P, hit: F) -> Option<f32>
    where
        P: Fn(ChildRef),
        F: FnMut(ChildRef, f32) -> Option<f32>,
    {
        self.closest::<true, P, F>(ray, t_max, prefetch, hit)
    }

    #[inline(always)]
    fn closest<const AVX: bool, P, F>(
        &self,
        ray: &Ray,
        t_max: f32,
        prefetch: P,
        hit: F,
    ) -> Option<f32>
    where
        P: Fn(ChildRef),
        F: FnMut(ChildRef, f32) -> Option<f32>,
    {
        let nray = NodeRay::new(ray.origin, ray.dir);
        self.closest_from::<AVX, P, F>(&nray, ChildRef { index: 0, count: 0 }, t_max, prefetch, hit)
    }

    /// [`Bvh::closest`] for the ray `nray` through the subtree under `start` (the root
    /// for a whole query; a packet's subtree when one of its rays goes on alone, see
    /// `packet_traverse.rs`): nearest child first, each leaf `hit(leaf, t_max)`.
    #[inline(always)]
    pub(super) fn closest_from<const AVX: bool, P, F>(
        &self,
        nray: &NodeRay,
        start: ChildRef,
        t_max: f32,
        prefetch: P,
        mut hit: F,
    ) -> Option<f32>
    where
        P: Fn(ChildRef),
        F: FnMut(ChildRef, f32) -> Option<f32>,
    {
        let mut t_max = t_max;
        let mut found = false;
        // Left uninitialised: zeroing 3 KiB per query cost more than many whole
        // traversals of small scenes. Only slots below `sp` are ever read.
        let mut stack: [MaybeUninit<Entry>; STACK] = [const { MaybeUninit::uninit() }; STACK];
        let mut sp = 0usize;
        let mut current = start;
        loop {
            if current.is_leaf() {
                if let Some(t) = hit(current, t_max) {
                    if t < t_max {
                        t_max = t;
                        found = true;
                    }
                }
            } else {
                let node = &self.nodes[current.index as usize];
                let (mask, t_near) = node.intersect_with::<AVX>(nray, t_max);
                if mask != 0 {
                    // Collect the entered children, sort them near to far, push all
                    // but the nearest (farthest pushed first) and descend into it.
                    let (hits, n) = self.entered_far_to_near(node, mask, &t_near, &prefetch);
                    for e in &hits[..n - 1] {
                        stack[sp] = MaybeUninit::new(*e);
                        sp += 1;
                    }
                    current = hits[n - 1].node;
                    continue;
                }
            }
            // Pop the next node that may still hold a nearer hit.
            loop {
                if sp == 0 {
                    return found.then_some(t_max);
                }
                sp -= 1;
                // SAFETY: every slot below the stack pointer was written by a push.
                let e = unsafe { stack[sp].assume_init() };
                if e.t_near <= t_max {
                    current = e.node;
                    break;
                }
            }
        }
    }

    /// Whether any primitive is hit with `0 < t < t_max`: `hit(slot, t_max)` says
    /// whether the primitive in `slot` is. Stops at the first hit, in no set order.
    #[inline]
    pub fn any_hit<F>(&self, ray: &Ray, t_max: f32, mut hit: F) -> bool
    where
        F: FnMut(u32, f32) -> bool,
    {
        self.any_hit_leaves(ray, t_max, |leaf, t_max| {
            (leaf.index..leaf.index + leaf.count).any(|slot| hit(slot, t_max))
        })
    }

    /// Like [`Bvh::any_hit`], but the closure gets a whole leaf.
    #[inline]
    pub fn any_hit_leaves<F>(&self, ray: &Ray, t_max: f32, hit: F) -> bool
    where
        F: FnMut(ChildRef, f32) -> bool,
    {
        #[cfg(target_arch = "x86_64")]
        if crate::packet::has_avx2() {
            // SAFETY: the CPU has AVX2.
            return unsafe { self.any_avx2(ray, t_max, hit) };
        }
        self.any::<false, F>(ray, t_max, hit)
    }

    /// The any-hit traversal compiled for AVX2.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    unsafe fn any_avx2<F>(&self, ray: &Ray, t_max: f32, hit: F) -> bool
    where
        F: FnMut(ChildRef, f32) -> bool,
    {
        self.any::<true, F>(ray, t_max, hit)
    }

    #[inline(always)]
    fn any<const AVX: bool, F>(&self, ray: &Ray, t_max: f32, mut hit: F) -> bool
    where
        F: FnMut(ChildRef, f32) -> bool,
    {
        let nray = NodeRay::new(ray.origin, ray.dir);
        let mut stack: [MaybeUninit<ChildRef>; STACK] = [const { MaybeUninit::uninit() }; STACK];
        let mut sp = 0usize;
        let mut current = ChildRef { index: 0, count: 0 };
        loop {
            if current.is_leaf() {
                if hit(current, t_max) {
                    return true;
                }
            } else {
                let node = &self.nodes[current.index as usize];
                let (mut mask, _) = node.intersect_with::<AVX>(&nray, t_max);
                if mask != 0 {
                    let first = mask.trailing_zeros() as usize;
                    mask &= mask - 1;
                    while mask != 0 {
                        let i = mask.trailing_zeros() as usize;
                        mask &= mask - 1;
                        stack[sp] = MaybeUninit::new(node.child_ref(i));
                        sp += 1;
                    }
                    current = node.child_ref(first);
                    continue;
                }
            }
            if sp == 0 {
                return false;
            }
            sp -= 1;
            // SAFETY: every slot below the stack pointer was written by a push.
            current = unsafe { stack[sp].assume_init() };
        }
    }
}
