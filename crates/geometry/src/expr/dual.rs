//! Forward-mode dual numbers carrying a value and its gradient with respect to up to
//! three variables (Griewank and Walther, *Evaluating Derivatives*, 2008, ch. 3).

use super::ast::{Binary, Func};
use super::number::Number;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Dual {
    pub v: f64,
    pub d: [f64; 3],
}

impl Dual {
    /// Variable number `index` with value `v` (seed 1 in its slot; indices >= 3 get no
    /// derivative slot and act as constants).
    pub fn variable(v: f64, index: usize) -> Self {
        let mut d = [0.0; 3];
        if index < 3 {
            d[index] = 1.0;
        }
        Self { v, d }
    }

    #[inline]
    fn chain(self, value: f64, slope: f64) -> Self {
        Self {
            v: value,
            d: [self.d[0] * slope, self.d[1] * slope, self.d[2] * slope],
        }
    }

    #[inline]
    fn combine(value: f64, a: Dual, da: f64, b: Dual, db: f64) -> Self {
        Self {
            v: value,
            d: [
                a.d[0] * da + b.d[0] * db,
                a.d[1] * da + b.d[1] * db,
                a.d[2] * da + b.d[2] * db,
            ],
        }
    }

    fn is_constant(&self) -> bool {
        self.d == [0.0; 3]
    }
}

impl Number for Dual {
    fn constant(c: f64) -> Self {
        Self { v: c, d: [0.0; 3] }
    }
    fn neg(self) -> Self {
        self.chain(-self.v, -1.0)
    }
    fn powi(self, n: i32) -> Self {
        if self.v.is_nan() {
            return self;
        }
        if n == 0 {
            return Self::constant(1.0);
        }
        self.chain(self.v.powi(n), n as f64 * self.v.powi(n - 1))
    }
    fn unary(self, f: Func) -> Self {
        let x = self.v;
        match f {
            Func::Sin => self.chain(x.sin(), x.cos()),
            Func::Cos => self.chain(x.cos(), -x.sin()),
            Func::Tan => {
                let t = x.tan();
                self.chain(t, 1.0 + t * t)
            }
            Func::Asin => self.chain(x.asin(), 1.0 / (1.0 - x * x).sqrt()),
            Func::Acos => self.chain(x.acos(), -1.0 / (1.0 - x * x).sqrt()),
            Func::Atan => self.chain(x.atan(), 1.0 / (1.0 + x * x)),
            Func::Sqrt => {
                let s = x.sqrt();
                self.chain(s, 0.5 / s)
            }
            Func::Exp => {
                let e = x.exp();
                self.chain(e, e)
            }
            Func::Log => self.chain(x.ln(), 1.0 / x),
            Func::Abs => self.chain(x.abs(), if x < 0.0 { -1.0 } else { 1.0 }),
            Func::Floor => self.chain(x.floor(), 0.0),
        }
    }
    fn binary(self, op: Binary, o: Self) -> Self {
        let (a, b) = (self.v, o.v);
        // NaN in, NaN out, as in the f64 evaluation.
        if a.is_nan() || b.is_nan() {
            return Self::constant(f64::NAN);
        }
        match op {
            Binary::Add => Self::combine(a + b, self, 1.0, o, 1.0),
            Binary::Sub => Self::combine(a - b, self, 1.0, o, -1.0),
            Binary::Mul => Self::combine(a * b, self, b, o, a),
            Binary::Div => Self::combine(a / b, self, 1.0 / b, o, -a / (b * b)),
            Binary::Pow => {
                let p = a.powf(b);
                if o.is_constant() {
                    // No logarithm: defined for negative bases with integer exponents.
                    self.chain(p, if b == 0.0 { 0.0 } else { b * a.powf(b - 1.0) })
                } else {
                    Self::combine(p, self, b * a.powf(b - 1.0), o, p * a.ln())
                }
            }
            Binary::Atan2 => {
                let r2 = a * a + b * b;
                Self::combine(a.atan2(b), self, b / r2, o, -a / r2)
            }
            Binary::Min => {
                if a <= b {
                    self
                } else {
                    o
                }
            }
            Binary::Max => {
                if a >= b {
                    self
                } else {
                    o
                }
            }
        }
    }
}
