//! Random-triangle scenes on a small screen, shared by the tests that compare the
//! rasterizer's paths with each other (fused against plain, threads, regions).

use glam::Vec3;
use irradia_geometry::generators::random_triangles::{
    random_triangles, RandomTriangles, SizeDistribution,
};
use irradia_raster::{Mesh, Pipeline, ViewParams};

/// A second copy of every triangle, drawn after the first in other colours.
pub struct Copies {
    /// Colours repeat every `period` vertices.
    pub period: u32,
    /// The second copy's alpha.
    pub alpha: f32,
}

/// `count` random triangles of sizes `sizes` (seed `seed`) with vertex normals, seen
/// from `eye` towards the origin on a 96 x 64 screen (60 degree field of view); with
/// `copies`, every triangle is given twice, in two colour ramps.
pub fn random_scene(
    count: usize,
    sizes: SizeDistribution,
    seed: u64,
    eye: Vec3,
    copies: Option<Copies>,
) -> (Pipeline, Mesh) {
    let m = random_triangles(&RandomTriangles::new(count, sizes, seed));
    let mut mesh = match copies {
        None => Mesh::new(m.positions, m.indices),
        Some(Copies { period, alpha }) => {
            let n = m.positions.len() as u32;
            let mut positions = m.positions.clone();
            positions.extend_from_slice(&m.positions);
            let mut indices = m.indices.clone();
            indices.extend(m.indices.iter().map(|t| t.map(|i| i + n)));
            let mut mesh = Mesh::new(positions, indices);
            mesh.colors = (0..2 * n)
                .map(|i| {
                    let f = (i % period) as f32 / (period - 1) as f32;
                    if i < n {
                        [f, 1.0 - f, 0.3, 1.0]
                    } else {
                        [0.2, f, 1.0 - f, alpha]
                    }
                })
                .collect();
            mesh
        }
    };
    mesh.compute_vertex_normals();
    let mut p = Pipeline::new(96, 64);
    p.view = ViewParams::look_at_perspective(eye, Vec3::ZERO, Vec3::Y, 60.0, 1.5, 0.5, 10.0);
    (p, mesh)
}

/// A rayon pool of `threads` threads.
pub fn pool(threads: usize) -> rayon::ThreadPool {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap()
}
