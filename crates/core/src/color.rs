//! Linear RGB colour (radiance, reflectance, radiosity) and the sRGB transfer curve.

use serde::{Deserialize, Serialize};
use std::ops::{Add, AddAssign, Div, DivAssign, Index, Mul, MulAssign, Sub};

/// A colour in linear light. Components are not clamped: radiance may exceed 1.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Rgb {
    pub r: f32,
    pub g: f32,
    pub b: f32,
}

impl Rgb {
    pub const BLACK: Rgb = Rgb {
        r: 0.0,
        g: 0.0,
        b: 0.0,
    };
    pub const WHITE: Rgb = Rgb {
        r: 1.0,
        g: 1.0,
        b: 1.0,
    };

    #[inline]
    pub const fn new(r: f32, g: f32, b: f32) -> Self {
        Self { r, g, b }
    }

    #[inline]
    pub const fn splat(v: f32) -> Self {
        Self { r: v, g: v, b: v }
    }

    #[inline]
    pub fn from_array(a: [f32; 3]) -> Self {
        Self::new(a[0], a[1], a[2])
    }

    #[inline]
    pub fn to_array(self) -> [f32; 3] {
        [self.r, self.g, self.b]
    }

    #[inline]
    pub fn is_black(&self) -> bool {
        self.r == 0.0 && self.g == 0.0 && self.b == 0.0
    }

    #[inline]
    pub fn max_component(&self) -> f32 {
        self.r.max(self.g).max(self.b)
    }

    #[inline]
    pub fn mean(&self) -> f32 {
        (self.r + self.g + self.b) / 3.0
    }

    /// Rec. 709 luminance.
    #[inline]
    pub fn luminance(&self) -> f32 {
        0.2126 * self.r + 0.7152 * self.g + 0.0722 * self.b
    }

    #[inline]
    pub fn is_finite(&self) -> bool {
        self.r.is_finite() && self.g.is_finite() && self.b.is_finite()
    }

    #[inline]
    pub fn map(self, f: impl Fn(f32) -> f32) -> Self {
        Self::new(f(self.r), f(self.g), f(self.b))
    }

    #[inline]
    pub fn clamp01(self) -> Self {
        self.map(|v| v.clamp(0.0, 1.0))
    }

    /// Encodes to 8-bit sRGB (IEC 61966-2-1), clamping to [0, 1]: the code whose
    /// sRGB value is nearest, found by binary search over the 255 linear-light
    /// boundaries between codes (no `powf` per channel).
    #[inline]
    pub fn to_srgb8(self) -> [u8; 3] {
        Srgb8Encoder::new().encode(self)
    }

    /// Decodes from 8-bit sRGB.
    pub fn from_srgb8(c: [u8; 3]) -> Self {
        let f = |v: u8| srgb_to_linear(v as f32 / 255.0);
        Self::new(f(c[0]), f(c[1]), f(c[2]))
    }
}

/// Linear values at which the nearest 8-bit sRGB code steps from `k` to `k + 1`:
/// `srgb_to_linear((k + 0.5) / 255)`, computed once.
fn srgb8_boundaries() -> &'static [f32; 255] {
    static TABLE: std::sync::OnceLock<[f32; 255]> = std::sync::OnceLock::new();
    TABLE.get_or_init(|| std::array::from_fn(|k| srgb_to_linear((k as f32 + 0.5) / 255.0)))
}

/// Bins of the linear range [0, 1] in [`srgb8_start`]: fine enough that no bin holds
/// two code boundaries (the closest two, near black, are 1 / (255 x 12.92) = 3.0e-4
/// apart; a bin is 2.4e-4 wide).
const SRGB8_BINS: usize = 4096;

/// For each bin `i` of [`SRGB8_BINS`], the code of its left end `i / SRGB8_BINS`: the
/// number of boundaries at or below it.
fn srgb8_start() -> &'static [u8; SRGB8_BINS] {
    static TABLE: std::sync::OnceLock<[u8; SRGB8_BINS]> = std::sync::OnceLock::new();
    TABLE.get_or_init(|| {
        let t = srgb8_boundaries();
        std::array::from_fn(|i| {
            let v = i as f32 / SRGB8_BINS as f32;
            t.partition_point(|&b| b <= v) as u8
        })
    })
}

/// One linear value (clamped to [0, 1]; NaN gives 0) to its nearest 8-bit sRGB code:
/// the code at the start of its bin, plus one if the bin's one boundary is at or
/// below the value (exact: the same code as counting every boundary).
#[inline]
pub fn encode_srgb8(v: f32) -> u8 {
    let v = v.clamp(0.0, 1.0);
    // v x 4096 is exact (a power of two), so the bin's left end is never above v; a
    // NaN converts to bin 0 and fails the comparison below.
    let bin = ((v * SRGB8_BINS as f32) as usize).min(SRGB8_BINS - 1);
    let code = srgb8_start()[bin];
    let t = srgb8_boundaries();
    if code < 255 && t[code as usize] <= v {
        code + 1
    } else {
        code
    }
}

/// [`encode_srgb8`] with its two tables looked up once, for encoding many values
/// (a whole image) without asking the lazily built tables for each channel.
#[derive(Clone, Copy)]
pub struct Srgb8Encoder {
    start: &'static [u8; SRGB8_BINS],
    boundaries: &'static [f32; 255],
}

