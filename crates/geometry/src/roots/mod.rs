//! Real roots of polynomials in f64, for the torus (a quartic in the ray parameter) and
//! any other shape whose intersection is a polynomial equation.
//!
//! Summary:
//! - [`Polynomial`]: coefficients in ascending order, evaluation (Horner), derivative.
//! - [`solve_quadratic`]: the numerically stable quadratic formula.
//! - [`real_roots_in`]: every real root of a polynomial of any degree inside a finite
//!   interval, by *derivative isolation*: the roots of `p'` split the interval into
//!   pieces on which `p` is monotone, so each piece holds at most one root, which a
//!   safeguarded Newton iteration (Newton steps kept inside a shrinking sign-change
//!   bracket, bisection when a step leaves it; "rtsafe", Numerical Recipes §9.4) finds
//!   to full precision. The roots of `p'` are found the same way, recursively, down to
//!   the quadratic. Unlike a closed-form quartic (Ferrari), no root is lost to
//!   cancellation in the resolvent cubic: a root is reported exactly when `p` changes
//!   sign, which is the property ray casting needs (Collins and Loos, "Real zeros of
//!   polynomials", 1982, describe the same isolation by derivative sequences).
//! - [`solve_quartic`]: Ferrari's closed form, each root polished by Newton on the
//!   original polynomial; kept as an independent check of [`real_roots_in`].

mod closed_form;
mod isolate;
mod polynomial;

pub use closed_form::{solve_cubic, solve_quartic};
pub use isolate::{real_roots_in, refine_bracketed};
pub use polynomial::{solve_quadratic, Polynomial};
