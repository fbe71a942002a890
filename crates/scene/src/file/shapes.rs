//! Shape constructors by `type`: each reads its own fields from the object's table and
//! validates them (a radius must be positive, a polygon must not be degenerate).

use super::reader::{unknown_name_message, Result, Table, Val};
use irradia_geometry::shapes::Sphere;
use irradia_geometry::Shape;
use std::sync::Arc;

/// Every primitive shape `type` the scene format knows (CSG nodes are handled by the
/// object reader).
pub const PRIMITIVES: &[&str] = &["sphere"];

/// Builds the primitive named `kind` from table `t`.
pub fn build_primitive(kind: &str, kind_v: &Val, t: &Table) -> Result<Arc<dyn Shape>> {
    let shape: Arc<dyn Shape> = match kind {
        "sphere" => Arc::new(Sphere::new(
            t.vec3_or("center", glam::Vec3::ZERO)?,
            t.req("radius")?.positive()?,
        )),
        _ => {
            let mut valid = PRIMITIVES.to_vec();
            valid.extend_from_slice(super::objects::CSG_KINDS);
            return Err(kind_v.err(unknown_name_message("object type", kind, &valid)));
        }
    };
    Ok(shape)
}
