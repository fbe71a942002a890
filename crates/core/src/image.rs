//! A floating-point RGB image in linear light, row-major, origin at the top left.

use crate::color::Rgb;
use thiserror::Error;

/// Errors from making, reading or writing images.
#[derive(Debug, Error)]
pub enum ImageError {
    #[error("image size {width}x{height} is invalid: width and height must be at least 1")]
    ZeroSize { width: u32, height: u32 },
    #[error("image size {width}x{height} needs {bytes} bytes, more than can be allocated here")]
    TooLarge {
        width: u32,
        height: u32,
        bytes: u128,
    },
    #[error("{path}: {message}")]
    File { path: String, message: String },
    #[error("{path}: unsupported image extension (use .png, .exr or .pfm)")]
    UnknownFormat { path: String },
}

/// Width and height of the largest image Irradia allocates (65536 x 65536 pixels would
/// need 48 GiB of f32 RGB); checked before any memory is taken.
pub const MAX_PIXELS: u64 = 1 << 30;

#[derive(Clone, Debug, PartialEq)]
pub struct Image {
    width: u32,
    height: u32,
    pixels: Vec<Rgb>,
}

impl Image {
    /// A black image. Fails, without allocating, when the size is zero or too large.
    pub fn new(width: u32, height: u32) -> Result<Self, ImageError> {
        Self::filled(width, height, Rgb::BLACK)
    }

    /// An image of one colour, with the same checks as [`Image::new`].
    pub fn filled(width: u32, height: u32, c: Rgb) -> Result<Self, ImageError> {
        let n = check_size(width, height, std::mem::size_of::<Rgb>())?;
        let mut pixels = Vec::new();
        pixels
            .try_reserve_exact(n)
            .map_err(|_| ImageError::TooLarge {
                width,
                height,
                bytes: n as u128 * std::mem::size_of::<Rgb>() as u128,
            })?;
        pixels.resize(n, c);
        Ok(Self {
            width,
            height,
            pixels,
        })
    }

    /// Wraps a pixel buffer of `width * height` colours.
    pub fn from_pixels(width: u32, height: u32, pixels: Vec<Rgb>) -> Self {
        assert_eq!(
            pixels.len(),
            width as usize * height as usize,
            "pixel count must be width*height"
        );
        Self {
            width,
            height,
            pixels,
        }
    }

    #[inline]
    pub fn width(&self) -> u32 {
        self.width
    }
    #[inline]
    pub fn height(&self) -> u32 {
        self.height
    }
    #[inline]
    pub fn pixels(&self) -> &[Rgb] {
        &self.pixels
    }
    #[inline]
    pub fn pixels_mut(&mut self) -> &mut [Rgb] {
        &mut self.pixels
    }
    #[inline]
    pub fn into_pixels(self) -> Vec<Rgb> {
        self.pixels
    }

    #[inline]
    pub fn get(&self, x: u32, y: u32) -> Rgb {
        self.pixels[y as usize * self.width as usize + x as usize]
    }

    #[inline]
    pub fn set(&mut self, x: u32, y: u32, c: Rgb) {
        let w = self.width as usize;
        self.pixels[y as usize * w + x as usize] = c;
    }

    /// Mean of all pixels.
    pub fn mean(&self) -> Rgb {
        let mut s = [0f64; 3];
        for p in &self.pixels {
            s[0] += p.r as f64;
            s[1] += p.g as f64;
            s[2] += p.b as f64;
        }
        let n = self.pixels.len() as f64;
        Rgb::new((s[0] / n) as f32, (s[1] / n) as f32, (s[2] / n) as f32)
    }

    /// Root-mean-square difference per channel value from another image of the same size.
    pub fn rmse(&self, other: &Image) -> f64 {
        assert_eq!((self.width, self.height), (other.width, other.height));
        let mut s = 0f64;
        for (a, b) in self.pixels.iter().zip(&other.pixels) {
            let d = *a - *b;
            s += (d.r as f64).powi(2) + (d.g as f64).powi(2) + (d.b as f64).powi(2);
        }
        (s / (3.0 * self.pixels.len() as f64)).sqrt()
    }

    /// Largest absolute per-channel difference from another image of the same size.
    pub fn max_abs_diff(&self, other: &Image) -> f32 {
        assert_eq!((self.width, self.height), (other.width, other.height));
        self.pixels
            .iter()
            .zip(&other.pixels)
            .map(|(a, b)| {
                let d = *a - *b;
                d.r.abs().max(d.g.abs()).max(d.b.abs())
            })
            .fold(0.0, f32::max)
    }

    /// The image as 8-bit sRGB bytes, row-major RGB.
    pub fn to_srgb8(&self) -> Vec<u8> {
        let enc = crate::color::Srgb8Encoder::new();
        let mut out = vec![0u8; self.pixels.len() * 3];
        for (o, p) in out.chunks_exact_mut(3).zip(&self.pixels) {
            o.copy_from_slice(&enc.encode(*p));
        }
        out
    }
}

/// Checks an image size before allocation; returns the pixel count.
pub fn check_size(width: u32, height: u32, bytes_per_pixel: usize) -> Result<usize, ImageError> {
    if width == 0 || height == 0 {
        return Err(ImageError::ZeroSize { width, height });
    }
    let n = width as u64 * height as u64;
    if n > MAX_PIXELS {
        return Err(ImageError::TooLarge {
            width,
            height,
            bytes: n as u128 * bytes_per_pixel as u128,
        });
    }
    Ok(n as usize)
}

/// Peak signal-to-noise ratio in dB between two 8-bit images of equal length.
pub fn psnr_u8(a: &[u8], b: &[u8]) -> f64 {
    assert_eq!(a.len(), b.len());
    let mse: f64 = a
        .iter()
        .zip(b)
        .map(|(&x, &y)| (x as f64 - y as f64).powi(2))
        .sum::<f64>()
        / a.len() as f64;
    if mse == 0.0 {
        return f64::INFINITY;
    }
    10.0 * (255.0f64 * 255.0 / mse).log10()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_are_checked_before_allocation() {
        assert!(matches!(Image::new(0, 5), Err(ImageError::ZeroSize { .. })));
        assert!(matches!(
            Image::new(100_000, 100_000),
            Err(ImageError::TooLarge { .. })
        ));
        let im = Image::new(3, 2).unwrap();
        assert_eq!(im.pixels().len(), 6);
    }

    #[test]
    fn psnr_of_identical_is_infinite() {
        assert!(psnr_u8(&[1, 2, 3], &[1, 2, 3]).is_infinite());
        assert!((psnr_u8(&[0], &[255]) - 0.0).abs() < 1e-9);
    }
}
