//! Triangle meshes: vertex positions, index triples, optional per-vertex normals and
//! texture coordinates, hit through their own BVH (the second level of the scene's
//! two-level hierarchy) with the watertight triangle test; optional named attributes
//! per vertex or per face ([`attributes`]).

pub mod attributes;
mod leaf_packets;
mod spans;
mod stream;

pub use stream::TIE_ULPS;

pub use attributes::{
    AttributeDomain, AttributeError, AttributePoint, AttributeValue, MeshAttribute, MeshAttributes,
};

use crate::packet::watertight4;
pub use crate::packet::Triangle4;

use crate::bvh::{Bvh, ChildRef};
use crate::shape::{CastHit, Facets, Hit, Shape, Span};
use crate::triangle::{TriangleHit, TriangleRay};
use glam::{Vec2, Vec3};
use irradia_core::{Aabb, Ray};
use leaf_packets::LeafPackets;
use rayon::prelude::*;

/// Why a mesh was refused. Indices and counts are 0-based.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MeshError {
    #[error("the mesh has no triangles")]
    Empty,
    #[error("triangle {triangle}: vertex index {index} is out of range (the mesh has {vertices} vertices)")]
    IndexOutOfRange {
        triangle: usize,
        index: u32,
        vertices: usize,
    },
    #[error("vertex {vertex}: position {value} is not finite")]
    NonFinitePosition { vertex: usize, value: String },
    #[error("vertex {vertex}: {what} {value} is not finite")]
    NonFiniteAttribute {
        vertex: usize,
        what: &'static str,
        value: String,
    },
    #[error("{what}: {got} given for {expected} vertices")]
    CountMismatch {
        what: &'static str,
        got: usize,
        expected: usize,
    },
    #[error("{vertices} vertices is more than 32-bit indices can address")]
    TooManyVertices { vertices: usize },
    #[error(transparent)]
    Attribute(#[from] AttributeError),
}

/// A triangle mesh. Triangles wind counter-clockwise seen from the side their normal
/// points to. Degenerate (zero-area) triangles are kept in the index list but never hit.
#[derive(Clone, Debug)]
pub struct TriangleMesh {
    positions: Vec<Vec3>,
    indices: Vec<[u32; 3]>,
    /// Unit vertex normals: given, or area-weighted averages of the face normals.
    normals: Vec<Vec3>,
    /// Whether `normals` came from the caller (then geometric normals are turned to
    /// agree with them, as pbrt does) or were computed from the winding.
    normals_given: bool,
    /// +1 closed and outward-wound, -1 closed and inward-wound, 0 open; worked out
    /// on first use (it hashes every edge, which ray casting alone does not need).
    orientation: std::sync::OnceLock<i8>,
    uvs: Option<Vec<Vec2>>,
    /// Named per-vertex and per-face values (vertex colours among them: PLY's
    /// red/green/blue, OBJ's `v x y z r g b`, glTF's COLOR_0 as `vertex_color`), read
    /// by the `mesh_attribute` texture.
    attributes: MeshAttributes,
    /// Leaves index `packets`: a leaf of n triangles owns ceil(n / 4) consecutive
    /// packets.
    bvh: Bvh,
    /// Triangle corners in leaf order, four to a packet, with each lane's triangle
    /// index; leaves of two packets start on a cache line (see `leaf_packets.rs`).
    packets: LeafPackets,
    bounds: Aabb,
}

