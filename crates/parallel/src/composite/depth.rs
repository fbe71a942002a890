//! Depth compositing of opaque layers (the z-buffer test across ranks; Molnar et al. 1994,
//! "A sorting classification of parallel rendering", sort-last): the nearer fragment
//! wins. Ties go to the layer in front in compositing order, matching a serial z-buffer
//! with a strict `<` test that draws the objects in rank order, so the composite is
//! bit-for-bit the serial image.

/// Blends incoming `(colors, depths)` into the local run `(lc, ld)`.
///
/// Branch-free: every pixel is written with a select, so the loop vectorises (a depth
/// compare, then a blend of depth and colour lanes by the mask) and its time does not
/// depend on how often the incoming fragment wins. 4-byte pixels (RGBA8) are blended as
/// `u32` lanes.
#[inline]
pub fn blend<P: bytemuck::Pod>(
    lc: &mut [P],
    ld: &mut [f32],
    colors: &[P],
    depths: &[f32],
    incoming_front: bool,
) {
    if std::mem::size_of::<P>() == 4 && std::mem::align_of::<P>() <= 4 {
        if let (Ok(lc), Ok(colors)) = (
            bytemuck::try_cast_slice_mut::<P, u32>(lc),
            bytemuck::try_cast_slice::<P, u32>(colors),
        ) {
            return blend_u32(lc, ld, colors, depths, incoming_front);
        }
    }
    blend_lanes(lc, ld, colors, depths, incoming_front)
}

/// The RGBA8 kernel: the compare becomes an all-ones or all-zero mask that picks depth
/// and colour bits with and/or, a form that compiles to vector compares and logic ops
/// (a plain `if` is easily turned back into a branch per pixel). Kept out of line so
/// that it is vectorised once, whatever it is inlined into.
#[inline(never)]
fn blend_u32(lc: &mut [u32], ld: &mut [f32], colors: &[u32], depths: &[f32], front: bool) {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: the CPU supports AVX2 (checked just above).
        return unsafe { blend_u32_avx2(lc, ld, colors, depths, front) };
    }
    blend_u32_portable(lc, ld, colors, depths, front)
}

/// The same kernel compiled for AVX2: eight pixels per instruction instead of four, and
/// masked stores that write only the pixels the incoming layer wins. (Compiled for
/// AVX-512F the same loop becomes gathers and scatters and runs slower.)
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn blend_u32_avx2(
    lc: &mut [u32],
    ld: &mut [f32],
    colors: &[u32],
    depths: &[f32],
    front: bool,
) {
    blend_u32_portable(lc, ld, colors, depths, front)
}

#[inline(always)]
fn blend_u32_portable(lc: &mut [u32], ld: &mut [f32], colors: &[u32], depths: &[f32], front: bool) {
    let n = lc.len();
    let (ld, colors, depths) = (&mut ld[..n], &colors[..n], &depths[..n]);
    if front {
        masked(lc, ld, colors, depths, |incoming, local| incoming <= local)
    } else {
        masked(lc, ld, colors, depths, |incoming, local| incoming < local)
    }
}

#[inline(always)]
fn masked(
    lc: &mut [u32],
    ld: &mut [f32],
    colors: &[u32],
    depths: &[f32],
    wins: impl Fn(f32, f32) -> bool + Copy,
) {
    let pick = |c: &mut u32, d: &mut f32, ic: u32, id: f32| {
        let m = (wins(id, *d) as u32).wrapping_neg();
        *d = f32::from_bits((id.to_bits() & m) | (d.to_bits() & !m));
        *c = (ic & m) | (*c & !m);
    };
    let n = lc.len();
    let whole = n - n % LANES;
    let blocks = lc[..whole]
        .chunks_exact_mut(LANES)
        .zip(ld[..whole].chunks_exact_mut(LANES))
        .zip(colors[..whole].chunks_exact(LANES))
        .zip(depths[..whole].chunks_exact(LANES));
    for (((c, d), ic), id) in blocks {
        for k in 0..LANES {
            pick(&mut c[k], &mut d[k], ic[k], id[k]);
        }
    }
    for k in whole..n {
        pick(&mut lc[k], &mut ld[k], colors[k], depths[k]);
    }
}

#[inline]
fn blend_lanes<T: Copy>(
    lc: &mut [T],
    ld: &mut [f32],
    colors: &[T],
    depths: &[f32],
    incoming_front: bool,
) {
    let n = lc.len();
    let (ld, colors, depths) = (&mut ld[..n], &colors[..n], &depths[..n]);
    if incoming_front {
        select(lc, ld, colors, depths, |incoming, local| incoming <= local)
    } else {
        select(lc, ld, colors, depths, |incoming, local| incoming < local)
    }
}

