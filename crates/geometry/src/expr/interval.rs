//! Interval arithmetic with outward rounding: every operation returns an interval that
//! contains the exact result for every choice of arguments in its input intervals
//! (Moore, *Interval Analysis*, 1966; the trigonometric cases follow Hickey, Ju and van
//! Emden, "Interval arithmetic: from principles to implementation", JACM 2001).
//!
//! Rounding: the basic operations and `sqrt` are correctly rounded in IEEE 754, so
//! moving each bound out by one ulp encloses the exact result; library functions
//! (`sin`, `exp`, `powf`, ...) are moved out by a few ulps more. Domains: outside the
//! domain of a function (`sqrt` of negatives, `log` of non-positives, `asin` beyond ±1)
//! the interval is clipped to the domain; an interval entirely outside is [`Interval::EMPTY`].
//! Division by an interval containing 0 gives [`Interval::ENTIRE`].

// `!(a < b)` comparisons are deliberate: they are also true when a value is NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use super::ast::{Binary, Func};
use super::number::Number;
use std::f64::consts::{FRAC_PI_2, PI};

/// The closed interval `[lo, hi]`; empty when `lo > hi`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Interval {
    pub lo: f64,
    pub hi: f64,
}

/// Ulps added to each bound of a library function's result.
const LIB_ULPS: f64 = 4.0;

/// Moves `x` down by at least `k` ulps (k >= 1); infinities stay.
#[inline]
fn down(x: f64, k: f64) -> f64 {
    if x.is_finite() {
        x - (x.abs() * f64::EPSILON * k + f64::from_bits(1) * k.max(1.0))
    } else {
        x
    }
}

#[inline]
fn up(x: f64, k: f64) -> f64 {
    -down(-x, k)
}

impl Interval {
    pub const EMPTY: Interval = Interval {
        lo: f64::INFINITY,
        hi: f64::NEG_INFINITY,
    };
    pub const ENTIRE: Interval = Interval {
        lo: f64::NEG_INFINITY,
        hi: f64::INFINITY,
    };

    /// `[lo, hi]`; an empty interval if `lo > hi` or either is NaN.
    pub fn new(lo: f64, hi: f64) -> Self {
        if lo <= hi {
            Self { lo, hi }
        } else {
            Self::EMPTY
        }
    }

    pub fn point(x: f64) -> Self {
        Self::new(x, x)
    }

    pub fn is_empty(&self) -> bool {
        !(self.lo <= self.hi)
    }

    pub fn contains(&self, x: f64) -> bool {
        self.lo <= x && x <= self.hi
    }

    pub fn width(&self) -> f64 {
        self.hi - self.lo
    }

    pub fn midpoint(&self) -> f64 {
        0.5 * (self.lo + self.hi)
    }

    /// The smallest interval containing both.
    pub fn hull(self, o: Interval) -> Interval {
        if self.is_empty() {
            return o;
        }
        if o.is_empty() {
            return self;
        }
        Interval::new(self.lo.min(o.lo), self.hi.max(o.hi))
    }

    fn widened(lo: f64, hi: f64, k: f64) -> Interval {
        Interval::new(down(lo, k), up(hi, k))
    }

    /// Bounds of `f` over the interval for a non-decreasing `f`, widened by library ulps.
    fn increasing(self, f: impl Fn(f64) -> f64) -> Interval {
        Self::widened(f(self.lo), f(self.hi), LIB_ULPS)
    }

    fn mul(self, o: Interval) -> Interval {
        // 0 * inf counts as 0, the convention of interval arithmetic (the product of any
        // real in one factor by any real in the other is finite).
        let m = |a: f64, b: f64| {
            let p = a * b;
            if p.is_nan() {
                0.0
            } else {
                p
            }
        };
        let p = [
            m(self.lo, o.lo),
            m(self.lo, o.hi),
            m(self.hi, o.lo),
            m(self.hi, o.hi),
        ];
        let lo = p.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = p.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        Self::widened(lo, hi, 1.0)
    }

