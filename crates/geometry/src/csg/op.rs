//! The four CSG operations as Boolean functions of "inside A" and "inside B".

/// How a CSG node combines its operands (left to right: `((A op B) op C) ...`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum CsgOp {
    /// Inside any operand. As in POV-Ray, a union's `intersect` reports the nearest
    /// surface of any operand, so inner surfaces stay visible (cheap, and right for
    /// opaque objects); its spans (when nested) have no inner surfaces.
    Union,
    /// Inside every operand.
    Intersection,
    /// Inside the first operand and no other: `A - B - C = A ∩ ¬B ∩ ¬C`.
    Difference,
    /// A union without inner surfaces (POV-Ray's `merge`): hits come from the combined
    /// spans, so a glass merge refracts only at its outer surface.
    Merge,
}

impl CsgOp {
    /// The result of the operation for one point.
    #[inline]
    pub fn apply(self, in_a: bool, in_b: bool) -> bool {
        match self {
            CsgOp::Union | CsgOp::Merge => in_a || in_b,
            CsgOp::Intersection => in_a && in_b,
            CsgOp::Difference => in_a && !in_b,
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            CsgOp::Union => "union",
            CsgOp::Intersection => "intersection",
            CsgOp::Difference => "difference",
            CsgOp::Merge => "merge",
        }
    }
}
