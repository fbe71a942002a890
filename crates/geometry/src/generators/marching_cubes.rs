//! Marching cubes (Lorensen and Cline, "Marching Cubes: A High Resolution 3D Surface
//! Construction Algorithm", SIGGRAPH 1987) over a scalar field sampled on a grid.
//!
//! Vertices sit on grid edges and are shared by every cell around the edge, so the
//! mesh is watertight: each edge inside the grid belongs to exactly two triangles.
//! The classic table is ambiguous on faces whose corners alternate in sign, and a
//! table built by symmetry resolves the same face differently in the two cells that
//! share it, leaving holes. Here the table is derived once from a rule that looks only
//! at the face (the positive corners are always cut off from each other), so both
//! cells agree: on each cube face the zero set is drawn as segments, the segments
//! chain into closed loops around the cube, and each loop is fanned into triangles
//! wound so that normals point towards increasing values.

use glam::{UVec3, Vec3};
use irradia_core::Aabb;
use std::sync::OnceLock;

/// A scalar field sampled on a regular grid: `values[x + nx (y + ny z)]` at
/// `bounds.min + (x, y, z) * spacing`.
#[derive(Clone, Debug)]
pub struct ScalarGrid {
    pub dims: UVec3,
    pub bounds: Aabb,
    pub values: Vec<f32>,
}

impl ScalarGrid {
    /// Samples `f` at `dims` points per axis spanning `bounds` (in parallel).
    pub fn sample(dims: UVec3, bounds: Aabb, f: impl Fn(Vec3) -> f32 + Sync) -> ScalarGrid {
        use rayon::prelude::*;
        assert!(dims.min_element() >= 2, "a grid needs 2 samples per axis");
        let step = bounds.extent() / (dims - UVec3::ONE).as_vec3();
        let (nx, ny) = (dims.x as usize, dims.y as usize);
        let n = nx * ny * dims.z as usize;
        let values = (0..n)
            .into_par_iter()
            .map(|i| {
                let (x, y, z) = (i % nx, (i / nx) % ny, i / (nx * ny));
                f(bounds.min + Vec3::new(x as f32, y as f32, z as f32) * step)
            })
            .collect();
        ScalarGrid {
            dims,
            bounds,
            values,
        }
    }

    /// Distance between neighbouring samples along each axis.
    pub fn spacing(&self) -> Vec3 {
        self.bounds.extent() / (self.dims - UVec3::ONE).as_vec3()
    }

    #[inline]
    fn at(&self, x: usize, y: usize, z: usize) -> f32 {
        self.values[x + self.dims.x as usize * (y + self.dims.y as usize * z)]
    }
}

/// A triangle soup with shared vertices: what a generator produces before it becomes
/// a [`crate::TriangleMesh`].
#[derive(Clone, Debug, Default)]
pub struct MeshData {
    pub positions: Vec<Vec3>,
    pub indices: Vec<[u32; 3]>,
}

/// The cube's corner `c` has coordinates (bit 0, bit 1, bit 2) = (x, y, z).
fn corner(c: usize) -> [usize; 3] {
    [c & 1, (c >> 1) & 1, (c >> 2) & 1]
}

/// Edges 0..4 run along x, 4..8 along y, 8..12 along z; within an axis the two other
/// coordinates (in axis order) count up as bits.
fn edge_between(a: usize, b: usize) -> usize {
    let d = a ^ b;
    let axis = d.trailing_zeros() as usize;
    let ca = corner(a);
    let others: Vec<usize> = (0..3).filter(|&k| k != axis).map(|k| ca[k]).collect();
    axis * 4 + others[0] + 2 * others[1]
}

/// The two corners of an edge.
fn edge_corners(e: usize) -> (usize, usize) {
    let axis = e / 4;
    let o = [e & 1, (e >> 1) & 1];
    let mut c = [0usize; 3];
    let mut k = 0;
    for (i, ci) in c.iter_mut().enumerate() {
        if i != axis {
            *ci = o[k];
            k += 1;
        }
    }
    let a = c[0] | c[1] << 1 | c[2] << 2;
    (a, a | 1 << axis)
}

/// Whether two edges of the cube lie on a common face.
fn share_face(a: usize, b: usize) -> bool {
    let faces = |e: usize| {
        let (c0, c1) = edge_corners(e);
        // A face (axis, side) holds the edge when both corners have that coordinate.
        (0..3)
            .flat_map(|axis| (0..2).map(move |side| (axis, side)))
            .filter(move |&(axis, side)| corner(c0)[axis] == side && corner(c1)[axis] == side)
    };
    faces(a).any(|fa| faces(b).any(|fb| fa == fb))
}

fn corner_pos(c: usize) -> Vec3 {
    let [x, y, z] = corner(c);
    Vec3::new(x as f32, y as f32, z as f32)
}

fn edge_mid(e: usize) -> Vec3 {
    let (a, b) = edge_corners(e);
    0.5 * (corner_pos(a) + corner_pos(b))
}