impl TriangleMesh {
    /// Checks and builds a mesh: every index in range, every position (and normal and
    /// uv, when given) finite, one normal and one uv per vertex.
    pub fn new(
        positions: Vec<Vec3>,
        indices: Vec<[u32; 3]>,
        normals: Option<Vec<Vec3>>,
        uvs: Option<Vec<Vec2>>,
    ) -> Result<TriangleMesh, MeshError> {
        let nv = positions.len();
        if indices.is_empty() {
            return Err(MeshError::Empty);
        }
        if nv > u32::MAX as usize {
            return Err(MeshError::TooManyVertices { vertices: nv });
        }
        if let Some(v) = positions.iter().position(|p| !p.is_finite()) {
            return Err(MeshError::NonFinitePosition {
                vertex: v,
                value: format!("{:?}", positions[v].to_array()),
            });
        }
        for (t, tri) in indices.iter().enumerate() {
            if let Some(&i) = tri.iter().find(|&&i| i as usize >= nv) {
                return Err(MeshError::IndexOutOfRange {
                    triangle: t,
                    index: i,
                    vertices: nv,
                });
            }
        }
        if let Some(n) = &normals {
            if n.len() != nv {
                return Err(MeshError::CountMismatch {
                    what: "normals",
                    got: n.len(),
                    expected: nv,
                });
            }
            if let Some(v) = n.iter().position(|p| !p.is_finite()) {
                return Err(MeshError::NonFiniteAttribute {
                    vertex: v,
                    what: "normal",
                    value: format!("{:?}", n[v].to_array()),
                });
            }
        }
        if let Some(uv) = &uvs {
            if uv.len() != nv {
                return Err(MeshError::CountMismatch {
                    what: "uvs",
                    got: uv.len(),
                    expected: nv,
                });
            }
            if let Some(v) = uv.iter().position(|p| !p.is_finite()) {
                return Err(MeshError::NonFiniteAttribute {
                    vertex: v,
                    what: "uv",
                    value: format!("{:?}", uv[v].to_array()),
                });
            }
        }
        let normals_given = normals.is_some();
        let orientation = std::sync::OnceLock::new();
        let normals = match normals {
            Some(n) => n.into_iter().map(|n| n.normalize_or_zero()).collect(),
            None => area_weighted_normals(&positions, &indices),
        };
        let corners = |t: &[u32; 3]| {
            [
                positions[t[0] as usize],
                positions[t[1] as usize],
                positions[t[2] as usize],
            ]
        };
        // Leaves are tested eight triangles at a time (two packets in one AVX2 pass),
        // so the SAH counts blocks of eight: leaves of 5-8 cost one test. Measured on
        // the gyroid against blocks of four: 5-7% faster rays, 13% faster build.
        let mut bvh = Bvh::build_blocked_by(
            indices.len(),
            |t| {
                let [a, b, c] = corners(&indices[t]);
                if (b - a).cross(c - a) == Vec3::ZERO {
                    // Degenerate: left out of the hierarchy, so never hit.
                    Aabb::EMPTY
                } else {
                    Aabb::new(a.min(b).min(c), a.max(b).max(c))
                }
            },
            8,
        );
        // At most one packet per leaf beyond a full packet per 4 triangles.
        let mut packets = LeafPackets::with_capacity(bvh.order().len() / 2 + 1);
        bvh.map_leaf_primitives(|tris| {
            packets.push(tris.len().div_ceil(4), |j| {
                let chunk = &tris[4 * j..(4 * j + 4).min(tris.len())];
                let mut lanes = [[Vec3::ZERO; 3]; 4];
                for (lane, &t) in lanes.iter_mut().zip(chunk) {
                    *lane = corners(&indices[t as usize]);
                }
                Triangle4::new(&lanes[..chunk.len()]).with_ids(chunk)
            })
        });
        let bounds = bvh.bounds();
        Ok(TriangleMesh {
            positions,
            indices,
            normals,
            normals_given,
            orientation,
            uvs,
            attributes: MeshAttributes::default(),
            bvh,
            packets,
            bounds,
        })
    }

    /// The mesh with `attributes` (Mitsuba's `Mesh::add_attribute`): each vertex
    /// attribute needs a row per vertex, each face attribute a row per triangle.
    pub fn with_attributes(
        mut self,
        attributes: MeshAttributes,
    ) -> Result<TriangleMesh, MeshError> {
        attributes.check_rows(self.positions.len(), self.indices.len())?;
        self.attributes = attributes;
        Ok(self)
    }

    pub fn attributes(&self) -> &MeshAttributes {
        &self.attributes
    }

