//! The in-place partition of a set of primitives at a split of the BVH build
//! ([`super::build`]): each primitive is classified once, moved to its side and added
//! to that side's centroid bounds, so the children's bins need no second pass.

use super::build::PrimRef;
use glam::Vec3A;

/// Bounds of (doubled) centroids.
#[derive(Clone, Copy, Debug)]
pub(super) struct Centroids {
    pub(super) lo: Vec3A,
    pub(super) hi: Vec3A,
}

impl Centroids {
    pub(super) const EMPTY: Centroids = Centroids {
        lo: Vec3A::splat(f32::INFINITY),
        hi: Vec3A::splat(f32::NEG_INFINITY),
    };
    #[inline(always)]
    pub(super) fn add(&mut self, p: &PrimRef) {
        let c = p.centroid2();
        self.lo = self.lo.min(c);
        self.hi = self.hi.max(c);
    }
}

/// Sets up to this size (256 KiB of primitives, in cache) are partitioned without
/// branches on the side of each primitive; larger ones, where the build waits on
/// memory rather than on mispredicted branches, by Hoare's scheme, which writes only
/// the primitives on the wrong side.
const BRANCHLESS_PARTITION: usize = 1 << 13;

/// In-place partition; returns the number of elements for which `left` holds, and
/// the centroid bounds of the two sides. Every element is classified once and added
/// to its side's bounds then. Which scheme runs changes only the order of the
/// primitives within each side, never the sides.
pub(super) fn partition(
    prims: &mut [PrimRef],
    left: impl Fn(&PrimRef) -> bool,
) -> (usize, Centroids, Centroids) {
    if prims.len() <= BRANCHLESS_PARTITION {
        partition_branchless(prims, left)
    } else {
        partition_hoare(prims, left)
    }
}

/// Lomuto's scheme with an unconditional swap: `prims[..i]` go left, `prims[i..j]`
/// right, so swapping `prims[j]` into place and advancing `i` by the outcome keeps
/// both true whichever side `prims[j]` is on, and the outcome never steers a branch
/// (the branch-free partitions of Edelkamp and Weiß, "BlockQuicksort: Avoiding Branch
/// Mispredictions in Quicksort", ESA 2016).
pub(super) fn partition_branchless(
    prims: &mut [PrimRef],
    left: impl Fn(&PrimRef) -> bool,
) -> (usize, Centroids, Centroids) {
    let mut sides = [Centroids::EMPTY; 2];
    let mut i = 0usize;
    for j in 0..prims.len() {
        let p = prims[j];
        let is_left = left(&p);
        sides[is_left as usize].add(&p);
        prims[j] = prims[i];
        prims[i] = p;
        i += is_left as usize;
    }
    (i, sides[1], sides[0])
}

pub(super) fn partition_hoare(
    prims: &mut [PrimRef],
    left: impl Fn(&PrimRef) -> bool,
) -> (usize, Centroids, Centroids) {
    let (mut cl, mut cr) = (Centroids::EMPTY, Centroids::EMPTY);
    let (mut i, mut j) = (0usize, prims.len());
    loop {
        while i < j {
            let p = &prims[i];
            if !left(p) {
                break;
            }
            cl.add(p);
            i += 1;
        }
        while i < j {
            let p = &prims[j - 1];
            if left(p) {
                break;
            }
            cr.add(p);
            j -= 1;
        }
        if i >= j {
            return (i, cl, cr);
        }
        // prims[i] goes right and prims[j - 1] left.
        cr.add(&prims[i]);
        cl.add(&prims[j - 1]);
        prims.swap(i, j - 1);
        i += 1;
        j -= 1;
    }
}
