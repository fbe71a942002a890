//! `W` = 16 `f32` lanes as plain arrays, with the arithmetic, comparisons and selects the
//! wide path kernel is written in. Sixteen `f32` fill one AVX-512 register (two AVX2
//! registers); the `w` in the type names ([`Fw`], [`Mw`], and the render crate's `Dw`)
//! means "W lanes".
//!
//! Every operation is a loop over the W lanes, `#[inline(always)]`, so that inside a
//! function compiled with `#[target_feature(enable = "avx512f,...")]` LLVM turns each one
//! into a single AVX-512 instruction (two AVX2 instructions in the AVX2 build, four SSE
//! instructions in the portable one).
//! This is the "SIMD lanes as arrays" programming model of Dr.Jit's LLVM backend (Jakob,
//! Speierer, Roussel, Nimier-David, Vicini, Zeltner, Nicolet, Crespo, Leroy, Zhang,
//! "Dr.Jit: A Just-In-Time Compiler for Differentiable Rendering", SIGGRAPH 2022), written
//! by hand: each lane computes exactly what the scalar code computes, in the same order
//! (no contraction into FMA: Rust never fuses `a * b + c`), so the lanes round like the
//! scalar estimator except where an approximation is named ([`sin_cos_quarter_pi`]).
//!
//! Masks are `i32` lanes holding `-1` (true) or `0`, the form vector compares produce.

// Lane loops index several arrays by the lane on purpose (LLVM vectorises them), and
// `V3`'s arithmetic methods are by-value helpers, not operator traits.
#![allow(clippy::needless_range_loop, clippy::should_implement_trait)]

use std::ops::{Add, BitAnd, BitOr, Div, Mul, Neg, Not, Sub};

/// Lanes of the kernel: 16, one AVX-512 register of `f32` (two AVX2 registers).
pub const W: usize = 16;

/// W `f32` lanes.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[repr(C, align(64))]
pub struct Fw(pub [f32; W]);

/// W lane masks (`-1` true, `0` false).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[repr(C, align(64))]
pub struct Mw(pub [i32; W]);

/// The indices of a mask's true lanes, lowest first ([`Mw::lanes`]).
#[derive(Clone, Copy, Debug)]
pub struct SetLanes(u32);

impl Iterator for SetLanes {
    type Item = usize;
    #[inline(always)]
    fn next(&mut self) -> Option<usize> {
        if self.0 == 0 {
            return None;
        }
        let lane = self.0.trailing_zeros() as usize;
        self.0 &= self.0 - 1;
        Some(lane)
    }
}

macro_rules! lanewise {
    ($trait:ident, $f:ident, $op:tt) => {
        impl $trait for Fw {
            type Output = Fw;
            #[inline(always)]
            fn $f(self, o: Fw) -> Fw {
                let mut r = [0.0; W];
                for i in 0..W {
                    r[i] = self.0[i] $op o.0[i];
                }
                Fw(r)
            }
        }
        impl $trait<f32> for Fw {
            type Output = Fw;
            #[inline(always)]
            fn $f(self, o: f32) -> Fw {
                self $op Fw::splat(o)
            }
        }
        impl $trait<Fw> for f32 {
            type Output = Fw;
            #[inline(always)]
            fn $f(self, o: Fw) -> Fw {
                Fw::splat(self) $op o
            }
        }
    };
}
lanewise!(Add, add, +);
lanewise!(Sub, sub, -);
lanewise!(Mul, mul, *);
lanewise!(Div, div, /);

impl Neg for Fw {
    type Output = Fw;
    #[inline(always)]
    fn neg(self) -> Fw {
        self.map(|x| -x)
    }
}

macro_rules! compare {
    ($name:ident, $op:tt) => {
        #[inline(always)]
        pub fn $name(self, o: impl Into<Fw>) -> Mw {
            let o = o.into();
            let mut r = [0; W];
            for i in 0..W {
                r[i] = -((self.0[i] $op o.0[i]) as i32);
            }
            Mw(r)
        }
    };
}

