//! Object transforms: a list of steps (translate, rotate, scale, matrix) applied in the
//! order written, so `[{scale = 2}, {translate = [1, 0, 0]}]` scales first and then
//! moves: the composed map is `M = M_n · … · M_1`.

use super::reader::{Result, Val};
use glam::{Affine3A, Mat3, Vec3};

/// Reads an optional `transform` list; identity when absent.
pub fn read_transform(v: Option<Val>) -> Result<Affine3A> {
    let Some(v) = v else {
        return Ok(Affine3A::IDENTITY);
    };
    let mut m = Affine3A::IDENTITY;
    for step in v.array()? {
        m = read_step(&step)? * m;
    }
    if !invertible(&m) {
        return Err(v.err("the transform is not invertible (it flattens the object)"));
    }
    Ok(m)
}

fn invertible(m: &Affine3A) -> bool {
    let det = m.matrix3.determinant();
    let scale = m.matrix3.x_axis.length() * m.matrix3.y_axis.length() * m.matrix3.z_axis.length();
    det.is_finite() && scale > 0.0 && det.abs() > scale * 1e-6
}

/// One step: a table with exactly one of translate, rotate, scale, matrix.
fn read_step(step: &Val) -> Result<Affine3A> {
    let t = step.table()?;
    let kinds = ["translate", "rotate", "scale", "matrix"];
    let present: Vec<Val> = kinds.iter().filter_map(|k| t.get(k)).collect();
    t.finish()?;
    let [v] = present.as_slice() else {
        return Err(step
            .err("each transform step must have exactly one of translate, rotate, scale, matrix"));
    };
    let key = v.path.rsplit('.').next().unwrap_or("");
    let m = match key {
        "translate" => Affine3A::from_translation(v.vec3()?),
        "rotate" => rotation(v)?,
        "scale" => {
            let s = if v.is_number() {
                Vec3::splat(v.f32()?)
            } else {
                v.vec3()?
            };
            if s.x == 0.0 || s.y == 0.0 || s.z == 0.0 {
                return Err(v.err("scale factors must not be zero"));
            }
            Affine3A::from_scale(s)
        }
        _ => matrix(v)?,
    };
    Ok(m)
}

/// `rotate = [ax, ay, az]` (degrees about x, then y, then z) or
/// `rotate = { axis = [x, y, z], angle = degrees }` (right-handed, counter-clockwise
/// looking down the axis towards the origin).
fn rotation(v: &Val) -> Result<Affine3A> {
    if v.is_table() {
        let t = v.table()?;
        let axis = t.req("axis")?.direction()?;
        let angle = t.req("angle")?.f32()?;
        t.finish()?;
        return Ok(Affine3A::from_axis_angle(
            axis.normalize(),
            angle.to_radians(),
        ));
    }
    if !v.is_array() {
        return Err(
            v.err("expected [x, y, z] angles in degrees or { axis = [x, y, z], angle = degrees }")
        );
    }
    let a = v.vec3()?;
    Ok(Affine3A::from_rotation_z(a.z.to_radians())
        * Affine3A::from_rotation_y(a.y.to_radians())
        * Affine3A::from_rotation_x(a.x.to_radians()))
}

/// `matrix = [[a, b, c, d], [e, f, g, h], [i, j, k, l]]` (rows; the fourth row
/// `[0, 0, 0, 1]` may be given too): `p' = M p` for column vectors.
fn matrix(v: &Val) -> Result<Affine3A> {
    let rows = v.array()?;
    if rows.len() != 3 && rows.len() != 4 {
        return Err(v.err(format!(
            "expected 3 or 4 rows of 4 numbers, found {} rows",
            rows.len()
        )));
    }
    let r: Vec<Vec<f32>> = rows.iter().map(|r| r.numbers(4)).collect::<Result<_>>()?;
    if rows.len() == 4 && r[3] != [0.0, 0.0, 0.0, 1.0] {
        return Err(rows[3].err("the last row of an affine matrix must be [0, 0, 0, 1]"));
    }
    let linear = Mat3::from_cols(
        Vec3::new(r[0][0], r[1][0], r[2][0]),
        Vec3::new(r[0][1], r[1][1], r[2][1]),
        Vec3::new(r[0][2], r[1][2], r[2][2]),
    );
    Ok(Affine3A::from_mat3_translation(
        linear,
        Vec3::new(r[0][3], r[1][3], r[2][3]),
    ))
}
