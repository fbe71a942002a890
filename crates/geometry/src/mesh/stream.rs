//! Batches of rays against a mesh: consecutive rays go eight at a time through the
//! packet traversal of the BVH ([`crate::bvh::packet_traverse`]) when they agree on
//! their direction signs (primary rays of a camera do, almost everywhere), and through
//! the single-ray traversal otherwise (Benthin, Wald et al. 2012 pick between packet
//! and single-ray traversal by the coherence of the rays; the test here is the
//! cheapest one, Wald et al. 2001's requirement of a common direction octant). The
//! batch's single rays are walked several at a time in turns, each as it would be
//! alone, so their cache misses overlap ([`crate::bvh`]'s `interleaved.rs`).
//!
//! The answers are bit for bit those of [`TriangleMesh::intersect_triangle`] and
//! [`TriangleMesh::intersect_cast_hit`], ray by ray. The single-ray traversal keeps the
//! first hit it meets among equally near ones, and which comes first depends on the
//! order it visits leaves in, which a packet does not share. So a packet ray records,
//! besides its nearest hit, the nearest *other* hit it met (its leaf tests run against
//! a bound a few ulps beyond its nearest hit): when that one lies within
//! [`TIE_ULPS`] of the nearest, the order could matter and the ray is traced again
//! alone. Otherwise the nearest hit is separated from every other by more than the
//! rounding of the watertight test's range check (`t_scaled < t_max det`, `t <
//! t_max`), so any visit order accepts it and rejects the rest.

use super::{Triangle4, TriangleMesh};
use crate::bvh::packet_traverse::{Lanes8, PacketRay, PACKET};
use crate::packet::watertight4;
use crate::shape::CastHit;
use crate::triangle::{TriangleHit, TriangleRay};
use irradia_core::Ray;

/// Relative gap (in units of `f32::EPSILON`) below which a second hit makes a packet
/// ray's answer depend on the visit order; such rays are traced again alone. The
/// range check's rounding is about 3 units of the unit roundoff (`EPSILON / 2`).
pub const TIE_ULPS: f32 = 8.0;

/// How far beyond its nearest hit a packet ray keeps testing (in `f32::EPSILON`), so
/// that every hit within [`TIE_ULPS`] of the nearest is met.
const LOOSE_ULPS: f32 = 32.0;

/// A nearest hit as the single-ray query finds it: packet, lane, hit.
type LaneHit<'a> = Option<(&'a Triangle4, usize, TriangleHit)>;

impl TriangleMesh {
    /// `out[i]` = [`TriangleMesh::intersect_triangle`]`(&rays[i], t_max)` for every ray,
    /// with coherent groups of eight consecutive rays traced as packets (see the
    /// module). `out` must be as long as `rays`.
    pub fn intersect_triangles(
        &self,
        rays: &[Ray],
        t_max: f32,
        out: &mut [Option<(u32, crate::triangle::TriangleHit)>],
    ) {
        assert_eq!(rays.len(), out.len(), "one answer per ray");
        self.closest_lanes_stream(rays, t_max, |i, hit| {
            out[i] = hit.map(|(p, lane, h)| (p.ids[lane], h));
        });
    }

    /// `out[i]` = [`TriangleMesh::intersect_cast_hit`]`(&rays[i], t_max)` for every ray,
    /// as [`TriangleMesh::intersect_triangles`] does. `out` must be as long as `rays`.
    pub fn intersect_cast_hits(&self, rays: &[Ray], t_max: f32, out: &mut [Option<CastHit>]) {
        assert_eq!(rays.len(), out.len(), "one answer per ray");
        if self.normals_given || self.uvs.is_some() {
            for (o, r) in out.iter_mut().zip(rays) {
                *o = self.intersect_cast_hit(r, t_max);
            }
            return;
        }
        self.closest_lanes_stream(rays, t_max, |i, hit| {
            out[i] = hit.map(|(p, lane, h)| Self::cast_hit_of(p, lane, &h));
        });
    }

