//! The display mesh: element corners welded into shared vertices (per patch), vertex
//! radiosity by area-weighted averaging of the elements around each vertex, and
//! triangles with no T-vertex cracks.
//!
//! Elements split by `Poly::split4` (adaptive refinement, hierarchical leaves) put new
//! corners at edge midpoints, where a coarser neighbour has no vertex: a T-vertex, which
//! cracks under Gouraud shading. Each element edge therefore looks up (recursively)
//! whether a vertex sits at its midpoint and, if so, includes it in its outline before
//! fan triangulation (Baum, Mann, Smith, Winget 1991, "Making radiosity usable").

use crate::mesh::Element;
use glam::DVec3;
use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};

/// The multiply-rotate hash of rustc (`FxHasher`) for the welder's integer keys: std's
/// SipHash took a third of the weld at 1,000,000 elements. Vertex numbers follow the
/// order of first use, so the hash changes no output.
#[derive(Default, Clone, Copy)]
struct Fx(u64);

impl Hasher for Fx {
    fn finish(&self) -> u64 {
        self.0
    }
    fn write(&mut self, bytes: &[u8]) {
        for b in bytes {
            self.write_u64(*b as u64);
        }
    }
    fn write_u32(&mut self, v: u32) {
        self.write_u64(v as u64);
    }
    fn write_u64(&mut self, v: u64) {
        self.0 = (self.0.rotate_left(5) ^ v).wrapping_mul(0x51_7c_c1_b7_27_22_0a_95);
    }
    fn write_i64(&mut self, v: i64) {
        self.write_u64(v as u64);
    }
    fn write_usize(&mut self, v: usize) {
        self.write_u64(v as u64);
    }
}

type FxMap<K, V> = HashMap<K, V, BuildHasherDefault<Fx>>;

/// Vertices with colours and triangles, ready for the rasterizer or a PLY file.
#[derive(Clone, Debug, Default)]
pub struct DisplayMesh {
    pub positions: Vec<DVec3>,
    pub normals: Vec<DVec3>,
    /// Radiosity per vertex (RGB).
    pub radiosity: Vec<[f64; 3]>,
    pub triangles: Vec<[u32; 3]>,
    /// Patch of each vertex.
    pub patch: Vec<u32>,
}

type Key = (u32, i64, i64, i64);

struct Welder {
    quantum: f64,
    map: FxMap<Key, u32>,
}

impl Welder {
    fn key(&self, patch: u32, p: DVec3) -> Key {
        let q = |x: f64| (x / self.quantum).round() as i64;
        (patch, q(p.x), q(p.y), q(p.z))
    }
}

/// Builds the display mesh of `elements` with per-element radiosity `b`.
pub fn weld(elements: &[Element], b: &[[f64; 3]], scale: f64) -> DisplayMesh {
    let mut w = Welder {
        quantum: (scale * 1e-8).max(1e-300),
        map: FxMap::with_capacity_and_hasher(elements.len() * 2, Default::default()),
    };
    let mut m = DisplayMesh::default();
    let mut weight: Vec<f64> = Vec::new();
    let mut corners: Vec<[u32; 4]> = Vec::with_capacity(elements.len());
    for (ei, e) in elements.iter().enumerate() {
        let mut c = [u32::MAX; 4];
        for (k, p) in e.poly.verts().iter().enumerate() {
            let key = w.key(e.patch, *p);
            let id = *w.map.entry(key).or_insert_with(|| {
                m.positions.push(*p);
                m.normals.push(e.normal);
                m.radiosity.push([0.0; 3]);
                m.patch.push(e.patch);
                weight.push(0.0);
                (m.positions.len() - 1) as u32
            });
            for (r, bc) in m.radiosity[id as usize].iter_mut().zip(b[ei]) {
                *r += e.area * bc;
            }
            weight[id as usize] += e.area;
            c[k] = id;
        }
        corners.push(c);
    }
    for (v, wt) in m.radiosity.iter_mut().zip(&weight) {
        if *wt > 0.0 {
            for ch in v.iter_mut() {
                *ch /= wt;
            }
        }
    }
    let mut outline: Vec<u32> = Vec::with_capacity(16);
    for (e, c) in elements.iter().zip(&corners) {
        let n = e.poly.n as usize;
        outline.clear();
        for (k, &ck) in c.iter().enumerate().take(n) {
            outline.push(ck);
            insert_midpoints(
                &w,
                e.patch,
                e.poly.v[k],
                e.poly.v[(k + 1) % n],
                0,
                &mut outline,
            );
        }
        let pos = &m.positions;
        for i in 1..outline.len() - 1 {
            let (a, b2, c2) = (outline[0], outline[i], outline[i + 1]);
            let area = (pos[b2 as usize] - pos[a as usize])
                .cross(pos[c2 as usize] - pos[a as usize])
                .length();
            if area > 1e-12 * e.area {
                m.triangles.push([a, b2, c2]);
            }
        }
    }
    m
}

fn insert_midpoints(w: &Welder, patch: u32, a: DVec3, b: DVec3, depth: u32, out: &mut Vec<u32>) {
    if depth > 20 {
        return;
    }
    let mid = 0.5 * (a + b);
    if let Some(&id) = w.map.get(&w.key(patch, mid)) {
        insert_midpoints(w, patch, a, mid, depth + 1, out);
        out.push(id);
        insert_midpoints(w, patch, mid, b, depth + 1, out);
    }
}

impl DisplayMesh {
    /// Every triangle edge is shared by exactly two triangles of the same patch or lies
    /// on the patch outline: counts the edges used once whose midpoint is a vertex of the
    /// same patch (T-vertices left). Zero for a crack-free mesh.
    pub fn t_vertices(&self) -> usize {
        let mut map: HashMap<(u32, i64, i64, i64), ()> = HashMap::new();
        let scale = self
            .positions
            .iter()
            .fold(0.0f64, |s, p| s.max(p.abs().max_element()))
            .max(1e-300);
        let q = scale * 1e-8;
        let key = |patch: u32, p: DVec3| {
            (
                patch,
                (p.x / q).round() as i64,
                (p.y / q).round() as i64,
                (p.z / q).round() as i64,
            )
        };
        for (i, p) in self.positions.iter().enumerate() {
            map.insert(key(self.patch[i], *p), ());
        }
        let mut count = 0;
        for t in &self.triangles {
            for k in 0..3 {
                let (a, b) = (t[k] as usize, t[(k + 1) % 3] as usize);
                let mid = 0.5 * (self.positions[a] + self.positions[b]);
                if map.contains_key(&key(self.patch[a], mid)) {
                    count += 1;
                }
            }
        }
        count
    }
}
