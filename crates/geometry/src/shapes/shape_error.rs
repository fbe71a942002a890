//! Why a shape could not be built: degenerate or non-finite input is reported, never
//! rendered as garbage (DESIGN.md, "Behaviour a user can count on").

use thiserror::Error;

/// A shape constructor refused its input. The message names the offending quantity so
/// that the scene loader can prefix it with the file, line and field.
#[derive(Clone, Debug, Error, PartialEq)]
pub enum ShapeError {
    /// A coordinate, coefficient or size is NaN or infinite.
    #[error("{what} is not a finite number")]
    NotFinite { what: &'static str },
    /// A radius, length or size that must be positive is zero or negative.
    #[error("{what} must be positive, got {value}")]
    NotPositive { what: &'static str, value: f64 },
    /// A polygon needs at least three vertices.
    #[error("a polygon needs at least 3 vertices, got {count}")]
    TooFewVertices { count: usize },
    /// The vertices are collinear or coincident: the polygon has no area.
    #[error("the polygon has zero area (its vertices are collinear or coincident)")]
    ZeroArea,
    /// A polygon's vertices do not lie in one plane.
    #[error("the polygon is not planar: vertex {vertex} lies {distance} from the plane (tolerance {tolerance})")]
    NotPlanar {
        vertex: usize,
        distance: f64,
        tolerance: f64,
    },
    /// Two points that must differ (the ends of a cylinder's axis, a box's corners).
    #[error("{what}: the two points coincide")]
    Coincident { what: &'static str },
    /// A normal or direction of zero length.
    #[error("{what} has zero length")]
    ZeroVector { what: &'static str },
    /// All ten quadric coefficients of the quadratic part and the linear part are zero.
    #[error("the quadric has no quadratic or linear term: it is not a surface")]
    NotASurface,
    /// The half-spaces of a polyhedron leave nothing, or only a flat or lower-dimensional set.
    #[error("the half-spaces enclose no volume (empty or flat polyhedron)")]
    EmptyPolyhedron,
    /// The half-spaces of a polyhedron do not close it off in every direction.
    #[error("the half-spaces do not bound a finite polyhedron (it is open towards {direction:?})")]
    UnboundedPolyhedron { direction: [f64; 3] },
    /// A CSG operand that does not bound a solid (a polygon, a disk, an open quadric).
    #[error("a CSG operand must be a closed solid, but a {kind} is an open surface")]
    NotSolid { kind: &'static str },
    /// A CSG node without operands.
    #[error("a CSG {op} needs at least one operand")]
    NoOperands { op: &'static str },
    /// A constructor's parameter is outside the range it accepts.
    #[error("{what}: {why}")]
    OutOfRange {
        what: &'static str,
        why: &'static str,
    },
}

/// Checks that every value is finite.
pub(crate) fn finite(what: &'static str, values: &[f64]) -> Result<(), ShapeError> {
    if values.iter().all(|v| v.is_finite()) {
        Ok(())
    } else {
        Err(ShapeError::NotFinite { what })
    }
}

/// Checks that a value is finite and positive.
pub(crate) fn positive(what: &'static str, value: f64) -> Result<(), ShapeError> {
    finite(what, &[value])?;
    if value > 0.0 {
        Ok(())
    } else {
        Err(ShapeError::NotPositive { what, value })
    }
}
