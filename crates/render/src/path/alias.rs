//! Walker's alias method: a discrete distribution sampled in constant time by one
//! table lookup and one comparison (Walker 1977, "An Efficient Method for Generating
//! Discrete Random Variables with General Distributions", ACM TOMS 3(3); the
//! construction of Vose 1991, "A Linear Algorithm for Generating Random Numbers with a
//! Given Distribution", IEEE TSE 17(9); Pharr, Jakob, Humphreys, *Physically Based
//! Rendering*, 4th ed., A.1 `AliasTable`).
//!
//! `n` bins of equal probability `1/n` each hold a threshold `q` and an alias: the
//! uniform number picks a bin, its fraction within the bin keeps the bin's own index
//! below `q` and takes the alias above, and that fraction, stretched back to `[0, 1)`,
//! is returned for placing the sample within the chosen cell (so one uniform number
//! serves both). The wide kernel's lanes sample the same table with the same `f32`
//! operations ([`crate::path::wide`]'s environment maps), two loads per lane where a
//! search of a cumulative table takes one dependent load per halving.

/// One bin: below `q` the bin's own index, above it `alias`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AliasBin {
    pub q: f32,
    pub alias: u32,
}

/// A discrete distribution over `0..n` in proportion to non-negative weights.
#[derive(Clone, Debug, Default)]
pub struct AliasTable {
    bins: Vec<AliasBin>,
}

/// The largest `f32` below 1: fractions are kept under it.
pub const ONE_MINUS_EPSILON: f32 = 1.0 - f32::EPSILON / 2.0;

impl AliasTable {
    /// The table of `weights` (negative, NaN and infinite weights count as 0); all
    /// zero, or none: uniform over the bins (at least one).
    pub fn new(weights: &[f32]) -> Self {
        let n = weights.len().max(1);
        let w = |i: usize| match weights.get(i) {
            Some(&x) if x.is_finite() && x > 0.0 => x as f64,
            _ => 0.0,
        };
        let total: f64 = (0..n).map(w).sum();
        // Each weight in units of the mean: bins below 1 are filled up from bins above.
        let mut p: Vec<f64> = (0..n)
            .map(|i| {
                if total > 0.0 {
                    w(i) / total * n as f64
                } else {
                    1.0
                }
            })
            .collect();
        let mut bins: Vec<AliasBin> = (0..n as u32)
            .map(|i| AliasBin { q: 1.0, alias: i })
            .collect();
        let (mut small, mut large): (Vec<usize>, Vec<usize>) = (0..n).partition(|&i| p[i] < 1.0);
        while let (Some(&s), Some(&l)) = (small.last(), large.last()) {
            small.pop();
            large.pop();
            bins[s] = AliasBin {
                q: p[s] as f32,
                alias: l as u32,
            };
            p[l] = (p[l] + p[s]) - 1.0;
            if p[l] < 1.0 {
                small.push(l);
            } else {
                large.push(l);
            }
        }
        // What is left holds its own bin whole (in exact arithmetic each is 1; rounding
        // leaves them a hair away).
        Self { bins }
    }

    /// The number of bins.
    pub fn len(&self) -> usize {
        self.bins.len()
    }

    pub fn is_empty(&self) -> bool {
        self.bins.is_empty()
    }

    /// The bins, for tables read in lanes.
    pub fn bins(&self) -> &[AliasBin] {
        &self.bins
    }

    /// The index drawn by `u ∈ [0, 1)` and `u`'s fraction within its choice, uniform in
    /// `[0, 1)` again.
    #[inline]
    pub fn sample(&self, u: f32) -> (usize, f32) {
        let n = self.bins.len();
        let (k, f) = bin_and_fraction(u, n as f32);
        let bin = self.bins[(k as usize).min(n - 1)];
        if f < bin.q {
            ((k as usize).min(n - 1), own_fraction(f, bin.q))
        } else {
            (bin.alias as usize, alias_fraction(f, bin.q))
        }
    }

    /// The probability of index `i` as the table draws it: its own bin's share below
    /// `q` and the shares above `q` of the bins whose alias it is (the tests' check).
    #[cfg(test)]
    fn probability(&self, i: usize) -> f64 {
        let n = self.bins.len() as f64;
        let own = self.bins[i].q.min(1.0) as f64;
        let given: f64 = self
            .bins
            .iter()
            .enumerate()
            .filter(|&(k, b)| b.alias as usize == i && k != i)
            .map(|(_, b)| 1.0 - b.q.min(1.0) as f64)
            .sum();
        (own + given) / n
    }
}

/// `u`'s bin among `n` (as `f32`; the caller clamps it to `n - 1`) and its fraction
/// within it, below 1.
#[inline(always)]
fn bin_and_fraction(u: f32, n: f32) -> (f32, f32) {
    let x = u * n;
    let k = x.floor();
    (k, (x - k).min(ONE_MINUS_EPSILON))
}

