//! Triangle scan conversion with half-space edge functions (Pineda 1988) in fixed point
//! with [`SUBPIXEL_BITS`] bits below the pixel, and the top-left fill rule of Direct3D
//! and OpenGL: a pixel centre exactly on an edge belongs to the triangle only when that
//! edge is a top or a left edge. Two triangles sharing an edge therefore never both
//! draw, and never both miss, a pixel on it (no cracks, no double writes).
//!
//! Pixel (i, j) is covered when its centre (i + 1/2, j + 1/2) is inside. Coordinates are
//! snapped to the 1/256 pixel grid once; everything after that is exact integer
//! arithmetic (i64: the guard band keeps coordinates below 2^24 in fixed point, so
//! products stay below 2^50), so coverage never depends on evaluation order, tile size
//! or thread count. The edge functions step incrementally across a row (one add per
//! edge per pixel).

use crate::screen::{Rect, ScreenTriangle, ScreenVertex};

/// Bits of sub-pixel precision.
pub const SUBPIXEL_BITS: u32 = 8;
pub(crate) const ONE: i64 = 1 << SUBPIXEL_BITS;
pub(crate) const HALF: i64 = ONE / 2;

/// Which faces are discarded.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum CullMode {
    /// Draw both sides.
    #[default]
    None,
    /// Discard triangles wound clockwise on screen (OpenGL's default front face is
    /// counter-clockwise).
    Back,
    /// Discard counter-clockwise triangles.
    Front,
}

/// A screen coordinate on the fixed-point grid.
#[inline(always)]
pub fn snap(v: f32) -> i64 {
    // Round half away from zero without a libm call (x86-64 has no SSE4.1 `round`).
    let t = v * ONE as f32;
    (t + if t >= 0.0 { 0.5 } else { -0.5 }) as i64
}

/// The screen coordinate whose [`snap`] is `p`, for `p` made by [`snap`] from a
/// coordinate below 2^16 pixels in magnitude (the guard band's range): `p` is below
/// 2^24 so `p as f32` is exact, and the division by a power of two too; between 2^23
/// and 2^24 [`snap`] only makes even values, which its rounding (half to even at that
/// magnitude) returns unchanged.
#[inline(always)]
pub(crate) fn unsnap(p: i64) -> f32 {
    p as f32 * (1.0 / ONE as f32)
}

/// Twice the signed area in fixed point (y down, so counter-clockwise as seen on
/// screen — front-facing — is negative).
#[inline(always)]
fn area2(p: &[(i64, i64); 3]) -> i64 {
    (p[1].0 - p[0].0) * (p[2].1 - p[0].1) - (p[1].1 - p[0].1) * (p[2].0 - p[0].0)
}

/// Inclusive pixel range whose centres can be inside (may be empty).
#[inline(always)]
fn pixel_bounds(p: &[(i64, i64); 3]) -> (i64, i64, i64, i64) {
    let minx = p[0].0.min(p[1].0).min(p[2].0);
    let maxx = p[0].0.max(p[1].0).max(p[2].0);
    let miny = p[0].1.min(p[1].1).min(p[2].1);
    let maxy = p[0].1.max(p[1].1).max(p[2].1);
    (
        (minx - HALF + ONE - 1) >> SUBPIXEL_BITS,
        (maxx - HALF) >> SUBPIXEL_BITS,
        (miny - HALF + ONE - 1) >> SUBPIXEL_BITS,
        (maxy - HALF) >> SUBPIXEL_BITS,
    )
}

#[inline(always)]
fn snapped(t: &ScreenTriangle) -> [(i64, i64); 3] {
    // Written out: `[0, 1, 2].map(..)` was left as an out-of-line call (`try_map`) on
    // the bands' path, with bounds checks on `k`.
    let [a, b, c] = &t.v;
    [
        (snap(a.x), snap(a.y)),
        (snap(b.x), snap(b.y)),
        (snap(c.x), snap(c.y)),
    ]
}

