//! Closed meshes as solids: a mesh whose every edge is shared by exactly two
//! triangles, wound consistently, bounds a solid, and CSG can use its spans. The
//! spans come from all hits along the ray's whole line, sorted, each classified as
//! entering or leaving by the sign of `dir · outward normal` (Roth 1982).

use super::TriangleMesh;
use crate::shape::{Boundary, Span};
use glam::{Vec2, Vec3};
use irradia_core::Ray;
use std::collections::HashMap;

/// +1 when the mesh is closed and wound counter-clockwise seen from outside, -1 when
/// closed and wound the other way, 0 when it is not closed.
pub(super) fn closed_orientation(positions: &[Vec3], indices: &[[u32; 3]]) -> i8 {
    let mut directed: HashMap<(u32, u32), u32> = HashMap::with_capacity(indices.len() * 3);
    for t in indices {
        for k in 0..3 {
            let e = (t[k], t[(k + 1) % 3]);
            if e.0 == e.1 {
                return 0;
            }
            *directed.entry(e).or_default() += 1;
        }
    }
    let closed = directed
        .iter()
        .all(|(&(a, b), &n)| n == 1 && directed.get(&(b, a)) == Some(&1));
    if !closed {
        return 0;
    }
    // The signed volume (divergence theorem) says which way the faces turn.
    let volume: f64 = indices
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|i| positions[i as usize].as_dvec3());
            a.dot(b.cross(c))
        })
        .sum();
    if volume > 0.0 {
        1
    } else if volume < 0.0 {
        -1
    } else {
        0
    }
}

impl TriangleMesh {
    /// Appends the spans of a closed mesh (nothing for an open one).
    pub(super) fn solid_spans(&self, ray: &Ray, out: &mut Vec<Span>) {
        let orientation = self.orientation();
        if orientation == 0 {
            return;
        }
        // Start the search before the mesh's box (where the whole line enters the
        // slabs, which may be at negative t) so hits behind the origin are found too.
        let inv = ray.dir.recip();
        let ta = (self.bounds.min - ray.origin) * inv;
        let tb = (self.bounds.max - ray.origin) * inv;
        let t_in = ta.min(tb).max_element();
        let t_out = ta.max(tb).min_element();
        if !(t_in <= t_out) || !t_in.is_finite() {
            return;
        }
        let t_start = t_in.min(0.0) - 1e-3 * (1.0 + t_in.abs());
        let start = Ray::new(ray.at(t_start), ray.dir);
        let tray = crate::triangle::TriangleRay::new(&start);
        let mut hits: Vec<(f32, u32, Vec3, Vec2)> = Vec::new();
        self.bvh
            .closest_hit_leaves(&start, f32::INFINITY, |leaf, _| {
                for (k, packet) in self.leaf_packets(leaf).iter().enumerate() {
                    let lanes = (leaf.count as usize - 4 * k).min(4);
                    let mut mask = packet.candidates(&tray, lanes, f32::INFINITY);
                    while mask != 0 {
                        let lane = mask.trailing_zeros() as usize;
                        mask &= mask - 1;
                        let [a, b, c] = packet.corners(lane);
                        if let Some(h) = tray.intersect(a, b, c, f32::INFINITY) {
                            let tri = packet.ids[lane];
                            let n = (b - a).cross(c - a).normalize() * orientation as f32;
                            let uv = match &self.uvs {
                                Some(_) => self.hit_record(tri, &h).uv,
                                None => Vec2::new(h.b1, h.b2),
                            };
                            hits.push((h.t + t_start, tri, n, uv));
                        }
                    }
                }
                None
            });
        hits.sort_by(|a, b| a.0.total_cmp(&b.0));
        // A ray through an edge or vertex hits every triangle there at (nearly) one t,
        // each computed with its own rounding: count each crossing once, merging hits
        // of the same direction closer than a tolerance scaled to the mesh.
        let scale = self.bounds.extent().length() / ray.dir.length();
        let tol = 1e-5 * scale;
        hits.dedup_by(|b, a| {
            (b.0 - a.0).abs() <= tol + 1e-6 * a.0.abs()
                && (b.2.dot(ray.dir) < 0.0) == (a.2.dot(ray.dir) < 0.0)
        });
        let mut depth = 0i32;
        let mut enter = Boundary::NEG_INFINITY;
        for (t, tri, n, uv) in hits {
            let boundary = Boundary {
                t,
                normal: n,
                uv,
                prim: tri,
                leaf: 0,
            };
            if n.dot(ray.dir) < 0.0 {
                if depth == 0 {
                    enter = boundary;
                }
                depth += 1;
            } else if depth > 0 {
                depth -= 1;
                if depth == 0 {
                    out.push(Span {
                        enter,
                        exit: boundary,
                    });
                }
            }
        }
    }
}
