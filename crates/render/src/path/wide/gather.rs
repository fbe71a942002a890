//! Reading records of the wide kernel's tables (triangles, materials, facets, light
//! choice) in the W lanes at once: one field of the rows the lanes index, by an AVX2
//! gather where the kernel is compiled for it ([`gather`]), after one bounds check of
//! every index.

use irradia_geometry::packet::lanes::{gather, Fw, V3, W};

/// `table[idx[i]]` in every lane (indices checked).
#[inline(always)]
pub(super) fn lookup(table: &[u32], idx: &[u32; W]) -> [u32; W] {
    std::array::from_fn(|i| table[idx[i] as usize])
}

/// One record field of `table` in every lane, rows `idx` (checked by [`checked`]).
#[inline(always)]
pub(super) fn field<const N: usize>(table: &[[f32; N]], idx: &[u32; W], at: usize) -> Fw {
    assert!(at < N);
    // SAFETY: `checked` verified every index against this table before.
    unsafe { gather(table, idx, at) }
}

#[inline(always)]
pub(super) fn field3<const N: usize>(table: &[[f32; N]], idx: &[u32; W], at: usize) -> V3 {
    V3::new(
        field(table, idx, at),
        field(table, idx, at + 1),
        field(table, idx, at + 2),
    )
}

/// Panics unless every index addresses a row of `table` (so gathers stay in bounds).
#[inline(always)]
pub(super) fn checked<const N: usize>(table: &[[f32; N]], idx: &[u32; W]) {
    let top = idx.iter().fold(0, |a, &i| a.max(i));
    assert!((top as usize) < table.len());
}
