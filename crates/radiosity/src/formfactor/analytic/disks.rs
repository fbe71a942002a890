//! Disks and the elliptical plate (lecture, "Form Factor Examples 2" and "3").

use super::{positive, Case};

/// Plane element to a coaxial parallel disk: `F = r² / (h² + r²)`.
pub const ELEMENT_COAXIAL_DISK: Case = Case {
    name: "element-coaxial-disk",
    geometry:
        "element at the origin, normal +z; disk of radius r centred at (0,0,h) in the plane z = h",
    params: &[("h", "distance to the disk"), ("r", "radius of the disk")],
    eval: |p| {
        let (h, r) = (positive("h", p[0])?, positive("r", p[1])?);
        Ok(r * r / (h * h + r * r))
    },
};

/// Plane element to a parallel disk whose axis is offset by `a`:
/// `F = ½ (1 − (1 + H² − R²) / √(Z² − 4R²))`, `H = h/a`, `R = r/a`, `Z = 1 + H² + R²`.
pub const ELEMENT_OFFSET_DISK: Case = Case {
    name: "element-offset-disk",
    geometry:
        "element at the origin, normal +z; disk of radius r centred at (a,0,h) in the plane z = h",
    params: &[
        ("h", "distance between the planes"),
        ("r", "radius of the disk"),
        ("a", "offset of the disk's axis from the element"),
    ],
    eval: |p| {
        let (h, r, a) = (
            positive("h", p[0])?,
            positive("r", p[1])?,
            positive("a", p[2])?,
        );
        let (hh, rr) = (h / a, r / a);
        let z = 1.0 + hh * hh + rr * rr;
        Ok(0.5 * (1.0 - (1.0 + hh * hh - rr * rr) / (z * z - 4.0 * rr * rr).sqrt()))
    },
};

/// Plane element to a disk in a perpendicular plane:
/// `F = (H/2) (Z / √(Z² − 4R²) − 1)`, `H = h/l`, `R = r/l`, `Z = 1 + H² + R²`.
pub const ELEMENT_PERPENDICULAR_DISK: Case = Case {
    name: "element-perpendicular-disk",
    geometry: "element at the origin, normal +z; disk of radius r in the plane x = h, centred at (h,0,l), \
               facing the element (l > r keeps the disk above the element's plane)",
    params: &[
        ("h", "distance from the element to the disk's plane"),
        ("r", "radius of the disk"),
        ("l", "height of the disk's centre above the element's plane"),
    ],
    eval: |p| {
        let (h, r, l) = (positive("h", p[0])?, positive("r", p[1])?, positive("l", p[2])?);
        if l < r {
            return Err(format!("--l {l} must be at least --r {r}: the disk must not cross the element's plane"));
        }
        let (hh, rr) = (h / l, r / l);
        let z = 1.0 + hh * hh + rr * rr;
        Ok(0.5 * hh * (z / (z * z - 4.0 * rr * rr).sqrt() - 1.0))
    },
};

/// Plane element to a parallel elliptical plate centred on its normal:
/// `F = ab / √((h² + a²)(h² + b²))`.
pub const ELEMENT_ELLIPTICAL_PLATE: Case = Case {
    name: "element-elliptical-plate",
    geometry: "element at the origin, normal +z; ellipse with semi-axes a (along x) and b (along y) centred at (0,0,h)",
    params: &[("a", "semi-axis along x"), ("b", "semi-axis along y"), ("h", "distance to the plate")],
    eval: |p| {
        let (a, b, h) = (positive("a", p[0])?, positive("b", p[1])?, positive("h", p[2])?);
        Ok(a * b / ((h * h + a * a) * (h * h + b * b)).sqrt())
    },
};

/// Parallel coaxial disks: `F_{1-2} = ½ [X − √(X² − 4 (R₂/R₁)²)]`,
/// `R_i = r_i/h`, `X = 1 + (1 + R₂²)/R₁²`.
pub const COAXIAL_DISKS: Case = Case {
    name: "coaxial-disks",
    geometry: "disk 1 of radius r1 at z = 0 (normal +z), disk 2 of radius r2 at z = h, both centred on the z axis",
    params: &[("r1", "radius of disk 1 (the sender)"), ("r2", "radius of disk 2"), ("h", "distance between the disks")],
    eval: |p| {
        let (r1, r2, h) = (positive("r1", p[0])?, positive("r2", p[1])?, positive("h", p[2])?);
        let (a, b) = (r1 / h, r2 / h);
        let x = 1.0 + (1.0 + b * b) / (a * a);
        Ok(0.5 * (x - (x * x - 4.0 * (b / a).powi(2)).sqrt()))
    },
};
