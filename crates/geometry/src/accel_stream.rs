//! Batches of rays against the two-level hierarchy of a scene of several objects: eight
//! consecutive rays that share a direction octant walk the top level together
//! ([`crate::bvh::packet_traverse`], as in a mesh), and at each instance they reach,
//! the rays that entered its box go on as one packet through the instance's mesh
//! (carried into object space first where the instance is transformed) — the
//! two-level packet tracing of Wald, Benthin, Slusallek ("Distributed Interactive Ray
//! Tracing of Dynamic Scenes", PVG 2003, section 4: rays transformed per instance, then
//! traced as a packet through the object's own BVH). Rays that share no octant, shapes
//! that are not meshes, and meshes whose cast hits need more than the leaf (given
//! normals or uvs) go ray by ray, as [`Accel::intersect_cast`].
//!
//! The answers are bit for bit those of [`Accel::intersect_cast`]. Each instance's
//! answer to a lane is the single-ray answer for that lane's bound (the mesh's packet
//! query guarantees it; see `mesh/stream.rs`). Which instance the single-ray traversal
//! keeps depends on its visit order only when two instances are hit at (nearly) the
//! same `t`: as inside a mesh, a packet ray keeps testing a little beyond its nearest
//! hit ([`LOOSE_ULPS`]) and records the nearest other instance's hit, and when that
//! lies within [`crate::mesh::TIE_ULPS`] of the nearest, the ray is traced again alone.
//! Otherwise the nearest instance's hit is separated from every other by more than the
//! rounding of the range checks, so any visit order keeps it.

use crate::accel::Accel;
use crate::bvh::packet_traverse::{Lanes8, PacketRay, PACKET};
use crate::instance::Instance;
use crate::mesh::TIE_ULPS;
use crate::shape::CastHit;
use irradia_core::Ray;

/// How far beyond its nearest hit a packet ray keeps asking instances (in
/// `f32::EPSILON`), so that every instance's hit within [`TIE_ULPS`] of it is seen.
const LOOSE_ULPS: f32 = 32.0;

impl Instance {
    /// For each lane `k` of `active` (bits of `rays`, at most [`PACKET`] rays, traced
    /// together as `packet`): `out[k]` = [`Instance::intersect_cast`]`(&rays[k],
    /// t_max[k])`, bit for bit. Other lanes of `out` are left as they are.
    pub fn intersect_cast_lanes(
        &self,
        rays: &[Ray],
        packet: &PacketRay,
        active: u32,
        t_max: &Lanes8,
        out: &mut [Option<CastHit>; PACKET],
    ) {
        if active.count_ones() > 1 {
            if let Some(mesh) = self.shape.as_triangle_mesh() {
                if self.is_identity() {
                    if mesh.intersect_cast_lanes(rays, packet, active, t_max, out) {
                        return;
                    }
                } else if mesh.casts_from_leaves() {
                    // The rays in object space, as `intersect_cast` carries each one.
                    let mut local = [Ray::new(rays[0].origin, rays[0].dir); PACKET];
                    for (l, r) in local.iter_mut().zip(rays) {
                        *l = self.object_ray(r);
                    }
                    let local = &local[..rays.len()];
                    if let Some(p) = PacketRay::new(local) {
                        if mesh.intersect_cast_lanes(local, &p, active, t_max, out) {
                            let mut m = active & p.lanes();
                            while m != 0 {
                                let k = m.trailing_zeros() as usize;
                                m &= m - 1;
                                if let Some(h) = &mut out[k] {
                                    h.normal = self.cast_normal_to_world(h.normal);
                                }
                            }
                            return;
                        }
                    }
                }
            }
        }
        let mut m = active;
        while m != 0 {
            let k = m.trailing_zeros() as usize;
            m &= m - 1;
            out[k] = self.intersect_cast(&rays[k], t_max.0[k]);
        }
    }
}

impl Accel {
    /// `out[i]` = [`Accel::intersect_cast`]`(&rays[i], t_max)` for every ray, bit for
    /// bit, coherent groups of eight consecutive rays traced together (see the module).
    /// A scene of one untransformed mesh ([`Accel::sole_mesh`]) goes straight to that
    /// mesh's batch query, a scene of several untransformed meshes through one mesh of
    /// all their triangles ([`crate::flat_meshes`]). `out` must be as long as `rays`.
    pub fn intersect_cast_hits(
        &self,
        rays: &[Ray],
        t_max: f32,
        out: &mut [Option<(u32, CastHit)>],
    ) {
        assert_eq!(rays.len(), out.len(), "one answer per ray");
        if let Some(mesh) = self.sole_mesh() {
            let mut hits = [None; 256];
            for (r, o) in rays.chunks(256).zip(out.chunks_mut(256)) {
                let hits = &mut hits[..r.len()];
                mesh.intersect_cast_hits(r, t_max, hits);
                for (o, h) in o.iter_mut().zip(hits.iter()) {
                    *o = h.map(|h| (0, h));
                }
            }
            return;
        }
        if let Some(flat) = self.flat_meshes() {
            if self.intersect_cast_flat(flat, rays, t_max, out) {
                return;
            }
        }
        let packets = self.unbounded_count() == 0 && t_max > 0.0 && crate::packet::has_avx2();
        for (group, out) in rays.chunks(PACKET).zip(out.chunks_mut(PACKET)) {
            let packet = if packets && group.len() > 1 {
                PacketRay::new(group)
            } else {
                None
            };
            match packet.and_then(|p| self.intersect_cast_packet(group, &p, t_max)) {
                Some(hits) => out.copy_from_slice(&hits[..group.len()]),
                None => {
                    for (o, r) in out.iter_mut().zip(group) {
                        *o = self.intersect_cast(r, t_max);
                    }
                }
            }
        }
    }

    /// The answers for the rays of `packet` (see the module); `None` where the packet
    /// traversal is not available.
    fn intersect_cast_packet(
        &self,
        rays: &[Ray],
        packet: &PacketRay,
        t_max: f32,
    ) -> Option<[Option<(u32, CastHit)>; PACKET]> {
        let mut best: [Option<(u32, CastHit)>; PACKET] = [None; PACKET];
        let mut second = [f32::INFINITY; PACKET];
        let mut bound = Lanes8([t_max; PACKET]);
        let loose = 1.0 + LOOSE_ULPS * f32::EPSILON;
        let order = self.bvh().order();
        let instances = self.instances();
        let done = self.bvh().packet_leaves(
            packet,
            packet.lanes(),
            &mut bound,
            |_| {},
            |leaf, lanes, bound| {
                for slot in leaf.index..leaf.index + leaf.count {
                    let i = order[slot as usize];
                    let mut hits = [None; PACKET];
                    instances[i as usize]
                        .intersect_cast_lanes(rays, packet, lanes, bound, &mut hits);
                    let mut m = lanes;
                    while m != 0 {
                        let k = m.trailing_zeros() as usize;
                        m &= m - 1;
                        let Some(h) = hits[k] else { continue };
                        match best[k] {
                            Some((_, old)) if h.t >= old.t => second[k] = second[k].min(h.t),
                            old => {
                                if let Some((_, old)) = old {
                                    second[k] = second[k].min(old.t);
                                }
                                best[k] = Some((i, h));
                                bound.0[k] = (h.t * loose).min(t_max);
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
        for k in 0..rays.len() {
            if let Some((_, h)) = best[k] {
                if second[k] <= h.t * tie {
                    best[k] = self.intersect_cast(&rays[k], t_max);
                }
            }
        }
        Some(best)
    }
}
