//! Packet traversal of the wide BVH: up to eight coherent rays walk the tree together
//! (Wald, Slusallek, Benthin, Wagner, "Interactive Rendering with Coherent Ray
//! Tracing", EG 2001), each with its own bit in an active mask, as in the masked
//! packet traversals of Reshetov, Soupikov, Hurley ("Multi-Level Ray Tracing
//! Algorithm", SIGGRAPH 2005) and Benthin, Wald et al. ("Combining Single and
//! Packet-Ray Tracing for Arbitrary Ray Distributions on the Intel MIC Architecture",
//! TVCG 2012).
//!
//! A node is read once for the whole packet: its boxes are tested child by child with
//! the rays in the eight lanes of an AVX2 register, so a child's test yields the mask
//! of the rays entering it and their entry distances at once. The arithmetic per ray
//! and box is that of the single-ray test ([`super::node::WideNode::intersect_avx2`]:
//! the same subtractions, products and min/max order), so a ray enters exactly the
//! boxes it enters alone. The rays must agree on the sign of each direction component
//! (so one near/far plane choice serves them all): [`PacketRay::new`] refuses them
//! otherwise, which is also the cheap coherence test callers use.
//!
//! Children are visited in the order of the packet's first active ray; each stacked
//! child keeps its rays' entry distances, and on pop a ray stays active only while its
//! entry lies within its own current bound. Which leaves each ray reaches is thus a
//! superset of what it needs; the caller's leaf test decides hits lane by lane.

use super::build::MAX_SAH_DEPTH;
use super::node::{ChildRef, NodeRay, ROBUST_FAR, WIDTH};
use super::Bvh;
use irradia_core::Ray;
use std::mem::MaybeUninit;

/// Rays in a packet.
pub const PACKET: usize = 8;

/// Subtrees that fewer rays than this enter are walked ray by ray (a packet's box
/// test costs one pass per child, a single ray's one pass per node).
pub const SINGLE_BELOW: usize = 3;

/// Stack depth, as for the single-ray traversal.
const STACK: usize = (WIDTH - 1) * (MAX_SAH_DEPTH as usize + 33);

/// Eight `f32`, 32-byte aligned for AVX loads.
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(C, align(32))]
pub struct Lanes8(pub [f32; PACKET]);

/// Up to [`PACKET`] rays prepared for the box test, one ray per lane (structure of
/// arrays), all with the same near planes.
#[derive(Clone, Copy, Debug)]
pub struct PacketRay {
    origin: [Lanes8; 3],
    inv_dir: [Lanes8; 3],
    near: [usize; 3],
    /// Lanes holding a ray (bit `k` for `rays[k]`).
    lanes: u32,
}

impl PacketRay {
    /// Prepares `rays` (1 to [`PACKET`] of them), or `None` when they do not agree on
    /// the near plane of every axis (the sign of each reciprocal direction component,
    /// as [`NodeRay::new`] picks it), or when there are none or too many.
    #[inline]
    pub fn new(rays: &[Ray]) -> Option<Self> {
        if rays.is_empty() || rays.len() > PACKET {
            return None;
        }
        let first = NodeRay::new(rays[0].origin, rays[0].dir);
        let mut p = PacketRay {
            origin: [Lanes8([0.0; PACKET]); 3],
            inv_dir: [Lanes8([0.0; PACKET]); 3],
            near: first.near,
            lanes: (1u32 << rays.len()) - 1,
        };
        for k in 0..PACKET {
            // Unused lanes repeat the first ray (they are never active).
            let r = if k < rays.len() {
                NodeRay::new(rays[k].origin, rays[k].dir)
            } else {
                first
            };
            if r.near != first.near {
                return None;
            }
            for axis in 0..3 {
                p.origin[axis].0[k] = r.origin[axis];
                p.inv_dir[axis].0[k] = r.inv_dir[axis];
            }
        }
        Some(p)
    }

    /// The lanes holding a ray.
    #[inline]
    pub fn lanes(&self) -> u32 {
        self.lanes
    }
}