    fn div(self, o: Interval) -> Interval {
        if o.lo <= 0.0 && o.hi >= 0.0 {
            // Includes division by exactly 0, which f64 answers with ±inf.
            return Interval::ENTIRE;
        }
        let q = [
            self.lo / o.lo,
            self.lo / o.hi,
            self.hi / o.lo,
            self.hi / o.hi,
        ];
        if q.iter().any(|v| v.is_nan()) {
            return Interval::ENTIRE;
        }
        let lo = q.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = q.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        Self::widened(lo, hi, 1.0)
    }

    fn powi_interval(self, n: i32) -> Interval {
        if n == 0 {
            return Interval::point(1.0);
        }
        if n < 0 {
            return Interval::point(1.0).div(self.powi_interval(-n));
        }
        // powi is not correctly rounded: allow n ulps of error.
        let k = n as f64 + 1.0;
        let (a, b) = (self.lo.powi(n), self.hi.powi(n));
        if n % 2 == 1 || self.lo >= 0.0 {
            Self::widened(a, b, k)
        } else if self.hi <= 0.0 {
            Self::widened(b, a, k)
        } else {
            Interval::new(0.0, up(a.max(b), k))
        }
    }

    fn pow(self, o: Interval) -> Interval {
        if o.lo == o.hi && o.lo.fract() == 0.0 && o.lo.abs() <= 1024.0 {
            return self.powi_interval(o.lo as i32);
        }
        if o.lo == o.hi {
            // Non-integer constant exponent: defined for bases >= 0 only.
            let base = Interval::new(self.lo.max(0.0), self.hi);
            if base.is_empty() {
                return Interval::EMPTY;
            }
            let b = o.lo;
            let (x, y) = (base.lo.powf(b), base.hi.powf(b));
            return Self::widened(x.min(y), x.max(y), LIB_ULPS);
        }
        if self.lo < 0.0 {
            // A negative base with an exponent that may be an integer: no useful bound.
            return Interval::ENTIRE;
        }
        // a^b = exp(b ln a) for a >= 0.
        self.unary_interval(Func::Log)
            .mul(o)
            .unary_interval(Func::Exp)
    }

    /// Whether some `c + k * period` (k integer) lies in `[lo, hi]`, counting points
    /// within a small slack as inside (erring towards "yes" keeps the result sound).
    fn contains_periodic(self, c: f64, period: f64) -> bool {
        let slack = 1e-9 * (1.0 + self.lo.abs().max(self.hi.abs()));
        let k = ((self.lo - slack - c) / period).ceil();
        c + k * period <= self.hi + slack
    }

