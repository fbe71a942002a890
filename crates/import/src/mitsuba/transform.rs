//! `<transform>`: Mitsuba's `translate`, `rotate`, `scale`, `matrix` and `lookat`,
//! applied in the order written (each one to the result of those before it), as
//! Irradia's `transform` steps are. Each becomes one Irradia step, and the whole
//! is also kept as a matrix (cameras and lights take their frame from it).

use super::props::{number, numbers, opt_number};
use super::xml::Elem;
use glam::{DMat4, DVec3, DVec4};
use irradia_scene::file::tree::Node;
use irradia_scene::SceneError;

/// A parsed `<transform>`.
#[derive(Debug, Clone)]
pub struct Xform {
    /// Irradia's transform steps, in order.
    pub steps: Vec<Node>,
    /// The whole map, object to world.
    pub m: DMat4,
    /// The 2D steps of a `to_uv` transform (Irradia's `to_uv` list).
    pub uv_steps: Vec<Node>,
}

impl Xform {
    pub fn identity() -> Xform {
        Xform {
            steps: Vec::new(),
            m: DMat4::IDENTITY,
            uv_steps: Vec::new(),
        }
    }

    /// `self` followed by `after`.
    pub fn then(&self, after: &Xform) -> Xform {
        let mut steps = self.steps.clone();
        steps.extend(after.steps.iter().cloned());
        Xform {
            steps,
            m: after.m * self.m,
            uv_steps: Vec::new(),
        }
    }

    pub fn point(&self, p: DVec3) -> DVec3 {
        self.m.transform_point3(p)
    }

    pub fn vector(&self, v: DVec3) -> DVec3 {
        self.m.transform_vector3(v)
    }
}

fn vec_node(v: DVec3, pos: usize) -> Node {
    Node::new(
        vec![v.x, v.y, v.z]
            .into_iter()
            .map(|x| Node::new(x, pos))
            .collect::<Vec<_>>(),
        pos,
    )
}

fn step(key: &str, value: Node, pos: usize) -> Node {
    let mut t = Node::table(pos);
    t.set(key, value);
    t
}

/// A 4x4 matrix as Irradia's `matrix` step (three rows).
pub fn matrix_node(m: &DMat4, pos: usize) -> Node {
    let rows: Vec<Node> = (0..3)
        .map(|r| {
            let row = m.row(r);
            Node::new(
                [row.x, row.y, row.z, row.w]
                    .into_iter()
                    .map(|x| Node::new(x, pos))
                    .collect::<Vec<_>>(),
                pos,
            )
        })
        .collect();
    step("matrix", Node::new(rows, pos), pos)
}

/// Mitsuba's `lookat`: the columns are left = up × dir, up' = dir × left, dir, origin.
pub fn look_at(origin: DVec3, target: DVec3, up: DVec3) -> Option<DMat4> {
    let dir = (target - origin).normalize();
    let mut left = up.normalize().cross(dir);
    if !dir.is_finite() || !left.is_finite() || left.length() < 1e-9 {
        // Mitsuba picks a frame when `up` is missing or parallel to the view.
        if !dir.is_finite() {
            return None;
        }
        left = dir.any_orthonormal_vector();
    }
    let left = left.normalize();
    let new_up = dir.cross(left);
    Some(DMat4::from_cols(
        left.extend(0.0),
        new_up.extend(0.0),
        dir.extend(0.0),
        origin.extend(1.0),
    ))
}