/// True when the triangle survives culling, has non-zero snapped area and its bounding
/// box holds a pixel centre inside `screen`. The geometry stage drops the rest.
#[inline]
pub fn may_cover(t: &ScreenTriangle, cull: CullMode, screen: &Rect) -> bool {
    covered_bounds(t, cull, screen).is_some()
}

/// [`may_cover`], returning the inclusive pixel bounds `(x0, x1, y0, y1)` clipped to
/// `screen` when the triangle survives.
#[inline]
pub fn covered_bounds(
    t: &ScreenTriangle,
    cull: CullMode,
    screen: &Rect,
) -> Option<(i64, i64, i64, i64)> {
    covered_bounds_of(&t.v[0], &t.v[1], &t.v[2], cull, screen)
}

/// [`covered_bounds`] of the triangle with these vertices.
#[inline(always)]
pub fn covered_bounds_of(
    a: &ScreenVertex,
    b: &ScreenVertex,
    c: &ScreenVertex,
    cull: CullMode,
    screen: &Rect,
) -> Option<(i64, i64, i64, i64)> {
    let k = candidate_of(a, b, c, cull, screen)?;
    if k.centres() <= EXACT_CULL_CENTRES && !k.covers_a_centre() {
        // A bounding box of a few pixel centres (most sub-pixel triangles: about a
        // third of the gyroid's survivors of clipping cover none) that misses them all.
        return None;
    }
    Some(k.bounds)
}

/// A triangle that survived culling, snapped, with a non-empty pixel box on screen.
pub(crate) struct Candidate {
    /// The snapped vertices.
    pub p: [(i64, i64); 3],
    /// Twice the signed area (non-zero).
    pub area: i64,
    /// Inclusive pixel bounds `(x0, x1, y0, y1)` clipped to the screen.
    pub bounds: (i64, i64, i64, i64),
}

impl Candidate {
    /// The number of pixel centres in the box.
    #[inline(always)]
    pub fn centres(&self) -> i64 {
        let (x0, x1, y0, y1) = self.bounds;
        (x1 - x0 + 1) * (y1 - y0 + 1)
    }

    /// Whether a pixel centre of the box is covered.
    #[inline(always)]
    pub fn covers_a_centre(&self) -> bool {
        let (x0, x1, y0, y1) = self.bounds;
        covers_a_centre(&self.p, self.area, x0, x1, y0, y1)
    }
}

/// The first part of [`covered_bounds_of`]: culling by facing and area, and the pixel
/// box on `screen`, without testing the centres of small boxes.
#[inline(always)]
pub(crate) fn candidate_of(
    a: &ScreenVertex,
    b: &ScreenVertex,
    c: &ScreenVertex,
    cull: CullMode,
    screen: &Rect,
) -> Option<Candidate> {
    let p = [
        (snap(a.x), snap(a.y)),
        (snap(b.x), snap(b.y)),
        (snap(c.x), snap(c.y)),
    ];
    candidate_of_snapped(p, cull, screen)
}

/// [`candidate_of`] from vertex positions already on the fixed-point grid (the
/// geometry stage snaps each shared vertex once, not once per triangle around it).
#[inline(always)]
pub(crate) fn candidate_of_snapped(
    p: [(i64, i64); 3],
    cull: CullMode,
    screen: &Rect,
) -> Option<Candidate> {
    let area = area2(&p);
    let keep = match cull {
        CullMode::None => area != 0,
        CullMode::Back => area < 0,
        CullMode::Front => area > 0,
    };
    if !keep {
        return None;
    }
    let (x0, x1, y0, y1) = pixel_bounds(&p);
    let (x0, x1) = (x0.max(screen.x0 as i64), x1.min(screen.x1 as i64 - 1));
    let (y0, y1) = (y0.max(screen.y0 as i64), y1.min(screen.y1 as i64 - 1));
    if x0 > x1 || y0 > y1 {
        return None;
    }
    Some(Candidate {
        p,
        area,
        bounds: (x0, x1, y0, y1),
    })
}

/// Bounding boxes of at most this many pixel centres are tested centre by centre by
/// [`covered_bounds_of`]; larger ones are kept without a test.
pub const EXACT_CULL_CENTRES: i64 = 8;

