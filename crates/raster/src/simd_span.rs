//! Eight pixels at a time: the interpolated-colour (Gouraud / unlit) RGBA8 path of the
//! rasterizer with AVX2, bit for bit equal to the scalar path of `fragment::draw`.
//!
//! The coverage test is the same fixed-point half-space test (Pineda 1988, "A Parallel
//! Algorithm for Polygon Rasterization"): the three edge functions of a row of eight
//! pixel centres are held in the eight i32 lanes of a register and stepped by eight
//! pixels with one add per edge (the incremental form of Giesen's "Optimizing the
//! basic rasterizer", 2013), and a pixel is covered when the OR of its three values
//! has a clear sign bit (all >= 0; the top-left bias is already folded into the
//! constants, as in [`Setup`]). Evaluating whole blocks of pixels with masks instead
//! of walking spans pixel by pixel is the scheme of Abrash, "Rasterization on
//! Larrabee" (Dr. Dobb's, 2009): no branch per pixel, so the unpredictable
//! enter/leave branches of small triangles disappear. Depth (a plane in f64, as in
//! [`Setup::depth_in_row`]) is tested on the eight lanes at once, and the covered,
//! passing lanes are written (blended into an unmasked store of the eight pixels, or
//! with masked stores at the end of the band); when any lane passes, the
//! perspective-correct colour is computed for all eight from the edge values
//! themselves, which are the unnormalised barycentric weights (Olano and Greer,
//! "Triangle Scan Conversion using
//! 2D Homogeneous Coordinates", 1997; Heckbert and Moreton 1991; see `interpolate`).
//!
//! Triangles that cannot pass the depth test anywhere are skipped before scanning
//! (`depth_bounds`).
//!
//! Exactness: every float operation is the scalar one, in the same order, lane by
//! lane (IEEE add, mul, div and conversions round identically in SSE/AVX lanes; no
//! FMA is used), and the edge values are converted from i32 instead of i64, which is
//! the same rounding as long as they fit: [`draw_interpolated_rgba8`] checks, per
//! triangle, that the edge values on the corners of the block of pixels it scans
//! (linear functions take their extremes there) and the eight-pixel step fit in i32,
//! and hands the rare triangle that does not (huge, guard-band ones) to the scalar
//! path. The test module compares both paths on random triangles, including vertices
//! on pixel centres and shared edges.

use crate::depth_bounds::DepthBounds;
use crate::fragment::{draw, DepthFunc, InterpolatedColor};
use crate::rasterizer::{Setup, HALF, ONE};
use crate::screen::{varying, Rect, ScreenTriangle};

/// Triangles scanning fewer blocks of eight pixels than this skip the depth-bound test.
const MIN_BLOCKS_TESTED: i64 = 3;

/// Whether this CPU runs [`draw_interpolated_rgba8`] (AVX2, detected at run time).
#[inline]
pub(crate) fn available() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        std::is_x86_feature_detected!("avx2")
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        false
    }
}

