//! Combining two lists of spans along a ray (Roth, "Ray casting for modeling solids",
//! Computer Graphics and Image Processing 18, 1982): walk both lists' boundaries in
//! order of `t`, track whether the ray is inside each operand, and emit a boundary
//! wherever the combined state changes.
//!
//! **Coincident surfaces.** All boundaries at exactly the same `t` are applied together
//! before the combined state is evaluated, so boundaries that cancel leave no surface:
//! two solids touching face to face unite without an inner face, `A - A` and a tangent
//! graze are empty. When the state does change there, the emitted boundary (normal,
//! texture coordinates, leaf) is the left operand's if the left operand's state changed
//! at that `t`, otherwise the right operand's: **the left operand wins ties**.
//!
//! **Subtracted faces.** In a difference, a boundary taken from the right operand is a
//! surface of the subtracted solid seen from outside it; its normal is negated so that
//! it points out of the result.

use super::op::CsgOp;
use crate::shape::{Boundary, Span};

/// The `i`-th boundary of a span list (enter of span `i/2` for even `i`, else exit).
#[inline]
fn event(spans: &[Span], i: usize) -> &Boundary {
    let s = &spans[i >> 1];
    if i & 1 == 0 {
        &s.enter
    } else {
        &s.exit
    }
}

/// Appends `a op b` to `out`. Both inputs must be sorted, non-overlapping span lists
/// (as `Shape::spans` produces); so is the output.
pub fn combine(op: CsgOp, a: &[Span], b: &[Span], out: &mut Vec<Span>) {
    if let ([x], [y]) = (a, b) {
        if x.enter.t < x.exit.t && y.enter.t < y.exit.t {
            return combine_single(op, x, y, out);
        }
    }
    combine_walk(op, a, b, out)
}

/// The general walk behind `combine` (public so tests can compare the single-span
/// fast path with it).
pub fn combine_walk(op: CsgOp, a: &[Span], b: &[Span], out: &mut Vec<Span>) {
    let (na, nb) = (2 * a.len(), 2 * b.len());
    let (mut ia, mut ib) = (0usize, 0usize);
    let (mut in_a, mut in_b, mut inside) = (false, false, false);
    let mut enter = Boundary::NEG_INFINITY;
    while ia < na || ib < nb {
        let t = match (ia < na, ib < nb) {
            (true, true) => event(a, ia).t.min(event(b, ib).t),
            (true, false) => event(a, ia).t,
            _ => event(b, ib).t,
        };
        let (was_a, ia0, ib0) = (in_a, ia, ib);
        let (mut last_a, mut last_b) = (None, None);
        while ia < na && event(a, ia).t == t {
            in_a = ia & 1 == 0;
            last_a = Some(event(a, ia));
            ia += 1;
        }
        while ib < nb && event(b, ib).t == t {
            in_b = ib & 1 == 0;
            last_b = Some(event(b, ib));
            ib += 1;
        }
        if ia == ia0 && ib == ib0 {
            // A NaN parameter (from a degenerate ray) equals nothing: skip it rather
            // than loop for ever.
            if ia < na {
                ia += 1;
            } else {
                ib += 1;
            }
            continue;
        }
        let now = op.apply(in_a, in_b);
        if now == inside {
            continue;
        }
        let boundary = match (in_a != was_a, last_a, last_b) {
            (true, Some(x), _) => *x,
            (_, _, Some(x)) => {
                let mut x = *x;
                if op == CsgOp::Difference {
                    x.normal = -x.normal;
                }
                x
            }
            // The state changed, so some operand changed at this t.
            (_, Some(x), None) => *x,
            (_, None, None) => unreachable!("a state change without a boundary"),
        };
        if now {
            enter = boundary;
        } else {
            out.push(Span {
                enter,
                exit: boundary,
            });
        }
        inside = now;
    }
}

/// `combine` for one non-degenerate span on each side (the common case: a ray through
/// two convex solids), with the same tie rule, without the general walk.
#[inline]
fn combine_single(op: CsgOp, a: &Span, b: &Span, out: &mut Vec<Span>) {
    // The earlier of two boundaries; on a tie the left operand's.
    let first = |x: &Boundary, y: &Boundary| if y.t < x.t { *y } else { *x };
    let last = |x: &Boundary, y: &Boundary| if y.t > x.t { *y } else { *x };
    match op {
        CsgOp::Intersection => {
            let (enter, exit) = (last(&a.enter, &b.enter), first(&a.exit, &b.exit));
            if enter.t < exit.t {
                out.push(Span { enter, exit });
            }
        }
        CsgOp::Union | CsgOp::Merge => {
            if a.exit.t < b.enter.t {
                out.extend_from_slice(&[*a, *b]);
            } else if b.exit.t < a.enter.t {
                out.extend_from_slice(&[*b, *a]);
            } else {
                out.push(Span {
                    enter: first(&a.enter, &b.enter),
                    exit: last(&a.exit, &b.exit),
                });
            }
        }
        CsgOp::Difference => {
            if b.exit.t <= a.enter.t || b.enter.t >= a.exit.t {
                out.push(*a);
                return;
            }
            let flip = |x: &Boundary| {
                let mut x = *x;
                x.normal = -x.normal;
                x
            };
            if a.enter.t < b.enter.t {
                out.push(Span {
                    enter: a.enter,
                    exit: flip(&b.enter),
                });
            }
            if b.exit.t < a.exit.t {
                out.push(Span {
                    enter: flip(&b.exit),
                    exit: a.exit,
                });
            }
        }
    }
}

/// The complement of a sorted span list over the whole line, appended to `out`
/// (normals negated: they point out of the complement). Used to check
/// `A - B = A ∩ ¬B`.
pub fn complement(spans: &[Span], out: &mut Vec<Span>) {
    let flip = |b: &Boundary| {
        let mut b = *b;
        b.normal = -b.normal;
        b
    };
    let mut enter = Boundary::NEG_INFINITY;
    for s in spans {
        if s.enter.t > enter.t {
            out.push(Span {
                enter,
                exit: flip(&s.enter),
            });
        }
        enter = flip(&s.exit);
    }
    if enter.t < f32::INFINITY {
        out.push(Span {
            enter,
            exit: Boundary::INFINITY,
        });
    }
}
