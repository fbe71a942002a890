//! Per-fragment work: the depth test, the pixel shader (interpolated Gouraud colour or
//! per-pixel Phong lighting, with the material's image texture looked up at the
//! perspective-correct texture coordinate) and the write to the colour buffer's format:
//! replaced (opaque triangles) or blended over what is there (transparent triangles,
//! drawn by [`draw_blended`] with the depth test on and depth writes off).

use crate::framebuffer::to_rgba8;
use crate::interpolate::{perspective_weights, varyings};
use crate::lighting::EyeLights;
use crate::rasterizer::Setup;
use crate::screen::{varying, Rect, ScreenTriangle};
use crate::texture::Texture;
use glam::{Mat4, Vec2, Vec3, Vec4};

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
    pub(crate) fn pass(self, new: f32, stored: f32) -> bool {
        match self {
            DepthFunc::Less => new < stored,
            DepthFunc::LessEqual => new <= stored,
            DepthFunc::Always => true,
        }
    }
}

/// Where a fragment is: its pixel and its interpolated NDC depth.
#[derive(Clone, Copy, Debug)]
pub(crate) struct FragCoord {
    pub x: u32,
    pub y: u32,
    pub z: f32,
}

/// Computes a fragment's colour from perspective-correct weights.
pub(crate) trait PixelShader: Sync {
    fn color(&self, tri: &ScreenTriangle, s: &Setup, w: [f32; 3], at: FragCoord) -> [f32; 4];

    /// A fragment of a transparent triangle: the colour it adds and, per channel, the
    /// fraction of the colour behind it that shows through (none unless a shader
    /// knows the materials).
    #[inline(always)]
    fn layer(
        &self,
        tri: &ScreenTriangle,
        s: &Setup,
        w: [f32; 3],
        at: FragCoord,
    ) -> ([f32; 4], [f32; 3]) {
        (self.color(tri, s, w, at), [0.0; 3])
    }
}

/// The texel of `tri`'s material at the fragment, or white without a texture.
#[inline(always)]
fn texel(
    lights: &EyeLights,
    textures: &[Texture],
    tri: &ScreenTriangle,
    s: &Setup,
    w: [f32; 3],
) -> Vec3 {
    match lights
        .material(tri.material)
        .texture
        .and_then(|i| textures.get(i as usize))
    {
        Some(t) => t.sample(Vec2::from(varyings::<2>(&s.v, w, varying::UV))),
        None => Vec3::ONE,
    }
}

/// Gouraud and unlit with materials that have textures or let light through: the
/// interpolated vertex colour times the texel (OpenGL's `GL_MODULATE`); a transparent
/// material's filter is its own, or the texel (the vertex colour is already lit).
pub(crate) struct MaterialColor<'a> {
    pub lights: &'a EyeLights,
    pub textures: &'a [Texture],
}

impl PixelShader for MaterialColor<'_> {
    #[inline(always)]
    fn color(&self, tri: &ScreenTriangle, s: &Setup, w: [f32; 3], at: FragCoord) -> [f32; 4] {
        self.layer(tri, s, w, at).0
    }

    #[inline(always)]
    fn layer(
        &self,
        tri: &ScreenTriangle,
        s: &Setup,
        w: [f32; 3],
        _at: FragCoord,
    ) -> ([f32; 4], [f32; 3]) {
        let c = varyings::<4>(&s.v, w, varying::COLOR);
        let t = texel(self.lights, self.textures, tri, s, w);
        let tr = self.lights.material(tri.material).transmittance(t);
        ([c[0] * t.x, c[1] * t.y, c[2] * t.z, c[3]], tr.to_array())
    }
}

/// Gouraud and unlit: the interpolated vertex colour.
pub(crate) struct InterpolatedColor;

impl PixelShader for InterpolatedColor {
    #[inline(always)]
    fn color(&self, _tri: &ScreenTriangle, s: &Setup, w: [f32; 3], _at: FragCoord) -> [f32; 4] {
        varyings::<4>(&s.v, w, varying::COLOR)
    }
}