/// Pixels per block of the select loop: a fixed trip count that the compiler unrolls and
/// turns into vector compares and blends.
const LANES: usize = 16;

#[inline(always)]
fn select<T: Copy>(
    lc: &mut [T],
    ld: &mut [f32],
    colors: &[T],
    depths: &[f32],
    wins: impl Fn(f32, f32) -> bool + Copy,
) {
    let n = lc.len();
    let whole = n - n % LANES;
    let blocks = lc[..whole]
        .chunks_exact_mut(LANES)
        .zip(ld[..whole].chunks_exact_mut(LANES))
        .zip(colors[..whole].chunks_exact(LANES))
        .zip(depths[..whole].chunks_exact(LANES));
    for (((c, d), ic), id) in blocks {
        let (c, d): (&mut [T; LANES], &mut [f32; LANES]) =
            (c.try_into().unwrap(), d.try_into().unwrap());
        let (ic, id): (&[T; LANES], &[f32; LANES]) =
            (ic.try_into().unwrap(), id.try_into().unwrap());
        for k in 0..LANES {
            let w = wins(id[k], d[k]);
            d[k] = if w { id[k] } else { d[k] };
            c[k] = if w { ic[k] } else { c[k] };
        }
    }
    for k in whole..n {
        let w = wins(depths[k], ld[k]);
        ld[k] = if w { depths[k] } else { ld[k] };
        lc[k] = if w { colors[k] } else { lc[k] };
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::composite::FAR;

    #[test]
    fn ties_go_to_the_front_layer() {
        let mut lc = [1u32, 1, 1];
        let mut ld = [1.0f32, 2.0, 3.0];
        blend(&mut lc, &mut ld, &[2, 2, 2], &[1.0, 1.0, 4.0], false);
        assert_eq!(lc, [1, 2, 1]);
        let mut lc = [1u32, 1, 1];
        let mut ld = [1.0f32, 2.0, 3.0];
        blend(&mut lc, &mut ld, &[2, 2, 2], &[1.0, 1.0, 4.0], true);
        assert_eq!(lc, [2, 2, 1]);
        assert_eq!(ld, [1.0, 1.0, 3.0]);
    }

    #[test]
    fn vector_kernels_match_the_scalar_z_test() {
        // Quantised depths (many ties), infinities and both tie rules, on lengths that
        // leave remainders after the 16-pixel blocks; RGBA8 (u32 lanes) and RGBA32F.
        let n = 1000;
        let h = |i: usize| ((i as u64).wrapping_mul(0x9e37_79b9_7f4a_7c15) >> 59) as f32;
        let depth = |i: usize| {
            if i.is_multiple_of(11) {
                FAR
            } else {
                h(i) * 0.5
            }
        };
        for len in [0, 1, 15, 16, 17, 999] {
            for front in [false, true] {
                let ld0: Vec<f32> = (0..n).map(depth).collect();
                let id: Vec<f32> = (0..n).map(|i| depth(i * 7 + 3)).collect();
                let lc0: Vec<[u8; 4]> = (0..n).map(|i| [i as u8, 1, 2, 3]).collect();
                let ic: Vec<[u8; 4]> = (0..n).map(|i| [i as u8, 9, 9, 9]).collect();
                let (mut lc, mut ld) = (lc0.clone(), ld0.clone());
                blend(&mut lc[..len], &mut ld[..len], &ic, &id, front);
                let (mut lf, mut lfd) = (
                    lc0.iter().map(|c| c.map(|v| v as f32)).collect::<Vec<_>>(),
                    ld0.clone(),
                );
                let icf: Vec<[f32; 4]> = ic.iter().map(|c| c.map(|v| v as f32)).collect();
                blend(&mut lf[..len], &mut lfd[..len], &icf, &id, front);
                for i in 0..n {
                    let wins = i < len
                        && if front {
                            id[i] <= ld0[i]
                        } else {
                            id[i] < ld0[i]
                        };
                    let (c, d) = if wins {
                        (ic[i], id[i])
                    } else {
                        (lc0[i], ld0[i])
                    };
                    assert_eq!(
                        (lc[i], ld[i].to_bits()),
                        (c, d.to_bits()),
                        "rgba8 {len} {i}"
                    );
                    assert_eq!(
                        (lf[i], lfd[i].to_bits()),
                        (c.map(|v| v as f32), d.to_bits())
                    );
                }
            }
        }
    }
}
