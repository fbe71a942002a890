//! Metaballs (Blinn 1982, "A generalization of algebraic surface drawing"): the
//! isosurface of a sum of radial fields, meshed by marching cubes — one of the
//! lecture's marching-cubes benchmark applications.

use super::marching_cubes::{marching_cubes, MeshData, ScalarGrid};
use glam::{UVec3, Vec3};
use irradia_core::{Aabb, Rng};

/// One ball: its field is `(radius / distance)^2`, so alone it meets the iso level 1
/// exactly at `radius`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ball {
    pub center: Vec3,
    pub radius: f32,
}

/// The summed field at `p`.
pub fn field(balls: &[Ball], p: Vec3) -> f32 {
    balls
        .iter()
        .map(|b| b.radius * b.radius / (p - b.center).length_squared().max(1e-12))
        .sum()
}

/// `count` balls with centres uniform in [-0.6, 0.6]^3 and radii in [0.15, 0.3].
pub fn random_balls(count: usize, seed: u64) -> Vec<Ball> {
    let mut rng = Rng::new(seed, 0x6d65_7461);
    (0..count)
        .map(|_| Ball {
            center: Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * 1.2
                - Vec3::splat(0.6),
            radius: 0.15 + 0.15 * rng.next_f32(),
        })
        .collect()
}

/// The surface `field = 1` sampled on `n`^3 points over [-1, 1]^3.
pub fn metaballs_mesh(balls: &[Ball], n: u32) -> MeshData {
    let grid = ScalarGrid::sample(
        UVec3::splat(n),
        Aabb::new(Vec3::splat(-1.0), Vec3::splat(1.0)),
        |p| field(balls, p),
    );
    marching_cubes(&grid, 1.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_single_ball_is_a_sphere_of_its_radius() {
        let b = [Ball {
            center: Vec3::new(0.1, -0.05, 0.0),
            radius: 0.5,
        }];
        let m = metaballs_mesh(&b, 48);
        assert!(m.indices.len() > 1000);
        for p in &m.positions {
            let r = (*p - b[0].center).length();
            assert!((r - 0.5).abs() < 0.01, "vertex at radius {r}");
        }
    }

    #[test]
    fn two_close_balls_merge_and_far_ones_do_not() {
        // Between two balls at distance 2d the field is 2 r^2 / d^2 at the midpoint.
        let close = [
            Ball {
                center: Vec3::new(-0.3, 0.0, 0.0),
                radius: 0.25,
            },
            Ball {
                center: Vec3::new(0.3, 0.0, 0.0),
                radius: 0.25,
            },
        ];
        assert!(field(&close, Vec3::ZERO) > 1.0);
        let far = [
            Ball {
                center: Vec3::new(-0.6, 0.0, 0.0),
                radius: 0.2,
            },
            Ball {
                center: Vec3::new(0.6, 0.0, 0.0),
                radius: 0.2,
            },
        ];
        assert!(field(&far, Vec3::ZERO) < 1.0);
        // The merged surface crosses the x axis only at its outer ends.
        let m = metaballs_mesh(&close, 40);
        assert!(m
            .positions
            .iter()
            .all(|p| p.x.abs() > 0.05 || p.y.abs() + p.z.abs() > 0.05));
        assert_eq!(random_balls(5, 1), random_balls(5, 1));
    }
}
