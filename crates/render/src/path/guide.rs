//! A guide table over a sorted table of cumulative probabilities: the search
//! `cdf.partition_point(|&c| c <= u)` for `u ∈ [0, 1)` in expected constant time, with
//! exactly the binary search's answer (Chen and Asau 1974, "On Generating Random
//! Variates from an Empirical Distribution", AIIE Transactions 6(2); Devroye,
//! *Non-Uniform Random Variate Generation*, 1986, III.2.4 "the method of guide tables").
//!
//! `[0, 1)` is cut into `g` equal buckets; each bucket remembers the answer at its lower
//! end, and the next bucket's bounds the answer from above, so a query searches only the
//! entries of the table whose values fall in its own bucket. With `g` about the table's
//! length a query looks at about one entry on average, whatever the distribution: a
//! bucket holds many entries only where the cells are improbable, and a uniform `u`
//! lands there rarely. Because the bounds are checked against the table itself (and
//! widened if rounding put a bucket's end on the wrong side of an entry), the index is
//! the one the plain binary search finds, bit for bit, so samples do not change.

/// The guide of one sorted table (kept beside it, not owning it).
#[derive(Clone, Debug, Default)]
pub struct GuideTable {
    /// `start[k]`: entries of the table `<= k / g`; `start[g]` is the table's length.
    start: Vec<u32>,
}

impl GuideTable {
    /// The guide of `cdf` (non-decreasing) with about one bucket per entry.
    pub fn new(cdf: &[f32]) -> Self {
        let g = cdf.len().max(1);
        let mut start = Vec::with_capacity(g + 1);
        let mut p = 0usize;
        for k in 0..g {
            let lo = k as f32 / g as f32;
            while p < cdf.len() && cdf[p] <= lo {
                p += 1;
            }
            start.push(p as u32);
        }
        start.push(cdf.len() as u32);
        Self { start }
    }

    /// `cdf.partition_point(|&c| c <= u)`, for the `cdf` this guide was built from.
    #[inline]
    pub fn partition_point(&self, cdf: &[f32], u: f32) -> usize {
        let g = self.start.len() - 1;
        // Outside [0, 1) (or NaN) the buckets say nothing: search it all.
        if !(0.0..1.0).contains(&u) || g == 0 {
            return cdf.partition_point(|&c| c <= u);
        }
        let b = ((u * g as f32) as usize).min(g - 1);
        let mut lo = self.start[b] as usize;
        let mut hi = self.start[b + 1] as usize;
        // Rounding of `u * g` may put `u` a hair outside its bucket: widen to be sure
        // every entry before `lo` is `<= u` and every entry from `hi` on is `> u`.
        while lo > 0 && cdf[lo - 1] > u {
            lo -= 1;
        }
        while hi < cdf.len() && cdf[hi] <= u {
            hi += 1;
        }
        lo + cdf[lo..hi].partition_point(|&c| c <= u)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use irradia_core::Rng;

    /// The guide's answer is the binary search's for random tables (with empty cells,
    /// repeated values and one dominant cell) at random `u`, at every entry of the table
    /// and at the floats just below and above each.
    #[test]
    fn same_index_as_binary_search() {
        let mut rng = Rng::for_pixel(1, 2, 3, 4);
        for case in 0..200 {
            let n = 1 + (rng.next_f32() * 300.0) as usize;
            let func: Vec<f32> = (0..n)
                .map(|i| match case % 4 {
                    0 => rng.next_f32(),
                    1 if rng.next_f32() < 0.5 => 0.0,
                    1 => rng.next_f32(),
                    2 if i == n / 2 => 1e6,
                    2 => rng.next_f32() * 1e-3,
                    _ => (rng.next_f32() * 4.0).floor(),
                })
                .collect();
            let total: f32 = func.iter().sum::<f32>().max(1e-30);
            let mut acc = 0.0f32;
            let mut cdf = vec![0.0f32];
            for f in &func {
                acc += f;
                cdf.push(acc / total);
            }
            *cdf.last_mut().unwrap() = 1.0;
            let guide = GuideTable::new(&cdf);
            let check = |u: f32| {
                assert_eq!(
                    guide.partition_point(&cdf, u),
                    cdf.partition_point(|&c| c <= u),
                    "case {case} u {u}"
                );
            };
            for _ in 0..500 {
                check(rng.next_f32());
            }
            for &c in &cdf {
                check(c);
                check(f32::from_bits(c.to_bits().saturating_sub(1)));
                check(f32::from_bits(c.to_bits() + 1));
            }
            for u in [0.0, 1.0 - f32::EPSILON / 2.0, 1.0, -0.5, 2.0, f32::NAN] {
                check(u);
            }
        }
    }
}
