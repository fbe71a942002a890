//! A scene of several untransformed triangle meshes flattened into one mesh, for
//! batches of cast rays: one hierarchy over every triangle of every object, as Embree
//! builds for a scene of several triangle geometries (and so Open3D's
//! `RaycastingScene`), instead of the scene's two levels, where a ray pays its setup,
//! a dynamic call and a descent from the root again in each object whose box it
//! enters (Wald, Benthin, Slusallek, PVG 2003, section 4, weigh the same trade:
//! instancing against one flat hierarchy over static geometry).
//!
//! The flat mesh holds the objects' triangles one object after another, with the same
//! corners in the same order, so a triangle's hit (t, barycentrics, the normal of its
//! corners) is bit for bit the one its own mesh computes. Which triangle wins between
//! two at (nearly) the same `t` depends on the visit order, which the flat hierarchy
//! does not share with the two levels: such rays (a second hit within
//! [`crate::mesh::TIE_ULPS`] of the nearest, see `mesh/stream.rs`) are traced again
//! through the scene's two levels, so every answer is [`Accel::intersect_cast`]'s.
//!
//! Built on the first batch ([`Accel::prepare_cast_batches`]), kept beside the scene's
//! meshes: it costs the memory of a second copy of them, and only batched ray casting
//! (`scene.cast_rays` from Python) asks for it; the renderers never do.

use crate::accel::Accel;
use crate::bvh::packet_traverse::{Lanes8, PacketRay, PACKET};
use crate::instance::Instance;
use crate::mesh::TriangleMesh;
use crate::shape::CastHit;
use irradia_core::Ray;

/// Every triangle of several meshes in one.
#[derive(Debug)]
pub struct FlatMeshes {
    mesh: TriangleMesh,
    /// Index of each object's first triangle in the flat mesh.
    starts: Vec<u32>,
}

impl FlatMeshes {
    /// The flat mesh of `instances`, when there are two or more, all untransformed
    /// triangle meshes whose cast hits come from the leaf alone (no given normals or
    /// uvs) and together fewer than 2^32 vertices.
    pub fn build(instances: &[Instance]) -> Option<Self> {
        if instances.len() < 2 {
            return None;
        }
        let mut meshes = Vec::with_capacity(instances.len());
        for i in instances {
            let m = i.shape.as_triangle_mesh()?;
            if !i.is_identity() || !m.casts_from_leaves() {
                return None;
            }
            meshes.push(m);
        }
        let vertices: usize = meshes.iter().map(|m| m.positions().len()).sum();
        let triangles: usize = meshes.iter().map(|m| m.indices().len()).sum();
        if vertices > u32::MAX as usize || triangles > u32::MAX as usize {
            return None;
        }
        let mut positions = Vec::with_capacity(vertices);
        let mut indices = Vec::with_capacity(triangles);
        let mut starts = Vec::with_capacity(meshes.len());
        for m in meshes {
            let base = positions.len() as u32;
            starts.push(indices.len() as u32);
            positions.extend_from_slice(m.positions());
            indices.extend(m.indices().iter().map(|t| t.map(|v| v + base)));
        }
        let mesh = TriangleMesh::new(positions, indices, None, None).ok()?;
        Some(Self { mesh, starts })
    }

    /// The object and its own triangle id of a flat hit.
    #[inline]
    fn object_hit(&self, mut h: CastHit) -> (u32, CastHit) {
        let object = self.starts.partition_point(|&s| s <= h.prim) - 1;
        h.prim -= self.starts[object];
        (object as u32, h)
    }
}

impl Accel {
    /// Prepares what [`Accel::intersect_cast_hits`] uses (the flat mesh of a scene of
    /// several untransformed meshes, built here once, in parallel on the current rayon
    /// pool); a batch prepares it too, but a caller about to spread batches over
    /// threads should call this first.
    pub fn prepare_cast_batches(&self) {
        self.flat_meshes();
    }

    /// Whether batches go through one flat mesh of every object (see the module).
    pub fn casts_flat(&self) -> bool {
        self.flat_meshes().is_some()
    }

    /// The scene flattened into one mesh, where it can be (see the module).
    pub(crate) fn flat_meshes(&self) -> Option<&FlatMeshes> {
        self.flat
            .get_or_init(|| {
                if self.unbounded_count() > 0 || self.sole_mesh().is_some() {
                    None
                } else {
                    FlatMeshes::build(self.instances())
                }
            })
            .as_ref()
    }

    /// `out[i]` = [`Accel::intersect_cast`]`(&rays[i], t_max)` through the flat mesh:
    /// groups of eight rays that share an octant as packets, the rest through the
    /// single-ray traversal, several in turns (`TriangleMesh::nearest_cast_stream`),
    /// near ties traced again through the two levels. `false`, having written
    /// nothing, where the packet traversal is not available.
    pub(crate) fn intersect_cast_flat(
        &self,
        flat: &FlatMeshes,
        rays: &[Ray],
        t_max: f32,
        out: &mut [Option<(u32, CastHit)>],
    ) -> bool {
        if !crate::packet::has_avx2() || t_max <= 0.0 {
            return false;
        }
        let bound = Lanes8([t_max; PACKET]);
        // Rays outside a coherent group (an 8-lane traversal of one ray took 1.2
        // times as long on incoherent rays than the single-ray one).
        let mut lone: Vec<usize> = Vec::new();
        for (g, (group, out)) in rays.chunks(PACKET).zip(out.chunks_mut(PACKET)).enumerate() {
            let packet = if group.len() > 1 {
                PacketRay::new(group)
            } else {
                None
            };
            match packet {
                Some(p) => self.flat_group(flat, group, &p, p.lanes(), &bound, t_max, out),
                None => lone.extend(g * PACKET..g * PACKET + group.len()),
            }
        }
        if lone.is_empty() {
            return true;
        }
        let lone_rays: Vec<Ray> = lone.iter().map(|&i| rays[i]).collect();
        let mut tied: Vec<usize> = Vec::new();
        let streamed = flat
            .mesh
            .nearest_cast_stream(&lone_rays, t_max, |k, hit, tie| {
                if tie {
                    tied.push(lone[k]);
                } else {
                    out[lone[k]] = hit.map(|h| flat.object_hit(h));
                }
            });
        if !streamed {
            // (Not reached: the flat mesh is built without given normals or uvs.)
            tied = lone;
        }
        for i in tied {
            out[i] = self.intersect_cast(&rays[i], t_max);
        }
        true
    }

    /// The answers for the rays of `packet` (lanes `active`) through the flat mesh.
    #[allow(clippy::too_many_arguments)]
    #[inline]
    fn flat_group(
        &self,
        flat: &FlatMeshes,
        rays: &[Ray],
        packet: &PacketRay,
        active: u32,
        bound: &Lanes8,
        t_max: f32,
        out: &mut [Option<(u32, CastHit)>],
    ) {
        let (hits, ties) = flat
            .mesh
            .nearest_cast_lanes(rays, packet, active, bound)
            .expect("AVX2 and a mesh of leaf-only cast hits");
        for (k, (o, r)) in out.iter_mut().zip(rays).enumerate() {
            *o = if ties & (1 << k) != 0 {
                self.intersect_cast(r, t_max)
            } else {
                hits[k].map(|h| flat.object_hit(h))
            };
        }
    }
}
