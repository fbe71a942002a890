//! The geometry stage's per-batch loops compiled for the widest instruction set the CPU
//! runs ([`SimdBuild`](irradia_geometry::packet::SimdBuild), picked at run time as the
//! path tracer's wide kernel picks its build), and the test that every build makes the
//! same triangles. The crate is built for the x86-64 baseline (SSE2), so
//! the inlined per-triangle code (transform, lighting, projection, snapping, culling,
//! binning) otherwise runs with two-operand SSE instructions and 16 vector registers;
//! with AVX2 it gets three-operand VEX forms, with AVX-512 also 32 registers (fewer
//! spills in a loop that keeps a triangle's three corners in flight).
//!
//! Results are bit for bit the same in every build: the code is the same IEEE
//! operations in the same order, and Rust never contracts a multiply and an add into
//! an FMA on its own (the `fma` feature only lets LLVM use the instruction where the
//! source asks for a fused multiply-add), so only the instruction encodings differ.
//! The test below compares the builds' triangles bit for bit.

#[cfg(test)]
mod tests {
    use crate::geometry_stage::{Batch, GeometryStage};
    use crate::lighting::{EyeLights, Lights, Material, Shading};
    use crate::mesh::{Mesh, Triangle, Vertex};
    use crate::rasterizer::CullMode;
    use crate::view::ViewParams;
    use glam::{Vec2, Vec3};
    use irradia_geometry::packet::SimdBuild;

    /// SplitMix64 numbers in [0, 1).
    struct Rng(u64);
    impl Rng {
        fn f(&mut self) -> f32 {
            self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
            let mut z = self.0;
            z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
            ((z ^ (z >> 31)) >> 40) as f32 / (1u64 << 24) as f32
        }
        fn v(&mut self, scale: f32) -> Vec3 {
            Vec3::new(self.f() - 0.5, self.f() - 0.5, self.f() - 0.5) * scale
        }
    }

    /// Everything a batch holds, bit for bit (`Debug` prints the shortest string that
    /// reads back as the same float).
    fn bits(batches: &[Batch]) -> Vec<String> {
        batches
            .iter()
            .map(|b| format!("{:?} {:?} {:?}", b.tris, b.frags, b.bins))
            .collect()
    }

    /// Soups (corners lit triangle by triangle, with and without normals), a mesh of
    /// shared vertices (lit once each) and independent triangles: many triangles of a
    /// few pixels, some large, some crossing the near plane and the screen's edges.
    #[test]
    fn every_build_makes_the_same_triangles_bit_for_bit() {
        let mut r = Rng(11);
        let n = 30_000;
        let mut soup = Mesh::default();
        for t in 0..n {
            let c = r.v(if t % 50 == 0 { 8.0 } else { 2.5 });
            let size = if t % 97 == 0 { 2.0 } else { 0.03 };
            for _ in 0..3 {
                soup.positions.push(c + r.v(size));
                soup.normals.push(r.v(2.0).normalize_or_zero());
            }
            soup.indices
                .push([3 * t, 3 * t + 1, 3 * t + 2].map(|i| i as u32));
        }
        let flat = Mesh {
            normals: Vec::new(),
            ..soup.clone()
        };
        // A grid of shared vertices, bent in depth.
        let side = 120u32;
        let mut grid = Mesh::default();
        for y in 0..side {
            for x in 0..side {
                let (u, v) = (x as f32 / side as f32 - 0.5, y as f32 / side as f32 - 0.5);
                grid.positions
                    .push(Vec3::new(u * 3.0, v * 3.0, (u * 9.0).sin() * 0.5));
                grid.normals
                    .push(Vec3::new(-(u * 9.0).cos(), 0.3, 1.0).normalize());
            }
        }
        for y in 0..side - 1 {
            for x in 0..side - 1 {
                let i = y * side + x;
                grid.indices.push([i, i + 1, i + side]);
                grid.indices.push([i + 1, i + side + 1, i + side]);
            }
        }
        let tris: Vec<Triangle> = soup
            .indices
            .iter()
            .enumerate()
            .map(|(t, idx)| Triangle {
                v: idx.map(|i| Vertex {
                    position: soup.positions[i as usize],
                    normal: soup.normals[i as usize],
                    color: [0.9, 0.6, 0.3, 1.0],
                    uv: Vec2::ZERO,
                }),
                id: t as u32,
                material: 0,
            })
            .collect();

        let (w, h) = (320, 200);
        let view = ViewParams::default();
        let material = Material {
            two_sided: true,
            ..Material::default()
        };
        let lights = EyeLights::new(&Lights::default(), &material, view.view, false);
        let run = |build: SimdBuild| {
            let stage = GeometryStage::new(
                view.view,
                view.proj,
                &lights,
                Shading::Gouraud,
                CullMode::None,
                w,
                h,
                true,
            )
            .with_fragments(true)
            .with_build(build);
            [
                bits(&stage.mesh(&soup)),
                bits(&stage.mesh(&flat)),
                bits(&stage.mesh(&grid)),
                bits(&stage.triangles(&tris)),
            ]
        };
        let portable = run(SimdBuild::Portable);
        let made: usize = portable.iter().flatten().map(|s| s.len()).sum();
        assert!(
            made > 1_000_000,
            "too little output to compare: {made} bytes"
        );
        for build in SimdBuild::ALL.into_iter().filter(|b| b.available()) {
            for (case, (a, b)) in ["soup", "flat", "grid", "triangles"]
                .iter()
                .zip(portable.iter().zip(run(build)))
            {
                assert!(
                    *a == b,
                    "{build:?} differs from the portable build ({case})"
                );
            }
        }
    }
}
