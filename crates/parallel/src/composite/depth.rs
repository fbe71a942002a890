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
            return blend_lanes(lc, ld, colors, depths, incoming_front);
        }
    }
    blend_lanes(lc, ld, colors, depths, incoming_front)
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

#[inline(always)]
fn select<T: Copy>(
    lc: &mut [T],
    ld: &mut [f32],
    colors: &[T],
    depths: &[f32],
    wins: impl Fn(f32, f32) -> bool,
) {
    for (((c, d), &ic), &id) in lc.iter_mut().zip(ld.iter_mut()).zip(colors).zip(depths) {
        let w = wins(id, *d);
        *d = if w { id } else { *d };
        *c = if w { ic } else { *c };
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
}