/// A stacked child: the rays that entered it and their entry distances.
#[derive(Clone, Copy)]
#[repr(C, align(32))]
struct Entry {
    t_near: Lanes8,
    node: ChildRef,
    lanes: u32,
}

impl Bvh {
    /// Walks the tree with the rays of `packet` in the lanes `active` (a subset of
    /// [`PacketRay::lanes`]). `t_max[k]` bounds ray `k`: boxes it enters beyond it are
    /// not entered. `leaf(leaf, lanes, t_max)` is called for each leaf with the lanes
    /// whose ray entered its box (never empty) and may lower their `t_max`;
    /// `prefetch(leaf)` as soon as some ray enters a leaf's box, so the caller can
    /// start loading its data.
    ///
    /// Where fewer than [`SINGLE_BELOW`] rays remain active in a subtree, each walks
    /// it alone (the ordered single-ray traversal, with the same box test), as
    /// Benthin et al. switch from packet to single-ray traversal.
    ///
    /// Needs AVX2 (the box test runs eight rays per instruction): returns `false`,
    /// having done nothing, where the CPU lacks it.
    #[inline]
    pub fn packet_leaves<P, F>(
        &self,
        packet: &PacketRay,
        active: u32,
        t_max: &mut Lanes8,
        prefetch: P,
        leaf: F,
    ) -> bool
    where
        P: Fn(ChildRef),
        F: FnMut(ChildRef, u32, &mut Lanes8),
    {
        #[cfg(target_arch = "x86_64")]
        if crate::packet::has_avx2() {
            // SAFETY: the CPU has AVX2.
            unsafe { self.packet_avx2(packet, active & packet.lanes, t_max, prefetch, leaf) };
            return true;
        }
        let _ = (packet, active, t_max, prefetch, leaf);
        false
    }