    /// Where object-space point `p` lies on triangle `tri` for attribute lookups: its
    /// corners and barycentric coordinates (of `p` projected into the triangle's
    /// plane, clamped to the triangle). `None` without attributes or for a triangle
    /// out of range.
    pub fn attribute_point(&self, p: Vec3, tri: u32) -> Option<AttributePoint<'_>> {
        if self.attributes.is_empty() {
            return None;
        }
        let t = *self.indices.get(tri as usize)?;
        let [a, b, c] = t.map(|i| self.positions[i as usize]);
        let (e1, e2, d) = (b - a, c - a, p - a);
        let (d11, d12, d22) = (e1.dot(e1), e1.dot(e2), e2.dot(e2));
        let (d1, d2) = (d.dot(e1), d.dot(e2));
        let det = d11 * d22 - d12 * d12;
        let (b1, b2) = if det.abs() > 0.0 && det.is_finite() {
            (
                ((d22 * d1 - d12 * d2) / det).clamp(0.0, 1.0),
                ((d11 * d2 - d12 * d1) / det).clamp(0.0, 1.0),
            )
        } else {
            (0.0, 0.0)
        };
        let (b1, b2) = if b1 + b2 > 1.0 {
            (b1 / (b1 + b2), b2 / (b1 + b2))
        } else {
            (b1, b2)
        };
        Some(AttributePoint {
            attributes: &self.attributes,
            triangle: tri,
            corners: t,
            barycentric: [1.0 - b1 - b2, b1, b2],
        })
    }

    pub fn positions(&self) -> &[Vec3] {
        &self.positions
    }
    pub fn indices(&self) -> &[[u32; 3]] {
        &self.indices
    }
    /// Unit vertex normals (zero where a vertex touches only degenerate triangles).
    pub fn normals(&self) -> &[Vec3] {
        &self.normals
    }
    pub fn uvs(&self) -> Option<&[Vec2]> {
        self.uvs.as_deref()
    }
    /// Whether the vertex normals came from the caller (then a hit's geometric normal
    /// is turned to the side of the interpolated one, as pbrt does) or were averaged
    /// from the faces (then the interpolated normal is turned to the geometric one's
    /// side); see the hits' `shading_normal`.
    pub fn normals_given(&self) -> bool {
        self.normals_given
    }
    pub fn bvh(&self) -> &Bvh {
        &self.bvh
    }
    pub fn triangle_count(&self) -> usize {
        self.indices.len()
    }

    /// The nearest triangle hit as (triangle index, hit), without building a `Hit`:
    /// the fast path for benchmarks and ray casting that needs only `t`.
    #[inline]
    pub fn intersect_triangle(&self, ray: &Ray, t_max: f32) -> Option<(u32, TriangleHit)> {
        let (packet, lane, h) = self.closest_lane(ray, t_max)?;
        Some((packet.ids[lane], h))
    }

    /// The nearest hit as ray casting reports it, with no look-up beyond the leaf that
    /// was hit: the triangle id and the corners come from its packet (the geometric
    /// normal `(p1 - p0) x (p2 - p0)` of the same corners as [`Shape::intersect`]'s),
    /// uv is the barycentric `(b1, b2)`. Meshes whose hits need more (given normals
    /// turn the geometric one, given uvs are interpolated) go through the whole hit.
    #[inline]
    pub fn intersect_cast_hit(&self, ray: &Ray, t_max: f32) -> Option<CastHit> {
        if self.normals_given || self.uvs.is_some() {
            return self.intersect(ray, t_max).map(|h| CastHit::from(&h));
        }
        let (packet, lane, h) = self.closest_lane(ray, t_max)?;
        Some(Self::cast_hit_of(packet, lane, &h))
    }

    /// What ray casting reports of hit `h` on lane `lane` of `packet`.
    #[inline]
    fn cast_hit_of(packet: &Triangle4, lane: usize, h: &TriangleHit) -> CastHit {
        let [p0, p1, p2] = packet.corners(lane);
        CastHit {
            t: h.t,
            prim: packet.ids[lane],
            uv: Vec2::new(h.b1, h.b2),
            normal: (p1 - p0).cross(p2 - p0).normalize(),
        }
    }

    /// The nearest hit's packet, lane and hit.
    #[inline]
    fn closest_lane(&self, ray: &Ray, t_max: f32) -> Option<(&Triangle4, usize, TriangleHit)> {
        let tray = TriangleRay::new(ray);
        let mut best: Option<(&Triangle4, usize, TriangleHit)> = None;
        let prefetch = |leaf: ChildRef| self.prefetch_leaf(leaf);
        self.bvh
            .closest_hit_leaves_prefetch(ray, t_max, prefetch, |leaf, t_max| {
                let packets = self.leaf_packets(leaf);
                let (i, h) =
                    watertight4::intersect_leaf(packets, leaf.count as usize, &tray, t_max)?;
                best = Some((&packets[i / 4], i % 4, h));
                Some(h.t)
            })?;
        best
    }

    /// Starts loading leaf `leaf`'s packets.
    #[inline(always)]
    fn prefetch_leaf(&self, leaf: ChildRef) {
        #[cfg(target_arch = "x86_64")]
        if let Some(p) = self.packets.as_slice().get(leaf.index as usize) {
            use std::arch::x86_64::{_mm_prefetch, _MM_HINT_T0};
            let p = p as *const Triangle4 as *const i8;
            // SAFETY: a prefetch is only a hint (never faults). The lines hold the
            // leaf's one or two 160-byte packets: a leaf of two starts on a line (5
            // lines), one packet starts at a line or 32 bytes into one (3 lines either
            // way; see `leaf_packets.rs`).
            unsafe {
                _mm_prefetch(p, _MM_HINT_T0);
                _mm_prefetch(p.add(64), _MM_HINT_T0);
                _mm_prefetch(p.add(128), _MM_HINT_T0);
                if leaf.count > 4 {
                    _mm_prefetch(p.add(192), _MM_HINT_T0);
                    _mm_prefetch(p.add(256), _MM_HINT_T0);
                }
            }
        }
        #[cfg(not(target_arch = "x86_64"))]
        let _ = leaf;
    }

    #[inline(always)]
    fn leaf_packets(&self, leaf: ChildRef) -> &[Triangle4] {
        let start = leaf.index as usize;
        &self.packets.as_slice()[start..start + (leaf.count as usize).div_ceil(4)]
    }

    /// +1 closed and wound counter-clockwise from outside, -1 closed and wound the
    /// other way, 0 open.
    pub fn orientation(&self) -> i8 {
        *self
            .orientation
            .get_or_init(|| spans::closed_orientation(&self.positions, &self.indices))
    }

    /// `(dp/du, dp/dv)` of triangle `tri` from its vertices' uv (zero without uv).
    pub fn triangle_uv_derivatives(&self, tri: u32) -> (Vec3, Vec3) {
        let Some(uv) = &self.uvs else {
            return (Vec3::ZERO, Vec3::ZERO);
        };
        let Some(&[i0, i1, i2]) = self.indices.get(tri as usize) else {
            return (Vec3::ZERO, Vec3::ZERO);
        };
        let [i0, i1, i2] = [i0 as usize, i1 as usize, i2 as usize];
        uv_derivatives(
            [self.positions[i0], self.positions[i1], self.positions[i2]],
            [uv[i0], uv[i1], uv[i2]],
        )
    }

    fn hit_record(&self, tri: u32, h: &TriangleHit) -> Hit {
        let [i0, i1, i2] = self.indices[tri as usize].map(|i| i as usize);
        let (p0, p1, p2) = (self.positions[i0], self.positions[i1], self.positions[i2]);
        let (point, error) = h.point_and_error(p0, p1, p2);
        let normal = (p1 - p0).cross(p2 - p0).normalize();
        let ns = (h.b0 * self.normals[i0] + h.b1 * self.normals[i1] + h.b2 * self.normals[i2])
            .normalize_or_zero();
        let (normal, shading_normal) = oriented_normals(normal, ns, self.normals_given);
        let uv = match &self.uvs {
            Some(uv) => h.b0 * uv[i0] + h.b1 * uv[i1] + h.b2 * uv[i2],
            None => Vec2::new(h.b1, h.b2),
        };
        Hit {
            t: h.t,
            point,
            normal,
            shading_normal,
            uv,
            prim: tri,
            leaf: 0,
            error,
        }
    }
}

