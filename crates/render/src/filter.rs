//! Pixel (reconstruction) filters by importance sampling: each camera sample is placed
//! around its pixel's centre with a density proportional to the filter, and carries the
//! weight `f / density` (constant, or nearly so), so a pixel's value is the filtered
//! image `∫ f(p - x) L(x) dx / ∫ f` without splatting samples into neighbouring pixels
//! (pbrt-v4, section 8.8.1, "Filter Sampling", after Ernst, Stamminger and Greiner,
//! "Filter Importance Sampling", RT 2006). Every pixel still owns its samples, so tiles,
//! crop windows and thread counts never change an image.
//!
//! The filters are Mitsuba 3's (`src/rfilters/box.cpp`, `tent.cpp`, `gaussian.cpp`):
//! separable, with the same parameters and defaults ([`PixelFilter`]). Mitsuba splats
//! each sample into every pixel its filter reaches and divides by the sum of weights;
//! both estimate the same filtered image.

use glam::Vec2;
use irradia_scene::PixelFilter;

/// Bins of the tabulated half of the Gaussian (its density is piecewise constant over
/// them; the weight `f / density` corrects the rest).
const GAUSSIAN_BINS: usize = 256;

/// A filter prepared for sampling.
#[derive(Clone, Debug)]
pub struct FilterSampler {
    filter: PixelFilter,
    /// Gaussian only: the tabulated `f` at bin centres over `[0, radius]`, and its
    /// running sum normalised to end at 1.
    table: Vec<f32>,
    cdf: Vec<f32>,
}

impl FilterSampler {
    pub fn new(filter: PixelFilter) -> Self {
        let (mut table, mut cdf) = (Vec::new(), Vec::new());
        if let PixelFilter::Gaussian { .. } = filter {
            let r = radius(filter);
            let dx = r / GAUSSIAN_BINS as f32;
            table = (0..GAUSSIAN_BINS)
                .map(|i| eval(filter, (i as f32 + 0.5) * dx))
                .collect();
            let total: f64 = table.iter().map(|&v| v as f64).sum();
            let mut run = 0.0f64;
            cdf = table
                .iter()
                .map(|&v| {
                    run += v as f64;
                    (run / total) as f32
                })
                .collect();
        }
        Self { filter, table, cdf }
    }

    pub fn filter(&self) -> PixelFilter {
        self.filter
    }

    /// Whether this is the default box of one pixel (samples stay where the sampler
    /// put them, with weight 1).
    pub fn is_unit_box(&self) -> bool {
        self.filter == PixelFilter::Box { radius: 0.5 }
    }

    /// Whether [`Self::warp`]'s weight is 1 for every sample: the box and tent filters,
    /// sampled exactly by their densities; not the Gaussian (tabulated: `f / density`).
    pub fn unit_weights(&self) -> bool {
        !matches!(self.filter, PixelFilter::Gaussian { .. })
    }

    /// The 1D filter `f(x)` (Mitsuba's definition, not normalised).
    pub fn eval(&self, x: f32) -> f32 {
        eval(self.filter, x)
    }

    /// `∫ f(x) dx` over the filter's support, in closed form.
    pub fn integral(&self) -> f64 {
        match self.filter {
            PixelFilter::Box { radius } => 2.0 * radius as f64,
            PixelFilter::Tent { radius } => radius as f64,
            PixelFilter::Gaussian { stddev } => {
                let s = stddev as f64;
                let r = 4.0 * s;
                let bias = (-r * r / (2.0 * s * s)).exp();
                s * (2.0 * std::f64::consts::PI).sqrt() * erf(r / (s * std::f64::consts::SQRT_2))
                    - 2.0 * r * bias
            }
        }
    }