/// Pixel centre and depth back to eye space: the inverse of projection, perspective
/// divide and viewport.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Unproject {
    inv_proj: Mat4,
    /// NDC x = x * sx + ox at pixel centres, NDC y = oy - y * sy.
    sx: f32,
    ox: f32,
    sy: f32,
    oy: f32,
}

impl Unproject {
    pub fn new(proj: Mat4, width: u32, height: u32) -> Self {
        let (w, h) = (width.max(1) as f32, height.max(1) as f32);
        Self {
            inv_proj: proj.inverse(),
            sx: 2.0 / w,
            ox: 1.0 / w - 1.0,
            sy: 2.0 / h,
            oy: 1.0 - 1.0 / h,
        }
    }

    /// The eye-space point seen at the centre of pixel (x, y) at NDC depth z.
    #[inline(always)]
    pub fn eye_point(&self, at: FragCoord) -> Vec3 {
        let ndc = Vec4::new(
            at.x as f32 * self.sx + self.ox,
            self.oy - at.y as f32 * self.sy,
            at.z,
            1.0,
        );
        let h = self.inv_proj * ndc;
        h.truncate() / h.w
    }
}

/// Phong: lighting evaluated at every pixel with the interpolated, renormalised normal
/// and the interpolated vertex colour (times the material's texel) as the diffuse base,
/// at the eye-space point the pixel sees (recovered from its depth), with the
/// triangle's material.
pub(crate) struct PhongShader<'a> {
    pub lights: &'a EyeLights,
    pub unproject: Unproject,
    pub textures: &'a [Texture],
}

impl PhongShader<'_> {
    #[inline(always)]
    fn shade(&self, tri: &ScreenTriangle, s: &Setup, w: [f32; 3], at: FragCoord) -> (Vec3, Vec3) {
        let n = Vec3::from(varyings::<3>(&s.v, w, varying::NORMAL)).normalize_or_zero();
        let mut base = Vec3::from(varyings::<3>(&s.v, w, varying::BASE_COLOR));
        if !self.textures.is_empty() {
            base *= texel(self.lights, self.textures, tri, s, w);
        }
        let p = self.unproject.eye_point(at);
        (self.lights.shade_with(tri.material, p, n, base), base)
    }
}

impl PixelShader for PhongShader<'_> {
    #[inline(always)]
    fn color(&self, tri: &ScreenTriangle, s: &Setup, w: [f32; 3], at: FragCoord) -> [f32; 4] {
        let (c, _) = self.shade(tri, s, w, at);
        [c.x, c.y, c.z, 1.0]
    }

    #[inline(always)]
    fn layer(
        &self,
        tri: &ScreenTriangle,
        s: &Setup,
        w: [f32; 3],
        at: FragCoord,
    ) -> ([f32; 4], [f32; 3]) {
        let (c, base) = self.shade(tri, s, w, at);
        let tr = self.lights.material(tri.material).transmittance(base);
        ([c.x, c.y, c.z, 1.0], tr.to_array())
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
        at: FragCoord,
        shader: &S,
    );
}

/// RGBA8 colour.
impl ColorTarget for [[u8; 4]] {
    #[inline(always)]
    fn write<S: PixelShader>(
        &mut self,
        i: usize,
        t: &ScreenTriangle,
        s: &Setup,
        l: [f32; 3],
        at: FragCoord,
        shader: &S,
    ) {
        self[i] = to_rgba8(shader.color(t, s, perspective_weights(&s.v, l), at));
    }
}