    fn unary_interval(self, f: Func) -> Interval {
        if self.is_empty() {
            return self;
        }
        let finite = self.lo.is_finite() && self.hi.is_finite();
        match f {
            Func::Sin | Func::Cos => {
                if !finite || self.width() >= 2.0 * PI {
                    return Interval::new(-1.0, 1.0);
                }
                // Maxima and minima of sin at pi/2 and -pi/2 (+2k pi); of cos at 0 and pi.
                let (max_at, min_at) = if f == Func::Sin {
                    (FRAC_PI_2, -FRAC_PI_2)
                } else {
                    (0.0, PI)
                };
                let g = |x: f64| if f == Func::Sin { x.sin() } else { x.cos() };
                let (a, b) = (g(self.lo), g(self.hi));
                let mut lo = down(a.min(b), LIB_ULPS).max(-1.0);
                let mut hi = up(a.max(b), LIB_ULPS).min(1.0);
                if self.contains_periodic(max_at, 2.0 * PI) {
                    hi = 1.0;
                }
                if self.contains_periodic(min_at, 2.0 * PI) {
                    lo = -1.0;
                }
                Interval::new(lo, hi)
            }
            Func::Tan => {
                if !finite || self.width() >= PI || self.contains_periodic(FRAC_PI_2, PI) {
                    return Interval::ENTIRE;
                }
                self.increasing(f64::tan)
            }
            Func::Asin | Func::Acos => {
                let c = Interval::new(self.lo.max(-1.0), self.hi.min(1.0));
                if c.is_empty() {
                    return Interval::EMPTY;
                }
                if f == Func::Asin {
                    c.increasing(f64::asin)
                } else {
                    Self::widened(c.hi.acos(), c.lo.acos(), LIB_ULPS)
                }
            }
            Func::Atan => self.increasing(f64::atan),
            Func::Sqrt => {
                if self.hi < 0.0 {
                    return Interval::EMPTY;
                }
                Self::widened(self.lo.max(0.0).sqrt(), self.hi.sqrt(), 1.0).clamp_lo(0.0)
            }
            Func::Exp => self.increasing(f64::exp).clamp_lo(0.0),
            Func::Log => {
                if self.hi < 0.0 {
                    return Interval::EMPTY;
                }
                let lo = if self.lo <= 0.0 {
                    f64::NEG_INFINITY
                } else {
                    self.lo.ln()
                };
                Self::widened(lo, self.hi.ln(), LIB_ULPS)
            }
            Func::Abs => {
                if self.lo >= 0.0 {
                    self
                } else if self.hi <= 0.0 {
                    Interval::new(-self.hi, -self.lo)
                } else {
                    Interval::new(0.0, (-self.lo).max(self.hi))
                }
            }
            Func::Floor => Interval::new(self.lo.floor(), self.hi.floor()),
        }
    }

    fn clamp_lo(self, m: f64) -> Interval {
        if self.is_empty() {
            return self;
        }
        Interval::new(self.lo.max(m), self.hi)
    }

    fn atan2(y: Interval, x: Interval) -> Interval {
        // Boxes touching the negative x axis (the branch cut) or the origin: everything.
        if x.lo <= 0.0 && y.lo <= 0.0 && y.hi >= 0.0 {
            return Interval::new(-PI, PI).widen_by(LIB_ULPS);
        }
        // Otherwise the angle is continuous over the (convex) box and its extremes are
        // at corners.
        let c = [
            y.lo.atan2(x.lo),
            y.lo.atan2(x.hi),
            y.hi.atan2(x.lo),
            y.hi.atan2(x.hi),
        ];
        let lo = c.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = c.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        Self::widened(lo, hi, LIB_ULPS)
    }

    fn widen_by(self, k: f64) -> Interval {
        Self::widened(self.lo, self.hi, k)
    }
}

impl Number for Interval {
    fn constant(c: f64) -> Self {
        Interval::point(c)
    }
    fn neg(self) -> Self {
        if self.is_empty() {
            return self;
        }
        Interval::new(-self.hi, -self.lo)
    }
    fn powi(self, n: i32) -> Self {
        if self.is_empty() {
            return self;
        }
        self.powi_interval(n)
    }
    fn unary(self, f: Func) -> Self {
        self.unary_interval(f)
    }
    fn binary(self, op: Binary, o: Self) -> Self {
        if self.is_empty() || o.is_empty() {
            return Interval::EMPTY;
        }
        match op {
            Binary::Add => Self::widened(self.lo + o.lo, self.hi + o.hi, 1.0),
            Binary::Sub => Self::widened(self.lo - o.hi, self.hi - o.lo, 1.0),
            Binary::Mul => self.mul(o),
            Binary::Div => self.div(o),
            Binary::Pow => self.pow(o),
            Binary::Atan2 => Self::atan2(self, o),
            Binary::Min => Interval::new(self.lo.min(o.lo), self.hi.min(o.hi)),
            Binary::Max => Interval::new(self.lo.max(o.lo), self.hi.max(o.hi)),
        }
    }
}