/// The derivatives `(dp/du, dp/dv)` of a triangle's points with respect to its
/// linearly interpolated texture coordinates (pbrt-v4's `Triangle::InteractionFromIntersection`;
/// Mitsuba's mesh `dp_du`, `dp_dv`); zero when the uv triangle is degenerate.
pub fn uv_derivatives(p: [Vec3; 3], uv: [Vec2; 3]) -> (Vec3, Vec3) {
    let (duv02, duv12) = (uv[0] - uv[2], uv[1] - uv[2]);
    let (dp02, dp12) = (p[0] - p[2], p[1] - p[2]);
    let det = duv02.x * duv12.y - duv02.y * duv12.x;
    if !det.is_finite() || det.abs() < 1e-12 {
        return (Vec3::ZERO, Vec3::ZERO);
    }
    let inv = 1.0 / det;
    (
        (dp02 * duv12.y - dp12 * duv02.y) * inv,
        (dp12 * duv02.x - dp02 * duv12.x) * inv,
    )
}

/// Vertex normals as area-weighted averages of the faces around each vertex (the
/// unnormalised cross product of a face is twice its area times its unit normal).
pub fn area_weighted_normals(positions: &[Vec3], indices: &[[u32; 3]]) -> Vec<Vec3> {
    let mut acc = vec![Vec3::ZERO; positions.len()];
    for t in indices {
        let [a, b, c] = t.map(|i| positions[i as usize]);
        let n = (b - a).cross(c - a);
        for &i in t {
            acc[i as usize] += n;
        }
    }
    acc.into_par_iter().map(|n| n.normalize_or_zero()).collect()
}

