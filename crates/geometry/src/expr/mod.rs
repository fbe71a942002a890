//! A small expression language for scene files: implicit surfaces `f(x, y, z) = 0` and
//! parametric surfaces `x(u, v), y(u, v), z(u, v)`.
//!
//! Summary / public API:
//! - Syntax: numbers (`2`, `0.5`, `1e-3`), the variables named at parse time, the
//!   constants `pi` and `e`, `+ - * / ^` (`^` binds tighter than unary minus and is right
//!   associative: `-x^2 = -(x^2)`, `2^3^2 = 2^9`), parentheses, and the functions `sin cos
//!   tan asin acos atan sqrt exp log abs floor` (one argument) and `atan2 min max pow`
//!   (two arguments).
//! - [`Expr::parse`]`(source, &["x", "y", "z"]) -> Result<Expr, ExprError>`; an
//!   [`ExprError`] carries the 1-based column of the offending character.
//! - [`Expr::eval`] in f64; [`Expr::eval_interval`] in interval arithmetic
//!   ([`Interval`], sound outward-rounded enclosures); [`Expr::eval_gradient`] value and
//!   gradient with respect to the first three variables by forward-mode dual numbers
//!   ([`Dual`]); [`Expr::eval_interval_directional`] encloses value and directional
//!   derivative over a box ([`IntervalDual`]), for monotonicity tests.
//!
//! Parsing builds an AST ([`Node`]); it is then compiled to a postfix tape that one
//! generic evaluator runs for every number type ([`Number`]): f64, [`Interval`] and
//! [`Dual`]. Interval arithmetic after Moore, *Interval Analysis* (1966); its use for ray
//! casting implicit surfaces is Mitchell, "Robust ray intersection with interval
//! arithmetic", Graphics Interface 1990.

mod ast;
mod dual;
mod interval;
mod interval_dual;
mod lexer;
mod number;
mod parser;
mod tape;

pub use ast::{Binary, Func, Node};
pub use dual::Dual;
pub use interval::Interval;
pub use interval_dual::IntervalDual;
pub use number::Number;
pub use parser::ExprError;

use tape::Tape;

/// A parsed, compiled expression over named variables.
#[derive(Clone, Debug)]
pub struct Expr {
    source: String,
    variables: Vec<String>,
    ast: Node,
    tape: Tape,
}

impl Expr {
    /// Parses `source` with the given variable names (which must not be `pi` or `e` or a
    /// function name). Errors name the 1-based column.
    pub fn parse(source: &str, variables: &[&str]) -> Result<Expr, ExprError> {
        let ast = parser::parse(source, variables)?;
        let ast = ast.fold_constants();
        let tape = Tape::compile(&ast);
        Ok(Expr {
            source: source.to_string(),
            variables: variables.iter().map(|s| s.to_string()).collect(),
            ast,
            tape,
        })
    }

    pub fn source(&self) -> &str {
        &self.source
    }

    pub fn variables(&self) -> &[String] {
        &self.variables
    }

    /// The syntax tree (after constant folding).
    pub fn ast(&self) -> &Node {
        &self.ast
    }

    /// Value in f64. `vars` holds one value per variable, in the order given to `parse`.
    pub fn eval(&self, vars: &[f64]) -> f64 {
        self.tape.run(vars)
    }

    /// A sound enclosure of the range of the expression over the box `vars`. An empty
    /// interval means the expression is undefined everywhere in the box (e.g. `sqrt` of
    /// a negative interval).
    pub fn eval_interval(&self, vars: &[Interval]) -> Interval {
        self.tape.run(vars)
    }

    /// Enclosures over the box `vars` of the value and of the directional derivative
    /// `∇f · dir` (`dir` holds one rate per variable). When the second excludes 0 the
    /// expression is strictly monotone along `dir` on the box.
    pub fn eval_interval_directional(
        &self,
        vars: &[Interval],
        dir: &[f64],
    ) -> (Interval, Interval) {
        let mut duals = [IntervalDual::constant(f64::NAN); 8];
        let n = vars.len().min(8);
        for i in 0..n {
            duals[i] = IntervalDual::variable(vars[i], dir.get(i).copied().unwrap_or(0.0));
        }
        let r = self.tape.run(&duals[..n]);
        (r.v, r.d)
    }

    /// Value and gradient with respect to the first (up to) three variables (at most
    /// eight variables are read).
    pub fn eval_gradient(&self, vars: &[f64]) -> (f64, [f64; 3]) {
        let mut duals = [Dual::constant(f64::NAN); 8];
        let n = vars.len().min(8);
        for (i, &v) in vars[..n].iter().enumerate() {
            duals[i] = Dual::variable(v, i);
        }
        let d = self.tape.run(&duals[..n]);
        (d.v, d.d)
    }

    /// Whether the expression mentions variable number `index`.
    pub fn uses_variable(&self, index: usize) -> bool {
        self.ast.uses_variable(index)
    }
}

impl std::fmt::Display for Expr {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.source)
    }
}