    /// Where in its pixel (from the pixel's top-left corner, in pixels) the sample with
    /// unit-square coordinates `u` goes, and its weight. The default box returns `u`
    /// itself with weight 1, bit for bit; `u = (0.5, 0.5)` (the pixel centre of a
    /// one-sample render) stays the centre for every filter.
    #[inline]
    pub fn warp(&self, u: Vec2) -> (Vec2, f32) {
        match self.filter {
            PixelFilter::Box { radius } if radius == 0.5 => (u, 1.0),
            PixelFilter::Box { radius } => (Vec2::splat(0.5) + (u - 0.5) * (2.0 * radius), 1.0),
            PixelFilter::Tent { radius } => (
                Vec2::new(0.5 + tent(u.x, radius), 0.5 + tent(u.y, radius)),
                1.0,
            ),
            PixelFilter::Gaussian { .. } => {
                let (x, wx) = self.tabulated(u.x);
                let (y, wy) = self.tabulated(u.y);
                (Vec2::new(0.5 + x, 0.5 + y), wx * wy)
            }
        }
    }

    /// One axis of the Gaussian: the sign from which half of `[0, 1)` `u` is in, the
    /// distance from the table, and the weight `f(x)` over the table's value there.
    fn tabulated(&self, u: f32) -> (f32, f32) {
        let v = (2.0 * u - 1.0).abs().min(1.0 - f32::EPSILON);
        let r = radius(self.filter);
        let bin = self.cdf.partition_point(|&c| c <= v).min(GAUSSIAN_BINS - 1);
        let lo = if bin == 0 { 0.0 } else { self.cdf[bin - 1] };
        let width = self.cdf[bin] - lo;
        let t = if width > 0.0 {
            ((v - lo) / width).clamp(0.0, 1.0)
        } else {
            0.5
        };
        let d = (bin as f32 + t) * (r / GAUSSIAN_BINS as f32);
        let w = eval(self.filter, d) / self.table[bin];
        (if u < 0.5 { -d } else { d }, w)
    }
}

/// How far the filter reaches from the pixel centre, in pixels.
pub fn radius(filter: PixelFilter) -> f32 {
    match filter {
        PixelFilter::Box { radius } | PixelFilter::Tent { radius } => radius,
        PixelFilter::Gaussian { stddev } => 4.0 * stddev,
    }
}

fn eval(filter: PixelFilter, x: f32) -> f32 {
    let x = x.abs();
    match filter {
        PixelFilter::Box { radius } => {
            if x <= radius {
                1.0
            } else {
                0.0
            }
        }
        PixelFilter::Tent { radius } => (1.0 - x / radius).max(0.0),
        PixelFilter::Gaussian { stddev } => {
            let alpha = -1.0 / (2.0 * stddev * stddev);
            let r = 4.0 * stddev;
            ((alpha * x * x).exp() - (alpha * r * r).exp()).max(0.0)
        }
    }
}

/// The inverse of the tent's distribution function on `[-radius, radius]`.
#[inline]
fn tent(u: f32, radius: f32) -> f32 {
    if u < 0.5 {
        radius * ((2.0 * u).sqrt() - 1.0)
    } else {
        radius * (1.0 - (2.0 - 2.0 * u).sqrt())
    }
}