    /// Ray `lane` of `p` alone through the subtree under `start`, nearest child first
    /// (the single-ray traversal of `traverse.rs`, bounded by `t_max[lane]`).
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    #[inline]
    unsafe fn single_subtree<P, F>(
        &self,
        p: &PacketRay,
        lane: usize,
        start: ChildRef,
        t_max: &mut Lanes8,
        prefetch: &P,
        leaf: &mut F,
    ) where
        P: Fn(ChildRef),
        F: FnMut(ChildRef, u32, &mut Lanes8),
    {
        let nray = NodeRay {
            origin: std::array::from_fn(|a| p.origin[a].0[lane]),
            inv_dir: std::array::from_fn(|a| p.inv_dir[a].0[lane]),
            near: p.near,
            avx2: true,
        };
        let bit = 1u32 << lane;
        // The leaf callback lowers `t_max[lane]` itself; handing it back keeps the
        // walk's bound the same.
        self.closest_from::<true, _, _>(&nray, start, t_max.0[lane], prefetch, |c, _| {
            leaf(c, bit, t_max);
            Some(t_max.0[lane])
        });
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    unsafe fn packet_avx2<P, F>(
        &self,
        p: &PacketRay,
        active: u32,
        t_max: &mut Lanes8,
        prefetch: P,
        mut leaf: F,
    ) where
        P: Fn(ChildRef),
        F: FnMut(ChildRef, u32, &mut Lanes8),
    {
        use std::arch::x86_64::*;
        if active == 0 {
            return;
        }
        let ld = |l: &Lanes8| _mm256_load_ps(l.0.as_ptr());
        let (ox, oy, oz) = (ld(&p.origin[0]), ld(&p.origin[1]), ld(&p.origin[2]));
        let (ix, iy, iz) = (ld(&p.inv_dir[0]), ld(&p.inv_dir[1]), ld(&p.inv_dir[2]));
        let far = |near: usize| if near >= 3 { near - 3 } else { near + 3 };
        let rows = [
            p.near[0],
            p.near[1],
            p.near[2],
            far(p.near[0]),
            far(p.near[1]),
            far(p.near[2]),
        ];
        let zero = _mm256_setzero_ps();
        let robust = _mm256_set1_ps(ROBUST_FAR);
        let mut stack: [MaybeUninit<Entry>; STACK] = [const { MaybeUninit::uninit() }; STACK];
        let mut sp = 0usize;
        let mut current = ChildRef { index: 0, count: 0 };
        let mut lanes = active;
        loop {
            if current.is_leaf() {
                leaf(current, lanes, t_max);
            } else if (lanes.count_ones() as usize) < SINGLE_BELOW {
                let mut m = lanes;
                while m != 0 {
                    let k = m.trailing_zeros() as usize;
                    m &= m - 1;
                    self.single_subtree(p, k, current, t_max, &prefetch, &mut leaf);
                }
            } else {
                let node = &self.nodes[current.index as usize];
                let tm = ld(t_max);
                let b = node.bounds.as_ptr() as *const f32;
                let mut ents: [Entry; WIDTH] = [Entry {
                    t_near: Lanes8([0.0; PACKET]),
                    node: ChildRef::EMPTY,
                    lanes: 0,
                }; WIDTH];
                let mut keys = [0f32; WIDTH];
                let mut order = [0u8; WIDTH];
                let mut n = 0;
                let lead = lanes.trailing_zeros() as usize;
                for i in 0..WIDTH {
                    let c = node.child_ref(i);
                    if c.is_empty() {
                        continue;
                    }
                    // One box against the packet: the single-ray test's operations.
                    let s = |row: usize, o: __m256, inv: __m256| {
                        _mm256_mul_ps(
                            _mm256_sub_ps(_mm256_set1_ps(*b.add(WIDTH * row + i)), o),
                            inv,
                        )
                    };
                    let nx = s(rows[0], ox, ix);
                    let ny = s(rows[1], oy, iy);
                    let nz = s(rows[2], oz, iz);
                    let fx = s(rows[3], ox, ix);
                    let fy = s(rows[4], oy, iy);
                    let fz = s(rows[5], oz, iz);
                    let t0 = _mm256_max_ps(nx, _mm256_max_ps(ny, _mm256_max_ps(nz, zero)));
                    let t1 = _mm256_min_ps(fx, _mm256_min_ps(fy, _mm256_min_ps(fz, tm)));
                    let t1 = _mm256_mul_ps(t1, robust);
                    let m = _mm256_movemask_ps(_mm256_cmp_ps::<_CMP_LE_OQ>(t0, t1)) as u32 & lanes;
                    if m == 0 {
                        continue;
                    }
                    if c.is_leaf() {
                        prefetch(c);
                    } else {
                        self.prefetch(c);
                    }
                    let e = &mut ents[n];
                    e.node = c;
                    e.lanes = m;
                    _mm256_store_ps(e.t_near.0.as_mut_ptr(), t0);
                    // Sort key: the entry distance of the leading ray, or of the first
                    // ray that enters when the leading one does not.
                    let k = if m & (1 << lead) != 0 {
                        lead
                    } else {
                        m.trailing_zeros() as usize
                    };
                    let key = e.t_near.0[k];
                    // Insertion sort of the indices, descending by key.
                    let mut j = n;
                    while j > 0 && keys[j - 1] < key {
                        order[j] = order[j - 1];
                        keys[j] = keys[j - 1];
                        j -= 1;
                    }
                    order[j] = n as u8;
                    keys[j] = key;
                    n += 1;
                }
                if n > 0 {
                    for &o in &order[..n - 1] {
                        stack[sp] = MaybeUninit::new(ents[o as usize]);
                        sp += 1;
                    }
                    let e = &ents[order[n - 1] as usize];
                    current = e.node;
                    lanes = e.lanes;
                    continue;
                }
            }
            // Pop the next child that some ray may still find a nearer hit in.
            loop {
                if sp == 0 {
                    return;
                }
                sp -= 1;
                // SAFETY: every slot below the stack pointer was written by a push.
                let e = stack[sp].assume_init();
                let keep = _mm256_movemask_ps(_mm256_cmp_ps::<_CMP_LE_OQ>(ld(&e.t_near), ld(t_max)))
                    as u32
                    & e.lanes;
                if keep != 0 {
                    current = e.node;
                    lanes = keep;
                    break;
                }
            }
        }
    }
}