/// RGBA32F colour.
impl ColorTarget for [[f32; 4]] {
    #[inline(always)]
    fn write<S: PixelShader>(
        &mut self,
        i: usize,
        t: &ScreenTriangle,
        s: &Setup,
        l: [f32; 3],
        at: FragCoord,
        shader: &S,
    ) {
        self[i] = shader.color(t, s, perspective_weights(&s.v, l), at);
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
        _at: FragCoord,
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
    for_each_fragment(&s, clip, width, band_y0, |i, at, e| {
        if func.pass(at.z, depth_buf[i]) {
            depth_buf[i] = at.z;
            target.write(i, tri, &s, s.lambda(e), at, shader);
        }
    });
}

/// Calls `f(i, at, e)` for every pixel of the set-up triangle inside `clip`, in scan
/// order: `i` is the pixel's index in a band of whole rows of `width` pixels starting at
/// row `band_y0`, `at` its coordinates and interpolated depth (one multiply-add per
/// pixel from the row's start), `e` its edge-function values.
#[inline(always)]
fn for_each_fragment(
    s: &Setup,
    clip: &Rect,
    width: usize,
    band_y0: u32,
    mut f: impl FnMut(usize, FragCoord, &[i64; 3]),
) {
    let mut row_y = u32::MAX;
    let mut row_z = 0.0;
    let mut row_i = 0;
    s.scan(clip, |x, y, e| {
        if y != row_y {
            row_y = y;
            row_z = s.depth_row(y);
            row_i = (y - band_y0) as usize * width;
        }
        let z = s.depth_in_row(row_z, x);
        f(row_i + x as usize, FragCoord { x, y, z }, e);
    });
}

/// Where transparent fragments go: blended over the stored colour.
pub(crate) trait BlendTarget {
    /// `dst = colour + transmittance * dst` per channel; alpha becomes
    /// `1 - (1 - dst alpha) * mean(transmittance)` (coverage: an opaque pixel stays
    /// opaque, empty background behind a clear surface stays mostly empty). A pixel
    /// nothing was drawn into yet (alpha 0) holds `background` when there is one, which
    /// then makes it opaque.
    fn blend(
        &mut self,
        i: usize,
        colour: [f32; 4],
        transmittance: [f32; 3],
        background: Option<[f32; 4]>,
    );
}

#[inline(always)]
fn over(c: [f32; 4], t: [f32; 3], d: [f32; 4], background: Option<[f32; 4]>) -> [f32; 4] {
    let d = match background {
        Some(bg) if d[3] == 0.0 => bg,
        _ => d,
    };
    let mean = (t[0] + t[1] + t[2]) * (1.0 / 3.0);
    [
        c[0] + t[0] * d[0],
        c[1] + t[1] * d[1],
        c[2] + t[2] * d[2],
        1.0 - (1.0 - d[3]) * mean,
    ]
}

impl BlendTarget for [[u8; 4]] {
    #[inline(always)]
    fn blend(&mut self, i: usize, c: [f32; 4], t: [f32; 3], bg: Option<[f32; 4]>) {
        let d = self[i].map(|v| v as f32 * (1.0 / 255.0));
        self[i] = to_rgba8(over(c, t, d, bg));
    }
}

impl BlendTarget for [[f32; 4]] {
    #[inline(always)]
    fn blend(&mut self, i: usize, c: [f32; 4], t: [f32; 3], bg: Option<[f32; 4]>) {
        self[i] = over(c, t, self[i], bg);
    }
}

/// [`draw`] for a transparent triangle: fragments that pass the depth test are blended
/// over the colour buffer ([`BlendTarget`]) and leave the depth buffer as it is, so
/// the opaque surfaces drawn before still hide what lies behind them and transparent
/// surfaces do not hide each other (drawn back to front by the caller).
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub(crate) fn draw_blended<C: BlendTarget + ?Sized, S: PixelShader>(
    tri: &ScreenTriangle,
    clip: &Rect,
    width: usize,
    band_y0: u32,
    depth_buf: &[f32],
    target: &mut C,
    shader: &S,
    func: DepthFunc,
    background: Option<[f32; 4]>,
) {
    let Some(s) = Setup::new(tri) else { return };
    for_each_fragment(&s, clip, width, band_y0, |i, at, e| {
        if func.pass(at.z, depth_buf[i]) {
            let w = perspective_weights(&s.v, s.lambda(e));
            let (c, t) = shader.layer(tri, &s, w, at);
            target.blend(i, c, t, background);
        }
    });
}