/// Draws `tri` with interpolated vertex colour into a band of an RGBA8 framebuffer
/// (rows from `band_y0`, whole rows of `width` pixels), inside `clip`: the same pixels,
/// depths and colours as `fragment::draw` with `InterpolatedColor`.
///
/// # Safety
/// The CPU must have AVX2 ([`available`]).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
#[allow(clippy::too_many_arguments)]
pub(crate) unsafe fn draw_interpolated_rgba8(
    tri: &ScreenTriangle,
    clip: &Rect,
    width: usize,
    band_y0: u32,
    depth_buf: &mut [f32],
    color: &mut [[u8; 4]],
    func: DepthFunc,
    bounds: &mut DepthBounds,
) {
    use std::arch::x86_64::*;

    let Some(s) = Setup::new(tri) else { return };
    let x0 = s.x0.max(clip.x0 as i64);
    let x1 = s.x1.min(clip.x1 as i64 - 1);
    let y0 = s.y0.max(clip.y0 as i64);
    let y1 = s.y1.min(clip.y1 as i64 - 1);
    if x0 > x1 || y0 > y1 {
        return;
    }
    let chunks = (x1 - x0) / 8 + 1;
    // The depth-bound test costs about as much as scanning a few blocks of eight
    // pixels: smaller triangles are not tested.
    let blocks = (y1 - y0 + 1) * chunks;
    if blocks >= MIN_BLOCKS_TESTED && bounds.hidden(depth_buf, &s, func, x0, x1, y0, y1, blocks) {
        return;
    }
    bounds.count_drawn(depth_buf);
    // The slices must hold rows y0..=y1 of the band (as the scalar path indexes them).
    let last = (y1 as usize - band_y0 as usize) * width + x1 as usize;
    assert!(last < depth_buf.len() && last < color.len());
    let x_end = x0 + chunks * 8 - 1; // the last lane's pixel
    let (px0, py0) = (x0 * ONE + HALF, y0 * ONE + HALF);
    let mut row: [i64; 3] = std::array::from_fn(|k| s.a[k] * px0 + s.b[k] * py0 + s.c[k]);
    let fits = (0..3).all(|k| {
        // The edge is linear: its extremes over the scanned block are at its corners.
        let across = s.a[k] * ONE * (x_end - x0);
        let down = s.b[k] * ONE * (y1 - y0);
        let lo = row[k] + across.min(0) + down.min(0);
        let hi = row[k] + across.max(0) + down.max(0);
        // `hi + 1`: the weight adds the fill-rule bias (0 or 1) before converting.
        lo > i32::MIN as i64 && hi < i32::MAX as i64 && (s.a[k] * ONE * 8).abs() < i32::MAX as i64
    });
    if !fits {
        draw(
            tri,
            clip,
            width,
            band_y0,
            depth_buf,
            color,
            &InterpolatedColor,
            func,
        );
        return;
    }

    let lane = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
    let step_x1: [__m256i; 3] = std::array::from_fn(|k| _mm256_set1_epi32((s.a[k] * ONE) as i32));
    let offsets: [__m256i; 3] = std::array::from_fn(|k| _mm256_mullo_epi32(step_x1[k], lane));
    let step_x8: [__m256i; 3] =
        std::array::from_fn(|k| _mm256_set1_epi32((s.a[k] * ONE * 8) as i32));
    let bias: [__m256i; 3] = std::array::from_fn(|k| _mm256_set1_epi32(s.bias[k] as i32));
    let inv_area = _mm256_set1_ps(s.inv_area);
    let inv_w: [__m256; 3] = std::array::from_fn(|k| _mm256_set1_ps(s.v[k].inv_w));
    // By channel, then vertex.
    let rgba: [[__m256; 3]; 4] = std::array::from_fn(|ch| {
        std::array::from_fn(|k| _mm256_set1_ps(s.v[k].var[varying::COLOR + ch]))
    });
    let zx = _mm256_set1_pd(s.zx);
    let (zero, one) = (_mm256_setzero_ps(), _mm256_set1_ps(1.0));
    let (scale, half) = (_mm256_set1_ps(255.0), _mm256_set1_ps(0.5));
    let all = _mm256_set1_epi32(-1);

    let step_y: [i64; 3] = std::array::from_fn(|k| s.b[k] * ONE);
    let len = depth_buf.len().min(color.len());
    let depth_ptr = depth_buf.as_mut_ptr();
    let color_ptr = color.as_mut_ptr() as *mut i32;
    for y in y0..=y1 {
        let row_z = _mm256_set1_pd(s.depth_row(y as u32));
        let row_i = (y as usize - band_y0 as usize) * width;
        let mut e: [__m256i; 3] =
            std::array::from_fn(|k| _mm256_add_epi32(_mm256_set1_epi32(row[k] as i32), offsets[k]));
        let mut x = x0;
        while x <= x1 {
            let in_row = _mm256_cmpgt_epi32(_mm256_set1_epi32((x1 - x + 1) as i32), lane);
            let any_negative = _mm256_or_si256(_mm256_or_si256(e[0], e[1]), e[2]);
            let covered = _mm256_andnot_si256(_mm256_srai_epi32::<31>(any_negative), in_row);
            if _mm256_testz_si256(covered, covered) == 0 {
                // Depth: the f64 plane at each lane's pixel, rounded to f32.
                let xs = _mm256_add_epi32(_mm256_set1_epi32(x as i32), lane);
                let z_lo = _mm256_cvtpd_ps(_mm256_add_pd(
                    row_z,
                    _mm256_mul_pd(zx, _mm256_cvtepi32_pd(_mm256_castsi256_si128(xs))),
                ));
                let z_hi = _mm256_cvtpd_ps(_mm256_add_pd(
                    row_z,
                    _mm256_mul_pd(zx, _mm256_cvtepi32_pd(_mm256_extracti128_si256::<1>(xs))),
                ));
                let z = _mm256_set_m128(z_hi, z_lo);
                // SAFETY: covered lanes are pixels x..=x1 of row y, inside the slices
                // (checked above); masked-off lanes are neither read nor written, except
                // when all eight pixels lie inside both slices (`whole`), which this
                // call borrows mutably.
                let dp = depth_ptr.add(row_i + x as usize);
                // Eight whole pixels of the band's own rows: read and written back
                // unmasked (blended), cheaper than masked moves (slow stores on AMD
                // Zen); lanes not written keep the value read. At a row's right end
                // the masked moves stay inside the slices.
                let whole = row_i + x as usize + 8 <= len;
                let stored = if whole {
                    _mm256_loadu_ps(dp)
                } else {
                    _mm256_maskload_ps(dp, covered)
                };
                let pass = match func {
                    DepthFunc::Less => _mm256_castps_si256(_mm256_cmp_ps::<_CMP_LT_OQ>(z, stored)),
                    DepthFunc::LessEqual => {
                        _mm256_castps_si256(_mm256_cmp_ps::<_CMP_LE_OQ>(z, stored))
                    }
                    DepthFunc::Always => all,
                };
                let write = _mm256_and_si256(covered, pass);
                if _mm256_testz_si256(write, write) == 0 {
                    if whole {
                        _mm256_storeu_ps(
                            dp,
                            _mm256_blendv_ps(stored, z, _mm256_castsi256_ps(write)),
                        );
                    } else {
                        _mm256_maskstore_ps(dp, write, z);
                    }
                    // Screen-space weights, then perspective-correct ones (interpolate.rs).
                    let p: [__m256; 3] = std::array::from_fn(|k| {
                        let l = _mm256_mul_ps(
                            _mm256_cvtepi32_ps(_mm256_add_epi32(e[k], bias[k])),
                            inv_area,
                        );
                        _mm256_mul_ps(l, inv_w[k])
                    });
                    let inv_sum =
                        _mm256_div_ps(one, _mm256_add_ps(_mm256_add_ps(p[0], p[1]), p[2]));
                    let w: [__m256; 3] = std::array::from_fn(|k| _mm256_mul_ps(p[k], inv_sum));
                    let mut packed = _mm256_setzero_si256();
                    for (ch, by_vertex) in rgba.iter().enumerate() {
                        let c = _mm256_add_ps(
                            _mm256_add_ps(
                                _mm256_mul_ps(w[0], by_vertex[0]),
                                _mm256_mul_ps(w[1], by_vertex[1]),
                            ),
                            _mm256_mul_ps(w[2], by_vertex[2]),
                        );
                        // to_rgba8: clamp (NaN gives 0, as `NaN as u8` does), scale, round.
                        let c = _mm256_min_ps(_mm256_max_ps(c, zero), one);
                        let q = _mm256_cvttps_epi32(_mm256_add_ps(_mm256_mul_ps(c, scale), half));
                        packed = _mm256_or_si256(
                            packed,
                            _mm256_sllv_epi32(q, _mm256_set1_epi32(8 * ch as i32)),
                        );
                    }
                    let cp = color_ptr.add(row_i + x as usize);
                    if whole {
                        let old = _mm256_loadu_si256(cp as *const __m256i);
                        let new = _mm256_blendv_epi8(old, packed, write);
                        _mm256_storeu_si256(cp as *mut __m256i, new);
                    } else {
                        _mm256_maskstore_epi32(cp, write, packed);
                    }
                }
            }
            for k in 0..3 {
                e[k] = _mm256_add_epi32(e[k], step_x8[k]);
            }
            x += 8;
        }
        for k in 0..3 {
            row[k] += step_y[k];
        }
    }
}