    /// The nearest hit of every ray, `emit(index, hit)` (in no set order), in groups
    /// of [`PACKET`]: coherent groups as packets, the rays of the others walked a few
    /// at a time in turns, each exactly as `closest_lane` walks it (see
    /// `bvh/interleaved.rs`).
    #[inline]
    fn closest_lanes_stream<'a>(
        &'a self,
        rays: &[Ray],
        t_max: f32,
        mut emit: impl FnMut(usize, LaneHit<'a>),
    ) {
        let mut lone: Vec<usize> = Vec::new();
        for (g, group) in rays.chunks(PACKET).enumerate() {
            let base = g * PACKET;
            let packet = if group.len() > 1 && t_max > 0.0 {
                PacketRay::new(group)
            } else {
                None
            };
            match packet.and_then(|p| self.closest_lanes_packet(group, &p, t_max)) {
                Some((hits, _)) => {
                    for (k, h) in hits.into_iter().take(group.len()).enumerate() {
                        emit(base + k, h);
                    }
                }
                None => lone.extend(base..base + group.len()),
            }
        }
        if lone.is_empty() {
            return;
        }
        let lone_rays: Vec<Ray> = lone.iter().map(|&i| rays[i]).collect();
        let trays: Vec<TriangleRay> = lone_rays.iter().map(TriangleRay::new).collect();
        let mut best: Vec<LaneHit<'a>> = vec![None; lone.len()];
        self.bvh.closest_hit_leaves_interleaved(
            &lone_rays,
            &vec![t_max; lone_rays.len()],
            |leaf| self.prefetch_leaf(leaf),
            |k, leaf, t_max| {
                let packets = self.leaf_packets(leaf);
                let (i, h) =
                    watertight4::intersect_leaf(packets, leaf.count as usize, &trays[k], t_max)?;
                best[k] = Some((&packets[i / 4], i % 4, h));
                Some(h.t)
            },
        );
        for (&i, h) in lone.iter().zip(best) {
            emit(i, h);
        }
    }