/// Whether the snapped triangle `p` of twice-area `area` (non-zero) covers (with the
/// fill rule) the centre of a pixel of the inclusive box `x0..=x1` x `y0..=y1`: the
/// same edge functions and the same test as [`Setup::scan`].
#[inline]
fn covers_a_centre(p: &[(i64, i64); 3], area: i64, x0: i64, x1: i64, y0: i64, y1: i64) -> bool {
    let q = if area < 0 { [p[0], p[2], p[1]] } else { *p };
    let mut a = [0; 3];
    let mut b = [0; 3];
    let mut c = [0; 3];
    for k in 0..3 {
        let (ax, ay) = q[(k + 1) % 3];
        let (bx, by) = q[(k + 2) % 3];
        let (dx, dy) = (bx - ax, by - ay);
        let top_left = dy < 0 || (dy == 0 && dx > 0);
        a[k] = -dy;
        b[k] = dx;
        // E >= 0 on top-left edges, E >= 1 on the others (as in `Setup::new`).
        c[k] = dy * ax - dx * ay - !top_left as i64;
    }
    for y in y0..=y1 {
        let py = y * ONE + HALF;
        for x in x0..=x1 {
            let px = x * ONE + HALF;
            let e = |k: usize| a[k] * px + b[k] * py + c[k];
            if (e(0) | e(1) | e(2)) >= 0 {
                return true;
            }
        }
    }
    false
}

/// Inclusive pixel rows `(y0, y1)` that the triangle may cover.
#[inline]
pub fn row_range(t: &ScreenTriangle) -> (i64, i64, i64, i64) {
    pixel_bounds(&snapped(t))
}

/// A triangle ready for scanning: vertices ordered so that the area is positive and
/// the edge functions with the fill-rule bias folded into their constants.
pub struct Setup<'a> {
    /// The vertices in scan order; `lambda[k]` of a fragment weights `v[k]`.
    pub v: [&'a ScreenVertex; 3],
    /// E_k(X, Y) = a[k] X + b[k] Y + c[k] at fixed-point pixel centres; edge k is
    /// opposite vertex k. Covered when all three are >= 0.
    pub(crate) a: [i64; 3],
    pub(crate) b: [i64; 3],
    pub(crate) c: [i64; 3],
    /// The fill-rule bias subtracted from `c[k]` (0 or 1); added back wherever the edge
    /// values are used as weights, so the depth plane and the barycentrics are exact.
    pub(crate) bias: [i64; 3],
    /// Twice the area in fixed point (positive: the vertices are in scan order).
    pub(crate) area: i64,
    pub(crate) inv_area: f32,
    /// Depth plane z = zc + zx x + zy y at pixel centres (pixel units, f64 so the plane
    /// is exact enough for thin slivers).
    pub(crate) zc: f64,
    pub(crate) zx: f64,
    pub(crate) zy: f64,
    /// Whether `v` is the input order with the last two vertices swapped.
    pub swapped: bool,
    /// Inclusive pixel bounds.
    pub(crate) x0: i64,
    pub(crate) x1: i64,
    pub(crate) y0: i64,
    pub(crate) y1: i64,
}

impl<'a> Setup<'a> {
    /// `None` for triangles with zero snapped area.
    #[inline(always)]
    pub fn new(t: &'a ScreenTriangle) -> Option<Self> {
        let p = snapped(t);
        let area = area2(&p);
        if area == 0 {
            return None;
        }
        Some(Self::with_snapped([&t.v[0], &t.v[1], &t.v[2]], p, area))
    }