#[cfg(all(test, target_arch = "x86_64"))]
mod tests {
    use super::*;
    use crate::screen::ScreenVertex;

    /// A small deterministic generator (SplitMix64).
    struct Rng(u64);
    impl Rng {
        fn next(&mut self) -> u64 {
            self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
            let mut z = self.0;
            z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
            z ^ (z >> 31)
        }
        fn f(&mut self) -> f32 {
            (self.next() >> 40) as f32 / (1u64 << 24) as f32
        }
    }

    fn vertex(r: &mut Rng, x: f32, y: f32) -> ScreenVertex {
        let mut v = ScreenVertex {
            x,
            y,
            z: r.f(),
            inv_w: 0.05 + r.f() * 2.0,
            ..Default::default()
        };
        for c in &mut v.var[..4] {
            *c = r.f() * 1.4 - 0.2; // some outside [0, 1], to exercise the clamp
        }
        v
    }

    /// Random triangles: small and large, vertices on pixel centres and on the
    /// sub-pixel grid, pairs sharing an edge, a few far outside the screen.
    fn triangles(r: &mut Rng, n: usize, w: f32, h: f32) -> Vec<ScreenTriangle> {
        let mut out = Vec::new();
        while out.len() < n {
            let size = [1.5, 3.0, 9.0, 40.0, 200.0][(r.next() % 5) as usize];
            let (cx, cy) = (r.f() * w, r.f() * h);
            let mut p = [0; 4].map(|_| (cx + (r.f() - 0.5) * size, cy + (r.f() - 0.5) * size));
            match r.next() % 4 {
                0 => p = p.map(|(x, y)| (x.floor() + 0.5, y.floor() + 0.5)), // pixel centres
                1 => p = p.map(|(x, y)| ((x * 256.0).round() / 256.0, (y * 256.0).round() / 256.0)),
                2 if r.next().is_multiple_of(8) => p[0] = (cx * 3000.0 - 1e5, cy * 2000.0), // guard band
                _ => {}
            }
            let v = p.map(|(x, y)| vertex(r, x, y));
            out.push(ScreenTriangle {
                v: [v[0], v[1], v[2]],
                id: out.len() as u32,
                ..Default::default()
            });
            // The other half of the quad: shares the edge v[1]-v[2].
            out.push(ScreenTriangle {
                v: [v[3], v[2], v[1]],
                id: out.len() as u32,
                ..Default::default()
            });
        }
        out
    }

