//! The AST compiled to a postfix tape, run on a value stack by one generic evaluator.

use super::ast::{Binary, Func, Node};
use super::number::Number;

#[derive(Clone, Copy, Debug)]
enum Op {
    Const(f64),
    Var(u32),
    Neg,
    PowI(i32),
    Call(Func),
    Binary(Binary),
}

#[derive(Clone, Debug)]
pub struct Tape {
    ops: Vec<Op>,
    max_stack: usize,
}

/// Tapes whose stack fits this many values run without allocating.
const INLINE_STACK: usize = 24;

impl Tape {
    pub fn compile(node: &Node) -> Tape {
        let mut ops = Vec::new();
        emit(node, &mut ops);
        let mut depth = 0usize;
        let mut max_stack = 0usize;
        for op in &ops {
            match op {
                Op::Const(_) | Op::Var(_) => depth += 1,
                Op::Binary(_) => depth -= 1,
                _ => {}
            }
            max_stack = max_stack.max(depth);
        }
        Tape { ops, max_stack }
    }

    /// Runs the tape. A variable index beyond `vars` reads as NaN (the parser only
    /// produces indices of declared variables, so this happens only when a caller passes
    /// too few values).
    pub fn run<T: Number>(&self, vars: &[T]) -> T {
        if self.max_stack <= INLINE_STACK {
            let mut stack = [T::constant(0.0); INLINE_STACK];
            self.run_on(vars, &mut stack)
        } else {
            let mut stack = vec![T::constant(0.0); self.max_stack];
            self.run_on(vars, &mut stack)
        }
    }

    fn run_on<T: Number>(&self, vars: &[T], stack: &mut [T]) -> T {
        let mut sp = 0usize;
        for op in &self.ops {
            match *op {
                Op::Const(c) => {
                    stack[sp] = T::constant(c);
                    sp += 1;
                }
                Op::Var(i) => {
                    stack[sp] = vars
                        .get(i as usize)
                        .copied()
                        .unwrap_or(T::constant(f64::NAN));
                    sp += 1;
                }
                Op::Neg => stack[sp - 1] = stack[sp - 1].neg(),
                Op::PowI(n) => stack[sp - 1] = stack[sp - 1].powi(n),
                Op::Call(f) => stack[sp - 1] = stack[sp - 1].unary(f),
                Op::Binary(b) => {
                    sp -= 1;
                    stack[sp - 1] = stack[sp - 1].binary(b, stack[sp]);
                }
            }
        }
        stack[0]
    }
}

fn emit(node: &Node, ops: &mut Vec<Op>) {
    match node {
        Node::Const(c) => ops.push(Op::Const(*c)),
        Node::Var(i) => ops.push(Op::Var(*i as u32)),
        Node::Neg(a) => {
            emit(a, ops);
            ops.push(Op::Neg);
        }
        Node::PowI(a, n) => {
            emit(a, ops);
            ops.push(Op::PowI(*n));
        }
        Node::Call(f, a) => {
            emit(a, ops);
            ops.push(Op::Call(*f));
        }
        Node::Binary(op, a, b) => {
            emit(a, ops);
            emit(b, ops);
            ops.push(Op::Binary(*op));
        }
    }
}
