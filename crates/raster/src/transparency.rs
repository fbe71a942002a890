//! Transparent surfaces in a z-buffer pipeline, as OpenGL practice draws them (the
//! lecture's "Parallel Rendering": a z-buffer resolves visibility in any order, blending
//! does not): first every opaque triangle, in submission order, with depth writes; then
//! the transparent ones sorted back to front, each fragment depth-tested against the
//! opaque surfaces but not writing depth, and blended over the colour behind it.
//!
//! The blend is the "over" operator with a premultiplied source (Porter and Duff 1984)
//! and a per-channel transmittance in place of `1 - alpha`:
//! `dst = colour + transmission * filter * dst`, the Whitted tracer's
//! `local + k_t * filter * (what the refracted ray sees)` without the bending: a
//! material with `transmission = t` and a white filter is "over" with alpha `1 - t`
//! applied to a colour already weighted by its opacity.
//!
//! The order is a total order computed from each screen triangle alone (its mean
//! clip-space w, the eye distance along the view axis, then its mean depth, farther
//! first; ties by triangle id, then by submission order), so any subset of the
//! triangles sorts to the subsequence of the whole: a region server of sort-first or
//! sort-middle that holds only the triangles touching its region blends them in the
//! same order as the serial render, and the images agree bit for bit.

use crate::lighting::EyeLights;
use crate::screen::ScreenTriangle;
use std::cmp::Ordering;

/// Where a triangle stands in the back-to-front order: larger is farther.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DepthKey {
    /// Mean of the vertices' clip-space w (1 for orthographic views).
    pub w: f32,
    /// Mean of the vertices' NDC depth.
    pub z: f32,
}

impl DepthKey {
    pub fn of(t: &ScreenTriangle) -> Self {
        let w = t.v.iter().map(|v| 1.0 / v.inv_w).sum::<f32>() / 3.0;
        let z = (t.v[0].z + t.v[1].z + t.v[2].z) / 3.0;
        Self { w, z }
    }

    /// Farther first.
    fn back_to_front(&self, other: &Self) -> Ordering {
        other
            .w
            .total_cmp(&self.w)
            .then_with(|| other.z.total_cmp(&self.z))
    }
}

/// The triangles drawn by the transparent pass (those whose material lets light
/// through) sorted back to front, and the others in their given order.
pub fn split_transparent(
    tris: &[ScreenTriangle],
    lights: &EyeLights,
) -> (Vec<ScreenTriangle>, Vec<ScreenTriangle>) {
    let (opaque, clear): (Vec<_>, Vec<_>) = tris
        .iter()
        .partition(|t| !lights.material(t.material).is_transparent());
    let mut keyed: Vec<(DepthKey, usize, &ScreenTriangle)> = clear
        .into_iter()
        .enumerate()
        .map(|(i, t)| (DepthKey::of(t), i, t))
        .collect();
    keyed.sort_unstable_by(|a, b| {
        a.0.back_to_front(&b.0)
            .then(a.2.id.cmp(&b.2.id))
            .then(a.1.cmp(&b.1))
    });
    (
        opaque.into_iter().copied().collect(),
        keyed.into_iter().map(|(_, _, t)| *t).collect(),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lighting::{Lights, Material};
    use crate::screen::ScreenVertex;
    use glam::Mat4;

    fn tri(w: f32, id: u32, material: u32) -> ScreenTriangle {
        let v = ScreenVertex {
            inv_w: 1.0 / w,
            z: 0.5,
            ..Default::default()
        };
        ScreenTriangle {
            v: [v; 3],
            id,
            material,
        }
    }

    #[test]
    fn opaque_keep_order_transparent_far_first_ties_by_id() {
        let clear = Material {
            transmission: 0.5,
            ..Material::default()
        };
        let lights = EyeLights::with_materials(
            &Lights::default(),
            &[Material::default(), clear],
            &Material::default(),
            Mat4::IDENTITY,
            false,
        );
        let tris = [
            tri(2.0, 0, 1),
            tri(9.0, 1, 0),
            tri(5.0, 4, 1),
            tri(1.0, 2, 0),
            tri(5.0, 3, 1),
        ];
        let (opaque, clear) = split_transparent(&tris, &lights);
        assert_eq!(opaque.iter().map(|t| t.id).collect::<Vec<_>>(), [1, 2]);
        assert_eq!(clear.iter().map(|t| t.id).collect::<Vec<_>>(), [3, 4, 0]);
        // Any subset sorts to the subsequence of the whole.
        let (_, part) = split_transparent(&[tris[4], tris[0]], &lights);
        assert_eq!(part.iter().map(|t| t.id).collect::<Vec<_>>(), [3, 0]);
    }
}