    #[allow(clippy::too_many_arguments)]
    fn render(
        tris: &[ScreenTriangle],
        clip: Rect,
        band_y0: u32,
        rows: u32,
        w: u32,
        func: DepthFunc,
        simd: bool,
        always_test: bool,
    ) -> (Vec<u32>, Vec<[u8; 4]>) {
        let n = (w * rows) as usize;
        let mut depth = vec![1.0f32; n];
        let mut color = vec![[7u8, 7, 7, 7]; n];
        let mut bounds = DepthBounds::new(&depth, w as usize, band_y0);
        if always_test {
            bounds = bounds.always_on();
        }
        for t in tris {
            if simd {
                unsafe {
                    draw_interpolated_rgba8(
                        t,
                        &clip,
                        w as usize,
                        band_y0,
                        &mut depth,
                        &mut color,
                        func,
                        &mut bounds,
                    )
                };
            } else {
                draw(
                    t,
                    &clip,
                    w as usize,
                    band_y0,
                    &mut depth,
                    &mut color[..],
                    &InterpolatedColor,
                    func,
                );
            }
        }
        (depth.iter().map(|d| d.to_bits()).collect(), color)
    }

    #[test]
    fn simd_path_equals_scalar_path_bit_for_bit() {
        if !available() {
            eprintln!("no AVX2: nothing to compare");
            return;
        }
        let (w, h) = (97, 61);
        let mut r = Rng(7);
        let tris = triangles(&mut r, 20000, w as f32, h as f32);
        let cases = [
            (Rect::full(w, h), 0, h),
            (Rect::new(0, 32, w, h), 32, h - 32), // a band lower down
            (Rect::new(13, 5, 50, 40), 0, h),     // a region inside the screen
            (Rect::new(90, 0, 97, 61), 0, h),     // narrower than eight pixels
        ];
        for func in [DepthFunc::Less, DepthFunc::LessEqual, DepthFunc::Always] {
            for &(clip, band_y0, rows) in &cases {
                let scalar = render(&tris, clip, band_y0, rows, w, func, false, false);
                let written = scalar.1.iter().filter(|c| **c != [7, 7, 7, 7]).count();
                assert!(
                    written > rows as usize * 5,
                    "too few pixels drawn to compare: {written}"
                );
                // As drawn (adaptive depth-bound tests), and with every triangle of
                // three or more blocks tested against the depth bounds.
                for always_test in [false, true] {
                    let simd = render(&tris, clip, band_y0, rows, w, func, true, always_test);
                    assert_eq!(
                        scalar.0, simd.0,
                        "depth differs ({func:?}, {clip:?}, {always_test})"
                    );
                    assert_eq!(
                        scalar.1, simd.1,
                        "colour differs ({func:?}, {clip:?}, {always_test})"
                    );
                }
            }
        }
    }