impl From<f32> for Fw {
    #[inline(always)]
    fn from(x: f32) -> Fw {
        Fw::splat(x)
    }
}

impl Fw {
    pub const ZERO: Fw = Fw([0.0; W]);

    #[inline(always)]
    pub fn splat(x: f32) -> Fw {
        Fw([x; W])
    }

    #[inline(always)]
    pub fn map(self, f: impl Fn(f32) -> f32) -> Fw {
        let mut r = [0.0; W];
        for i in 0..W {
            r[i] = f(self.0[i]);
        }
        Fw(r)
    }

    #[inline(always)]
    pub fn zip(self, o: Fw, f: impl Fn(f32, f32) -> f32) -> Fw {
        let mut r = [0.0; W];
        for i in 0..W {
            r[i] = f(self.0[i], o.0[i]);
        }
        Fw(r)
    }

    #[inline(always)]
    pub fn sqrt(self) -> Fw {
        self.map(f32::sqrt)
    }
    #[inline(always)]
    pub fn abs(self) -> Fw {
        self.map(f32::abs)
    }
    /// `f32::max` in every lane (the non-NaN operand wins, as in the scalar code).
    #[inline(always)]
    pub fn max(self, o: impl Into<Fw>) -> Fw {
        self.zip(o.into(), f32::max)
    }
    #[inline(always)]
    pub fn min(self, o: impl Into<Fw>) -> Fw {
        self.zip(o.into(), f32::min)
    }
    /// `1.0f32.copysign(self)`: ±1 with the sign bit of each lane.
    #[inline(always)]
    pub fn sign_one(self) -> Fw {
        self.map(|x| 1.0f32.copysign(x))
    }
    /// `self * b + c` with one rounding (`f32::mul_add`: one FMA instruction where
    /// the FMA feature is enabled).
    #[inline(always)]
    pub fn mul_add(self, b: Fw, c: Fw) -> Fw {
        let mut r = [0.0; W];
        for i in 0..W {
            r[i] = self.0[i].mul_add(b.0[i], c.0[i]);
        }
        Fw(r)
    }
    /// The sign bit of every lane (as the bits of an `f32`: `-0.0` or `0.0`).
    #[inline(always)]
    pub fn sign_bit(self) -> Fw {
        self.map(|x| f32::from_bits(x.to_bits() & 0x8000_0000))
    }
    /// The bits of `self` exclusive-or those of `m`.
    #[inline(always)]
    pub fn xor_bits(self, m: Fw) -> Fw {
        self.zip(m, |x, y| f32::from_bits(x.to_bits() ^ y.to_bits()))
    }
    /// True in lanes holding neither an infinity nor a NaN.
    #[inline(always)]
    pub fn finite(self) -> Mw {
        let mut r = [0; W];
        for i in 0..W {
            r[i] = -(self.0[i].is_finite() as i32);
        }
        Mw(r)
    }

    compare!(lt, <);
    compare!(le, <=);
    compare!(gt, >);
    compare!(ge, >=);
    compare!(eq, ==);
    compare!(ne, !=);
}

impl Mw {
    pub const FALSE: Mw = Mw([0; W]);
    pub const TRUE: Mw = Mw([-1; W]);

