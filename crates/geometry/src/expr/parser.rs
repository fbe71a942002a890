//! Recursive-descent parser with precedence levels:
//! `sum := product (('+'|'-') product)*`, `product := unary (('*'|'/') unary)*`,
//! `unary := ('-'|'+') unary | power`, `power := primary ('^' unary)?` (right
//! associative, so `-x^2 = -(x^2)` and `2^-1` is allowed),
//! `primary := number | constant | variable | function '(' args ')' | '(' sum ')'`.

use super::ast::{Binary, Func, Node};
use super::lexer::{tokenize, Token};

/// A parse error at a 1-based column of the expression.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ExprError {
    pub column: usize,
    pub message: String,
}

impl ExprError {
    pub fn new(column: usize, message: impl Into<String>) -> Self {
        Self {
            column,
            message: message.into(),
        }
    }
}

impl std::fmt::Display for ExprError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "column {}: {}", self.column, self.message)
    }
}

impl std::error::Error for ExprError {}

/// Nesting deeper than this is refused (it would overflow the stack).
const MAX_DEPTH: usize = 200;

pub fn parse(src: &str, variables: &[&str]) -> Result<Node, ExprError> {
    for v in variables {
        if *v == "pi" || *v == "e" || Func::from_name(v).is_some() {
            return Err(ExprError::new(
                1,
                format!("'{v}' cannot be a variable name"),
            ));
        }
    }
    let tokens = tokenize(src)?;
    if tokens.len() == 1 {
        return Err(ExprError::new(1, "the expression is empty"));
    }
    let mut p = Parser {
        tokens,
        pos: 0,
        variables,
        depth: 0,
    };
    let node = p.sum()?;
    let (tok, col) = p.peek();
    if *tok != Token::End {
        let msg = if *tok == Token::RParen {
            "unmatched ')'".to_string()
        } else {
            format!("expected an operator, found {}", tok.describe())
        };
        return Err(ExprError::new(col, msg));
    }
    Ok(node)
}

struct Parser<'a> {
    tokens: Vec<(Token, usize)>,
    pos: usize,
    variables: &'a [&'a str],
    depth: usize,
}

impl Parser<'_> {
    fn peek(&self) -> (&Token, usize) {
        let (t, c) = &self.tokens[self.pos];
        (t, *c)
    }
    fn next(&mut self) -> (Token, usize) {
        let t = self.tokens[self.pos].clone();
        if self.pos + 1 < self.tokens.len() {
            self.pos += 1;
        }
        t
    }

    fn sum(&mut self) -> Result<Node, ExprError> {
        let mut left = self.product()?;
        loop {
            let op = match self.peek().0 {
                Token::Plus => Binary::Add,
                Token::Minus => Binary::Sub,
                _ => return Ok(left),
            };
            self.next();
            let right = self.product()?;
            left = Node::Binary(op, Box::new(left), Box::new(right));
        }
    }

    fn product(&mut self) -> Result<Node, ExprError> {
        let mut left = self.unary()?;
        loop {
            let op = match self.peek().0 {
                Token::Star => Binary::Mul,
                Token::Slash => Binary::Div,
                _ => return Ok(left),
            };
            self.next();
            let right = self.unary()?;
            left = Node::Binary(op, Box::new(left), Box::new(right));
        }
    }

    fn unary(&mut self) -> Result<Node, ExprError> {
        let col = self.peek().1;
        self.depth += 1;
        if self.depth > MAX_DEPTH {
            return Err(ExprError::new(col, "the expression is nested too deeply"));
        }
        let r = match self.peek().0 {
            Token::Minus => {
                self.next();
                Ok(Node::Neg(Box::new(self.unary()?)))
            }
            Token::Plus => {
                self.next();
                self.unary()
            }
            _ => self.power(),
        };
        self.depth -= 1;
        r
    }

    fn power(&mut self) -> Result<Node, ExprError> {
        let base = self.primary()?;
        if *self.peek().0 == Token::Caret {
            self.next();
            let exponent = self.unary()?;
            return Ok(Node::Binary(
                Binary::Pow,
                Box::new(base),
                Box::new(exponent),
            ));
        }
        Ok(base)
    }

    fn primary(&mut self) -> Result<Node, ExprError> {
        let (tok, col) = self.next();
        match tok {
            Token::Number(v) => Ok(Node::Const(v)),
            Token::LParen => {
                let inner = self.sum()?;
                self.expect_close(col)?;
                Ok(inner)
            }
            Token::Ident(name) => {
                if *self.peek().0 == Token::LParen {
                    return self.call(&name, col);
                }
                if let Some(i) = self.variables.iter().position(|v| *v == name) {
                    return Ok(Node::Var(i));
                }
                match name.as_str() {
                    "pi" => Ok(Node::Const(std::f64::consts::PI)),
                    "e" => Ok(Node::Const(std::f64::consts::E)),
                    _ if Func::from_name(&name).is_some()
                        || Binary::from_function_name(&name).is_some() =>
                    {
                        Err(ExprError::new(
                            col,
                            format!("function '{name}' needs arguments in parentheses"),
                        ))
                    }
                    _ => Err(ExprError::new(
                        col,
                        format!(
                            "unknown name '{name}' (variables: {}; constants: pi, e)",
                            if self.variables.is_empty() {
                                "none".to_string()
                            } else {
                                self.variables.join(", ")
                            }
                        ),
                    )),
                }
            }
            Token::End => Err(ExprError::new(col, "unexpected end of the expression")),
            other => Err(ExprError::new(
                col,
                format!("expected a number, name or '(', found {}", other.describe()),
            )),
        }
    }

    fn expect_close(&mut self, open_col: usize) -> Result<(), ExprError> {
        let (tok, col) = self.next();
        match tok {
            Token::RParen => Ok(()),
            Token::End => Err(ExprError::new(
                col,
                format!("missing ')' for the '(' at column {open_col}"),
            )),
            other => Err(ExprError::new(
                col,
                format!("expected ')', found {}", other.describe()),
            )),
        }
    }

    fn call(&mut self, name: &str, col: usize) -> Result<Node, ExprError> {
        let (_, open_col) = self.next(); // '('
        let mut args = vec![self.sum()?];
        while *self.peek().0 == Token::Comma {
            self.next();
            args.push(self.sum()?);
        }
        self.expect_close(open_col)?;
        let arity_error = |want: usize| {
            ExprError::new(
                col,
                format!(
                    "function '{name}' takes {want} argument{}, got {}",
                    if want == 1 { "" } else { "s" },
                    args.len()
                ),
            )
        };
        if let Some(f) = Func::from_name(name) {
            if args.len() != 1 {
                return Err(arity_error(1));
            }
            return Ok(Node::Call(f, Box::new(args.pop().unwrap())));
        }
        if let Some(op) = Binary::from_function_name(name) {
            if args.len() != 2 {
                return Err(arity_error(2));
            }
            let b = args.pop().unwrap();
            let a = args.pop().unwrap();
            return Ok(Node::Binary(op, Box::new(a), Box::new(b)));
        }
        Err(ExprError::new(
            col,
            format!(
                "unknown function '{name}' (known: sin cos tan asin acos atan atan2 sqrt exp \
                 log abs min max pow floor)"
            ),
        ))
    }
}
