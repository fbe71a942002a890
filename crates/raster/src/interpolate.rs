//! Attribute interpolation across a triangle.
//!
//! Depth (z/w) is affine in screen space and is interpolated with the screen-space
//! barycentric weights directly. Every other attribute `a` is affine in eye space, so
//! `a/w` and `1/w` are affine on screen and the perspective-correct value is
//! `sum(l_i a_i / w_i) / sum(l_i / w_i)` (Heckbert and Moreton 1991; Blinn 1992).

use crate::screen::{ScreenVertex, VARYINGS};

/// NDC depth at the fragment with screen-space weights `l`.
#[inline(always)]
pub fn depth(v: &[&ScreenVertex; 3], l: [f32; 3]) -> f32 {
    l[0] * v[0].z + l[1] * v[1].z + l[2] * v[2].z
}

/// Perspective-correct weights: `l_i / w_i`, normalised to sum to one.
#[inline(always)]
pub fn perspective_weights(v: &[&ScreenVertex; 3], l: [f32; 3]) -> [f32; 3] {
    let p = [l[0] * v[0].inv_w, l[1] * v[1].inv_w, l[2] * v[2].inv_w];
    let s = 1.0 / (p[0] + p[1] + p[2]);
    [p[0] * s, p[1] * s, p[2] * s]
}

/// `N` consecutive varyings starting at `start`, blended with weights `w`.
#[inline(always)]
pub fn varyings<const N: usize>(v: &[&ScreenVertex; 3], w: [f32; 3], start: usize) -> [f32; N] {
    debug_assert!(start + N <= VARYINGS);
    let mut out = [0.0; N];
    for (i, o) in out.iter_mut().enumerate() {
        *o = w[0] * v[0].var[start + i] + w[1] * v[1].var[start + i] + w[2] * v[2].var[start + i];
    }
    out
}