    #[inline(always)]
    pub fn from_fn(f: impl Fn(usize) -> bool) -> Mw {
        Mw(std::array::from_fn(|i| -(f(i) as i32)))
    }
    #[inline(always)]
    pub fn get(self, lane: usize) -> bool {
        self.0[lane] != 0
    }
    #[inline(always)]
    pub fn set(&mut self, lane: usize, v: bool) {
        self.0[lane] = -(v as i32);
    }
    /// The true lanes' indices in order, from [`Self::bits`]: a lane loop that skips
    /// lanes by this integer does not reload one lane of a just-stored vector mask (a
    /// 4-byte load from a wide store, which the store buffer does not always forward).
    #[inline(always)]
    pub fn lanes(self) -> SetLanes {
        SetLanes(self.bits())
    }
    /// Lane `i` in bit `i`.
    #[inline(always)]
    pub fn bits(self) -> u32 {
        let mut b = 0;
        for i in 0..W {
            b |= ((self.0[i] != 0) as u32) << i;
        }
        b
    }
    #[inline(always)]
    pub fn any(self) -> bool {
        self.0.iter().fold(0, |a, &m| a | m) != 0
    }
    #[inline(always)]
    pub fn and_not(self, o: Mw) -> Mw {
        self & !o
    }
    /// `a` in the lanes of the mask, `b` elsewhere.
    #[inline(always)]
    pub fn select(self, a: Fw, b: Fw) -> Fw {
        let mut r = [0.0; W];
        for i in 0..W {
            let m = self.0[i] as u32;
            r[i] = f32::from_bits((a.0[i].to_bits() & m) | (b.0[i].to_bits() & !m));
        }
        Fw(r)
    }
    /// [`Mw::select`] of integer lanes (indices).
    #[inline(always)]
    pub fn select_u32(self, a: [u32; W], b: [u32; W]) -> [u32; W] {
        std::array::from_fn(|i| {
            let m = self.0[i] as u32;
            (a[i] & m) | (b[i] & !m)
        })
    }
    /// `a` in the lanes of the mask, zero elsewhere.
    #[inline(always)]
    pub fn keep(self, a: Fw) -> Fw {
        self.select(a, Fw::ZERO)
    }
}

impl BitAnd for Mw {
    type Output = Mw;
    #[inline(always)]
    fn bitand(self, o: Mw) -> Mw {
        Mw(std::array::from_fn(|i| self.0[i] & o.0[i]))
    }
}
impl BitOr for Mw {
    type Output = Mw;
    #[inline(always)]
    fn bitor(self, o: Mw) -> Mw {
        Mw(std::array::from_fn(|i| self.0[i] | o.0[i]))
    }
}
impl Not for Mw {
    type Output = Mw;
    #[inline(always)]
    fn not(self) -> Mw {
        Mw(std::array::from_fn(|i| !self.0[i]))
    }
}

/// W 3-vectors, one per lane (structure of arrays).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct V3 {
    pub x: Fw,
    pub y: Fw,
    pub z: Fw,
}

impl V3 {
    pub const ZERO: V3 = V3 {
        x: Fw::ZERO,
        y: Fw::ZERO,
        z: Fw::ZERO,
    };

    #[inline(always)]
    pub fn new(x: Fw, y: Fw, z: Fw) -> V3 {
        V3 { x, y, z }
    }
    /// Lane `i` as a `glam` vector.
    #[inline(always)]
    pub fn lane(&self, i: usize) -> glam::Vec3 {
        glam::Vec3::new(self.x.0[i], self.y.0[i], self.z.0[i])
    }
    #[inline(always)]
    pub fn set_lane(&mut self, i: usize, v: glam::Vec3) {
        self.x.0[i] = v.x;
        self.y.0[i] = v.y;
        self.z.0[i] = v.z;
    }
    #[inline(always)]
    pub fn set_lane_array(&mut self, i: usize, v: [f32; 3]) {
        self.x.0[i] = v[0];
        self.y.0[i] = v[1];
        self.z.0[i] = v[2];
    }
    /// `x*x' + y*y' + z*z'`, summed in `glam`'s order.
    #[inline(always)]
    pub fn dot(self, o: V3) -> Fw {
        self.x * o.x + self.y * o.y + self.z * o.z
    }
    #[inline(always)]
    pub fn scale(self, s: Fw) -> V3 {
        V3::new(self.x * s, self.y * s, self.z * s)
    }
    /// Every component divided by `s` (as `glam`'s `Vec3 / f32`).
    #[inline(always)]
    pub fn div(self, s: Fw) -> V3 {
        V3::new(self.x / s, self.y / s, self.z / s)
    }
    #[inline(always)]
    pub fn mul(self, o: V3) -> V3 {
        V3::new(self.x * o.x, self.y * o.y, self.z * o.z)
    }
    #[inline(always)]
    pub fn add(self, o: V3) -> V3 {
        V3::new(self.x + o.x, self.y + o.y, self.z + o.z)
    }
    #[inline(always)]
    pub fn sub(self, o: V3) -> V3 {
        V3::new(self.x - o.x, self.y - o.y, self.z - o.z)
    }
    #[inline(always)]
    pub fn neg(self) -> V3 {
        V3::new(-self.x, -self.y, -self.z)
    }
    #[inline(always)]
    pub fn abs(self) -> V3 {
        V3::new(self.x.abs(), self.y.abs(), self.z.abs())
    }
    /// `glam`'s `normalize`: times the reciprocal of the length.
    #[inline(always)]
    pub fn normalize(self) -> V3 {
        self.scale(1.0 / self.dot(self).sqrt())
    }
    #[inline(always)]
    pub fn select(m: Mw, a: V3, b: V3) -> V3 {
        V3::new(m.select(a.x, b.x), m.select(a.y, b.y), m.select(a.z, b.z))
    }
    /// `a` in the lanes of `m`, zero elsewhere.
    #[inline(always)]
    pub fn keep(self, m: Mw) -> V3 {
        V3::new(m.keep(self.x), m.keep(self.y), m.keep(self.z))
    }
    /// `Rgb::max_component`: `r.max(g).max(b)`.
    #[inline(always)]
    pub fn max_component(self) -> Fw {
        self.x.max(self.y).max(self.z)
    }
    /// True where every component is zero (`Rgb::is_black`).
    #[inline(always)]
    pub fn is_zero(self) -> Mw {
        self.x.eq(0.0) & self.y.eq(0.0) & self.z.eq(0.0)
    }
    #[inline(always)]
    pub fn finite(self) -> Mw {
        self.x.finite() & self.y.finite() & self.z.finite()
    }
}

