//! pbrt's transformation directives as 4x4 matrices acting on column vectors, each
//! post-multiplied onto the current transformation matrix (CTM) as pbrt does:
//! `Translate`, `Scale`, `Rotate` (angle in degrees about an axis, the usual
//! right-hand-rule matrix), `LookAt` (pbrt's camera-from-world), `Transform` and
//! `ConcatTransform` (16 numbers, column by column: the translation is numbers 13–15).

use glam::{DMat4, DVec3, DVec4};

pub fn translate(d: [f64; 3]) -> DMat4 {
    DMat4::from_translation(DVec3::from(d))
}

pub fn scale(s: [f64; 3]) -> DMat4 {
    DMat4::from_scale(DVec3::from(s))
}

/// pbrt's `Rotate(theta, axis)`; `None` for a zero axis.
pub fn rotate(degrees: f64, axis: [f64; 3]) -> Option<DMat4> {
    let a = DVec3::from(axis);
    if a.length_squared() == 0.0 || !a.is_finite() {
        return None;
    }
    Some(DMat4::from_axis_angle(a.normalize(), degrees.to_radians()))
}

/// The 16 numbers of `Transform` / `ConcatTransform` (pbrt reads them as the
/// transpose of a row-major matrix: column-major).
pub fn from_pbrt(m: &[f64]) -> DMat4 {
    DMat4::from_cols_slice(m)
}

/// pbrt's `LookAt`: the camera-from-world matrix of a camera at `eye` looking at `look`
/// with `up`; `None` when the view direction is zero or parallel to `up`.
pub fn look_at(eye: [f64; 3], look: [f64; 3], up: [f64; 3]) -> Option<DMat4> {
    let pos = DVec3::from(eye);
    let dir = (DVec3::from(look) - pos).normalize_or_zero();
    let up = DVec3::from(up).normalize_or_zero();
    if dir == DVec3::ZERO || up == DVec3::ZERO {
        return None;
    }
    let right = up.cross(dir);
    if right.length() < 1e-9 {
        return None;
    }
    let right = right.normalize();
    let new_up = dir.cross(right);
    let world_from_camera = DMat4::from_cols(
        right.extend(0.0),
        new_up.extend(0.0),
        dir.extend(0.0),
        pos.extend(1.0),
    );
    Some(world_from_camera.inverse())
}

/// Whether `m` maps a right-handed frame to a left-handed one (negative determinant of
/// its linear part), pbrt's `SwapsHandedness`.
pub fn swaps_handedness(m: &DMat4) -> bool {
    glam::DMat3::from_mat4(*m).determinant() < 0.0
}

/// `m` as Irradia's transform step `{ matrix = [[a, b, c, d], [e, f, g, h], [i, j, k, l]] }`
/// rows (the last row of an affine pbrt matrix is `[0, 0, 0, 1]`; a projective one is
/// refused by the caller).
pub fn rows(m: &DMat4) -> [[f64; 4]; 3] {
    let r = |i: usize| -> [f64; 4] { m.row(i).to_array() };
    [r(0), r(1), r(2)]
}

/// Whether the last row is `[0, 0, 0, 1]`.
pub fn is_affine(m: &DMat4) -> bool {
    let r = m.row(3);
    (r - DVec4::new(0.0, 0.0, 0.0, 1.0)).abs().max_element() < 1e-9
}

/// The matrix is finite and invertible.
pub fn is_invertible(m: &DMat4) -> bool {
    let d = glam::DMat3::from_mat4(*m).determinant();
    m.is_finite() && d.is_finite() && d.abs() > 1e-300
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rotate_z_90_takes_x_to_y() {
        let m = rotate(90.0, [0.0, 0.0, 1.0]).unwrap();
        let p = m.transform_point3(DVec3::X);
        assert!((p - DVec3::Y).length() < 1e-12);
    }

    #[test]
    fn look_at_maps_the_target_to_plus_z() {
        let m = look_at([0.0, 0.0, -5.0], [0.0, 0.0, 0.0], [0.0, 1.0, 0.0]).unwrap();
        let p = m.transform_point3(DVec3::ZERO);
        assert!((p - DVec3::new(0.0, 0.0, 5.0)).length() < 1e-12);
        let x = m.transform_point3(DVec3::new(1.0, 0.0, 0.0));
        assert!(x.x > 0.0, "pbrt's camera x is world +x here: {x}");
    }

    #[test]
    fn column_major_translation() {
        let m = from_pbrt(&[
            1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 1.0, 2.0, 3.0, 1.0,
        ]);
        assert_eq!(m.transform_point3(DVec3::ZERO), DVec3::new(1.0, 2.0, 3.0));
    }
}
