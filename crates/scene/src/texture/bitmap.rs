//! Mitsuba 3's `bitmap` texture: an image file looked up by (transformed) uv with
//! nearest or bilinear filtering and a wrap mode, decoded from sRGB unless `raw`.
//!
//! Conventions, as Mitsuba's `bitmap.cpp` and Dr.Jit's `Texture` define them: uv (0, 0)
//! is the top-left corner of the file's first row, u runs right and v runs down; texel
//! (i, j) covers `[i/w, (i+1)/w] × [j/h, (j+1)/h]`, its centre is where bilinear
//! filtering returns it exactly. 8- and 16-bit files (PNG, JPEG) hold sRGB-encoded
//! values and are decoded to linear unless `raw = true`; float files (EXR, HDR) are
//! linear. One-channel files stay one channel; alpha is dropped.

use super::uv_transform::UvTransform;
use glam::Vec2;
use irradia_core::Rgb;
use std::path::{Path, PathBuf};

/// Mitsuba's `filter_type`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum FilterType {
    Nearest,
    #[default]
    Bilinear,
}

/// Mitsuba's `wrap_mode`: what a texel index outside the image reads.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum WrapMode {
    #[default]
    Repeat,
    Mirror,
    Clamp,
}

impl WrapMode {
    /// The texel index in `0..n` that index `i` reads.
    pub fn wrap(self, i: i64, n: u32) -> u32 {
        let n = i64::from(n);
        let j = match self {
            WrapMode::Repeat => i.rem_euclid(n),
            WrapMode::Clamp => i.clamp(0, n - 1),
            WrapMode::Mirror => {
                let k = i.rem_euclid(2 * n);
                if k < n {
                    k
                } else {
                    2 * n - 1 - k
                }
            }
        };
        j as u32
    }
}

/// The decoded texels: linear values, row-major from the top row, 1 or 3 per texel.
#[derive(Clone, Debug, PartialEq)]
pub struct Texels {
    pub width: u32,
    pub height: u32,
    /// 1 (grey) or 3 (RGB).
    pub channels: u8,
    pub data: Vec<f32>,
}

impl Texels {
    /// The texel at column `x`, row `y` (both in range) as a colour.
    pub fn get(&self, x: u32, y: u32) -> Rgb {
        let i = (y as usize * self.width as usize + x as usize) * self.channels as usize;
        if self.channels == 1 {
            Rgb::splat(self.data[i])
        } else {
            Rgb::new(self.data[i], self.data[i + 1], self.data[i + 2])
        }
    }

    /// Every texel times `k` (a grey image times a colour becomes a colour one): the
    /// bitmap's `scale`, glTF's factors beside their textures, pbrt's `imagemap`
    /// `scale`.
    pub fn scale(&mut self, k: Rgb) {
        if k == Rgb::splat(1.0) {
            return;
        }
        if self.channels == 1 && !(k.r == k.g && k.g == k.b) {
            self.data = self.data.iter().flat_map(|&v| [v, v, v]).collect();
            self.channels = 3;
        }
        if self.channels == 1 {
            self.data.iter_mut().for_each(|v| *v *= k.r);
        } else {
            for t in self.data.chunks_exact_mut(3) {
                t[0] *= k.r;
                t[1] *= k.g;
                t[2] *= k.b;
            }
        }
    }

    /// The mean over all texels.
    pub fn mean(&self) -> Rgb {
        let n = (self.width as usize * self.height as usize).max(1);
        let mut sum = [0.0f64; 3];
        for y in 0..self.height {
            for x in 0..self.width {
                let c = self.get(x, y);
                sum[0] += f64::from(c.r);
                sum[1] += f64::from(c.g);
                sum[2] += f64::from(c.b);
            }
        }
        Rgb::new(
            (sum[0] / n as f64) as f32,
            (sum[1] / n as f64) as f32,
            (sum[2] / n as f64) as f32,
        )
    }
}

/// A `bitmap` texture with its decoded texels.
#[derive(Clone, Debug, PartialEq)]
pub struct Bitmap {
    /// The file, as resolved against the scene file's folder.
    pub filename: PathBuf,
    pub texels: Texels,
    pub filter_type: FilterType,
    pub wrap_mode: WrapMode,
    /// The file's values were used as stored (no sRGB decoding).
    pub raw: bool,
    pub to_uv: UvTransform,
}

impl Bitmap {
    /// The colour at surface coordinates `uv`.
    pub fn eval(&self, uv: Vec2) -> Rgb {
        let st = self.to_uv.apply(uv);
        if !st.is_finite() {
            return Rgb::BLACK;
        }
        let (w, h) = (self.texels.width, self.texels.height);
        let at = |x: i64, y: i64| {
            self.texels
                .get(self.wrap_mode.wrap(x, w), self.wrap_mode.wrap(y, h))
        };
        let p = Vec2::new(st.x * w as f32, st.y * h as f32);
        match self.filter_type {
            FilterType::Nearest => at(p.x.floor() as i64, p.y.floor() as i64),
            FilterType::Bilinear => {
                let q = p - Vec2::splat(0.5);
                let (x0, y0) = (q.x.floor(), q.y.floor());
                let (fx, fy) = (q.x - x0, q.y - y0);
                let (x0, y0) = (x0 as i64, y0 as i64);
                at(x0, y0) * ((1.0 - fx) * (1.0 - fy))
                    + at(x0 + 1, y0) * (fx * (1.0 - fy))
                    + at(x0, y0 + 1) * ((1.0 - fx) * fy)
                    + at(x0 + 1, y0 + 1) * (fx * fy)
            }
        }
    }
}

