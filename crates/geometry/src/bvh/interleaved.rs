//! Several incoherent rays walked in turns, one node or leaf each, so that while one
//! ray waits for the node it has just asked for, the others work.
//!
//! An incoherent ray through a large mesh spends most of its time waiting: the nearest
//! child it descends into was requested (prefetched) only a moment before, so every
//! step of its walk pays a cache miss, and one ray has no other work to overlap with
//! it. Taking turns among [`LANES`] independent rays keeps several misses in flight
//! (memory-level parallelism, as in Ramani/Gribble's ray streams or coroutine-
//! interleaved tree searches: Psaropoulos et al., "Interleaving with Coroutines",
//! VLDB 2017; Kocberber et al., "Asynchronous Memory Access Chaining", VLDB 2015).
//!
//! Each ray's walk is exactly [`Bvh::closest_hit_leaves_prefetch`]'s: the same nodes
//! in the same order, the same leaf calls with the same `t_max`, so every answer is
//! the single-ray one bit for bit; only the interleaving of different rays' steps
//! changes.

use super::node::{ChildRef, NodeRay};
use super::traverse::{Entry, Walk};
use super::Bvh;
use irradia_core::Ray;

/// Rays in flight at once (at most 32). Measured on the 2.25M-triangle gyroid (one
/// thread, CPU seconds, each against the step before): 4 rays in turns within each group
/// of eight 0.70 of the single-ray time, 8 0.88, all of a batch's non-packet rays as one
/// stream 0.76, 16 in flight 0.92: about half the single-ray time in all.
pub const LANES: usize = 16;
const _: () = assert!(LANES <= 32);

impl Bvh {
    /// The nearest hit of each of `rays` (ray `i` bounded by `t_max[i]`), walked
    /// [`LANES`] at a time in turns: `hit(ray_index, leaf, t_max)` and
    /// `prefetch(leaf)` as in [`Bvh::closest_hit_leaves_prefetch`] (the leaf closure
    /// records the hits; a ray's calls come in its single-ray order).
    pub fn closest_hit_leaves_interleaved<P, F>(
        &self,
        rays: &[Ray],
        t_max: &[f32],
        prefetch: P,
        hit: F,
    ) where
        P: Fn(ChildRef),
        F: FnMut(usize, ChildRef, f32) -> Option<f32>,
    {
        assert_eq!(t_max.len(), rays.len(), "one bound per ray");
        if rays.is_empty() {
            return;
        }
        #[cfg(target_arch = "x86_64")]
        if crate::packet::has_avx2() {
            // SAFETY: the CPU has AVX2.
            return unsafe { self.interleaved_avx2(rays, t_max, prefetch, hit) };
        }
        self.interleaved::<false, P, F>(rays, t_max, prefetch, hit)
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    unsafe fn interleaved_avx2<P, F>(&self, rays: &[Ray], t_max: &[f32], prefetch: P, hit: F)
    where
        P: Fn(ChildRef),
        F: FnMut(usize, ChildRef, f32) -> Option<f32>,
    {
        self.interleaved::<true, P, F>(rays, t_max, prefetch, hit)
    }

    #[inline(always)]
    fn interleaved<const AVX: bool, P, F>(
        &self,
        rays: &[Ray],
        t_max: &[f32],
        prefetch: P,
        mut hit: F,
    ) where
        P: Fn(ChildRef),
        F: FnMut(usize, ChildRef, f32) -> Option<f32>,
    {
        let root = ChildRef { index: 0, count: 0 };
        let begin = |w: &mut Walk<Entry>, index: usize| {
            w.restart(
                NodeRay::new(rays[index].origin, rays[index].dir),
                index,
                root,
                t_max[index],
            );
        };
        // The walks are set up once and restarted in place (a new one would copy its
        // stack).
        let mut walks: [Walk<Entry>; LANES] = std::array::from_fn(|_| {
            Walk::new(NodeRay::new(rays[0].origin, rays[0].dir), 0, root, t_max[0])
        });
        take_turns(&mut walks, rays.len(), begin, |w| {
            self.closest_step::<AVX, P, F>(w, &prefetch, &mut hit)
        });
    }
}

/// Walks `count` rays [`LANES`] at a time in turns: `begin(walk, i)` sets a slot to
/// ray `i`'s start, `step(walk)` takes one step of it and says whether it goes on;
/// a slot whose ray is done takes the next ray.
#[inline(always)]
fn take_turns<W>(
    walks: &mut [W; LANES],
    count: usize,
    begin: impl Fn(&mut W, usize),
    mut step: impl FnMut(&mut W) -> bool,
) {
    let live_n = LANES.min(count);
    for (k, w) in walks.iter_mut().enumerate().take(live_n) {
        begin(w, k);
    }
    let mut live: u32 = (1u32 << live_n) - 1;
    let mut next = live_n;
    while live != 0 {
        let mut m = live;
        while m != 0 {
            let k = m.trailing_zeros() as usize;
            m &= m - 1;
            let w = &mut walks[k];
            if step(w) {
                continue;
            }
            // This ray is done: the next one takes its turn.
            if next < count {
                begin(w, next);
                next += 1;
            } else {
                live &= !(1 << k);
            }
        }
    }
}

impl Bvh {
    /// Whether each of `rays` hits anything with `0 < t < t_max[i]`, written to
    /// `out[i]`: [`Bvh::any_hit_leaves`] for every ray, walked [`LANES`] at a time in
    /// turns (`hit(ray_index, leaf, t_max)` says whether the leaf blocks the ray).
    /// Each walk is the single-ray one (the same nodes in the same order with the same
    /// bound), so every answer is the same.
    pub fn any_hit_leaves_interleaved<F>(
        &self,
        rays: &[Ray],
        t_max: &[f32],
        out: &mut [bool],
        hit: F,
    ) where
        F: FnMut(usize, ChildRef, f32) -> bool,
    {
        assert!(t_max.len() == rays.len() && out.len() == rays.len());
        if rays.is_empty() {
            return;
        }
        #[cfg(target_arch = "x86_64")]
        if crate::packet::has_avx2() {
            // SAFETY: the CPU has AVX2.
            return unsafe { self.any_interleaved_avx2(rays, t_max, out, hit) };
        }
        self.any_interleaved::<false, F>(rays, t_max, out, hit)
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    unsafe fn any_interleaved_avx2<F>(&self, rays: &[Ray], t_max: &[f32], out: &mut [bool], hit: F)
    where
        F: FnMut(usize, ChildRef, f32) -> bool,
    {
        self.any_interleaved::<true, F>(rays, t_max, out, hit)
    }

    #[inline(always)]
    fn any_interleaved<const AVX: bool, F>(
        &self,
        rays: &[Ray],
        t_max: &[f32],
        out: &mut [bool],
        mut hit: F,
    ) where
        F: FnMut(usize, ChildRef, f32) -> bool,
    {
        let root = ChildRef { index: 0, count: 0 };
        let begin = |w: &mut Walk<ChildRef>, index: usize| {
            w.restart(
                NodeRay::new(rays[index].origin, rays[index].dir),
                index,
                root,
                t_max[index],
            );
        };
        let mut walks: [Walk<ChildRef>; LANES] = std::array::from_fn(|_| {
            Walk::new(NodeRay::new(rays[0].origin, rays[0].dir), 0, root, 0.0)
        });
        take_turns(&mut walks, rays.len(), begin, |w| {
            match self.any_step::<AVX, F>(w, &mut hit) {
                None => true,
                Some(blocked) => {
                    out[w.index] = blocked;
                    false
                }
            }
        });
    }
}