/// Triangles (as edge numbers) for each of the 256 sign patterns (bit c set when
/// corner c is positive).
fn table() -> &'static [Vec<[u8; 3]>; 256] {
    static TABLE: OnceLock<[Vec<[u8; 3]>; 256]> = OnceLock::new();
    TABLE.get_or_init(|| std::array::from_fn(|case| triangulate_case(case as u8)))
}

fn triangulate_case(case: u8) -> Vec<[u8; 3]> {
    let positive = |c: usize| case >> c & 1 == 1;
    let mut next = [usize::MAX; 12];
    for axis in 0..3 {
        for side in 0..2 {
            let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
            // Corners of the face in cyclic order.
            let cyc: Vec<usize> = [(0, 0), (1, 0), (1, 1), (0, 1)]
                .iter()
                .map(|&(a, b)| side << axis | a << u | b << v)
                .collect();
            let mut normal = Vec3::ZERO;
            normal[axis] = if side == 1 { 1.0 } else { -1.0 };
            let crossing: Vec<usize> = (0..4)
                .filter(|&i| positive(cyc[i]) != positive(cyc[(i + 1) % 4]))
                .collect();
            // Segments as pairs of positions in the cycle (edge i joins corners i, i+1).
            let segments: Vec<(usize, usize)> = match crossing.len() {
                0 => vec![],
                2 => vec![(crossing[0], crossing[1])],
                4 => {
                    // Alternating signs: cut off each positive corner k, which lies
                    // between edges k-1 and k.
                    (0..4)
                        .filter(|&k| positive(cyc[k]))
                        .map(|k| ((k + 3) % 4, k))
                        .collect()
                }
                _ => unreachable!("a face has an even number of sign changes"),
            };
            for (i, j) in segments {
                let ei = edge_between(cyc[i], cyc[(i + 1) % 4]);
                let ej = edge_between(cyc[j], cyc[(j + 1) % 4]);
                let (p, q) = (edge_mid(ei), edge_mid(ej));
                let m = 0.5 * (p + q);
                // g: within the face, towards the positive side of the segment.
                let g = if (j + 4 - i) % 4 == 1 || (i + 4 - j) % 4 == 1 {
                    // Adjacent edges: they cut off the corner they share.
                    let k = if (j + 4 - i) % 4 == 1 { j } else { i };
                    let s = if positive(cyc[k]) { 1.0 } else { -1.0 };
                    s * (corner_pos(cyc[k]) - m)
                } else {
                    let pos: Vec<Vec3> = cyc
                        .iter()
                        .filter(|&&c| positive(c))
                        .map(|&c| corner_pos(c))
                        .collect();
                    pos.iter().sum::<Vec3>() / pos.len() as f32 - m
                };
                // Walk so the surface (inside the cube) is on the left seen from the
                // positive side: direction g x n.
                let d = g.cross(normal);
                let (from, to) = if (q - p).dot(d) > 0.0 {
                    (ei, ej)
                } else {
                    (ej, ei)
                };
                assert_eq!(next[from], usize::MAX, "case {case}: edge {from} twice");
                next[from] = to;
            }
        }
    }
    let mut seen = [false; 12];
    let mut tris = Vec::new();
    for start in 0..12 {
        if next[start] == usize::MAX || seen[start] {
            continue;
        }
        let mut lp = vec![];
        let mut e = start;
        while !seen[e] {
            seen[e] = true;
            lp.push(e as u8);
            e = next[e];
            assert!(e != usize::MAX, "case {case}: open loop");
        }
        assert_eq!(e, start, "case {case}: loop does not close");
        // Fan from a corner whose diagonals never join two vertices on one cube face:
        // the neighbouring cell may use that pair as a segment or diagonal too, and
        // the edge would then belong to more than two triangles.
        let n = lp.len();
        let conflicts = |k: usize| {
            (0..n)
                .filter(|&j| j != k && j != (k + 1) % n && (j + 1) % n != k)
                .filter(|&j| share_face(lp[k] as usize, lp[j] as usize))
                .count()
        };
        let apex = (0..n).min_by_key(|&k| conflicts(k)).unwrap_or(0);
        for k in 1..n - 1 {
            tris.push([lp[apex], lp[(apex + k) % n], lp[(apex + k + 1) % n]]);
        }
    }
    tris
}

/// The isosurface `value = iso` of a volume read from a file ([`crate::io::volume`]).
pub fn volume_mesh(grid: &ScalarGrid, iso: f32) -> MeshData {
    marching_cubes(grid, iso)
}