/// `table[idx[i]][at]` in every lane `i`.
///
/// The element offsets are formed in `i32` and sign-extended (the table is asserted
/// to hold fewer than 2³¹ floats), the form of AVX-512's `vgatherdps`: the sixteen
/// lanes are one gather of 32-bit offsets, where `usize` offsets would take two
/// gathers of 64-bit ones and a shuffle to join them.
///
/// # Safety
/// Every index must address a row of `table` and `at < N`.
#[inline(always)]
pub unsafe fn gather<const N: usize>(table: &[[f32; N]], idx: &[u32; W], at: usize) -> Fw {
    assert!(table.len() * N <= i32::MAX as usize);
    let base = table.as_ptr() as *const f32;
    let (n, at) = (N as i32, at as i32);
    // SAFETY: in bounds by the caller's contract (`idx[i] < table.len()`, `at < N`);
    // the offset `idx[i] N + at < table.len() N` fits in `i32` by the assertion.
    Fw(std::array::from_fn(|i| unsafe {
        *base.offset((idx[i] as i32 * n + at) as isize)
    }))
}

/// `column.0[idx[i]]` in every lane `i`: one AVX-512 lane permute (`vpermps`, Intel's
/// `_mm512_permutexvar_ps`) of a column held in one register. For a table of at most W
/// rows stored by field (column `at` holding field `at` of every row), it reads the
/// same bits as [`gather`] of that field, without the gather's one load per lane:
/// on Zen 4 and Intel's AVX-512 cores a 16-lane `vgatherdps` issues about as many
/// µops as lanes, a `vpermps` one or two (Fog, "Instruction tables", 2022;
/// uops.info). Only the low four bits of each index are read.
///
/// # Safety
/// The CPU must support AVX-512 F.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f")]
#[inline]
pub unsafe fn permute_avx512(column: &Fw, idx: &[u32; W]) -> Fw {
    use std::arch::x86_64::{
        _mm512_load_ps, _mm512_loadu_si512, _mm512_permutexvar_ps, _mm512_store_ps,
    };
    let mut r = Fw::ZERO;
    // SAFETY: `Fw` is 64 bytes aligned to 64; `idx` is 64 bytes (an unaligned load).
    unsafe {
        let i = _mm512_loadu_si512(idx.as_ptr().cast());
        let c = _mm512_load_ps(column.0.as_ptr());
        _mm512_store_ps(r.0.as_mut_ptr(), _mm512_permutexvar_ps(i, c));
    }
    r
}

