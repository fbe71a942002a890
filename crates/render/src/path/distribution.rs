//! Piecewise-constant distributions in one and two dimensions (Pharr, Jakob, Humphreys,
//! *Physically Based Rendering*, 4th ed., A.5 `PiecewiseConstant1D` /
//! `PiecewiseConstant2D`): the density of the 2D one is the marginal density of a row
//! times the conditional density of a column within it, so `pdf` is exactly the density
//! `sample` draws from. A cell is drawn by an [`AliasTable`] (constant time, and two
//! loads per lane in the wide kernel) rather than by inverting the cumulative table,
//! and the number's fraction left over places the point within the cell.

use super::alias::AliasTable;
use glam::Vec2;

/// A density on [0, 1) proportional to `n` non-negative cell values.
#[derive(Clone, Debug)]
pub struct Piecewise1D {
    /// The cell values.
    func: Vec<f32>,
    /// The integral of the step function over [0, 1): mean of `func`.
    integral: f32,
    /// Draws a cell in proportion to `func` (uniformly when all are zero).
    alias: AliasTable,
}

impl Piecewise1D {
    pub fn new(func: &[f32]) -> Self {
        let n = func.len().max(1);
        let func: Vec<f32> = (0..n)
            .map(|i| {
                let f = func.get(i).copied().unwrap_or(0.0);
                if f.is_finite() && f > 0.0 {
                    f
                } else {
                    0.0
                }
            })
            .collect();
        let acc: f64 = func.iter().map(|&f| f as f64).sum();
        Self {
            alias: AliasTable::new(&func),
            func,
            integral: (acc / n as f64) as f32,
        }
    }

    pub fn len(&self) -> usize {
        self.func.len()
    }

    pub fn is_empty(&self) -> bool {
        self.func.is_empty()
    }

    pub fn integral(&self) -> f32 {
        self.integral
    }

    /// A point of [0, 1) and the cell it lies in, drawn with density `pdf`: the cell by
    /// the alias table, the point within it by the number's fraction left over.
    #[inline]
    pub fn sample(&self, u: f32) -> (f32, usize) {
        let n = self.func.len();
        let (i, du) = self.alias.sample(u);
        ((i as f32 + du.min(1.0 - f32::EPSILON)) / n as f32, i)
    }

    /// The cell table the wide kernel's lanes read ([`AliasTable::bins`]).
    pub(crate) fn alias(&self) -> &AliasTable {
        &self.alias
    }

    /// The density at a point of cell `i`.
    #[inline]
    pub fn pdf(&self, i: usize) -> f32 {
        if self.integral > 0.0 {
            self.func[i.min(self.func.len() - 1)] / self.integral
        } else {
            0.0
        }
    }
}

/// A density on [0, 1)² proportional to a `width x height` grid of cell values (row
/// `j` covers `v ∈ [j, j+1) / height`).
#[derive(Clone, Debug)]
pub struct Piecewise2D {
    rows: Vec<Piecewise1D>,
    marginal: Piecewise1D,
    /// `pdf(i, j)` of every cell, row by row: the product of the marginal and
    /// conditional densities worked out once (the same `f32` product, so the same bits),
    /// one load per query instead of four dependent ones and two divisions.
    pdfs: Vec<f32>,
    width: usize,
}

impl Piecewise2D {
    /// `func` in rows of `width`, top row first.
    pub fn new(func: &[f32], width: usize, height: usize) -> Self {
        let rows: Vec<Piecewise1D> = (0..height)
            .map(|j| Piecewise1D::new(&func[j * width..(j + 1) * width]))
            .collect();
        let marginal = Piecewise1D::new(&rows.iter().map(|r| r.integral()).collect::<Vec<_>>());
        let width = rows.first().map_or(1, |r| r.len());
        let pdfs = (0..rows.len())
            .flat_map(|j| {
                let (m, row) = (marginal.pdf(j), &rows[j]);
                (0..width).map(move |i| m * row.pdf(i))
            })
            .collect();
        Self {
            rows,
            marginal,
            pdfs,
            width,
        }
    }

    /// The integral of the step function over the unit square.
    pub fn integral(&self) -> f32 {
        self.marginal.integral()
    }

    /// The distribution of rows (`sample` draws `v` and the row from it).
    pub(crate) fn marginal(&self) -> &Piecewise1D {
        &self.marginal
    }

