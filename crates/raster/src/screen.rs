//! Screen-space triangles: what the geometry stage hands to the rasterizer.
//!
//! In the lecture's "Building Blocks" a geometry unit (transform, clip, light) feeds a
//! rasterizer (scan conversion, shading). [`ScreenTriangle`] is the data that crosses
//! that boundary — in sort-middle rendering it is what travels over the network — so it
//! is plain old data with a fixed byte encoding ([`ScreenTriangle::write_bytes`]).

/// Number of per-vertex values interpolated across a triangle.
pub const VARYINGS: usize = 8;

/// Where each value lives in [`ScreenVertex::var`].
///
/// Gouraud and unlit shading carry the lit RGBA colour in `0..4`; Phong carries the
/// view-space normal in `0..3` and the vertex colour (the diffuse base, RGB) in `3..6`
/// (the view-space position of a Phong fragment is recovered from its pixel and depth
/// through the inverse projection, so it needs no varyings). Both keep the texture
/// coordinate in `6..8`.
pub mod varying {
    pub const COLOR: usize = 0;
    pub const NORMAL: usize = 0;
    /// Phong's vertex colour (RGB).
    pub const BASE_COLOR: usize = 3;
    /// Slots `3..6` held the view-space position before Phong reconstructed it; they
    /// now hold [`BASE_COLOR`].
    #[deprecated(
        note = "Phong fragments recover the view position from depth; slots 3..6 are BASE_COLOR"
    )]
    pub const VIEW_POS: usize = 3;
    pub const UV: usize = 6;
}

/// A vertex after transformation, clipping, perspective divide and viewport mapping.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
#[repr(C)]
pub struct ScreenVertex {
    /// Position in pixels, origin at the top-left corner, y down; the centre of pixel
    /// (i, j) is (i + 0.5, j + 0.5).
    pub x: f32,
    pub y: f32,
    /// Normalised device depth in [0, 1] (0 at the near plane); linear in screen space.
    pub z: f32,
    /// 1 / w_clip, for perspective-correct interpolation of `var`.
    pub inv_w: f32,
    /// Attributes (see [`varying`]), interpolated perspective-correctly.
    pub var: [f32; VARYINGS],
}

/// A lit, clipped, screen-space triangle with the caller's item id (written by the ID
/// buffer mode, e.g. the patch number of a hemicube) and its material index (per-pixel
/// Phong shades with that entry of the pipeline's material table).
#[derive(Clone, Copy, Debug, PartialEq, Default)]
#[repr(C)]
pub struct ScreenTriangle {
    pub v: [ScreenVertex; 3],
    pub id: u32,
    pub material: u32,
}

/// Bytes of one triangle in [`ScreenTriangle::write_bytes`].
pub const SCREEN_TRIANGLE_BYTES: usize = 3 * (4 + VARYINGS) * 4 + 8;

impl ScreenTriangle {
    /// Appends the little-endian encoding ([`SCREEN_TRIANGLE_BYTES`] bytes).
    pub fn write_bytes(&self, out: &mut Vec<u8>) {
        for v in &self.v {
            for f in [v.x, v.y, v.z, v.inv_w].iter().chain(v.var.iter()) {
                out.extend_from_slice(&f.to_le_bytes());
            }
        }
        out.extend_from_slice(&self.id.to_le_bytes());
        out.extend_from_slice(&self.material.to_le_bytes());
    }

    /// Decodes one triangle written by [`ScreenTriangle::write_bytes`]; `None` when
    /// `bytes` is shorter than [`SCREEN_TRIANGLE_BYTES`].
    pub fn read_bytes(bytes: &[u8]) -> Option<Self> {
        if bytes.len() < SCREEN_TRIANGLE_BYTES {
            return None;
        }
        let f = |i: usize| f32::from_le_bytes(bytes[4 * i..4 * i + 4].try_into().unwrap());
        let mut t = ScreenTriangle::default();
        let stride = 4 + VARYINGS;
        for (k, v) in t.v.iter_mut().enumerate() {
            let b = k * stride;
            v.x = f(b);
            v.y = f(b + 1);
            v.z = f(b + 2);
            v.inv_w = f(b + 3);
            for j in 0..VARYINGS {
                v.var[j] = f(b + 4 + j);
            }
        }
        let word = |at: usize| u32::from_le_bytes(bytes[at..at + 4].try_into().unwrap());
        t.id = word(SCREEN_TRIANGLE_BYTES - 8);
        t.material = word(SCREEN_TRIANGLE_BYTES - 4);
        Some(t)
    }
}

/// A rectangle of pixels `[x0, x1) x [y0, y1)` (a screen region in sort-first and
/// sort-middle rendering).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Rect {
    pub x0: u32,
    pub y0: u32,
    pub x1: u32,
    pub y1: u32,
}

impl Rect {
    pub fn new(x0: u32, y0: u32, x1: u32, y1: u32) -> Self {
        Self { x0, y0, x1, y1 }
    }

    /// The whole screen.
    pub fn full(width: u32, height: u32) -> Self {
        Self::new(0, 0, width, height)
    }

    pub fn width(&self) -> u32 {
        self.x1.saturating_sub(self.x0)
    }

    pub fn height(&self) -> u32 {
        self.y1.saturating_sub(self.y0)
    }

    pub fn is_empty(&self) -> bool {
        self.x1 <= self.x0 || self.y1 <= self.y0
    }

    /// The overlap of two rectangles (possibly empty).
    pub fn intersect(&self, o: &Rect) -> Rect {
        Rect::new(
            self.x0.max(o.x0),
            self.y0.max(o.y0),
            self.x1.min(o.x1),
            self.y1.min(o.y1),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bytes_round_trip() {
        let mut t = ScreenTriangle {
            id: 77,
            material: 5,
            ..Default::default()
        };
        t.v[1].x = 3.5;
        t.v[2].var[7] = -1.25;
        let mut b = Vec::new();
        t.write_bytes(&mut b);
        assert_eq!(b.len(), SCREEN_TRIANGLE_BYTES);
        assert_eq!(ScreenTriangle::read_bytes(&b), Some(t));
        assert_eq!(ScreenTriangle::read_bytes(&b[1..]), None);
    }
}
