//! Rectangles (lecture, "Form Factor Examples 1" second and fourth cases, and the first
//! case of "Examples 2").

use super::{positive, Case};
use std::f64::consts::PI;

/// Plane element to a parallel rectangle, the element's normal through a corner:
/// `F = 1/(2π) [X/√(1+X²) atan(Y/√(1+X²)) + Y/√(1+Y²) atan(X/√(1+Y²))]`.
pub const ELEMENT_PARALLEL_RECTANGLE: Case = Case {
    name: "element-parallel-rectangle",
    geometry: "element at the origin, normal +z; rectangle x in [0,a], y in [0,b] at z = c",
    params: &[
        ("a", "first side"),
        ("b", "second side"),
        ("c", "distance between the planes"),
    ],
    eval: |p| {
        let (a, b, c) = (
            positive("a", p[0])?,
            positive("b", p[1])?,
            positive("c", p[2])?,
        );
        let (x, y) = (a / c, b / c);
        let (sx, sy) = ((1.0 + x * x).sqrt(), (1.0 + y * y).sqrt());
        Ok((x / sx * (y / sx).atan() + y / sy * (x / sy).atan()) / (2.0 * PI))
    },
};

/// Plane element to a rectangle in a plane at 90° to the element's:
/// `F = 1/(2π) [atan(1/Y) − Y/√(X²+Y²) atan(1/√(X²+Y²))]`, `X = a/b`, `Y = c/b`.
pub const ELEMENT_PERPENDICULAR_RECTANGLE: Case = Case {
    name: "element-perpendicular-rectangle",
    geometry:
        "element at the origin, normal +z; rectangle in the plane y = c, x in [0,b], z in [0,a]",
    params: &[
        ("a", "height of the rectangle along the element's normal"),
        (
            "b",
            "width of the rectangle, from the foot of the element's perpendicular",
        ),
        ("c", "distance from the element to the rectangle's plane"),
    ],
    eval: |p| {
        let (a, b, c) = (
            positive("a", p[0])?,
            positive("b", p[1])?,
            positive("c", p[2])?,
        );
        let (x, y) = (a / b, c / b);
        let s = (x * x + y * y).sqrt();
        Ok(((1.0 / y).atan() - y / s * (1.0 / s).atan()) / (2.0 * PI))
    },
};

/// Two finite rectangles of the same length with a common edge at 90°:
/// the lecture's `F_{1-2}` with `H = h/l`, `W = w/l`.
pub const PERPENDICULAR_RECTANGLES: Case = Case {
    name: "perpendicular-rectangles",
    geometry:
        "rectangle 1: x in [0,w], y in [0,l], z = 0 (normal +z); rectangle 2: x = 0, y in [0,l], \
               z in [0,h] (normal +x); common edge along y",
    params: &[
        ("h", "height of rectangle 2 (the receiver)"),
        ("l", "length of the common edge"),
        ("w", "width of rectangle 1 (the sender)"),
    ],
    eval: |p| {
        let (h, l, w) = (
            positive("h", p[0])?,
            positive("l", p[1])?,
            positive("w", p[2])?,
        );
        Ok(perpendicular_rectangles(h / l, w / l))
    },
};

/// `F_{1-2}` for perpendicular rectangles with a common edge, `H = h/l`, `W = w/l`.
pub fn perpendicular_rectangles(hh: f64, ww: f64) -> f64 {
    let (h2, w2) = (hh * hh, ww * ww);
    let s = (h2 + w2).sqrt();
    let t1 = ww * (1.0 / ww).atan() + hh * (1.0 / hh).atan() - s * (1.0 / s).atan();
    // ln of the product, as a sum of logs for range safety.
    let l1 = ((1.0 + w2) * (1.0 + h2) / (1.0 + w2 + h2)).ln();
    let l2 = w2 * (w2 * (1.0 + w2 + h2) / ((1.0 + w2) * (w2 + h2))).ln();
    let l3 = h2 * (h2 * (1.0 + h2 + w2) / ((1.0 + h2) * (h2 + w2))).ln();
    (t1 + 0.25 * (l1 + l2 + l3)) / (PI * ww)
}