    /// Each row's distribution (`sample` draws `u` and the cell from the drawn row's),
    /// all of one length.
    pub(crate) fn rows(&self) -> &[Piecewise1D] {
        &self.rows
    }

    /// A point `(u, v)` and its cell `(i, j)`, drawn with density `pdf`.
    #[inline]
    pub fn sample(&self, u: Vec2) -> (Vec2, (usize, usize)) {
        let (v, j) = self.marginal.sample(u.y);
        let (x, i) = self.rows[j].sample(u.x);
        (Vec2::new(x, v), (i, j))
    }

    /// The density at a point of cell `(i, j)`.
    #[inline]
    pub fn pdf(&self, i: usize, j: usize) -> f32 {
        let j = j.min(self.rows.len() - 1);
        self.pdfs[j * self.width + i.min(self.width - 1)]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Cell densities, and points that fall in the cell `sample` names, spread over
    /// it (the first and second halves of a cell alike).
    #[test]
    fn one_dimension_samples_cells_in_proportion() {
        let d = Piecewise1D::new(&[1.0, 0.0, 3.0]);
        assert!((d.integral() - 4.0 / 3.0).abs() < 1e-6);
        assert!((d.pdf(2) - 3.0 / (4.0 / 3.0)).abs() < 1e-6);
        assert_eq!(d.pdf(1), 0.0);
        let mut rng = irradia_core::Rng::new(1, 2);
        let mut halves = [[0u32; 2]; 3];
        for _ in 0..40_000 {
            let (x, i) = d.sample(rng.next_f32());
            assert_eq!((x * 3.0) as usize, i, "{x} outside cell {i}");
            halves[i][((x * 3.0).fract() * 2.0) as usize] += 1;
        }
        assert_eq!(halves[1], [0, 0], "the empty cell was drawn");
        for (i, share) in [(0, 0.25), (2, 0.75)] {
            let [a, b] = halves[i];
            let f = (a + b) as f64 / 40_000.0;
            assert!((f - share).abs() < 0.01, "cell {i}: {f}");
            assert!(
                (a as f64 / b as f64 - 1.0).abs() < 0.06,
                "cell {i}: halves {a} {b}"
            );
        }
    }

    /// The table of cell densities holds exactly the product of the marginal and the
    /// conditional densities (empty rows and cells included), and `sample`'s cells are
    /// drawn in proportion to the cell values (chi-square).
    #[test]
    fn two_dimensions_pdf_table_and_sampling() {
        let (w, h) = (4, 3);
        let func = [
            1.0, 2.0, 0.0, 3.0, //
            0.0, 0.0, 0.0, 0.0, //
            5.0, 0.5, 4.0, 0.25,
        ];
        let d = Piecewise2D::new(&func, w, h);
        for j in 0..h {
            for i in 0..w {
                let want = d.marginal.pdf(j) * d.rows[j].pdf(i);
                assert_eq!(d.pdf(i, j).to_bits(), want.to_bits(), "({i}, {j})");
            }
        }
        let total: f32 = func.iter().sum();
        let n = 200_000;
        let mut counts = vec![0u32; w * h];
        let mut rng = irradia_core::Rng::for_pixel(7, 8, 9, 10);
        for _ in 0..n {
            let (p, (i, j)) = d.sample(rng.next_2d());
            assert_eq!(
                (i, j),
                ((p.x * w as f32) as usize, (p.y * h as f32) as usize)
            );
            // The density of the point is the cell's share times the cell count.
            let share = func[j * w + i] / total;
            assert!((d.pdf(i, j) - share * (w * h) as f32).abs() < 1e-4);
            counts[j * w + i] += 1;
        }
        let mut chi2 = 0.0;
        for (c, &f) in counts.iter().zip(&func) {
            let expected = n as f64 * (f / total) as f64;
            if expected == 0.0 {
                assert_eq!(*c, 0, "an empty cell was sampled");
            } else {
                chi2 += (*c as f64 - expected).powi(2) / expected;
            }
        }
        // Eight non-empty cells: 7 degrees of freedom; 24.3 is the 0.999 quantile.
        assert!(chi2 < 24.3, "chi-square {chi2}: {counts:?}");
    }
}
