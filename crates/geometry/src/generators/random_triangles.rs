//! The lecture's "random triangles" benchmark application: independent triangles with
//! centres uniform in a box, random orientation (or all facing one way), and areas
//! drawn from a chosen distribution.
//!
//! Every triangle draws from its own random stream (seed, triangle index), so the set
//! is the same for any thread count and a prefix of a larger set equals a smaller one.

use super::marching_cubes::MeshData;
use glam::Vec3;
use irradia_core::sampling::uniform_sphere;
use irradia_core::{Aabb, Frame, Rng};
use rayon::prelude::*;

/// The distribution of triangle areas (world units squared).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SizeDistribution {
    /// Every triangle has this area.
    Constant(f32),
    /// Areas uniform in `[min, max]`.
    Uniform { min: f32, max: f32 },
    /// Exponentially distributed areas with this mean (many small, few large).
    Exponential { mean: f32 },
    /// Log-normal areas: `median * exp(sigma * N(0, 1))`.
    LogNormal { median: f32, sigma: f32 },
}

impl SizeDistribution {
    /// One area drawn with `rng`.
    pub fn sample(&self, rng: &mut Rng) -> f32 {
        match *self {
            SizeDistribution::Constant(a) => a,
            SizeDistribution::Uniform { min, max } => min + (max - min) * rng.next_f32(),
            SizeDistribution::Exponential { mean } => -mean * (1.0 - rng.next_f64()).ln() as f32,
            SizeDistribution::LogNormal { median, sigma } => {
                // Box-Muller.
                let u1 = 1.0 - rng.next_f64();
                let u2 = rng.next_f64();
                let n = (-2.0 * u1.ln()).sqrt() * (2.0 * std::f64::consts::PI * u2).cos();
                median * (sigma as f64 * n).exp() as f32
            }
        }
    }

    /// The cumulative distribution function at `x` (for goodness-of-fit tests).
    pub fn cdf(&self, x: f64) -> f64 {
        match *self {
            SizeDistribution::Constant(a) => {
                if x >= a as f64 {
                    1.0
                } else {
                    0.0
                }
            }
            SizeDistribution::Uniform { min, max } => {
                ((x - min as f64) / (max as f64 - min as f64)).clamp(0.0, 1.0)
            }
            SizeDistribution::Exponential { mean } => {
                if x <= 0.0 {
                    0.0
                } else {
                    1.0 - (-x / mean as f64).exp()
                }
            }
            SizeDistribution::LogNormal { median, sigma } => {
                if x <= 0.0 {
                    0.0
                } else {
                    0.5 * (1.0
                        + erf((x / median as f64).ln() / (sigma as f64 * std::f64::consts::SQRT_2)))
                }
            }
        }
    }

    /// The mean area.
    pub fn mean(&self) -> f64 {
        match *self {
            SizeDistribution::Constant(a) => a as f64,
            SizeDistribution::Uniform { min, max } => 0.5 * (min as f64 + max as f64),
            SizeDistribution::Exponential { mean } => mean as f64,
            SizeDistribution::LogNormal { median, sigma } => {
                median as f64 * (0.5 * (sigma as f64).powi(2)).exp()
            }
        }
    }
}

/// The error function (Abramowitz and Stegun 7.1.26 is too coarse for tests; this is
/// the Numerical Recipes `erfc` Chebyshev fit, relative error below 1.2e-7).
fn erf(x: f64) -> f64 {
    let z = x.abs();
    let t = 1.0 / (1.0 + 0.5 * z);
    let ans = t
        * (-z * z - 1.265_512_23
            + t * (1.000_023_68
                + t * (0.374_091_96
                    + t * (0.096_784_18
                        + t * (-0.186_288_06
                            + t * (0.278_868_07
                                + t * (-1.135_203_98
                                    + t * (1.488_515_87
                                        + t * (-0.822_152_23 + t * 0.170_872_77)))))))))
            .exp();
    if x >= 0.0 {
        1.0 - ans
    } else {
        ans - 1.0
    }
}

/// What to generate.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RandomTriangles {
    pub count: usize,
    pub area: SizeDistribution,
    /// Triangle centres are uniform in this box.
    pub bounds: Aabb,
    /// `Some(n)`: every triangle's normal (by winding) is `n`; `None`: uniform on the
    /// sphere.
    pub facing: Option<Vec3>,
    pub seed: u64,
}

impl RandomTriangles {
    /// `count` triangles in [-1, 1]^3, random orientation.
    pub fn new(count: usize, area: SizeDistribution, seed: u64) -> Self {
        Self {
            count,
            area,
            bounds: Aabb::new(Vec3::splat(-1.0), Vec3::splat(1.0)),
            facing: None,
            seed,
        }
    }
}