    /// [`Setup::new`] from the triangle's vertices `v`, their snapped positions `p` and
    /// twice-area `area` (non-zero), as [`candidate_of`] found them.
    #[inline(always)]
    pub(crate) fn with_snapped(v: [&'a ScreenVertex; 3], p: [(i64, i64); 3], area: i64) -> Self {
        Self::edges(v, p, area).with_plane()
    }

    /// The integer part of [`Setup::with_snapped`]: vertex order, edge functions, bias
    /// and bounds, enough for [`Setup::scan`]; the depth plane and `inv_area` are zero
    /// until [`Setup::with_plane`] computes them (the tiny-triangle path skips them
    /// for the triangles that cover no pixel centre).
    #[inline(always)]
    pub(crate) fn edges(
        mut v: [&'a ScreenVertex; 3],
        mut p: [(i64, i64); 3],
        mut area: i64,
    ) -> Self {
        let swapped = area < 0;
        if swapped {
            p.swap(1, 2);
            v.swap(1, 2);
            area = -area;
        }
        let mut a = [0; 3];
        let mut b = [0; 3];
        let mut c = [0; 3];
        let mut bias = [0; 3];
        for k in 0..3 {
            // Edge from p[k+1] to p[k+2], opposite vertex k:
            // E(P) = (bx-ax)(Py-ay) - (by-ay)(Px-ax), positive inside.
            let (ax, ay) = p[(k + 1) % 3];
            let (bx, by) = p[(k + 2) % 3];
            let (dx, dy) = (bx - ax, by - ay);
            a[k] = -dy;
            b[k] = dx;
            c[k] = dy * ax - dx * ay;
            // Top-left rule: interior to the right of the edge (a left edge: dy < 0) or
            // below a horizontal edge (a top edge, y down: dy == 0, dx > 0) owns centres
            // on the edge; other edges give them up (E >= 1 instead of E >= 0).
            let top_left = dy < 0 || (dy == 0 && dx > 0);
            if !top_left {
                bias[k] = 1;
                c[k] -= 1;
            }
        }
        let (x0, x1, y0, y1) = pixel_bounds(&p);
        Self {
            v,
            a,
            b,
            c,
            bias,
            swapped,
            area,
            inv_area: 0.0,
            zc: 0.0,
            zx: 0.0,
            zy: 0.0,
            x0,
            x1,
            y0,
            y1,
        }
    }

    /// Completes a set-up made by [`Setup::edges`]: `inv_area` and the depth plane.
    #[inline(always)]
    pub(crate) fn with_plane(mut self) -> Self {
        self.plane();
        self
    }

    /// [`Setup::with_plane`] in place (for a set-up that is scanned before it knows
    /// whether it needs the plane).
    #[inline(always)]
    pub(crate) fn plane(&mut self) {
        let (a, b, c, bias, v) = (self.a, self.b, self.c, self.bias, self.v);
        let inv = 1.0 / self.area as f64;
        let z = [v[0].z as f64, v[1].z as f64, v[2].z as f64];
        let mut zc = 0.0;
        let mut zx = 0.0;
        let mut zy = 0.0;
        for k in 0..3 {
            zx += (a[k] * ONE) as f64 * z[k];
            zy += (b[k] * ONE) as f64 * z[k];
            zc += (a[k] * HALF + b[k] * HALF + c[k] + bias[k]) as f64 * z[k];
        }
        self.inv_area = inv as f32;
        self.zc = zc * inv;
        self.zx = zx * inv;
        self.zy = zy * inv;
    }

    /// Screen-space barycentric weights of `self.v` from the edge values of a fragment.
    #[inline(always)]
    pub fn lambda(&self, e: &[i64; 3]) -> [f32; 3] {
        [
            (e[0] + self.bias[0]) as f32 * self.inv_area,
            (e[1] + self.bias[1]) as f32 * self.inv_area,
            (e[2] + self.bias[2]) as f32 * self.inv_area,
        ]
    }

    /// The interpolated NDC depth at the centre of pixel (x, y).
    #[inline(always)]
    pub fn depth(&self, x: u32, y: u32) -> f32 {
        self.depth_in_row(self.depth_row(y), x)
    }

    /// The part of the depth plane that depends on the row only.
    #[inline(always)]
    pub fn depth_row(&self, y: u32) -> f64 {
        self.zc + self.zy * y as f64
    }

    /// Depth at pixel (x, y) from `depth_row(y)`.
    #[inline(always)]
    pub fn depth_in_row(&self, row: f64, x: u32) -> f32 {
        (row + self.zx * x as f64) as f32
    }

    /// Calls `f(x, y, edges)` for every covered pixel inside `clip`, row by row;
    /// [`Setup::lambda`] turns `edges` into barycentric weights.
    #[inline(always)]
    pub fn scan(&self, clip: &Rect, mut f: impl FnMut(u32, u32, &[i64; 3])) {
        let x0 = self.x0.max(clip.x0 as i64);
        let x1 = self.x1.min(clip.x1 as i64 - 1);
        let y0 = self.y0.max(clip.y0 as i64);
        let y1 = self.y1.min(clip.y1 as i64 - 1);
        if x0 > x1 || y0 > y1 {
            return;
        }
        let px = x0 * ONE + HALF;
        let step_x = [self.a[0] * ONE, self.a[1] * ONE, self.a[2] * ONE];
        let step_y = [self.b[0] * ONE, self.b[1] * ONE, self.b[2] * ONE];
        let mut row: [i64; 3] =
            std::array::from_fn(|k| self.a[k] * px + self.b[k] * (y0 * ONE + HALF) + self.c[k]);
        let wide = x1 - x0 >= 16;
        for y in y0..=y1 {
            let mut e = row;
            let mut x = x0;
            if wide {
                // Skip the uncovered start of the row in one step per edge: for an
                // edge that is negative here and rising, the first x where it is >= 0.
                let mut start = x0;
                let mut empty = false;
                for k in 0..3 {
                    if e[k] < 0 {
                        if step_x[k] > 0 {
                            start = start.max(x0 + (-e[k] + step_x[k] - 1) / step_x[k]);
                        } else {
                            empty = true;
                        }
                    }
                }
                if empty || start > x1 {
                    x = x1 + 1;
                } else if start > x {
                    let n = start - x;
                    for k in 0..3 {
                        e[k] += step_x[k] * n;
                    }
                    x = start;
                }
            }
            // The covered pixels of a row are contiguous (the triangle is convex).
            let mut inside = false;
            while x <= x1 {
                if (e[0] | e[1] | e[2]) >= 0 {
                    inside = true;
                    f(x as u32, y as u32, &e);
                } else if inside {
                    break;
                }
                e[0] += step_x[0];
                e[1] += step_x[1];
                e[2] += step_x[2];
                x += 1;
            }
            for k in 0..3 {
                row[k] += step_y[k];
            }
        }
    }
}

/// Calls `f(x, y, lambda)` for every pixel of `clip` that `t` covers, with the
/// screen-space barycentric weights of `t.v` (in the triangle's own vertex order) (a convenience
/// for tests and custom fragment processing; the pipeline uses [`Setup`] directly).
pub fn for_each_fragment(t: &ScreenTriangle, clip: &Rect, mut f: impl FnMut(u32, u32, [f32; 3])) {
    if let Some(s) = Setup::new(t) {
        s.scan(clip, |x, y, e| {
            let l = s.lambda(e);
            f(x, y, if s.swapped { [l[0], l[2], l[1]] } else { l })
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `unsnap` puts a snapped coordinate back where `snap` finds it again, over the
    /// guard band's range and around 2^23 in fixed point, where `snap`'s rounding
    /// changes (half to even).
    #[test]
    fn unsnap_round_trips_snapped_coordinates() {
        let mut xs: Vec<f32> = (-40_000..40_000).map(|i| i as f32 * 0.37 + 0.001).collect();
        for k in -3000..3000 {
            let t = (1 << 23) as f32 + k as f32 * 0.5;
            xs.extend([t / ONE as f32, -t / ONE as f32]);
        }
        xs.extend([
            0.0,
            -0.0,
            0.5 / ONE as f32,
            -0.5 / ONE as f32,
            65_535.99,
            -65_535.99,
        ]);
        for x in xs {
            let p = snap(x);
            assert_eq!(snap(unsnap(p)), p, "x = {x}, p = {p}");
        }
    }
}