/// Reads a `<transform>` element.
pub fn parse_transform(t: &Elem) -> Result<Xform, SceneError> {
    let mut x = Xform::identity();
    let pos = t.main_pos;
    for op in &t.children {
        let (m, node, uv) = match op.tag.as_str() {
            "translate" => {
                op.check_attrs(&["x", "y", "z", "value"])?;
                let v = xyz(op, 0.0)?;
                (
                    DMat4::from_translation(v),
                    step("translate", vec_node(v, pos), pos),
                    step(
                        "translate",
                        Node::new(vec![Node::new(v.x, pos), Node::new(v.y, pos)], pos),
                        pos,
                    ),
                )
            }
            "scale" => {
                op.check_attrs(&["x", "y", "z", "value"])?;
                let v = xyz(op, 1.0)?;
                if v.x == 0.0 || v.y == 0.0 || v.z == 0.0 {
                    return Err(op.err("scale", "a scale factor of 0 cannot be undone"));
                }
                (
                    DMat4::from_scale(v),
                    step("scale", vec_node(v, pos), pos),
                    step(
                        "scale",
                        Node::new(vec![Node::new(v.x, pos), Node::new(v.y, pos)], pos),
                        pos,
                    ),
                )
            }
            "rotate" => {
                op.check_attrs(&["x", "y", "z", "value", "angle"])?;
                let axis = xyz(op, 0.0)?;
                let angle = number(op, "angle")?;
                let a = axis.normalize();
                if !a.is_finite() {
                    return Err(op.err("rotate", "the rotation axis is zero"));
                }
                let mut r = Node::table(pos);
                r.set("axis", vec_node(axis, pos));
                r.put("angle", angle, pos);
                let uv = if axis.x == 0.0 && axis.y == 0.0 {
                    step("rotate", Node::new(angle * axis.z.signum(), pos), pos)
                } else {
                    matrix2(&DMat4::from_axis_angle(a, angle.to_radians()), pos)
                };
                (
                    DMat4::from_axis_angle(a, angle.to_radians()),
                    step("rotate", r, pos),
                    uv,
                )
            }
            "matrix" => {
                op.check_attrs(&["value"])?;
                let v = numbers(op, "value")?;
                let m = match v.len() {
                    16 => DMat4::from_cols_array(&[
                        v[0], v[4], v[8], v[12], v[1], v[5], v[9], v[13], v[2], v[6], v[10],
                        v[14], v[3], v[7], v[11], v[15],
                    ]),
                    9 => DMat4::from_cols(
                        DVec4::new(v[0], v[3], v[6], 0.0),
                        DVec4::new(v[1], v[4], v[7], 0.0),
                        DVec4::new(v[2], v[5], v[8], 0.0),
                        DVec4::W,
                    ),
                    n => {
                        return Err(op.err_at(
                            "value",
                            "matrix",
                            format!("a matrix has 16 (4x4) or 9 (3x3) numbers, not {n}"),
                        ))
                    }
                };
                let last = m.row(3);
                if (last - DVec4::W).abs().max_element() > 1e-9 {
                    return Err(op.err_at(
                        "value",
                        "matrix",
                        "projective matrices are not supported: the last row must be 0 0 0 1",
                    ));
                }
                (m, matrix_node(&m, pos), matrix2(&m, pos))
            }
            "lookat" => {
                op.check_attrs(&["origin", "target", "up"])?;
                let o = vec3_attr(op, "origin")?;
                let t = vec3_attr(op, "target")?;
                let up = match op.get("up") {
                    Some(_) => vec3_attr(op, "up")?,
                    None => DVec3::ZERO,
                };
                let m = look_at(o, t, up)
                    .ok_or_else(|| op.err("lookat", "origin and target must differ"))?;
                (m, matrix_node(&m, pos), matrix2(&m, pos))
            }
            other => {
                return Err(op.err(
                    other,
                    format!(
                        "unknown directive <{other}> in <transform> (valid: translate, rotate, scale, matrix, lookat)"
                    ),
                ))
            }
        };
        if m.determinant().abs() < 1e-300 || !m.is_finite() {
            return Err(op.err(&op.tag, "the transform cannot be undone (determinant 0)"));
        }
        x.m = m * x.m;
        x.steps.push(node);
        x.uv_steps.push(uv);
    }
    Ok(x)
}

/// The uv part of a 4x4 transform (rows and columns x, y and the translation), as
/// Mitsuba's `to_uv` reads it.
fn matrix2(m: &DMat4, pos: usize) -> Node {
    let n = |x: f64| Node::new(x, pos);
    let rows = vec![
        Node::new(vec![n(m.x_axis.x), n(m.y_axis.x), n(m.w_axis.x)], pos),
        Node::new(vec![n(m.x_axis.y), n(m.y_axis.y), n(m.w_axis.y)], pos),
    ];
    step("matrix", Node::new(rows, pos), pos)
}

/// `x`, `y`, `z` attributes (each `default` when absent), or `value` with one number
/// (all three) or three.
fn xyz(op: &Elem, default: f64) -> Result<DVec3, SceneError> {
    if op.get("value").is_some() {
        if op.get("x").is_some() || op.get("y").is_some() || op.get("z").is_some() {
            return Err(op.err("value", "give either value or x, y, z"));
        }
        let v = numbers(op, "value")?;
        return match v.len() {
            1 => Ok(DVec3::splat(v[0])),
            3 => Ok(DVec3::new(v[0], v[1], v[2])),
            n => Err(op.err_at(
                "value",
                "value",
                format!("expected 1 or 3 numbers, not {n}"),
            )),
        };
    }
    Ok(DVec3::new(
        opt_number(op, "x", default)?,
        opt_number(op, "y", default)?,
        opt_number(op, "z", default)?,
    ))
}

fn vec3_attr(op: &Elem, attr: &str) -> Result<DVec3, SceneError> {
    let v = numbers(op, attr)?;
    if v.len() != 3 {
        return Err(op.err_at(attr, attr, format!("expected 3 numbers, not {}", v.len())));
    }
    Ok(DVec3::new(v[0], v[1], v[2]))
}