/// Extracts the surface `value = iso` from the grid. Corners with `value > iso` are
/// "positive"; triangle normals (by winding) point towards increasing values.
pub fn marching_cubes(grid: &ScalarGrid, iso: f32) -> MeshData {
    let table = table();
    let (nx, ny, nz) = (
        grid.dims.x as usize,
        grid.dims.y as usize,
        grid.dims.z as usize,
    );
    let spacing = grid.spacing();
    let origin = grid.bounds.min;
    let mut out = MeshData::default();
    let pos = |x: usize, y: usize, z: usize| -> Vec3 {
        origin + Vec3::new(x as f32, y as f32, z as f32) * spacing
    };
    // Vertex ids of edges in the current and next layer (x and y edges) and of the
    // z edges between them; u32::MAX where the edge has no crossing.
    let layer = nx * ny;
    let mut xe = [vec![u32::MAX; layer], vec![u32::MAX; layer]];
    let mut ye = [vec![u32::MAX; layer], vec![u32::MAX; layer]];
    let mut ze = vec![u32::MAX; layer];
    let vertex = |out: &mut MeshData, a: (usize, usize, usize), b: (usize, usize, usize)| {
        let (fa, fb) = (grid.at(a.0, a.1, a.2), grid.at(b.0, b.1, b.2));
        let t = ((iso - fa) / (fb - fa)).clamp(0.0, 1.0);
        let pa = pos(a.0, a.1, a.2);
        let pb = pos(b.0, b.1, b.2);
        out.positions.push(pa + (pb - pa) * t);
        (out.positions.len() - 1) as u32
    };
    let crosses = |a: f32, b: f32| (a > iso) != (b > iso);
    let fill_layer = |out: &mut MeshData, xe: &mut Vec<u32>, ye: &mut Vec<u32>, z: usize| {
        for y in 0..ny {
            for x in 0..nx {
                let f = grid.at(x, y, z);
                xe[x + nx * y] = if x + 1 < nx && crosses(f, grid.at(x + 1, y, z)) {
                    vertex(out, (x, y, z), (x + 1, y, z))
                } else {
                    u32::MAX
                };
                ye[x + nx * y] = if y + 1 < ny && crosses(f, grid.at(x, y + 1, z)) {
                    vertex(out, (x, y, z), (x, y + 1, z))
                } else {
                    u32::MAX
                };
            }
        }
    };
    {
        let (a, _) = xe.split_at_mut(1);
        let (c, _) = ye.split_at_mut(1);
        fill_layer(&mut out, &mut a[0], &mut c[0], 0);
    }
    for z in 0..nz - 1 {
        let (cur, nxt) = (z % 2, (z + 1) % 2);
        {
            let [x0, x1] = &mut xe;
            let [y0, y1] = &mut ye;
            let (xn, yn) = if nxt == 1 { (x1, y1) } else { (x0, y0) };
            fill_layer(&mut out, xn, yn, z + 1);
        }
        for y in 0..ny {
            for x in 0..nx {
                ze[x + nx * y] = if crosses(grid.at(x, y, z), grid.at(x, y, z + 1)) {
                    vertex(&mut out, (x, y, z), (x, y, z + 1))
                } else {
                    u32::MAX
                };
            }
        }
        for y in 0..ny - 1 {
            for x in 0..nx - 1 {
                let mut case = 0usize;
                for c in 0..8 {
                    let [dx, dy, dz] = corner(c);
                    if grid.at(x + dx, y + dy, z + dz) > iso {
                        case |= 1 << c;
                    }
                }
                if case == 0 || case == 255 {
                    continue;
                }
                let i = x + nx * y;
                // Edge numbering of `edge_between`: x edges at (y, z) offsets, then y
                // edges at (x, z), then z edges at (x, y).
                let ids = [
                    xe[cur][i],
                    xe[cur][i + nx],
                    xe[nxt][i],
                    xe[nxt][i + nx],
                    ye[cur][i],
                    ye[cur][i + 1],
                    ye[nxt][i],
                    ye[nxt][i + 1],
                    ze[i],
                    ze[i + 1],
                    ze[i + nx],
                    ze[i + nx + 1],
                ];
                for t in &table[case] {
                    out.indices.push(t.map(|e| {
                        let id = ids[e as usize];
                        debug_assert!(id != u32::MAX);
                        id
                    }));
                }
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_case_has_closed_loops_and_clean_fans() {
        for case in 0..=255u8 {
            let tris = triangulate_case(case);
            // Triangles come in fans, so no triangle edge joins two vertices on one
            // face unless it is a loop segment; count each undirected edge.
            let mut count = std::collections::HashMap::new();
            for t in &tris {
                for k in 0..3 {
                    let (a, b) = (t[k], t[(k + 1) % 3]);
                    *count.entry((a.min(b), a.max(b))).or_insert(0) += 1;
                }
            }
            for (&(a, b), &n) in &count {
                // An inner diagonal (used twice) never joins two vertices of one face.
                if n == 2 {
                    assert!(!share_face(a as usize, b as usize), "case {case}: {a}-{b}");
                } else {
                    assert_eq!(n, 1, "case {case}");
                    assert!(share_face(a as usize, b as usize), "case {case}");
                }
            }
            assert_eq!(tris.is_empty(), case == 0 || case == 255);
        }
    }
}
