//! Depth compositing of opaque layers (the z-buffer test across ranks; Molnar et al. 1994,
//! "A sorting classification of parallel rendering", sort-last): the nearer fragment
//! wins. Ties go to the layer in front in compositing order, matching a serial z-buffer
//! with a strict `<` test that draws the objects in rank order, so the composite is
//! bit-for-bit the serial image.

/// Blends incoming `(colors, depths)` into the local run `(lc, ld)`.
#[inline]
pub fn blend<P: Copy>(
    lc: &mut [P],
    ld: &mut [f32],
    colors: &[P],
    depths: &[f32],
    incoming_front: bool,
) {
    let n = lc.len();
    let (ld, colors, depths) = (&mut ld[..n], &colors[..n], &depths[..n]);
    if incoming_front {
        for i in 0..n {
            if depths[i] <= ld[i] {
                ld[i] = depths[i];
                lc[i] = colors[i];
            }
        }
    } else {
        for i in 0..n {
            if depths[i] < ld[i] {
                ld[i] = depths[i];
                lc[i] = colors[i];
            }
        }
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
