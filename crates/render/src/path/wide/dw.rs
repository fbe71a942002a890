//! W `f64` lanes as a plain array, for the parts of the wide kernel that the
//! scalar code computes in `f64` (the sphere's quadratic, the conductor's Fresnel
//! reflectance): the same "SIMD lanes as arrays" model as
//! [`lanes`](irradia_geometry::packet::lanes) (Jakob et al., "Dr.Jit", SIGGRAPH 2022),
//! which LLVM compiles to two AVX-512 instructions per operation (four 4-wide AVX2
//! ones, eight SSE2 ones in the portable build). Every operation is the scalar one
//! lane by lane (no contraction into FMA: Rust never fuses `a * b + c`), so results
//! equal the scalar code's bit for bit.

// Lane loops index several arrays by the lane on purpose (LLVM vectorises them).
#![allow(clippy::needless_range_loop)]

use irradia_geometry::packet::lanes::{Fw, Mw, W};
use std::ops::{Add, Div, Mul, Neg, Sub};

/// W `f64` lanes.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[repr(C, align(64))]
pub(crate) struct Dw(pub [f64; W]);

macro_rules! lanewise {
    ($trait:ident, $f:ident, $op:tt) => {
        impl $trait for Dw {
            type Output = Dw;
            #[inline(always)]
            fn $f(self, o: Dw) -> Dw {
                let mut r = [0.0; W];
                for i in 0..W {
                    r[i] = self.0[i] $op o.0[i];
                }
                Dw(r)
            }
        }
        impl $trait<f64> for Dw {
            type Output = Dw;
            #[inline(always)]
            fn $f(self, o: f64) -> Dw {
                self $op Dw::splat(o)
            }
        }
        impl $trait<Dw> for f64 {
            type Output = Dw;
            #[inline(always)]
            fn $f(self, o: Dw) -> Dw {
                Dw::splat(self) $op o
            }
        }
    };
}
lanewise!(Add, add, +);
lanewise!(Sub, sub, -);
lanewise!(Mul, mul, *);
lanewise!(Div, div, /);

impl Neg for Dw {
    type Output = Dw;
    #[inline(always)]
    fn neg(self) -> Dw {
        let mut r = [0.0; W];
        for i in 0..W {
            r[i] = -self.0[i];
        }
        Dw(r)
    }
}

macro_rules! compare {
    ($name:ident, $op:tt) => {
        /// The lane comparison as a mask (false where either side is NaN, as in
        /// the scalar comparison).
        #[inline(always)]
        pub fn $name(self, o: impl Into<Dw>) -> Mw {
            let o = o.into();
            let mut r = [0; W];
            for i in 0..W {
                r[i] = -((self.0[i] $op o.0[i]) as i32);
            }
            Mw(r)
        }
    };
}

impl From<f64> for Dw {
    #[inline(always)]
    fn from(x: f64) -> Dw {
        Dw::splat(x)
    }
}

impl Dw {
    pub const ZERO: Dw = Dw([0.0; W]);

    #[inline(always)]
    pub fn splat(x: f64) -> Dw {
        Dw([x; W])
    }
    /// Every lane of `x` widened (exact).
    #[inline(always)]
    pub fn widen(x: Fw) -> Dw {
        let mut r = [0.0; W];
        for i in 0..W {
            r[i] = x.0[i] as f64;
        }
        Dw(r)
    }
    /// Every lane rounded to `f32` (`as f32`).
    #[inline(always)]
    pub fn narrow(self) -> Fw {
        let mut r = [0.0; W];
        for i in 0..W {
            r[i] = self.0[i] as f32;
        }
        Fw(r)
    }
    #[inline(always)]
    pub fn sqrt(self) -> Dw {
        let mut r = [0.0; W];
        for i in 0..W {
            r[i] = self.0[i].sqrt();
        }
        Dw(r)
    }
    #[inline(always)]
    pub fn abs(self) -> Dw {
        let mut r = [0.0; W];
        for i in 0..W {
            r[i] = self.0[i].abs();
        }
        Dw(r)
    }
    /// `f64::max` in every lane (the other operand where one is NaN).
    #[inline(always)]
    pub fn max(self, o: impl Into<Dw>) -> Dw {
        let o = o.into();
        let mut r = [0.0; W];
        for i in 0..W {
            r[i] = self.0[i].max(o.0[i]);
        }
        Dw(r)
    }
    /// `f64::signum` in every lane: ±1 by the sign bit (zeros included), NaN for NaN.
    #[inline(always)]
    pub fn signum(self) -> Dw {
        let mut r = [0.0; W];
        for i in 0..W {
            r[i] = self.0[i].signum();
        }
        Dw(r)
    }
    compare!(gt, >);
    compare!(lt, <);
    compare!(le, <=);
    compare!(eq, ==);
}

/// `a` in the lanes of `m`, `b` elsewhere.
#[inline(always)]
pub(crate) fn select(m: Mw, a: Dw, b: Dw) -> Dw {
    let mut r = [0.0; W];
    for i in 0..W {
        r[i] = if m.0[i] != 0 { a.0[i] } else { b.0[i] };
    }
    Dw(r)
}

/// W 3-vectors of `f64`, one per lane.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct DV3 {
    pub x: Dw,
    pub y: Dw,
    pub z: Dw,
}

impl DV3 {
    /// `glam`'s `DVec3::dot`: `x*x' + y*y' + z*z'` in that order.
    #[inline(always)]
    pub fn dot(self, o: DV3) -> Dw {
        self.x * o.x + self.y * o.y + self.z * o.z
    }
    #[inline(always)]
    pub fn sub(self, o: DV3) -> DV3 {
        DV3 {
            x: self.x - o.x,
            y: self.y - o.y,
            z: self.z - o.z,
        }
    }
    #[inline(always)]
    pub fn add(self, o: DV3) -> DV3 {
        DV3 {
            x: self.x + o.x,
            y: self.y + o.y,
            z: self.z + o.z,
        }
    }
    #[inline(always)]
    pub fn scale(self, s: Dw) -> DV3 {
        DV3 {
            x: self.x * s,
            y: self.y * s,
            z: self.z * s,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lanes_compute_the_scalar_operations() {
        // Eight cases, repeated over the W lanes.
        let xs = [1.5, -2.0, 0.0, -0.0, f64::NAN, 3.0, 1e300, -7.25];
        let ys = [0.5, 4.0, -1.0, 2.0, 1.0, f64::NAN, 1e-300, 7.25];
        let a = Dw(std::array::from_fn(|i| xs[i % xs.len()]));
        let b = Dw(std::array::from_fn(|i| ys[i % ys.len()]));
        for i in 0..W {
            let (x, y) = (a.0[i], b.0[i]);
            let same = |p: f64, q: f64| p.to_bits() == q.to_bits() || (p.is_nan() && q.is_nan());
            assert!(same((a + b).0[i], x + y));
            assert!(same((a - b).0[i], x - y));
            assert!(same((a * b).0[i], x * y));
            assert!(same((a / b).0[i], x / y));
            assert!(same(a.sqrt().0[i], x.sqrt()));
            assert!(same(a.max(b).0[i], x.max(y)));
            assert!(same(a.signum().0[i], x.signum()));
            assert_eq!(a.lt(b).get(i), x < y);
            assert_eq!(a.le(b).get(i), x <= y);
            assert!(same(select(a.gt(b), a, b).0[i], if x > y { x } else { y }));
        }
    }
}