    /// The packet traversal's answers for `rays` (prepared as `packet`), each the
    /// single-ray answer (rays whose answer could depend on the visit order are
    /// traced again alone, bits of the second value); `None` where the packet
    /// traversal is not available.
    #[inline]
    fn closest_lanes_packet<'a>(
        &'a self,
        rays: &[Ray],
        packet: &PacketRay,
        t_max: f32,
    ) -> Option<([LaneHit<'a>; PACKET], u32)> {
        self.closest_lanes_packet_masked(rays, packet, packet.lanes(), &Lanes8([t_max; PACKET]))
    }

    /// [`Self::closest_lanes_packet`] for the rays in lanes `active` only, each
    /// bounded by its own `t_max[k]`: lane `k`'s answer is
    /// [`TriangleMesh::closest_lane`]`(&rays[k], t_max[k])` bit for bit (other lanes
    /// are `None`).
    #[inline]
    fn closest_lanes_packet_masked<'a>(
        &'a self,
        rays: &[Ray],
        packet: &PacketRay,
        active: u32,
        t_max: &Lanes8,
    ) -> Option<([LaneHit<'a>; PACKET], u32)> {
        let (mut best, ties) = self.nearest_lanes(rays, packet, active, t_max)?;
        let mut m = ties;
        while m != 0 {
            let k = m.trailing_zeros() as usize;
            m &= m - 1;
            best[k] = self.closest_lane(&rays[k], t_max.0[k]);
        }
        Some((best, ties))
    }

    /// The packet traversal's nearest hit of each ray in lanes `active` (bounded by
    /// `t_max[k]`), and the lanes whose nearest hit has another within [`TIE_ULPS`]
    /// (where the single-ray traversal's visit order decides, so the caller traces
    /// them again alone); elsewhere the hit is the single-ray one, bit for bit.
    /// `None` where the packet traversal is not available.
    #[inline]
    fn nearest_lanes<'a>(
        &'a self,
        rays: &[Ray],
        packet: &PacketRay,
        active: u32,
        t_max: &Lanes8,
    ) -> Option<([LaneHit<'a>; PACKET], u32)> {
        let active = active & packet.lanes();
        // Lanes beyond the rays repeat the first (they are never active).
        let first = TriangleRay::new(&rays[0]);
        let mut trays = [first; PACKET];
        for (t, r) in trays.iter_mut().zip(rays).skip(1) {
            *t = TriangleRay::new(r);
        }
        let mut best: [LaneHit<'a>; PACKET] = [None; PACKET];
        let mut second = [f32::INFINITY; PACKET];
        let mut bound = *t_max;
        let loose = 1.0 + LOOSE_ULPS * f32::EPSILON;
        let done = self.bvh.packet_leaves(
            packet,
            active,
            &mut bound,
            |l| self.prefetch_leaf(l),
            |leaf, lanes, bound| {
                let packets = self.leaf_packets(leaf);
                let count = leaf.count as usize;
                let mut m = lanes;
                while m != 0 {
                    let k = m.trailing_zeros() as usize;
                    m &= m - 1;
                    let ray = &trays[k];
                    let mut cand = watertight4::leaf_candidates(packets, count, ray, bound.0[k]);
                    while cand != 0 {
                        let i = cand.trailing_zeros() as usize;
                        cand &= cand - 1;
                        let [a, b, c] = packets[i / 4].corners(i % 4);
                        let Some(h) = ray.intersect(a, b, c, bound.0[k]) else {
                            continue;
                        };
                        match best[k] {
                            Some((_, _, old)) if h.t >= old.t => {
                                second[k] = second[k].min(h.t);
                            }
                            old => {
                                if let Some((_, _, old)) = old {
                                    second[k] = second[k].min(old.t);
                                }
                                best[k] = Some((&packets[i / 4], i % 4, h));
                                bound.0[k] = (h.t * loose).min(t_max.0[k]);
                            }
                        }
                    }
                }
            },
        );
        if !done {
            return None;
        }
        let tie = 1.0 + TIE_ULPS * f32::EPSILON;
        let mut ties = 0;
        let mut m = active;
        while m != 0 {
            let k = m.trailing_zeros() as usize;
            m &= m - 1;
            if let Some((_, _, h)) = best[k] {
                if second[k] <= h.t * tie {
                    ties |= 1 << k;
                }
            }
        }
        Some((best, ties))
    }

    /// The nearest cast hit (bounded by `t_max`) of each of `rays` through the
    /// single-ray traversal, walked several at a time in turns (see
    /// `bvh/interleaved.rs`), and whether another hit lies within [`TIE_ULPS`] of it:
    /// what [`Self::nearest_cast_lanes`] answers for one lane, without carrying seven
    /// empty lanes through the 8-wide packet traversal (for rays outside a coherent
    /// group, which are most rays of an incoherent batch); `emit(index, hit, tied)`
    /// once per ray. The same rule as [`Self::nearest_lanes`]: the leaves' tests run
    /// against a bound [`LOOSE_ULPS`] beyond the nearest hit so far, every other hit
    /// met is kept as the second, and a second within [`TIE_ULPS`] of the nearest
    /// flags the ray. `false`, having emitted nothing, where the mesh's cast hits
    /// need more than the leaf.
    pub(crate) fn nearest_cast_stream(
        &self,
        rays: &[Ray],
        t_max: f32,
        mut emit: impl FnMut(usize, Option<CastHit>, bool),
    ) -> bool {
        if !self.casts_from_leaves() {
            return false;
        }
        let trays: Vec<TriangleRay> = rays.iter().map(TriangleRay::new).collect();
        let mut best: Vec<LaneHit<'_>> = vec![None; rays.len()];
        let mut second = vec![f32::INFINITY; rays.len()];
        self.bvh.closest_hit_leaves_interleaved(
            rays,
            &vec![t_max; rays.len()],
            |l| self.prefetch_leaf(l),
            |k, leaf, bound| {
                self.nearest_in_leaf(leaf, &trays[k], bound, t_max, &mut best[k], &mut second[k])
            },
        );
        let tie = 1.0 + TIE_ULPS * f32::EPSILON;
        for (k, (best, second)) in best.into_iter().zip(second).enumerate() {
            let tied = matches!(best, Some((_, _, h)) if second <= h.t * tie);
            emit(
                k,
                best.map(|(p, lane, h)| Self::cast_hit_of(p, lane, &h)),
                tied,
            );
        }
        true
    }

    /// One leaf of [`Self::nearest_cast_stream`]'s walk for one ray: its hits within
    /// `bound` update the nearest (`best`) and the nearest other (`second`); the
    /// tightened bound ([`LOOSE_ULPS`] beyond a new nearest) when there is one.
    #[inline(always)]
    fn nearest_in_leaf<'a>(
        &'a self,
        leaf: crate::bvh::ChildRef,
        tray: &TriangleRay,
        bound: f32,
        t_max: f32,
        best: &mut LaneHit<'a>,
        second: &mut f32,
    ) -> Option<f32> {
        let loose = 1.0 + LOOSE_ULPS * f32::EPSILON;
        let packets = self.leaf_packets(leaf);
        let mut cand = watertight4::leaf_candidates(packets, leaf.count as usize, tray, bound);
        let mut tightened = None;
        while cand != 0 {
            let i = cand.trailing_zeros() as usize;
            cand &= cand - 1;
            let [a, b, c] = packets[i / 4].corners(i % 4);
            let Some(h) = tray.intersect(a, b, c, bound) else {
                continue;
            };
            match *best {
                Some((_, _, old)) if h.t >= old.t => *second = second.min(h.t),
                old => {
                    if let Some((_, _, old)) = old {
                        *second = second.min(old.t);
                    }
                    *best = Some((&packets[i / 4], i % 4, h));
                    tightened = Some((h.t * loose).min(t_max));
                }
            }
        }
        tightened
    }

    /// [`Self::nearest_lanes`] as cast hits (triangle ids as the mesh numbers them):
    /// for each lane `k` of `active`, the nearest hit bounded by `t_max[k]`, and the
    /// lanes with a near tie (their answers are to be traced again by the caller).
    /// `None` where the packet traversal is not available or the mesh's cast hits need
    /// more than the leaf.
    pub(crate) fn nearest_cast_lanes(
        &self,
        rays: &[Ray],
        packet: &PacketRay,
        active: u32,
        t_max: &Lanes8,
    ) -> Option<([Option<CastHit>; PACKET], u32)> {
        if !self.casts_from_leaves() || rays.is_empty() {
            return None;
        }
        let (hits, ties) = self.nearest_lanes(rays, packet, active, t_max)?;
        Some((
            hits.map(|h| h.map(|(p, lane, h)| Self::cast_hit_of(p, lane, &h))),
            ties,
        ))
    }

    /// Whether [`Self::intersect_cast_lanes`] traces packets for this mesh: its cast
    /// hits come from the leaf alone (no given normals or uvs).
    #[inline]
    pub(crate) fn casts_from_leaves(&self) -> bool {
        !(self.normals_given || self.uvs.is_some())
    }

    /// For each lane `k` of `active`: `out[k]` = [`TriangleMesh::intersect_cast_hit`]
    /// `(&rays[k], t_max[k])`, bit for bit, the lanes traced together as `packet`
    /// (which must hold `rays`). Returns `false`, having written nothing, where the
    /// packet traversal is not available (no AVX2, or a mesh whose cast hits need more
    /// than the leaf: see [`Self::casts_from_leaves`]).
    pub fn intersect_cast_lanes(
        &self,
        rays: &[Ray],
        packet: &PacketRay,
        active: u32,
        t_max: &Lanes8,
        out: &mut [Option<CastHit>; PACKET],
    ) -> bool {
        if !self.casts_from_leaves() || rays.is_empty() {
            return false;
        }
        let Some((hits, _)) = self.closest_lanes_packet_masked(rays, packet, active, t_max) else {
            return false;
        };
        let mut m = active & packet.lanes();
        while m != 0 {
            let k = m.trailing_zeros() as usize;
            m &= m - 1;
            out[k] = hits[k].map(|(p, lane, h)| Self::cast_hit_of(p, lane, &h));
        }
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    /// A flat grid of `n` x `n` unit squares in z = 0, two triangles each.
    fn grid(n: u32) -> TriangleMesh {
        let mut positions = Vec::new();
        for y in 0..=n {
            for x in 0..=n {
                positions.push(Vec3::new(x as f32, y as f32, 0.0));
            }
        }
        let v = |x: u32, y: u32| y * (n + 1) + x;
        let mut indices = Vec::new();
        for y in 0..n {
            for x in 0..n {
                indices.push([v(x, y), v(x + 1, y), v(x + 1, y + 1)]);
                indices.push([v(x, y), v(x + 1, y + 1), v(x, y + 1)]);
            }
        }
        TriangleMesh::new(positions, indices, None, None).unwrap()
    }

    /// Rays from one eye through grid vertices and edge midpoints hit several triangles
    /// at (nearly) the same t: the packet must notice the near-tie, trace those rays
    /// alone, and so answer exactly as the single-ray query does.
    #[test]
    fn near_ties_are_traced_alone_and_agree() {
        if !crate::packet::has_avx2() {
            return;
        }
        let mesh = grid(32);
        let eye = Vec3::new(13.3, 9.7, 7.0);
        let mut retraced_total = 0;
        for y in 0..64 {
            let rays: Vec<Ray> = (0..64)
                .map(|x| Ray::new(eye, Vec3::new(x as f32 * 0.5, y as f32 * 0.5, 0.0) - eye))
                .collect();
            for group in rays.chunks(PACKET) {
                let packet = PacketRay::new(group);
                let Some(packet) = packet else { continue };
                let (hits, retraced) = mesh
                    .closest_lanes_packet(group, &packet, f32::INFINITY)
                    .unwrap();
                retraced_total += retraced.count_ones();
                for (k, r) in group.iter().enumerate() {
                    let a = hits[k].map(|(p, l, h)| (p.ids[l], h.t.to_bits(), h.b1.to_bits()));
                    let b = mesh
                        .closest_lane(r, f32::INFINITY)
                        .map(|(p, l, h)| (p.ids[l], h.t.to_bits(), h.b1.to_bits()));
                    assert_eq!(a, b, "ray {r:?}");
                }
            }
        }
        assert!(
            retraced_total > 0,
            "the grid's vertices must produce near-ties"
        );
    }
}