    #[test]
    fn shared_edges_through_pixel_centres_are_drawn_once() {
        if !available() {
            return;
        }
        // A fan of triangles around a pixel centre, edges through pixel centres, with
        // depth test Always: a pixel drawn twice would show up in the count.
        let (w, h) = (40u32, 40u32);
        let mut r = Rng(3);
        let c = (20.5, 20.5);
        let ring = [
            (5.5, 5.5),
            (20.5, 2.5),
            (35.5, 5.5),
            (37.5, 20.5),
            (35.5, 35.5),
            (20.5, 37.5),
            (5.5, 35.5),
            (2.5, 20.5),
        ];
        let mut count = vec![0u32; (w * h) as usize];
        for i in 0..ring.len() {
            let (a, b) = (ring[i], ring[(i + 1) % ring.len()]);
            let t = ScreenTriangle {
                v: [
                    vertex(&mut r, c.0, c.1),
                    vertex(&mut r, a.0, a.1),
                    vertex(&mut r, b.0, b.1),
                ],
                ..Default::default()
            };
            let mut depth = vec![1.0; (w * h) as usize];
            let mut color = vec![[0u8; 4]; (w * h) as usize];
            let mut bounds = DepthBounds::new(&depth, w as usize, 0);
            unsafe {
                draw_interpolated_rgba8(
                    &t,
                    &Rect::full(w, h),
                    w as usize,
                    0,
                    &mut depth,
                    &mut color,
                    DepthFunc::Always,
                    &mut bounds,
                )
            };
            for (n, d) in count.iter_mut().zip(&depth) {
                *n += (*d != 1.0) as u32;
            }
        }
        // Every pixel centre strictly inside the octagon's convex hull is covered once.
        assert_eq!(count.iter().copied().max(), Some(1));
        assert_eq!(count[(20 * w + 20) as usize], 1);
        assert!(count.iter().filter(|&&n| n == 1).count() > 900);
    }
}
