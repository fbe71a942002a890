//! Strips (lecture, "Form Factor Examples 1", first and third cases).

use super::{positive, Case};
use std::f64::consts::PI;

/// Strip of finite length b and differential width to a differential strip of the same
/// length on a parallel generating line: `dF = (cos φ / π) dφ atan(b / r)`.
pub const STRIP_TO_STRIP: Case = Case {
    name: "strip-to-strip",
    geometry: "strip 1 along z from 0 to b at the origin, normal (0,1,0); strip 2 parallel at distance r \
               in direction (sin φ, cos φ, 0), facing strip 1, of angular width dφ seen from strip 1",
    params: &[
        ("b", "length of both strips"),
        ("r", "distance between the strips"),
        ("phi", "angle (radians) between strip 1's normal and the direction to strip 2"),
        ("dphi", "angular width (radians) of strip 2 seen from strip 1"),
    ],
    eval: |p| {
        let (b, r) = (positive("b", p[0])?, positive("r", p[1])?);
        let (phi, dphi) = (p[2], p[3]);
        if phi.abs() >= PI / 2.0 {
            return Err(format!("--phi {phi} must lie in (-π/2, π/2): strip 2 must be in front of strip 1"));
        }
        if dphi <= 0.0 {
            return Err(format!("--dphi {dphi} must be positive"));
        }
        Ok(phi.cos() / PI * dphi * (b / r).atan())
    },
};

/// Strip element to a rectangle in a plane parallel to the strip, the strip opposite one
/// edge of the rectangle: `F = 1/(πY) [√(1+Y²) atan(X/√(1+Y²)) − atan X + XY/√(1+X²) atan(Y/√(1+X²))]`.
pub const STRIP_PARALLEL_RECTANGLE: Case = Case {
    name: "strip-parallel-rectangle",
    geometry: "strip along y from 0 to b at x = z = 0, normal +z; rectangle x in [0,a], y in [0,b] at z = c, facing down",
    params: &[
        ("a", "side of the rectangle perpendicular to the strip"),
        ("b", "length of the strip and of the rectangle's side above it"),
        ("c", "distance between the planes"),
    ],
    eval: |p| {
        let (a, b, c) = (positive("a", p[0])?, positive("b", p[1])?, positive("c", p[2])?);
        let (x, y) = (a / c, b / c);
        let sy = (1.0 + y * y).sqrt();
        let sx = (1.0 + x * x).sqrt();
        Ok((sy * (x / sy).atan() - x.atan() + x * y / sx * (y / sx).atan()) / (PI * y))
    },
};
