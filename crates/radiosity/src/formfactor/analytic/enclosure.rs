//! The infinitely long enclosure formed by three plane areas (lecture, "Form Factor
//! Examples 2"): the crossed-strings rule `F_{1-2} = (A_1 + A_2 − A_3) / (2 A_1)`.

use super::{positive, Case};

pub const THREE_PLANE_ENCLOSURE: Case = Case {
    name: "three-plane-enclosure",
    geometry: "an infinitely long prism whose cross-section is the triangle with sides a1, a2, a3 \
               (areas per unit length); F from side 1 to side 2",
    params: &[
        ("a1", "width of plane 1 (the sender)"),
        ("a2", "width of plane 2 (the receiver)"),
        ("a3", "width of plane 3"),
    ],
    eval: |p| {
        let (a1, a2, a3) = (
            positive("a1", p[0])?,
            positive("a2", p[1])?,
            positive("a3", p[2])?,
        );
        let m = a1.max(a2).max(a3);
        if 2.0 * m >= a1 + a2 + a3 {
            return Err(format!(
                "widths {a1}, {a2}, {a3} do not make a triangle: each must be shorter than the other two together"
            ));
        }
        Ok((a1 + a2 - a3) / (2.0 * a1))
    },
};
