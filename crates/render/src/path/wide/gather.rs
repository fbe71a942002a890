//! The wide kernel's tables (triangles, materials, facets, sphere lights, light
//! choice) and reading one field of the rows the W lanes index, after one bounds check
//! of every index: by a gather ([`gather`]: AVX2's or AVX-512's `vgatherdps` where
//! the kernel is compiled for it), or, for a table of at most W rows under the
//! AVX-512 build, by one lane permute of the field's column ([`permute_avx512`]),
//! which moves the same bits without a load per lane. Scenes of few materials and
//! emitters (the speed suite's) read every material and light field so.

use irradia_geometry::packet::lanes::{gather, Fw, V3, W};
use irradia_geometry::packet::SimdBuild;
use std::ops::Deref;

/// Records of `N` fields, read in lanes by [`field`]; dereferences to the rows.
pub(crate) struct Table<const N: usize> {
    rows: Vec<[f32; N]>,
    /// The table by field (`columns[at]` holds field `at` of every row, zeros past
    /// the last), when it has at most W rows and the kernel runs its AVX-512 build.
    columns: Option<Box<[Fw]>>,
}

impl<const N: usize> Table<N> {
    /// A table read by gathers until [`Self::set_build`] says otherwise.
    pub fn new(rows: Vec<[f32; N]>) -> Self {
        Self {
            rows,
            columns: None,
        }
    }

    /// Reads by lane permutes when `build` is AVX-512 and there are at most W rows,
    /// otherwise by gathers.
    pub fn set_build(&mut self, build: SimdBuild) {
        let permute =
            cfg!(target_arch = "x86_64") && build == SimdBuild::Avx512 && self.rows.len() <= W;
        self.columns = permute.then(|| {
            (0..N)
                .map(|at| {
                    Fw(std::array::from_fn(|r| {
                        self.rows.get(r).map_or(0.0, |row| row[at])
                    }))
                })
                .collect()
        });
    }
}

impl<const N: usize> Deref for Table<N> {
    type Target = [[f32; N]];
    fn deref(&self) -> &[[f32; N]] {
        &self.rows
    }
}

/// What [`field`] reads: a [`Table`], or a slice of rows (read by gathers).
pub(super) trait Fields<const N: usize> {
    fn rows(&self) -> &[[f32; N]];
    /// The rows by field, where they are read by lane permutes.
    fn columns(&self) -> Option<&[Fw]>;
}

impl<const N: usize> Fields<N> for Table<N> {
    #[inline(always)]
    fn rows(&self) -> &[[f32; N]] {
        &self.rows
    }
    #[inline(always)]
    fn columns(&self) -> Option<&[Fw]> {
        self.columns.as_deref()
    }
}

impl<const N: usize> Fields<N> for [[f32; N]] {
    #[inline(always)]
    fn rows(&self) -> &[[f32; N]] {
        self
    }
    #[inline(always)]
    fn columns(&self) -> Option<&[Fw]> {
        None
    }
}

/// `table[idx[i]]` in every lane (indices checked).
#[inline(always)]
pub(super) fn lookup(table: &[u32], idx: &[u32; W]) -> [u32; W] {
    std::array::from_fn(|i| table[idx[i] as usize])
}

/// One record field of `table` in every lane, rows `idx` (checked by [`checked`]).
#[inline(always)]
pub(super) fn field<const N: usize, T: Fields<N> + ?Sized>(
    table: &T,
    idx: &[u32; W],
    at: usize,
) -> Fw {
    assert!(at < N);
    match table.columns() {
        // SAFETY: `columns` exist only under the AVX-512 build, which runs only on a
        // CPU that has AVX-512 (`SimdBuild::chosen`, `WideScene::with_build`); `at < N`
        // is the column's index.
        #[cfg(target_arch = "x86_64")]
        Some(columns) => unsafe {
            irradia_geometry::packet::lanes::permute_avx512(&columns[at], idx)
        },
        // SAFETY: `checked` verified every index against this table before.
        _ => unsafe { gather(table.rows(), idx, at) },
    }
}

#[inline(always)]
pub(super) fn field3<const N: usize, T: Fields<N> + ?Sized>(
    table: &T,
    idx: &[u32; W],
    at: usize,
) -> V3 {
    V3::new(
        field(table, idx, at),
        field(table, idx, at + 1),
        field(table, idx, at + 2),
    )
}

/// Panics unless every index addresses a row of `table` (so gathers stay in bounds,
/// and permutes read rows, not the zeros past them).
#[inline(always)]
pub(super) fn checked<const N: usize, T: Fields<N> + ?Sized>(table: &T, idx: &[u32; W]) {
    let top = idx.iter().fold(0, |a, &i| a.max(i));
    assert!((top as usize) < table.rows().len());
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Under every build the CPU runs, a small and a large table read the rows'
    /// fields bit for bit.
    #[test]
    fn fields_are_the_rows_fields_in_every_build() {
        let mut rng = irradia_core::Rng::new(2, 3);
        for rows in [1, 5, W, W + 1, 40] {
            let data: Vec<[f32; 4]> = (0..rows)
                .map(|_| std::array::from_fn(|_| rng.next_f32() - 0.5))
                .collect();
            for build in SimdBuild::ALL.into_iter().filter(|b| b.available()) {
                let mut t = Table::new(data.clone());
                t.set_build(build);
                assert_eq!(t.columns.is_some(), build == SimdBuild::Avx512 && rows <= W);
                let idx: [u32; W] = std::array::from_fn(|i| ((i * 5 + rows) % rows) as u32);
                checked(&t, &idx);
                for at in 0..4 {
                    let got = field(&t, &idx, at);
                    for (lane, &i) in idx.iter().enumerate() {
                        assert_eq!(got.0[lane].to_bits(), data[i as usize][at].to_bits());
                    }
                }
            }
        }
    }
}
