//! The mesh's triangle packets in leaf order, placed so that every leaf of two or
//! more packets starts on a cache line.
//!
//! A packet is 160 bytes, two and a half 64-byte lines. Stored back to back from a
//! 16-byte aligned base (what the allocator gives a `Vec<Triangle4>`), a two-packet
//! leaf (the gyroid's usual leaf of 5-8 triangles) spans 6 lines wherever it starts,
//! and a one-packet leaf 3 or 4. Here storage is allocated in pairs of packets aligned
//! to 64 bytes, so even packet indices start a line: a leaf of several packets is put
//! at an even index (5 lines for two packets), and the odd slot skipped for it is
//! filled by a later one-packet leaf (3 lines at either parity). Incoherent rays miss
//! the cache on nearly every leaf they open, so lines per leaf is memory traffic per
//! ray (Embree aligns its leaf blocks the same way: Wald et al., "Embree: A Kernel
//! Framework for Efficient CPU Ray Tracing", SIGGRAPH 2014).

use crate::packet::Triangle4;

/// Two packets on a line boundary: 320 bytes, five lines.
#[derive(Clone, Copy, Debug)]
#[repr(C, align(64))]
struct Pair([Triangle4; 2]);

const _: () = assert!(std::mem::size_of::<Pair>() == 2 * std::mem::size_of::<Triangle4>());

/// What unused slots hold: no leaf refers to them.
const FILLER: Triangle4 = Triangle4 {
    p: [[[0.0; 4]; 3]; 3],
    ids: [u32::MAX; 4],
};

/// Packets indexed as one slice ([`LeafPackets::as_slice`]); leaf `i`'s packets start
/// at the index [`LeafPackets::push`] returned for it.
#[derive(Clone, Debug, Default)]
pub(super) struct LeafPackets {
    pairs: Vec<Pair>,
    /// Packets in use, holes included: `pairs` holds `len.div_ceil(2)` pairs.
    len: usize,
    /// Odd slots skipped for a leaf of several packets, waiting for a one-packet leaf.
    holes: Vec<usize>,
}

impl LeafPackets {
    /// Room for `packets` packets without reallocating (holes may need a little more),
    /// advised onto huge pages.
    pub(super) fn with_capacity(packets: usize) -> Self {
        let mut pairs = Vec::with_capacity(packets.div_ceil(2) + 1);
        irradia_core::pages::prefer_huge_pages_raw(pairs.as_mut_ptr(), pairs.capacity());
        Self {
            pairs,
            len: 0,
            holes: Vec::new(),
        }
    }

    /// Stores one leaf's `n` packets (at least one), `packet(j)` for `j` in `0..n`,
    /// and returns the index of its first.
    pub(super) fn push(&mut self, n: usize, mut packet: impl FnMut(usize) -> Triangle4) -> u32 {
        debug_assert!(n > 0);
        let start = if n == 1 {
            self.holes.pop().unwrap_or(self.len)
        } else {
            if self.len % 2 == 1 {
                self.holes.push(self.len);
                self.len += 1;
            }
            self.len
        };
        let mut j = 0;
        while j < n {
            let (pair, half) = ((start + j) / 2, (start + j) % 2);
            if pair == self.pairs.len() {
                // A new pair begins here (an odd slot always lies in an existing
                // pair): written once, with the next packet or a filler.
                debug_assert_eq!(half, 0);
                let a = packet(j);
                let b = if j + 1 < n {
                    j += 1;
                    packet(j)
                } else {
                    FILLER
                };
                self.pairs.push(Pair([a, b]));
            } else {
                self.pairs[pair].0[half] = packet(j);
            }
            j += 1;
        }
        self.len = self.len.max(start + n);
        start as u32
    }

    #[inline(always)]
    pub(super) fn as_slice(&self) -> &[Triangle4] {
        debug_assert!(self.len <= 2 * self.pairs.len());
        // SAFETY: `Pair` is `repr(C)` around `[Triangle4; 2]` with no padding (asserted
        // above), so the pairs are `2 * pairs.len()` consecutive, initialised,
        // suitably aligned packets, and `len` never exceeds that.
        unsafe { std::slice::from_raw_parts(self.pairs.as_ptr().cast::<Triangle4>(), self.len) }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    fn packet(id: u32) -> Triangle4 {
        let v = Vec3::splat(id as f32);
        Triangle4::new(&[[v, v + Vec3::X, v + Vec3::Y]]).with_ids(&[id])
    }

    #[test]
    fn leaves_of_several_packets_start_on_a_cache_line_and_holes_are_filled() {
        let mut store = LeafPackets::with_capacity(4);
        // Leaf sizes in packets; each leaf's packets carry its number as ids.
        let sizes = [1, 2, 2, 1, 1, 2, 1, 3, 1, 2];
        let mut starts = Vec::new();
        for (leaf, &n) in sizes.iter().enumerate() {
            starts.push(store.push(n, |_| packet(leaf as u32)) as usize);
        }
        let all = store.as_slice();
        let base = all.as_ptr() as usize;
        let mut used = vec![false; all.len()];
        for (leaf, (&n, &s)) in sizes.iter().zip(&starts).enumerate() {
            for (k, slot) in used.iter_mut().enumerate().skip(s).take(n) {
                assert!(!*slot, "slot {k} given twice");
                *slot = true;
                assert_eq!(all[k].ids[0], leaf as u32);
            }
            if n > 1 {
                assert_eq!((base + s * std::mem::size_of::<Triangle4>()) % 64, 0);
            }
        }
        // Two holes were opened (for leaves 1 and 5) and the one-packet leaves 3 and
        // 6 filled them.
        assert!(used.iter().all(|&u| u), "{used:?}");
    }
}