/// Generates the triangles (three vertices each, none shared).
pub fn random_triangles(spec: &RandomTriangles) -> MeshData {
    let b = spec.bounds;
    let tris: Vec<[Vec3; 3]> = (0..spec.count)
        .into_par_iter()
        .with_min_len(4096)
        .map(|i| {
            let mut rng = Rng::new(spec.seed, i as u64);
            let area = spec.area.sample(&mut rng);
            let centre =
                b.min + (b.max - b.min) * Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32());
            let normal = spec
                .facing
                .map(|n| n.normalize())
                .unwrap_or_else(|| uniform_sphere(rng.next_2d()));
            let frame = Frame::from_normal(normal);
            // Corners on the unit circle at jittered thirds: never degenerate (each gap
            // between corners stays within [60, 180) degrees).
            let third = std::f32::consts::TAU / 3.0;
            let spin = rng.next_f32() * std::f32::consts::TAU;
            let corners = [0.0, 1.0, 2.0].map(|k: f32| {
                let a = spin + third * (k + 0.25 * (rng.next_f32() - 0.5));
                (a.cos(), a.sin())
            });
            let flat = |c: (f32, f32)| frame.to_world(Vec3::new(c.0, c.1, 0.0));
            let p = corners.map(flat);
            let unit_area = 0.5 * (p[1] - p[0]).cross(p[2] - p[0]).length();
            let s = (area / unit_area).sqrt();
            let mean = (p[0] + p[1] + p[2]) / 3.0;
            p.map(|q| centre + (q - mean) * s)
        })
        .collect();
    MeshData {
        positions: tris.iter().flatten().copied().collect(),
        indices: (0..spec.count as u32)
            .map(|i| [3 * i, 3 * i + 1, 3 * i + 2])
            .collect(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn area(m: &MeshData, t: usize) -> f64 {
        let [a, b, c] = m.indices[t].map(|i| m.positions[i as usize]);
        0.5 * (b - a).cross(c - a).length() as f64
    }

    /// Kolmogorov-Smirnov statistic of the generated areas against the requested CDF.
    fn ks(dist: SizeDistribution) -> f64 {
        let m = random_triangles(&RandomTriangles::new(4000, dist, 7));
        let mut a: Vec<f64> = (0..m.indices.len()).map(|t| area(&m, t)).collect();
        a.sort_by(|x, y| x.partial_cmp(y).unwrap());
        let n = a.len() as f64;
        a.iter()
            .enumerate()
            .map(|(i, &x)| {
                let f = dist.cdf(x);
                (f - i as f64 / n).abs().max((f - (i + 1) as f64 / n).abs())
            })
            .fold(0.0, f64::max)
    }

    #[test]
    fn areas_follow_the_requested_distribution() {
        // The 0.1% critical value of the KS statistic for n = 4000 is 1.95 / sqrt(n).
        let crit = 1.95 / 4000f64.sqrt();
        for d in [
            SizeDistribution::Uniform {
                min: 0.001,
                max: 0.01,
            },
            SizeDistribution::Exponential { mean: 0.004 },
            SizeDistribution::LogNormal {
                median: 0.003,
                sigma: 0.7,
            },
        ] {
            let k = ks(d);
            assert!(k < crit, "{d:?}: KS statistic {k} >= {crit}");
        }
        // And a wrong distribution is rejected, so the test can fail.
        let m = random_triangles(&RandomTriangles::new(
            4000,
            SizeDistribution::Exponential { mean: 0.004 },
            7,
        ));
        let mut a: Vec<f64> = (0..m.indices.len()).map(|t| area(&m, t)).collect();
        a.sort_by(|x, y| x.partial_cmp(y).unwrap());
        let wrong = SizeDistribution::Exponential { mean: 0.0044 };
        let n = a.len() as f64;
        let k = a
            .iter()
            .enumerate()
            .map(|(i, &x)| (wrong.cdf(x) - i as f64 / n).abs())
            .fold(0.0, f64::max);
        assert!(k > crit, "a 10% wrong mean should be detected: {k}");
    }

    #[test]
    fn constant_area_centres_in_box_and_facing() {
        let mut spec = RandomTriangles::new(500, SizeDistribution::Constant(0.02), 3);
        spec.facing = Some(Vec3::Z);
        let m = random_triangles(&spec);
        for t in 0..500 {
            assert!((area(&m, t) - 0.02).abs() < 1e-5);
            let [a, b, c] = m.indices[t].map(|i| m.positions[i as usize]);
            let n = (b - a).cross(c - a).normalize();
            assert!((n - Vec3::Z).length() < 1e-4, "{n}");
            let centre = (a + b + c) / 3.0;
            assert!(centre.abs().max_element() <= 1.0 + 1e-5);
        }
        // Deterministic: the same seed gives the same triangles.
        assert_eq!(random_triangles(&spec).positions, m.positions);
    }
}