/// The error function, to about 1e-7 (Abramowitz and Stegun, "Handbook of Mathematical
/// Functions", formula 7.1.26).
pub fn erf(x: f64) -> f64 {
    let t = 1.0 / (1.0 + 0.327_591_1 * x.abs());
    let poly = t
        * (0.254_829_592
            + t * (-0.284_496_736
                + t * (1.421_413_741 + t * (-1.453_152_027 + t * 1.061_405_429))));
    let y = 1.0 - poly * (-x * x).exp();
    if x < 0.0 {
        -y
    } else {
        y
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn filters() -> Vec<PixelFilter> {
        vec![
            PixelFilter::Box { radius: 0.5 },
            PixelFilter::Box { radius: 1.5 },
            PixelFilter::Tent { radius: 1.0 },
            PixelFilter::Tent { radius: 2.0 },
            PixelFilter::Gaussian { stddev: 0.5 },
            PixelFilter::Gaussian { stddev: 0.3 },
        ]
    }

    /// The filter normalised by its closed-form integral integrates to one (midpoint
    /// rule over its support).
    #[test]
    fn normalised_filters_integrate_to_one() {
        for f in filters() {
            let s = FilterSampler::new(f);
            let r = radius(f) as f64;
            let n = 200_000;
            let dx = 2.0 * r / n as f64;
            let sum: f64 = (0..n)
                .map(|i| s.eval((-r + (i as f64 + 0.5) * dx) as f32) as f64 * dx)
                .sum();
            assert!(
                (sum / s.integral() - 1.0).abs() < 1e-4,
                "{f:?}: {sum} vs {}",
                s.integral()
            );
        }
    }

    /// The weighted samples reproduce the normalised filter: over bins of the support,
    /// the weight that lands in each (divided by the total weight) is the filter's
    /// integral over the bin divided by its whole integral; the weights sum to one over
    /// the support. The bins are checked to 3.5 standard errors of their estimate.
    #[test]
    fn weighted_samples_follow_the_normalised_filter() {
        for f in filters() {
            let s = FilterSampler::new(f);
            let r = radius(f);
            let bins = 16usize;
            let mut hist = vec![0.0f64; bins];
            let mut hist_sq = vec![0.0f64; bins];
            let mut total = 0.0f64;
            let n = 200_000u32;
            let mut rng = irradia_core::Rng::new(7, 3);
            for _ in 0..n {
                let u = Vec2::new(rng.next_f32(), rng.next_f32());
                let (p, w) = s.warp(u);
                let x = p.x - 0.5;
                assert!(x.abs() <= r + 1e-5, "{f:?}: {x} outside the support");
                // The other axis's weight factor: integrate it out with its own mean.
                let b = (((x + r) / (2.0 * r)) * bins as f32).clamp(0.0, bins as f32 - 1.0);
                hist[b as usize] += w as f64;
                hist_sq[b as usize] += (w as f64).powi(2);
                total += w as f64;
            }
            for (i, (&h, &h2)) in hist.iter().zip(&hist_sq).enumerate() {
                let (a, b) = (
                    -r as f64 + 2.0 * r as f64 * i as f64 / bins as f64,
                    -r as f64 + 2.0 * r as f64 * (i + 1) as f64 / bins as f64,
                );
                let m = 2000;
                let exact: f64 = (0..m)
                    .map(|k| s.eval((a + (k as f64 + 0.5) * (b - a) / m as f64) as f32) as f64)
                    .sum::<f64>()
                    * (b - a)
                    / m as f64
                    / s.integral();
                let got = h / total;
                let se = (h2 / n as f64).sqrt() / (total / n as f64) / (n as f64).sqrt() + 1e-9;
                assert!(
                    (got - exact).abs() <= 3.5 * se + 2e-4,
                    "{f:?} bin {i}: {got} vs {exact} (se {se})"
                );
            }
        }
    }

    #[test]
    fn the_centre_stays_the_centre_and_the_unit_box_is_the_identity() {
        for f in filters() {
            let (p, _) = FilterSampler::new(f).warp(Vec2::splat(0.5));
            assert!((p - Vec2::splat(0.5)).length() < 1e-6, "{f:?}: {p}");
        }
        let unit = FilterSampler::new(PixelFilter::default());
        for u in [Vec2::new(0.1, 0.9), Vec2::new(0.333, 0.0)] {
            assert_eq!(unit.warp(u), (u, 1.0));
        }
    }

    #[test]
    fn erf_matches_known_values() {
        for (x, e) in [
            (0.0, 0.0),
            (0.5, 0.520_499_877_8),
            (1.0, 0.842_700_792_9),
            (2.0, 0.995_322_265),
        ] {
            assert!((erf(x) - e).abs() < 2e-7, "erf({x}) = {}", erf(x));
            assert!((erf(-x) + e).abs() < 2e-7);
        }
    }
}
