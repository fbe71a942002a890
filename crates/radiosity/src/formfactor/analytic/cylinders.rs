//! Cylinders (lecture, "Form Factor Examples 3").

use super::{positive, Case};
use std::f64::consts::PI;

/// Strip element of any length to a parallel infinitely long cylinder:
/// `F = Y / (X² + Y²)`, `X = x/r`, `Y = y/r`.
pub const STRIP_CYLINDER: Case = Case {
    name: "strip-cylinder",
    geometry:
        "strip along z in the plane y = 0 (normal +y); cylinder of radius r with its axis along z \
               through (x, y); y > r keeps the cylinder above the strip's plane",
    params: &[
        ("x", "offset of the axis along the strip's plane"),
        ("y", "height of the axis above the strip's plane"),
        ("r", "radius of the cylinder"),
    ],
    eval: |p| {
        let (x, y, r) = (p[0], positive("y", p[1])?, positive("r", p[2])?);
        if y < r {
            return Err(format!(
                "--y {y} must be at least --r {r}: the cylinder must not cross the strip's plane"
            ));
        }
        let (xx, yy) = (x / r, y / r);
        Ok(yy / (xx * xx + yy * yy))
    },
};

/// Element of any length on a cylinder to an infinite plane: `F = ½ (1 + cos φ)`.
pub const CYLINDER_ELEMENT_PLANE: Case = Case {
    name: "cylinder-element-plane",
    geometry: "element on a cylinder whose normal makes the angle φ with the direction straight towards an \
               infinite plane (the normal of the plane, reversed)",
    params: &[("phi", "angle (radians, 0..π) between the element's normal and the direction to the plane")],
    eval: |p| {
        let phi = p[0];
        if !(0.0..=PI).contains(&phi) {
            return Err(format!("--phi {phi} must lie in [0, π]"));
        }
        Ok(0.5 * (1.0 + phi.cos()))
    },
};