/// Sine and cosine of `a` for `|a| <= π/4`: the minimax polynomials of Cephes'
/// `sinf`/`cosf` (Moshier, "Methods and Programs for Mathematical Functions", 1989),
/// the kernel Dr.Jit and SLEEF also use; within 2 ulp of the correctly rounded value
/// on that range, with no range reduction and no branch, so W lanes cost a
/// handful of vector multiplies instead of W calls of `sinf` and `cosf`. The lanes of
/// `irradia_core::sincos::sin_cos_quarter_pi`, bit for bit (its coefficients, its order).
#[inline(always)]
pub fn sin_cos_quarter_pi(a: Fw) -> (Fw, Fw) {
    use irradia_core::sincos::{COS_COEFFS as Q, SIN_COEFFS as P};
    let z = a * a;
    let s = ((P[0] * z + P[1]) * z + P[2]) * z * a + a;
    let c = ((Q[0] * z + Q[1]) * z + Q[2]) * z * z - 0.5 * z + 1.0;
    (s, c)
}

/// [`irradia_core::sin_cos`] in every lane: the same reduction by `π/2` in three
/// parts, the same polynomials ([`sin_cos_quarter_pi`], as
/// `irradia_core::sincos::sin_cos_quarter_pi`) and the same quadrant, with selects
/// where the scalar function branches, so every lane is the scalar result bit for bit.
#[inline(always)]
pub fn sin_cos(x: Fw) -> (Fw, Fw) {
    use irradia_core::sincos::PI_2_PARTS as P;
    let k = (x * std::f32::consts::FRAC_2_PI).map(f32::round_ties_even);
    let r = ((x - k * P[0]) - k * P[1]) - k * P[2];
    let (s, c) = sin_cos_quarter_pi(r);
    let q: [i32; W] = std::array::from_fn(|i| k.0[i] as i32 & 3);
    let odd = Mw(std::array::from_fn(|i| -(q[i] & 1)));
    let half = Mw(std::array::from_fn(|i| -(q[i] >> 1 & 1)));
    let (s, c) = (odd.select(c, s), odd.select(-s, c));
    (half.select(-s, s), half.select(-c, c))
}

/// [`irradia_core::atan2`] in every lane: the same reduction, polynomial
/// ([`irradia_core::atan::COEFFS`], Horner's scheme in the same order) and quadrant
/// restoration, with selects where the scalar function branches, so every lane is the
/// scalar result bit for bit (0 where both arguments are 0; NaN for a NaN argument
/// where the scalar gives NaN).
#[inline(always)]
pub fn atan2(y: Fw, x: Fw) -> Fw {
    use irradia_core::atan::COEFFS as C;
    use std::f32::consts::{FRAC_PI_2, PI};
    let (ax, ay) = (x.abs(), y.abs());
    let swap = ay.gt(ax);
    let (lo, hi) = (swap.select(ax, ay), swap.select(ay, ax));
    let a = lo / hi;
    let s = a * a;
    let p = Fw::splat(C[7]);
    let p = p * s + C[6];
    let p = p * s + C[5];
    let p = p * s + C[4];
    let p = p * s + C[3];
    let p = p * s + C[2];
    let p = p * s + C[1];
    let p = p * s + C[0];
    let r = a * p;
    let r = swap.select(FRAC_PI_2 - r, r);
    let r = x.lt(0.0).select(PI - r, r);
    let r = y.lt(0.0).select(-r, r);
    hi.eq(0.0).select(Fw::ZERO, r)
}

/// [`irradia_core::offset_ray_origin`] in every lane: the point `p` moved off its
/// surface along `n` by its error bound and a few ulps (Wächter and Binder, "A Fast and
/// Robust Method for Avoiding Self-Intersection", Ray Tracing Gems, 2019), bit for bit.
#[inline(always)]
pub fn offset_ray_origin(p: V3, n: V3, extra_error: Fw) -> V3 {
    let p = p.add(n.scale(extra_error));
    V3::new(
        offset_axis(p.x, n.x),
        offset_axis(p.y, n.y),
        offset_axis(p.z, n.z),
    )
}