/// A smooth-shaded triangle's geometric and shading normals on one side: `ns` is the
/// normalised blend of the vertex normals (zero when they cancel: the geometric normal
/// stands in). Normals given by the file turn the geometric normal to their side;
/// then the shading normal is turned to the geometric normal's side. The mesh's hits
/// and the path tracer's baked copy of the mesh both apply these rules.
#[inline]
pub fn oriented_normals(normal: Vec3, ns: Vec3, normals_given: bool) -> (Vec3, Vec3) {
    if ns == Vec3::ZERO {
        return (normal, normal);
    }
    let normal = if normals_given && normal.dot(ns) < 0.0 {
        -normal
    } else {
        normal
    };
    let ns = if normal.dot(ns) < 0.0 { -ns } else { ns };
    (normal, ns)
}

impl Shape for TriangleMesh {
    fn kind(&self) -> &'static str {
        "mesh"
    }

    fn bounds(&self) -> Aabb {
        self.bounds
    }

    fn intersect(&self, ray: &Ray, t_max: f32) -> Option<Hit> {
        let (tri, h) = self.intersect_triangle(ray, t_max)?;
        Some(self.hit_record(tri, &h))
    }

    fn intersect_cast(&self, ray: &Ray, t_max: f32) -> Option<CastHit> {
        self.intersect_cast_hit(ray, t_max)
    }

    fn as_triangle_mesh(&self) -> Option<&TriangleMesh> {
        Some(self)
    }

    fn uv_derivatives(&self, _p: Vec3, _uv: Vec2, prim: u32) -> (Vec3, Vec3) {
        self.triangle_uv_derivatives(prim)
    }

    fn attributes(&self) -> Option<&MeshAttributes> {
        Some(&self.attributes)
    }

    fn attribute_point(&self, hit: &Hit) -> Option<AttributePoint<'_>> {
        TriangleMesh::attribute_point(self, hit.point, hit.prim)
    }

    fn occluded(&self, ray: &Ray, t_max: f32) -> bool {
        let tray = TriangleRay::new(ray);
        self.bvh.any_hit_leaves(ray, t_max, |leaf, t_max| {
            watertight4::occluded_leaf(self.leaf_packets(leaf), leaf.count as usize, &tray, t_max)
        })
    }

    /// True for closed meshes (every edge shared by two consistently wound triangles).
    fn is_solid(&self) -> bool {
        self.orientation() != 0
    }

    fn spans(&self, ray: &Ray, out: &mut Vec<Span>) {
        self.solid_spans(ray, out)
    }

    fn facets(&self, _detail: u32) -> Option<Facets> {
        Some(Facets {
            vertices: self.positions.clone(),
            faces: self.indices.iter().map(|t| t.to_vec()).collect(),
            normals: self.normals.clone(),
        })
    }
}