/// Reads and decodes an image file (PNG, JPEG, EXR, HDR, and the other formats the
/// `image` crate was built with): sRGB-decoded unless `raw` or a float format.
pub fn read_texels(path: &Path, raw: bool) -> Result<Texels, String> {
    read_texels_selected(path, raw, None, None)
}

/// [`read_texels`] of image `image` embedded in a glTF or GLB file (`None`: `path` is
/// the image file), keeping only colour channel `channel` (0 to 3: R, G, B, A; `None`:
/// the image as it is).
pub fn read_texels_selected(
    path: &Path,
    raw: bool,
    image: Option<usize>,
    channel: Option<usize>,
) -> Result<Texels, String> {
    let img = match image {
        None => image::ImageReader::open(path)
            .map_err(|e| format!("cannot open {}: {e}", path.display()))?
            .with_guessed_format()
            .map_err(|e| format!("cannot read {}: {e}", path.display()))?
            .decode()
            .map_err(|e| format!("cannot decode {}: {e}", path.display()))?,
        Some(index) => {
            let file =
                irradia_geometry::io::gltf::GltfFile::open(path).map_err(|e| e.to_string())?;
            let bytes = match file.embedded_image(index).map_err(|e| e.to_string())? {
                Some(b) => b,
                None => {
                    let uri = file.image_uri(index).unwrap_or_default();
                    let dir = path.parent().unwrap_or(Path::new("."));
                    std::fs::read(dir.join(&uri))
                        .map_err(|e| format!("cannot open {}: {e}", dir.join(&uri).display()))?
                }
            };
            image::load_from_memory(&bytes)
                .map_err(|e| format!("cannot decode image {index} of {}: {e}", path.display()))?
        }
    };
    // One channel of the image as a grey one (16 bits keep 8- and 16-bit files exact;
    // a float file keeps its values).
    let img = match channel {
        None => img,
        Some(c)
            if matches!(
                img.color(),
                image::ColorType::Rgb32F | image::ColorType::Rgba32F
            ) =>
        {
            let rgba = img.to_rgba32f();
            let (w, h) = (rgba.width(), rgba.height());
            image::DynamicImage::ImageRgb32F(image::ImageBuffer::from_fn(w, h, |x, y| {
                let v = rgba.get_pixel(x, y).0[c.min(3)];
                image::Rgb([v, v, v])
            }))
        }
        Some(c) => {
            let rgba = img.to_rgba16();
            let (w, h) = (rgba.width(), rgba.height());
            image::DynamicImage::ImageLuma16(image::ImageBuffer::from_fn(w, h, |x, y| {
                image::Luma([rgba.get_pixel(x, y).0[c.min(3)]])
            }))
        }
    };
    let color = img.color();
    let float = matches!(color, image::ColorType::Rgb32F | image::ColorType::Rgba32F);
    let channels: u8 = if color.has_color() { 3 } else { 1 };
    let (width, height) = (img.width(), img.height());
    if width == 0 || height == 0 {
        return Err(format!("{} has no pixels", path.display()));
    }
    let values: Vec<f32> = if channels == 3 {
        img.to_rgb32f().into_raw()
    } else {
        img.to_luma32f().into_raw()
    };
    let data = if float || raw {
        values
    } else {
        values
            .into_iter()
            .map(irradia_core::color::srgb_to_linear)
            .collect()
    };
    if data.iter().any(|v| !v.is_finite()) {
        return Err(format!(
            "{} holds a value that is not finite",
            path.display()
        ));
    }
    Ok(Texels {
        width,
        height,
        channels,
        data,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scale_multiplies_every_texel_and_a_colour_turns_grey_into_colour() {
        let mut t = Texels {
            width: 2,
            height: 1,
            channels: 1,
            data: vec![0.5, 1.0],
        };
        t.scale(Rgb::splat(2.0));
        assert_eq!((t.channels, t.data.clone()), (1, vec![1.0, 2.0]));
        t.scale(Rgb::new(1.0, 0.5, 0.25));
        assert_eq!(t.channels, 3);
        assert_eq!(t.get(1, 0), Rgb::new(2.0, 1.0, 0.5));
        assert_eq!(t.get(0, 0), Rgb::new(1.0, 0.5, 0.25));
    }

    #[test]
    fn wrap_modes_fold_indices_as_mitsuba_does() {
        let idx = |m: WrapMode| (-3..7).map(|i| m.wrap(i, 3)).collect::<Vec<_>>();
        assert_eq!(idx(WrapMode::Repeat), [0, 1, 2, 0, 1, 2, 0, 1, 2, 0]);
        assert_eq!(idx(WrapMode::Clamp), [0, 0, 0, 0, 1, 2, 2, 2, 2, 2]);
        assert_eq!(idx(WrapMode::Mirror), [2, 1, 0, 0, 1, 2, 2, 1, 0, 0]);
    }
}