/// One coordinate of [`offset_ray_origin`] (after the error offset).
#[inline(always)]
fn offset_axis(p: Fw, n: Fw) -> Fw {
    const ORIGIN: f32 = 1.0 / 32.0;
    const FLOAT_SCALE: f32 = 1.0 / 65536.0;
    const INT_SCALE: f32 = 256.0;
    let mut r = [0.0; W];
    for i in 0..W {
        let (pc, nc) = (p.0[i], n.0[i]);
        // |n| <= 1, so the product fits an i32 and truncates as `as i32` would; the
        // clamp (exact for every such value) keeps even a NaN lane defined, and lets
        // the conversion be one vector instruction.
        // SAFETY: the clamped product is finite and within ±256.
        // (`clamp` would keep a NaN.)
        #[allow(clippy::manual_clamp)]
        let oi = unsafe { (INT_SCALE * nc.max(-1.0).min(1.0)).to_int_unchecked::<i32>() };
        let bits = pc.to_bits() as i32;
        let moved = if pc < 0.0 {
            bits.wrapping_sub(oi)
        } else {
            bits.wrapping_add(oi)
        };
        r[i] = if pc.abs() < ORIGIN {
            pc + FLOAT_SCALE * nc
        } else {
            f32::from_bits(moved as u32)
        };
    }
    Fw(r)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sine_and_cosine_are_accurate_on_the_quarter_circle() {
        let mut worst = 0f32;
        for k in 0..=2000 {
            let a = (k as f32 / 1000.0 - 1.0) * std::f32::consts::FRAC_PI_4;
            let (s, c) = sin_cos_quarter_pi(Fw::splat(a));
            worst = worst
                .max((s.0[3] - (a as f64).sin() as f32).abs())
                .max((c.0[5] - (a as f64).cos() as f32).abs());
        }
        assert!(worst < 2.5e-7, "worst error {worst}");
    }

    /// Every lane is `irradia_core::atan2` bit for bit: random arguments of every
    /// quadrant and octant at many magnitudes, the axes, signed zeros, ties `|x| = |y|`,
    /// infinities and NaN.
    #[test]
    fn atan2_matches_the_scalar_polynomial_bit_for_bit() {
        let mut rng = irradia_core::Rng::new(11, 12);
        let special = [
            0.0f32,
            -0.0,
            1.0,
            -1.0,
            0.5,
            -2.0,
            1e-30,
            -3e25,
            f32::INFINITY,
            f32::NEG_INFINITY,
            f32::NAN,
        ];
        let mut cases = Vec::new();
        for &y in &special {
            for &x in &special {
                cases.push((y, x));
            }
        }
        for k in 0..4000 {
            let m = [1e-6f32, 1.0, 3e4][k % 3];
            let (y, x) = ((rng.next_f32() - 0.5) * m, (rng.next_f32() - 0.5) * m);
            cases.push((y, x));
            cases.push((x, x));
            cases.push((-y, y));
        }
        for chunk in cases.chunks(W) {
            let y = Fw(std::array::from_fn(|i| chunk[i % chunk.len()].0));
            let x = Fw(std::array::from_fn(|i| chunk[i % chunk.len()].1));
            let got = atan2(y, x);
            for i in 0..W {
                let want = irradia_core::atan2(y.0[i], x.0[i]);
                if want.is_nan() {
                    assert!(got.0[i].is_nan(), "atan2({}, {})", y.0[i], x.0[i]);
                    continue;
                }
                assert_eq!(
                    got.0[i].to_bits(),
                    want.to_bits(),
                    "atan2({}, {}): {} != {want}",
                    y.0[i],
                    x.0[i],
                    got.0[i]
                );
            }
        }
    }

    /// Every lane's sine and cosine are the scalar polynomial's bit for bit, over a few
    /// turns either way, at the quadrants' edges and for NaN and infinities.
    #[test]
    fn sin_cos_matches_the_scalar_polynomial_bit_for_bit() {
        use std::f32::consts::{FRAC_PI_2, FRAC_PI_4, PI};
        let mut rng = irradia_core::Rng::new(13, 14);
        let mut xs: Vec<f32> = (0..8000).map(|_| (rng.next_f32() - 0.5) * 40.0).collect();
        for k in -8..=8 {
            for base in [k as f32 * FRAC_PI_2, k as f32 * FRAC_PI_4 + FRAC_PI_4] {
                let b = base.to_bits();
                xs.extend([
                    base,
                    f32::from_bits(b + 1),
                    f32::from_bits(b.wrapping_sub(1)),
                ]);
            }
        }
        xs.extend([
            0.0,
            -0.0,
            PI,
            2.0 * PI,
            1e-30,
            f32::NAN,
            f32::INFINITY,
            -f32::INFINITY,
        ]);
        for chunk in xs.chunks(W) {
            let x = Fw(std::array::from_fn(|i| chunk[i % chunk.len()]));
            let (s, c) = sin_cos(x);
            for i in 0..W {
                let (ws, wc) = irradia_core::sin_cos(x.0[i]);
                for (got, want) in [(s.0[i], ws), (c.0[i], wc)] {
                    assert!(
                        got.to_bits() == want.to_bits() || (got.is_nan() && want.is_nan()),
                        "sin_cos({}): {got} != {want}",
                        x.0[i]
                    );
                }
            }
        }
    }

    #[test]
    fn offsets_match_the_scalar_function_bit_for_bit() {
        let mut rng = irradia_core::Rng::new(3, 4);
        for _ in 0..200 {
            let mut v = || (rng.next_f32() - 0.5) * 8.0;
            let (p, n) = (
                glam::Vec3::new(v(), v() * 0.01, v()),
                glam::Vec3::new(v(), v(), v()).normalize(),
            );
            let e = v().abs() * 1e-5;
            let mut pw = V3::ZERO;
            let mut nw = V3::ZERO;
            for i in 0..W {
                pw.set_lane(i, p);
                nw.set_lane(i, n);
            }
            let o = offset_ray_origin(pw, nw, Fw::splat(e));
            let s = irradia_core::offset_ray_origin(p, n, e);
            assert_eq!(
                o.lane(6).to_array().map(f32::to_bits),
                s.to_array().map(f32::to_bits)
            );
        }
    }

    /// The permute reads what the gather reads, for every row of tables of 1 to W rows.
    #[cfg(target_arch = "x86_64")]
    #[test]
    fn permutes_equal_gathers() {
        if !crate::packet::simd_build::has_avx512() {
            return;
        }
        let mut rng = irradia_core::Rng::new(7, 8);
        for rows in 1..=W {
            let table: Vec<[f32; 3]> = (0..rows)
                .map(|_| {
                    [
                        rng.next_f32(),
                        -rng.next_f32(),
                        f32::from_bits(rng.next_u32()),
                    ]
                })
                .collect();
            for round in 0..20 {
                let idx: [u32; W] = std::array::from_fn(|i| ((i * 7 + round) % rows) as u32);
                for at in 0..3 {
                    let column = Fw(std::array::from_fn(|r| {
                        table.get(r).map_or(0.0, |row| row[at])
                    }));
                    // SAFETY: AVX-512 F was checked; every index is a row, `at < 3`.
                    let (p, g) =
                        unsafe { (permute_avx512(&column, &idx), gather(&table, &idx, at)) };
                    assert_eq!(p.0.map(f32::to_bits), g.0.map(f32::to_bits));
                }
            }
        }
    }

    #[test]
    fn selects_and_masks_follow_the_lanes() {
        let a = Fw(std::array::from_fn(|i| i as f32));
        let m = a.lt(3.0) | a.eq(6.0);
        assert_eq!(m.bits(), 0b0100_0111);
        assert_eq!(m.select(a, -a).0[6], 6.0);
        assert_eq!(m.select(a, -a).0[5], -5.0);
        assert!(!(m & !m).any());
    }
}
