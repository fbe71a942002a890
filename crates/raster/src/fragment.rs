//! Per-fragment work: the depth test, the pixel shader (interpolated Gouraud colour or
//! per-pixel Phong lighting) and the write to the colour buffer's format.

use crate::framebuffer::to_rgba8;
use crate::interpolate::{perspective_weights, varyings};
use crate::lighting::EyeLights;
use crate::rasterizer::Setup;
use crate::screen::{varying, Rect, ScreenTriangle};
use glam::Vec3;

/// The depth comparison (the fragment passes when `new OP stored`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum DepthFunc {
    #[default]
    Less,
    LessEqual,
    /// No depth test (depth is still written).
    Always,
}

impl DepthFunc {
    #[inline(always)]
    fn pass(self, new: f32, stored: f32) -> bool {
        match self {
            DepthFunc::Less => new < stored,
            DepthFunc::LessEqual => new <= stored,
            DepthFunc::Always => true,
        }
    }
}

/// Computes a fragment's colour from perspective-correct weights.
pub(crate) trait PixelShader: Sync {
    fn color(&self, s: &Setup, w: [f32; 3]) -> [f32; 4];
}

/// Gouraud and unlit: the interpolated vertex colour.
pub(crate) struct InterpolatedColor;

impl PixelShader for InterpolatedColor {
    #[inline(always)]
    fn color(&self, s: &Setup, w: [f32; 3]) -> [f32; 4] {
        varyings::<4>(&s.v, w, varying::COLOR)
    }
}

/// Phong: lighting evaluated with the interpolated, renormalised normal.
pub(crate) struct PhongShader<'a>(pub &'a EyeLights);

impl PixelShader for PhongShader<'_> {
    #[inline(always)]
    fn color(&self, s: &Setup, w: [f32; 3]) -> [f32; 4] {
        let n = Vec3::from(varyings::<3>(&s.v, w, varying::NORMAL)).normalize_or_zero();
        let p = Vec3::from(varyings::<3>(&s.v, w, varying::VIEW_POS));
        let c = self.0.shade(p, n, Vec3::ONE);
        [c.x, c.y, c.z, 1.0]
    }
}

/// Where fragments go: one band of rows of the colour buffer.
pub(crate) trait ColorTarget {
    fn write<S: PixelShader>(
        &mut self,
        i: usize,
        tri: &ScreenTriangle,
        s: &Setup,
        l: [f32; 3],
        shader: &S,
    );
}

/// RGBA8 colour.
impl ColorTarget for [[u8; 4]] {
    #[inline(always)]
    fn write<S: PixelShader>(
        &mut self,
        i: usize,
        _t: &ScreenTriangle,
        s: &Setup,
        l: [f32; 3],
        shader: &S,
    ) {
        self[i] = to_rgba8(shader.color(s, perspective_weights(&s.v, l)));
    }
}

/// RGBA32F colour.
impl ColorTarget for [[f32; 4]] {
    #[inline(always)]
    fn write<S: PixelShader>(
        &mut self,
        i: usize,
        _t: &ScreenTriangle,
        s: &Setup,
        l: [f32; 3],
        shader: &S,
    ) {
        self[i] = shader.color(s, perspective_weights(&s.v, l));
    }
}

/// Item ids.
impl ColorTarget for [u32] {
    #[inline(always)]
    fn write<S: PixelShader>(
        &mut self,
        i: usize,
        t: &ScreenTriangle,
        _s: &Setup,
        _l: [f32; 3],
        _shader: &S,
    ) {
        self[i] = t.id;
    }
}

/// Rasterizes `tri` into a band of rows starting at row `band_y0` (the slices hold
/// whole rows of `width` pixels), inside `clip`.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub(crate) fn draw<C: ColorTarget + ?Sized, S: PixelShader>(
    tri: &ScreenTriangle,
    clip: &Rect,
    width: usize,
    band_y0: u32,
    depth_buf: &mut [f32],
    target: &mut C,
    shader: &S,
    func: DepthFunc,
) {
    let Some(s) = Setup::new(tri) else { return };
    let mut row_y = u32::MAX;
    let mut row_z = 0.0;
    let mut row_i = 0;
    s.scan(clip, |x, y, e| {
        if y != row_y {
            row_y = y;
            row_z = s.depth_row(y);
            row_i = (y - band_y0) as usize * width;
        }
        let i = row_i + x as usize;
        let z = s.depth_in_row(row_z, x);
        if func.pass(z, depth_buf[i]) {
            depth_buf[i] = z;
            target.write(i, tri, &s, s.lambda(e), shader);
        }
    });
}