/// The fraction `f < q` stretched over the bin's own share.
#[inline(always)]
fn own_fraction(f: f32, q: f32) -> f32 {
    (f / q).min(ONE_MINUS_EPSILON)
}

/// The fraction `f >= q` stretched over the alias's share.
#[inline(always)]
fn alias_fraction(f: f32, q: f32) -> f32 {
    ((f - q) / (1.0 - q)).min(ONE_MINUS_EPSILON)
}

#[cfg(test)]
mod tests {
    use super::*;
    use irradia_core::Rng;

    fn weights(rng: &mut Rng, case: usize, n: usize) -> Vec<f32> {
        (0..n)
            .map(|i| match case % 5 {
                0 => rng.next_f32(),
                1 if rng.next_f32() < 0.5 => 0.0,
                1 => rng.next_f32(),
                2 if i == n / 2 => 1e6,
                2 => rng.next_f32() * 1e-3,
                3 => (rng.next_f32() * 4.0).floor(),
                _ => 1.0,
            })
            .collect()
    }

    /// The table draws every index with its weight's share (to rounding), never one of
    /// weight 0, for tables with empty cells, ties, a dominant cell and equal weights.
    #[test]
    fn probabilities_are_the_weights_shares() {
        let mut rng = Rng::new(3, 4);
        for case in 0..200 {
            let n = 1 + (rng.next_f32() * 300.0) as usize;
            let w = weights(&mut rng, case, n);
            let total: f64 = w.iter().map(|&x| x as f64).sum();
            let t = AliasTable::new(&w);
            assert_eq!(t.len(), n);
            let mut sum = 0.0;
            for (i, &x) in w.iter().enumerate() {
                let (got, want) = (t.probability(i), x as f64 / total);
                assert!(
                    (got - want).abs() <= 1e-6 * want + 1e-9,
                    "case {case} index {i}: {got} vs {want}"
                );
                if x == 0.0 {
                    assert_eq!(got, 0.0, "case {case}: index {i} of weight 0 has a share");
                    assert!(t.bins().iter().all(|b| b.alias as usize != i || b.q >= 1.0));
                }
                sum += got;
            }
            assert!((sum - 1.0).abs() < 1e-6, "case {case}: shares sum to {sum}");
        }
    }

    /// Samples land on indices in proportion to the weights (chi-square), never on a
    /// weight-0 index, and the returned fraction is uniform in [0, 1) (chi-square over
    /// ten strata) and below 1 even at the largest `u`.
    #[test]
    fn samples_follow_the_weights_with_uniform_fractions() {
        let w = [1.0, 0.0, 3.0, 0.5, 2.5, 0.0, 1.0];
        let t = AliasTable::new(&w);
        let total: f32 = w.iter().sum();
        let mut rng = Rng::new(9, 10);
        let n = 200_000;
        let mut counts = [0u32; 7];
        let mut strata = [0u32; 10];
        for _ in 0..n {
            let (i, f) = t.sample(rng.next_f32());
            assert!((0.0..1.0).contains(&f), "fraction {f}");
            counts[i] += 1;
            strata[(f * 10.0) as usize] += 1;
        }
        let mut chi2 = 0.0;
        for (c, &x) in counts.iter().zip(&w) {
            let expected = n as f64 * (x / total) as f64;
            if expected == 0.0 {
                assert_eq!(*c, 0, "a weight-0 index was drawn");
            } else {
                chi2 += (*c as f64 - expected).powi(2) / expected;
            }
        }
        // Five non-empty indices: 4 degrees of freedom; 18.5 is the 0.999 quantile.
        assert!(chi2 < 18.5, "chi-square {chi2}: {counts:?}");
        let expected = n as f64 / 10.0;
        let chi2: f64 = strata
            .iter()
            .map(|&c| (c as f64 - expected).powi(2) / expected)
            .sum();
        // 9 degrees of freedom: 27.9 is the 0.999 quantile.
        assert!(chi2 < 27.9, "fractions not uniform: {strata:?}");
        for u in [0.0, ONE_MINUS_EPSILON, 0.5] {
            let (i, f) = t.sample(u);
            assert!(w[i] > 0.0 && (0.0..1.0).contains(&f), "u {u}: {i} {f}");
        }
    }

    /// All-zero and empty weights: uniform over the bins.
    #[test]
    fn no_weight_is_uniform() {
        let t = AliasTable::new(&[0.0, 0.0, f32::NAN, -1.0]);
        for i in 0..4 {
            assert_eq!(t.probability(i), 0.25);
        }
        let t = AliasTable::new(&[]);
        assert_eq!(t.len(), 1);
        assert_eq!(t.sample(0.7).0, 0);
    }
}
