//! Marching cubes: a sphere comes out on the surface, closed and outward-facing; random
//! fields (every ambiguous case) come out closed; the gyroid has the expected size.

use glam::UVec3;
use irradia_core::{Aabb, Rng, Vec3};
use irradia_geometry::generators::{gyroid, gyroid_mesh, marching_cubes, MeshData, ScalarGrid};
use std::collections::HashMap;

/// Every edge used by exactly two triangles, once in each direction (closed and
/// consistently wound). Returns the number of distinct edges.
fn assert_closed(m: &MeshData) -> usize {
    let mut directed: HashMap<(u32, u32), u32> = HashMap::new();
    for t in &m.indices {
        for k in 0..3 {
            *directed.entry((t[k], t[(k + 1) % 3])).or_default() += 1;
        }
    }
    for (&(a, b), &n) in &directed {
        assert_eq!(n, 1, "edge {a}->{b} used {n} times in the same direction");
        assert_eq!(directed.get(&(b, a)), Some(&1), "edge {a}-{b} is on a hole");
    }
    directed.len() / 2
}

#[test]
fn sphere_is_on_the_surface_closed_and_outward() {
    let r = 0.9f32;
    let grid = ScalarGrid::sample(
        UVec3::splat(40),
        Aabb::new(Vec3::splat(-1.2), Vec3::splat(1.2)),
        |p| p.length() - r,
    );
    let h = grid.spacing().x;
    let m = marching_cubes(&grid, 0.0);
    assert!(m.indices.len() > 1000);
    // Linear interpolation of |p| along an edge of length h errs by at most h²/(2r).
    let worst = m
        .positions
        .iter()
        .map(|p| (p.length() - r).abs())
        .fold(0f32, f32::max);
    assert!(
        worst <= h * h / (2.0 * r) + 1e-5,
        "worst distance {worst}, spacing {h}"
    );
    let edges = assert_closed(&m);
    // A sphere: Euler characteristic 2.
    let euler = m.positions.len() as i64 - edges as i64 + m.indices.len() as i64;
    assert_eq!(euler, 2);
    // Normals (by winding) point out, towards increasing values; the enclosed volume
    // (divergence theorem) is that of the sphere within 1%.
    let mut volume = 0.0f64;
    for t in &m.indices {
        let [a, b, c] = t.map(|i| m.positions[i as usize]);
        let n = (b - a).cross(c - a);
        assert!(n.dot(a + b + c) >= 0.0);
        volume += a.dot(b.cross(c)) as f64 / 6.0;
    }
    let exact = 4.0 / 3.0 * std::f64::consts::PI * (r as f64).powi(3);
    assert!(
        (volume / exact - 1.0).abs() < 0.01,
        "volume {volume} vs {exact}"
    );
}

#[test]
fn random_fields_give_closed_surfaces() {
    // Random signs inside, negative on the border: every one of the 256 cube cases and
    // every ambiguous face occurs, and the surface must still be closed.
    let mut rng = Rng::new(3, 9);
    let mut seen = [false; 256];
    for _ in 0..20 {
        let n = 12u32;
        let values: Vec<f32> = (0..n * n * n)
            .map(|i| {
                let (x, y, z) = (i % n, (i / n) % n, i / (n * n));
                if [x, y, z].iter().any(|&c| c == 0 || c == n - 1) {
                    -1.0
                } else {
                    rng.next_f32() - 0.5
                }
            })
            .collect();
        let grid = ScalarGrid {
            dims: UVec3::splat(n),
            bounds: Aabb::new(Vec3::ZERO, Vec3::ONE),
            values,
        };
        for z in 0..n - 1 {
            for y in 0..n - 1 {
                for x in 0..n - 1 {
                    let mut case = 0;
                    for c in 0..8u32 {
                        let (dx, dy, dz) = (c & 1, (c >> 1) & 1, (c >> 2) & 1);
                        let i = (x + dx) + n * ((y + dy) + n * (z + dz));
                        if grid.values[i as usize] > 0.0 {
                            case |= 1 << c;
                        }
                    }
                    seen[case] = true;
                }
            }
        }
        let m = marching_cubes(&grid, 0.0);
        assert_closed(&m);
    }
    assert!(seen.iter().filter(|&&s| s).count() > 200);
}

#[test]
fn gyroid_small_grid_matches_its_function() {
    let m = gyroid_mesh(40);
    assert!(m.indices.len() > 10_000);
    let h = 2.0 / 39.0;
    for p in &m.positions {
        assert!(p.abs().max_element() <= 1.0 + 1e-6);
        // |∇f| <= 2π·√6 ... the value at a vertex is within the linear-interpolation
        // error of the sampled function: |f| <= max|f''| h² / 8 with |f''| <= 2(2π)²·3.
        assert!(gyroid(*p).abs() < 6.0 * (2.0 * std::f32::consts::PI).powi(2) * h * h / 8.0 + 1e-4);
    }
}
