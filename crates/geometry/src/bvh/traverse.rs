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
/// Plus one: the nearest-hit walk sorts a node's entered children on the stack before
/// it pops the nearest, so it writes one slot above what it keeps.
pub(super) const STACK: usize = (WIDTH - 1) * (MAX_SAH_DEPTH as usize + 33) + 1;

#[derive(Clone, Copy)]
pub(super) struct Entry {
    pub(super) node: ChildRef,
    pub(super) t_near: f32,
}

/// One ray's walk in progress: its ray, its bound, the node it is at and its stack
/// (of [`Entry`] for the nearest-hit walk, of bare [`ChildRef`]s for the any-hit walk).
pub(super) struct Walk<E> {
    pub(super) ray: NodeRay,
    /// Which of the caller's rays (for walks taken in turns).
    pub(super) index: usize,
    pub(super) t_max: f32,
    pub(super) current: ChildRef,
    pub(super) sp: usize,
    /// Left uninitialised: zeroing 3 KiB per query cost more than many whole
    /// traversals of small scenes. Only slots below `sp` are ever read.
    pub(super) stack: [MaybeUninit<E>; STACK],
}

impl<E: Copy> Walk<E> {
    #[inline(always)]
    pub(super) fn new(ray: NodeRay, index: usize, start: ChildRef, t_max: f32) -> Self {
        Walk {
            ray,
            index,
            t_max,
            current: start,
            sp: 0,
            stack: [const { MaybeUninit::uninit() }; STACK],
        }
    }

    /// Starts this walk again for another ray (the stack is reused in place, not copied).
    #[inline(always)]
    pub(super) fn restart(&mut self, ray: NodeRay, index: usize, start: ChildRef, t_max: f32) {
        self.ray = ray;
        self.index = index;
        self.t_max = t_max;
        self.current = start;
        self.sp = 0;
    }
}

impl Bvh {
    /// Pushes the children of `node` that `mask` says the walk's ray enters (at
    /// distances `t_near`) onto `w`'s stack sorted far to near, each prefetched (a leaf
    /// by `leaf_prefetch`, a node by [`Bvh::prefetch`]), then pops the nearest into
    /// `w.current`. The entries are sorted in place on the stack: sorting them in an
    /// array of their own and copying that cost a store-forwarding stall per node (the
    /// copy's 32-byte loads of the sort's 4- and 8-byte stores: 13% of the walk's
    /// samples on the bunny).
    #[inline(always)]
    fn descend_nearest_first(
        &self,
        w: &mut Walk<Entry>,
        node: &super::node::WideNode,
        mut mask: u32,
        t_near: &[f32; WIDTH],
        leaf_prefetch: impl Fn(ChildRef),
    ) {
        let base = w.sp;
        let mut top = base;
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
            let mut j = top;
            // SAFETY: slots `base..top` were written by this loop.
            while j > base && unsafe { w.stack[j - 1].assume_init() }.t_near < e.t_near {
                w.stack[j] = w.stack[j - 1];
                j -= 1;
            }
            w.stack[j] = MaybeUninit::new(e);
            top += 1;
        }
        // The caller entered at least one child; the nearest is on top.
        w.sp = top - 1;
        // SAFETY: written above.
        w.current = unsafe { w.stack[top - 1].assume_init() }.node;
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
        let mut w = Walk::new(*nray, 0, start, t_max);
        let mut leaf = |_: usize, c: ChildRef, t_max: f32| hit(c, t_max);
        while self.closest_step::<AVX, P, _>(&mut w, &prefetch, &mut leaf) {}
        // The bound only ever shrinks, to a nearer hit.
        (w.t_max < t_max).then_some(w.t_max)
    }

    /// One step of `w`'s nearest-hit walk: a leaf (`hit(w.index, leaf, t_max)`, and the
    /// bound shrinks to a nearer hit), or a node and the descent into its nearest entered
    /// child (the others pushed far to near), or pops up to the next node that may still
    /// hold a nearer hit. Returns whether the walk goes on. The single-ray walk
    /// (`Bvh::closest_from`) and the walks taken in turns (`interleaved.rs`) are loops
    /// over this step.
    #[inline(always)]
    pub(super) fn closest_step<const AVX: bool, P, F>(
        &self,
        w: &mut Walk<Entry>,
        prefetch: &P,
        hit: &mut F,
    ) -> bool
    where
        P: Fn(ChildRef),
        F: FnMut(usize, ChildRef, f32) -> Option<f32>,
    {
        let current = w.current;
        if current.is_leaf() {
            if let Some(t) = hit(w.index, current, w.t_max) {
                if t < w.t_max {
                    w.t_max = t;
                }
            }
        } else {
            let node = &self.nodes[current.index as usize];
            let (mask, t_near) = node.intersect_with::<AVX>(&w.ray, w.t_max);
            if mask != 0 {
                self.descend_nearest_first(w, node, mask, &t_near, prefetch);
                return true;
            }
        }
        // Pop the next node that may still hold a nearer hit.
        loop {
            if w.sp == 0 {
                return false;
            }
            w.sp -= 1;
            // SAFETY: every slot below the stack pointer was written by a push.
            let e = unsafe { w.stack[w.sp].assume_init() };
            if e.t_near <= w.t_max {
                w.current = e.node;
                return true;
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
        let root = ChildRef { index: 0, count: 0 };
        let mut w = Walk::new(NodeRay::new(ray.origin, ray.dir), 0, root, t_max);
        let mut leaf = |_: usize, c: ChildRef, t_max: f32| hit(c, t_max);
        loop {
            if let Some(blocked) = self.any_step::<AVX, _>(&mut w, &mut leaf) {
                return blocked;
            }
        }
    }

    /// One step of `w`'s any-hit walk: a leaf (`hit(w.index, leaf, t_max)` says whether
    /// it blocks the ray), or a node and the descent into its first entered child (the
    /// others pushed, in no order that matters), or a pop. `None` while the walk goes
    /// on, else whether the ray is blocked. `Bvh::any` and the shadow walks taken in
    /// turns (`interleaved.rs`) are loops over this step.
    #[inline(always)]
    pub(super) fn any_step<const AVX: bool, F>(
        &self,
        w: &mut Walk<ChildRef>,
        hit: &mut F,
    ) -> Option<bool>
    where
        F: FnMut(usize, ChildRef, f32) -> bool,
    {
        let current = w.current;
        if current.is_leaf() {
            if hit(w.index, current, w.t_max) {
                return Some(true);
            }
        } else {
            let node = &self.nodes[current.index as usize];
            let (mut mask, _) = node.intersect_with::<AVX>(&w.ray, w.t_max);
            if mask != 0 {
                let first = mask.trailing_zeros() as usize;
                mask &= mask - 1;
                while mask != 0 {
                    let i = mask.trailing_zeros() as usize;
                    mask &= mask - 1;
                    w.stack[w.sp] = MaybeUninit::new(node.child_ref(i));
                    w.sp += 1;
                }
                w.current = node.child_ref(first);
                return None;
            }
        }
        if w.sp == 0 {
            return Some(false);
        }
        w.sp -= 1;
        // SAFETY: every slot below the stack pointer was written by a push.
        w.current = unsafe { w.stack[w.sp].assume_init() };
        None
    }
}