impl Srgb8Encoder {
    #[inline]
    pub fn new() -> Self {
        Self {
            start: srgb8_start(),
            boundaries: srgb8_boundaries(),
        }
    }

    /// [`encode_srgb8`] of one value.
    #[inline]
    pub fn encode_one(&self, v: f32) -> u8 {
        let v = v.clamp(0.0, 1.0);
        let bin = ((v * SRGB8_BINS as f32) as usize).min(SRGB8_BINS - 1);
        let code = self.start[bin];
        if code < 255 && self.boundaries[code as usize] <= v {
            code + 1
        } else {
            code
        }
    }

    /// [`Rgb::to_srgb8`].
    #[inline]
    pub fn encode(&self, c: Rgb) -> [u8; 3] {
        [
            self.encode_one(c.r),
            self.encode_one(c.g),
            self.encode_one(c.b),
        ]
    }
}

impl Default for Srgb8Encoder {
    fn default() -> Self {
        Self::new()
    }
}

/// The sRGB encoding curve for one linear value in [0, 1].
#[inline]
pub fn linear_to_srgb(v: f32) -> f32 {
    if v <= 0.003_130_8 {
        12.92 * v
    } else {
        1.055 * v.powf(1.0 / 2.4) - 0.055
    }
}

/// The sRGB decoding curve for one encoded value in [0, 1].
#[inline]
pub fn srgb_to_linear(v: f32) -> f32 {
    if v <= 0.040_45 {
        v / 12.92
    } else {
        ((v + 0.055) / 1.055).powf(2.4)
    }
}

impl Add for Rgb {
    type Output = Rgb;
    #[inline]
    fn add(self, o: Rgb) -> Rgb {
        Rgb::new(self.r + o.r, self.g + o.g, self.b + o.b)
    }
}
impl AddAssign for Rgb {
    #[inline]
    fn add_assign(&mut self, o: Rgb) {
        *self = *self + o;
    }
}
impl Sub for Rgb {
    type Output = Rgb;
    #[inline]
    fn sub(self, o: Rgb) -> Rgb {
        Rgb::new(self.r - o.r, self.g - o.g, self.b - o.b)
    }
}
impl Mul for Rgb {
    type Output = Rgb;
    #[inline]
    fn mul(self, o: Rgb) -> Rgb {
        Rgb::new(self.r * o.r, self.g * o.g, self.b * o.b)
    }
}
impl MulAssign for Rgb {
    #[inline]
    fn mul_assign(&mut self, o: Rgb) {
        *self = *self * o;
    }
}
impl Mul<f32> for Rgb {
    type Output = Rgb;
    #[inline]
    fn mul(self, s: f32) -> Rgb {
        Rgb::new(self.r * s, self.g * s, self.b * s)
    }
}
impl Mul<Rgb> for f32 {
    type Output = Rgb;
    #[inline]
    fn mul(self, c: Rgb) -> Rgb {
        c * self
    }
}
impl MulAssign<f32> for Rgb {
    #[inline]
    fn mul_assign(&mut self, s: f32) {
        *self = *self * s;
    }
}
impl Div<f32> for Rgb {
    type Output = Rgb;
    #[inline]
    fn div(self, s: f32) -> Rgb {
        self * (1.0 / s)
    }
}
impl DivAssign<f32> for Rgb {
    #[inline]
    fn div_assign(&mut self, s: f32) {
        *self = *self / s;
    }
}
impl Index<usize> for Rgb {
    type Output = f32;
    fn index(&self, i: usize) -> &f32 {
        match i {
            0 => &self.r,
            1 => &self.g,
            2 => &self.b,
            _ => panic!("Rgb index {i} out of range"),
        }
    }
}
impl std::iter::Sum for Rgb {
    fn sum<I: Iterator<Item = Rgb>>(iter: I) -> Rgb {
        iter.fold(Rgb::BLACK, |a, b| a + b)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn table_encoding_matches_the_curve() {
        for i in 0..=100_000u32 {
            let v = i as f32 / 100_000.0;
            let exact = linear_to_srgb(v) * 255.0;
            let code = encode_srgb8(v) as f32;
            // The nearest code, up to float rounding right at a boundary.
            assert!(
                (code - exact).abs() <= 0.5 + 1e-3,
                "v {v}: code {code}, curve {exact}"
            );
        }
        assert_eq!(encode_srgb8(-1.0), 0);
        assert_eq!(encode_srgb8(7.0), 255);
        assert_eq!(encode_srgb8(f32::NAN), 0);
    }

    #[test]
    fn binned_encoding_counts_the_boundaries_exactly() {
        // Every boundary and its neighbours one ulp away, plus a dense sweep: the
        // binned lookup equals counting the boundaries at or below the value.
        let t = srgb8_boundaries();
        let count = |v: f32| t.partition_point(|&b| b <= v) as u8;
        let mut values: Vec<f32> = (0..=1_000_000u32).map(|i| i as f32 / 1e6).collect();
        for &b in t.iter() {
            values.extend([
                f32::from_bits(b.to_bits() - 1),
                b,
                f32::from_bits(b.to_bits() + 1),
            ]);
        }
        for v in values {
            assert_eq!(encode_srgb8(v), count(v), "v {v}");
        }
    }

    #[test]
    fn srgb_round_trips_every_byte() {
        for v in 0..=255u8 {
            let c = Rgb::from_srgb8([v, v, v]);
            assert_eq!(c.to_srgb8(), [v, v, v]);
        }
    }
}
