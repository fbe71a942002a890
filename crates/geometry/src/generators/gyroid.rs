//! The gyroid `sin x cos y + sin y cos z + sin z cos x = 0` of PEERS.md's triangles
//! workload: two periods per axis, sampled on a cubic grid and scaled to [-1, 1]^3.

use super::marching_cubes::{marching_cubes, MeshData, ScalarGrid};
use glam::{UVec3, Vec3};
use irradia_core::Aabb;
use std::f32::consts::PI;

/// The grid size of the benchmark mesh (2,254,089 triangles in PEERS.md).
pub const BENCHMARK_GRID: u32 = 342;

/// The gyroid's implicit function at `p` in [-1, 1]^3 (two periods per axis: the
/// angle runs over [0, 4π], as in the peer's mesh: skimage's marching cubes on that
/// grid gives PEERS.md's 2,254,089 triangles, while [-2π, 2π] gives 2,254,092).
pub fn gyroid(p: Vec3) -> f32 {
    let q = (p + Vec3::ONE) * (2.0 * PI);
    q.x.sin() * q.y.cos() + q.y.sin() * q.z.cos() + q.z.sin() * q.x.cos()
}

/// The gyroid sampled on `n`^3 points over [-1, 1]^3 and meshed by marching cubes.
/// The function is separable into per-axis sines and cosines, so they are tabulated
/// once per axis (in f64, then rounded) instead of per sample.
pub fn gyroid_mesh(n: u32) -> MeshData {
    use rayon::prelude::*;
    assert!(n >= 2);
    let n_us = n as usize;
    let angle = |i: usize| 4.0 * std::f64::consts::PI * i as f64 / (n_us - 1) as f64;
    let s: Vec<f64> = (0..n_us).map(|i| angle(i).sin()).collect();
    let c: Vec<f64> = (0..n_us).map(|i| angle(i).cos()).collect();
    let values = (0..n_us * n_us * n_us)
        .into_par_iter()
        .map(|i| {
            let (x, y, z) = (i % n_us, (i / n_us) % n_us, i / (n_us * n_us));
            (s[x] * c[y] + s[y] * c[z] + s[z] * c[x]) as f32
        })
        .collect();
    let grid = ScalarGrid {
        dims: UVec3::splat(n),
        bounds: Aabb::new(Vec3::splat(-1.0), Vec3::splat(1.0)),
        values,
    };
    marching_cubes(&grid, 0.0)
}
