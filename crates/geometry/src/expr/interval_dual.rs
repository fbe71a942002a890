//! Interval dual numbers: an enclosure of a function's value together with an enclosure
//! of its derivative along one direction, over a box. When the derivative enclosure
//! excludes 0 the function is strictly monotone along that direction on the box, so it
//! has at most one root there (Mitchell, "Robust ray intersection with interval
//! arithmetic", Graphics Interface 1990, §4: the derivative test that stops subdivision).
//!
//! Each rule is the chain rule evaluated in interval arithmetic, so the derivative
//! enclosure is sound wherever the function is differentiable; where it is not (the kink
//! of `abs`, the jumps of `floor`, the branch cut of `atan2`, the poles of `tan` and of
//! division), the derivative enclosure is widened to contain 0 or made entire, so no
//! false monotonicity is ever claimed.

use super::ast::{Binary, Func};
use super::interval::Interval;
use super::number::Number;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct IntervalDual {
    pub v: Interval,
    pub d: Interval,
}

impl IntervalDual {
    /// A variable ranging over `v` whose rate along the direction is `slope`.
    pub fn variable(v: Interval, slope: f64) -> Self {
        Self {
            v,
            d: Interval::point(slope),
        }
    }

    fn new(v: Interval, d: Interval) -> Self {
        if v.is_empty() {
            return Self {
                v,
                d: Interval::EMPTY,
            };
        }
        Self { v, d }
    }
}

fn c(x: f64) -> Interval {
    Interval::point(x)
}

impl Number for IntervalDual {
    fn constant(x: f64) -> Self {
        Self { v: c(x), d: c(0.0) }
    }

    fn neg(self) -> Self {
        Self::new(self.v.neg(), self.d.neg())
    }

    fn powi(self, n: i32) -> Self {
        if n == 0 {
            return Self::new(c(1.0).binary(Binary::Mul, self.v.powi(0)), c(0.0));
        }
        let d = c(n as f64)
            .binary(Binary::Mul, self.v.powi(n - 1))
            .binary(Binary::Mul, self.d);
        Self::new(self.v.powi(n), d)
    }

    fn unary(self, f: Func) -> Self {
        let (v, d) = (self.v, self.d);
        let mul = |a: Interval, b: Interval| a.binary(Binary::Mul, b);
        let div = |a: Interval, b: Interval| a.binary(Binary::Div, b);
        let value = v.unary(f);
        let slope = match f {
            Func::Sin => mul(v.unary(Func::Cos), d),
            Func::Cos => mul(v.unary(Func::Sin).neg(), d),
            Func::Tan => mul(c(1.0).binary(Binary::Add, value.powi(2)), d),
            Func::Asin | Func::Acos => {
                let s = c(1.0).binary(Binary::Sub, v.powi(2)).unary(Func::Sqrt);
                let q = div(d, s);
                if f == Func::Asin {
                    q
                } else {
                    q.neg()
                }
            }
            Func::Atan => div(d, c(1.0).binary(Binary::Add, v.powi(2))),
            Func::Sqrt => div(mul(c(0.5), d), value),
            Func::Exp => mul(value, d),
            Func::Log => div(d, v),
            Func::Abs => {
                if v.lo >= 0.0 {
                    d
                } else if v.hi <= 0.0 {
                    d.neg()
                } else {
                    // The kink: either slope may apply.
                    d.hull(d.neg())
                }
            }
            Func::Floor => {
                if v.lo.floor() == v.hi.floor() {
                    c(0.0)
                } else {
                    Interval::ENTIRE // a jump inside the box
                }
            }
        };
        Self::new(value, slope)
    }

    fn binary(self, op: Binary, o: Self) -> Self {
        let (a, da, b, db) = (self.v, self.d, o.v, o.d);
        let mul = |x: Interval, y: Interval| x.binary(Binary::Mul, y);
        let add = |x: Interval, y: Interval| x.binary(Binary::Add, y);
        let sub = |x: Interval, y: Interval| x.binary(Binary::Sub, y);
        let div = |x: Interval, y: Interval| x.binary(Binary::Div, y);
        match op {
            Binary::Add => Self::new(add(a, b), add(da, db)),
            Binary::Sub => Self::new(sub(a, b), sub(da, db)),
            Binary::Mul => Self::new(mul(a, b), add(mul(da, b), mul(a, db))),
            Binary::Div => {
                let q = div(a, b);
                Self::new(q, div(sub(da, mul(q, db)), b))
            }
            Binary::Pow => {
                let value = a.binary(Binary::Pow, b);
                let slope = if db == c(0.0) && b.lo == b.hi {
                    // Constant exponent e: e * a^(e-1) * da.
                    let e = b.lo;
                    mul(mul(c(e), a.binary(Binary::Pow, c(e - 1.0))), da)
                } else if a.lo <= 0.0 {
                    // A base that may be 0 or negative with a varying exponent (defined
                    // only at integer exponents there): no useful bound.
                    Interval::ENTIRE
                } else {
                    // a^b (db ln a + b da / a), for a > 0.
                    mul(value, add(mul(db, a.unary(Func::Log)), div(mul(b, da), a)))
                };
                Self::new(value, slope)
            }
            Binary::Atan2 => {
                let value = a.binary(Binary::Atan2, b);
                // A box across the branch cut gives [-pi, pi]: the value may jump there.
                let slope = if value.width() >= 6.0 {
                    Interval::ENTIRE
                } else {
                    // d atan2(y, x) = (x dy - y dx) / (x² + y²)
                    div(sub(mul(b, da), mul(a, db)), add(b.powi(2), a.powi(2)))
                };
                Self::new(value, slope)
            }
            Binary::Min | Binary::Max => {
                let value = a.binary(op, b);
                let first_wins = if op == Binary::Min {
                    a.hi < b.lo
                } else {
                    a.lo > b.hi
                };
                let second_wins = if op == Binary::Min {
                    b.hi < a.lo
                } else {
                    b.lo > a.hi
                };
                let slope = if first_wins {
                    da
                } else if second_wins {
                    db
                } else {
                    // min/max of two functions monotone the same way is monotone.
                    da.hull(db)
                };
                Self::new(value, slope)
            }
        }
    }
}
