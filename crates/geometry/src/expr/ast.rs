//! The syntax tree of an expression, constant folding, and a fully parenthesised
//! printer (used by tests to check precedence).

use super::number::Number;

/// Functions of one argument.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Func {
    Sin,
    Cos,
    Tan,
    Asin,
    Acos,
    Atan,
    Sqrt,
    Exp,
    Log,
    Abs,
    Floor,
}

/// Operators and functions of two arguments.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Binary {
    Add,
    Sub,
    Mul,
    Div,
    /// `a ^ b` and `pow(a, b)`.
    Pow,
    Atan2,
    Min,
    Max,
}

impl Func {
    pub fn from_name(name: &str) -> Option<Func> {
        Some(match name {
            "sin" => Func::Sin,
            "cos" => Func::Cos,
            "tan" => Func::Tan,
            "asin" => Func::Asin,
            "acos" => Func::Acos,
            "atan" => Func::Atan,
            "sqrt" => Func::Sqrt,
            "exp" => Func::Exp,
            "log" => Func::Log,
            "abs" => Func::Abs,
            "floor" => Func::Floor,
            _ => return None,
        })
    }
    pub fn name(self) -> &'static str {
        match self {
            Func::Sin => "sin",
            Func::Cos => "cos",
            Func::Tan => "tan",
            Func::Asin => "asin",
            Func::Acos => "acos",
            Func::Atan => "atan",
            Func::Sqrt => "sqrt",
            Func::Exp => "exp",
            Func::Log => "log",
            Func::Abs => "abs",
            Func::Floor => "floor",
        }
    }
}

impl Binary {
    /// The two-argument functions callable by name.
    pub fn from_function_name(name: &str) -> Option<Binary> {
        Some(match name {
            "atan2" => Binary::Atan2,
            "min" => Binary::Min,
            "max" => Binary::Max,
            "pow" => Binary::Pow,
            _ => return None,
        })
    }
    fn symbol(self) -> &'static str {
        match self {
            Binary::Add => "+",
            Binary::Sub => "-",
            Binary::Mul => "*",
            Binary::Div => "/",
            Binary::Pow => "^",
            Binary::Atan2 => "atan2",
            Binary::Min => "min",
            Binary::Max => "max",
        }
    }
}

/// A node of the syntax tree.
#[derive(Clone, Debug, PartialEq)]
pub enum Node {
    Const(f64),
    /// Index into the variable list given to the parser.
    Var(usize),
    Neg(Box<Node>),
    /// `a ^ n` with a small integer constant `n` (from constant folding): exact rules
    /// for even powers in interval arithmetic and no logarithm in the derivative.
    PowI(Box<Node>, i32),
    Call(Func, Box<Node>),
    Binary(Binary, Box<Node>, Box<Node>),
}

impl Node {
    /// Evaluates constant sub-trees and turns `a ^ n` for integer constants
    /// `|n| <= 64` into [`Node::PowI`].
    pub fn fold_constants(self) -> Node {
        match self {
            Node::Neg(a) => match a.fold_constants() {
                Node::Const(c) => Node::Const(-c),
                a => Node::Neg(Box::new(a)),
            },
            Node::Call(f, a) => match a.fold_constants() {
                Node::Const(c) => Node::Const(c.unary(f)),
                a => Node::Call(f, Box::new(a)),
            },
            Node::PowI(a, n) => Node::PowI(Box::new(a.fold_constants()), n),
            Node::Binary(op, a, b) => {
                let (a, b) = (a.fold_constants(), b.fold_constants());
                match (a, b) {
                    (Node::Const(x), Node::Const(y)) => Node::Const(x.binary(op, y)),
                    (a, Node::Const(n))
                        if op == Binary::Pow && n.fract() == 0.0 && n.abs() <= 64.0 =>
                    {
                        Node::PowI(Box::new(a), n as i32)
                    }
                    (a, b) => Node::Binary(op, Box::new(a), Box::new(b)),
                }
            }
            n => n,
        }
    }

    pub fn uses_variable(&self, index: usize) -> bool {
        match self {
            Node::Const(_) => false,
            Node::Var(i) => *i == index,
            Node::Neg(a) | Node::PowI(a, _) | Node::Call(_, a) => a.uses_variable(index),
            Node::Binary(_, a, b) => a.uses_variable(index) || b.uses_variable(index),
        }
    }

    /// Fully parenthesised form with variables written as `$0, $1, ...`.
    pub fn to_parenthesised(&self) -> String {
        match self {
            Node::Const(c) => format!("{c}"),
            Node::Var(i) => format!("${i}"),
            Node::Neg(a) => format!("(-{})", a.to_parenthesised()),
            Node::PowI(a, n) => format!("({}^{n})", a.to_parenthesised()),
            Node::Call(f, a) => format!("{}({})", f.name(), a.to_parenthesised()),
            Node::Binary(op, a, b) => match op {
                Binary::Atan2 | Binary::Min | Binary::Max => format!(
                    "{}({}, {})",
                    op.symbol(),
                    a.to_parenthesised(),
                    b.to_parenthesised()
                ),
                _ => format!(
                    "({} {} {})",
                    a.to_parenthesised(),
                    op.symbol(),
                    b.to_parenthesised()
                ),
            },
        }
    }
}
