//! The arithmetic one evaluator runs for every number type: f64, intervals, duals.

use super::ast::{Binary, Func};

/// A number type the expression tape can be evaluated in.
pub trait Number: Copy + std::fmt::Debug {
    fn constant(c: f64) -> Self;
    fn neg(self) -> Self;
    fn powi(self, n: i32) -> Self;
    fn unary(self, f: Func) -> Self;
    fn binary(self, op: Binary, other: Self) -> Self;
}

impl Number for f64 {
    #[inline]
    fn constant(c: f64) -> Self {
        c
    }
    #[inline]
    fn neg(self) -> Self {
        -self
    }
    #[inline]
    fn powi(self, n: i32) -> Self {
        // NaN in, NaN out (std gives NaN^0 = 1): undefined stays undefined, as in the
        // interval evaluation.
        if self.is_nan() {
            return self;
        }
        f64::powi(self, n)
    }
    #[inline]
    fn unary(self, f: Func) -> Self {
        match f {
            Func::Sin => self.sin(),
            Func::Cos => self.cos(),
            Func::Tan => self.tan(),
            Func::Asin => self.asin(),
            Func::Acos => self.acos(),
            Func::Atan => self.atan(),
            Func::Sqrt => self.sqrt(),
            Func::Exp => self.exp(),
            Func::Log => self.ln(),
            Func::Abs => self.abs(),
            Func::Floor => self.floor(),
        }
    }
    #[inline]
    fn binary(self, op: Binary, o: Self) -> Self {
        // NaN in, NaN out: std's min/max return the other operand and powf(1, NaN) = 1,
        // which would make an undefined sub-expression look defined.
        if self.is_nan() || o.is_nan() {
            return f64::NAN;
        }
        match op {
            Binary::Add => self + o,
            Binary::Sub => self - o,
            Binary::Mul => self * o,
            Binary::Div => self / o,
            Binary::Pow => self.powf(o),
            Binary::Atan2 => self.atan2(o),
            Binary::Min => self.min(o),
            Binary::Max => self.max(o),
        }
    }
}
