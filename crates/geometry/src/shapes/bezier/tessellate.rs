//! Uniform tessellation of Bézier patches into one triangle mesh with no cracks.
//!
//! Every patch is cut into an `n × n` grid of parameter cells (two triangles each).
//! Adjacent patches that share a boundary curve get bit-identical vertices along it:
//! boundary vertices are computed from the edge's four control points only, by one
//! function, with the curve put in a canonical direction first (the lexicographically
//! smaller of the control-point sequence and its reverse) and the parameter taken as the
//! exact ratio `k / n` in that direction. Two patches that share an edge therefore compute
//! the same numbers in the same order, whichever way their own parameters run, and the
//! watertight triangle test (Woop, Benthin and Wald 2013) leaves no gap between triangles
//! whose shared edge has identical end points. Corners are the control points themselves
//! (Bernstein weights are exactly 1 and 0 there). Triangles with two coincident corners
//! (at collapsed edges such as the teapot's poles) are dropped.
//!
//! Vertex normals are the patches' exact normals (`BezierPatch::normal`), vertex uvs the
//! patch parameters, so a hit's interpolated uv addresses the patch for exact shading.

use super::patch::{cubic_point, BezierPatch};
use glam::{Vec2, Vec3};

/// Triangles of a tessellated patch set, ready for `TriangleMesh::new`.
#[derive(Clone, Debug, Default)]
pub struct PatchTriangles {
    pub positions: Vec<Vec3>,
    pub normals: Vec<Vec3>,
    /// `(u, v)` of the vertex in its own patch.
    pub uvs: Vec<Vec2>,
    pub indices: Vec<[u32; 3]>,
    /// The patch each triangle came from.
    pub triangle_patch: Vec<u32>,
}

/// The point at `k / n` along the cubic with control points `c`, computed so that the
/// same curve given in reverse yields the bit-identical point at `(n - k) / n`.
fn canonical_edge_point(c: [Vec3; 4], k: u32, n: u32) -> Vec3 {
    let key = |p: &Vec3| [p.x.to_bits(), p.y.to_bits(), p.z.to_bits()];
    let fwd = [key(&c[0]), key(&c[1]), key(&c[2]), key(&c[3])];
    let rev = [key(&c[3]), key(&c[2]), key(&c[1]), key(&c[0])];
    let (c, k) = if rev < fwd {
        ([c[3], c[2], c[1], c[0]], n - k)
    } else {
        (c, k)
    };
    if k == 0 {
        return c[0];
    }
    if k == n {
        return c[3];
    }
    cubic_point(&c, k as f64 / n as f64).as_vec3()
}

/// Tessellates every patch into `level × level` cells (`level >= 1`).
pub fn tessellate(patches: &[BezierPatch], level: u32) -> PatchTriangles {
    let n = level.max(1);
    let per_patch = ((n + 1) * (n + 1)) as usize;
    let mut out = PatchTriangles::default();
    out.positions.reserve(per_patch * patches.len());
    for (pi, patch) in patches.iter().enumerate() {
        let base = out.positions.len() as u32;
        for i in 0..=n {
            for j in 0..=n {
                let (u, v) = (i as f64 / n as f64, j as f64 / n as f64);
                let p = if i == 0 {
                    canonical_edge_point(patch.edge(0), j, n)
                } else if i == n {
                    canonical_edge_point(patch.edge(1), j, n)
                } else if j == 0 {
                    canonical_edge_point(patch.edge(2), i, n)
                } else if j == n {
                    canonical_edge_point(patch.edge(3), i, n)
                } else {
                    patch.eval(u, v).as_vec3()
                };
                out.positions.push(p);
                out.normals.push(patch.normal(u, v));
                out.uvs.push(Vec2::new(u as f32, v as f32));
            }
        }
        let idx = |i: u32, j: u32| base + i * (n + 1) + j;
        for i in 0..n {
            for j in 0..n {
                // (i,j) -> (i+1,j) -> (i+1,j+1) winds along ∂u then ∂v: the triangle's
                // normal is ∂P/∂u × ∂P/∂v, the patch's orientation.
                for tri in [
                    [idx(i, j), idx(i + 1, j), idx(i + 1, j + 1)],
                    [idx(i, j), idx(i + 1, j + 1), idx(i, j + 1)],
                ] {
                    let [a, b, c] = tri.map(|k| out.positions[k as usize]);
                    if a == b || b == c || a == c {
                        continue;
                    }
                    out.indices.push(tri);
                    out.triangle_patch.push(pi as u32);
                }
            }
        }
    }
    out
}
