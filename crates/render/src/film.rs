//! The film: what every integrator's samples add up to. Per pixel of the rendered
//! window (the whole image, or its crop window), the filter-weighted sums of the
//! samples' radiance and of their squared luminance, and the sum of the weights, in
//! f64; so the image (`sum / weight`, pbrt-v4's `RGBFilm`), a per-pixel variance
//! estimate and the error of the whole image are known at any time, and a checkpoint of
//! it can be written and resumed.
//!
//! A render of one sample per pixel has no use for the sums after its one pass (no
//! variance before two samples, no second pass to resume), so its film can keep each
//! pixel's value alone ([`Film::for_one_sample`]): 12 bytes a pixel written once, in
//! place of 40 bytes kept for the image to be computed from afterwards (a 1280x720
//! film of sums is 37 MB, whose first touch alone showed as a tenth of a one-sample
//! Whitted render). Tiles still add their samples into [`FilmPixel`]s of their own, so
//! the value stored is the very `sum / weight` the sums would give.

use irradia_core::{Image, ImageError, Rgb};
use irradia_scene::{CropWindow, Scene};
use rayon::prelude::*;
use std::path::Path;

const MAGIC: &[u8; 16] = b"IRRADIA-FILM-v2\n";
/// Header: magic, window (x, y, width, height), samples, fingerprint.
const HEADER: usize = 16 + 5 * 4 + 8;
/// Per pixel: three sums, the sum of squared luminance, the weight.
const PIXEL: usize = 5 * 8;

/// One pixel's accumulated samples.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[repr(C)]
pub struct FilmPixel {
    pub sum: [f64; 3],
    pub sum_sq: f64,
    pub weight: f64,
}

impl FilmPixel {
    /// Adds one sample of radiance `l` with filter weight `w` (non-finite samples count
    /// as black).
    #[inline]
    pub fn add(&mut self, l: Rgb, w: f32) {
        let w = w as f64;
        let v = if l.is_finite() {
            [l.r as f64 * w, l.g as f64 * w, l.b as f64 * w]
        } else {
            [0.0; 3]
        };
        self.sum[0] += v[0];
        self.sum[1] += v[1];
        self.sum[2] += v[2];
        let y = luminance(&v);
        self.sum_sq += y * y;
        self.weight += w;
    }

    /// The variance of this pixel's mean over `n` samples (luminance samples are
    /// `w·y`; their mean over the mean weight is the pixel's value, the weights being 1
    /// for the box and tent filters); 0 for a pixel of no weight.
    #[inline]
    fn variance_of_mean(&self, n: f64) -> f64 {
        let mean_w = self.weight / n;
        if mean_w <= 0.0 {
            return 0.0;
        }
        let mean = luminance(&self.sum) / n;
        let var = ((self.sum_sq / n - mean * mean) * n / (n - 1.0)).max(0.0);
        var / n / (mean_w * mean_w)
    }

    /// The filtered mean (black before the first sample).
    #[inline]
    pub fn value(&self) -> Rgb {
        if self.weight > 0.0 {
            let k = self.weight;
            Rgb::new(
                (self.sum[0] / k) as f32,
                (self.sum[1] / k) as f32,
                (self.sum[2] / k) as f32,
            )
        } else {
            Rgb::BLACK
        }
    }
}

/// `n` empty pixels from a zeroed allocation: the kernel hands out zero pages as they
/// are first written, instead of the pixels being written twice (a 1280x720 film is
/// 37 MB, a noticeable part of a one-sample render).
fn zeroed_pixels(n: usize) -> Vec<FilmPixel> {
    // `vec!` of an all-zero f64 array allocates zeroed memory (calloc).
    let mut raw = std::mem::ManuallyDrop::new(vec![[0.0f64; 5]; n]);
    let (ptr, len, cap) = (raw.as_mut_ptr(), raw.len(), raw.capacity());
    // SAFETY: `FilmPixel` is `repr(C)` of five f64 (size 40, align 8), exactly the
    // layout of `[f64; 5]`, and all-zero bits are its default (every field 0.0); the
    // allocation is handed over whole (pointer, length and capacity), never freed twice.
    let mut v = unsafe { Vec::from_raw_parts(ptr.cast::<FilmPixel>(), len, cap) };
    // calloc's zeroed pages of a large block are mapped on first write: ask for 2 MiB
    // ones, before any is written.
    irradia_core::pages::prefer_huge_pages(&mut v);
    v
}

/// `n` black pixel values from a zeroed allocation (mapped by the kernel on first
/// write, as [`zeroed_pixels`]), on 2 MiB pages where the kernel agrees.
fn zeroed_values(n: usize) -> Vec<Rgb> {
    let layout = std::alloc::Layout::array::<Rgb>(n).expect("the size was checked");
    if layout.size() == 0 {
        return Vec::new();
    }
    // SAFETY: the block is allocated by the global allocator with exactly the layout a
    // `Vec<Rgb>` of capacity `n` has, and all-zero bits are a valid `Rgb` (three f32
    // zeros, whatever the field order); a null pointer (out of memory) is handled.
    let mut v = unsafe {
        let ptr = std::alloc::alloc_zeroed(layout).cast::<Rgb>();
        if ptr.is_null() {
            std::alloc::handle_alloc_error(layout);
        }
        Vec::from_raw_parts(ptr, n, n)
    };
    irradia_core::pages::prefer_huge_pages(&mut v);
    v
}

/// What a film keeps of each pixel.
#[derive(Clone, Debug, PartialEq)]
enum Store {
    /// The running sums: any number of passes, error estimates, checkpoints.
    Sums(Vec<FilmPixel>),
    /// The finished value alone ([`FilmPixel::value`] of the pixel's one sample),
    /// written once by the one pass of a one-sample render ([`Film::for_one_sample`]).
    Values(Vec<Rgb>),
}

/// Accumulated samples of a window of the image. Progressive renders give every pixel
/// the same number of samples ([`Film::samples`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Film {
    window: CropWindow,
    samples: u32,
    store: Store,
}

/// Errors reading a checkpoint.
#[derive(Debug, thiserror::Error)]
pub enum CheckpointError {
    #[error("{path}: {message}")]
    Io { path: String, message: String },
    #[error("{path}: not an Irradia checkpoint, or a damaged one ({message})")]
    Format { path: String, message: String },
    #[error("{path}: this checkpoint belongs to another scene or image size; delete it or render without --resume")]
    Mismatch { path: String },
}

impl Film {
    /// An empty film of a whole `width` x `height` image; the size is checked before
    /// allocating.
    pub fn new(width: u32, height: u32) -> Result<Self, ImageError> {
        Self::for_window(CropWindow {
            x: 0,
            y: 0,
            width,
            height,
        })
    }

    /// An empty film of the pixels of `window`.
    pub fn for_window(window: CropWindow) -> Result<Self, ImageError> {
        let n = irradia_core::image::check_size(window.width, window.height, 40)?;
        Ok(Self {
            window,
            samples: 0,
            store: Store::Sums(zeroed_pixels(n)),
        })
    }

    /// An empty film of the pixels of `window` for a render of one sample per pixel in
    /// one pass: it keeps each pixel's value, not its sums, so it takes that one pass
    /// only, gives no error estimate (none exists below two samples) and cannot be
    /// checkpointed. Its image is the one a film of sums gives, bit for bit.
    pub fn for_one_sample(window: CropWindow) -> Result<Self, ImageError> {
        let n = irradia_core::image::check_size(window.width, window.height, 12)?;
        Ok(Self {
            window,
            samples: 0,
            store: Store::Values(zeroed_values(n)),
        })
    }

    /// An empty film of the scene's window (its crop window, or the whole image).
    pub fn for_scene(scene: &Scene) -> Result<Self, ImageError> {
        Self::for_window(scene.settings.window())
    }

    /// Width of the film (of the crop window, if any).
    pub fn width(&self) -> u32 {
        self.window.width
    }
    pub fn height(&self) -> u32 {
        self.window.height
    }
    /// The rectangle of the image this film holds.
    pub fn window(&self) -> CropWindow {
        self.window
    }
    /// Samples per pixel accumulated so far (by progressive passes).
    pub fn samples(&self) -> u32 {
        self.samples
    }

    /// Number of pixels (of the window).
    pub fn len(&self) -> usize {
        match &self.store {
            Store::Sums(p) => p.len(),
            Store::Values(v) => v.len(),
        }
    }

    /// Whether the film has no pixels (never: sizes are checked to be positive).
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The pixels' sums; `None` for a film of values ([`Film::for_one_sample`]).
    pub fn sums(&self) -> Option<&[FilmPixel]> {
        match &self.store {
            Store::Sums(p) => Some(p),
            Store::Values(_) => None,
        }
    }

    /// The pixel at image coordinates (x, y), which must lie in the window.
    #[inline]
    pub(crate) fn index(&self, x: u32, y: u32) -> usize {
        (y - self.window.y) as usize * self.window.width as usize + (x - self.window.x) as usize
    }

    /// Stores `row`, the pixels from index `at` on (a tile's row, its film values plus
    /// its new samples).
    #[inline]
    pub(crate) fn store_row(&mut self, at: usize, row: &[FilmPixel]) {
        match &mut self.store {
            Store::Sums(p) => p[at..at + row.len()].copy_from_slice(row),
            Store::Values(v) => {
                for (o, p) in v[at..at + row.len()].iter_mut().zip(row) {
                    *o = p.value();
                }
            }
        }
    }

    /// Appends the `n` pixels from index `at` on to `out`: their sums, or, for a film
    /// of values before its one pass, empty pixels.
    pub(crate) fn read_row(&self, at: usize, n: usize, out: &mut Vec<FilmPixel>) {
        match &self.store {
            Store::Sums(p) => out.extend_from_slice(&p[at..at + n]),
            Store::Values(_) => {
                assert_eq!(self.samples, 0, "a film of values takes one pass only");
                out.resize(out.len() + n, FilmPixel::default());
            }
        }
    }

    pub(crate) fn finish_pass(&mut self, samples: u32) {
        self.samples += samples;
        if matches!(self.store, Store::Values(_)) {
            assert!(self.samples <= 1, "a film of values holds one sample");
        }
    }

    /// The filtered mean of the samples (black before the first sample).
    pub fn image(&self) -> Image {
        let px = match &self.store {
            Store::Sums(p) => {
                let mut px = Vec::with_capacity(p.len());
                irradia_core::pages::prefer_huge_pages(px.spare_capacity_mut());
                px.extend(p.iter().map(FilmPixel::value));
                px
            }
            Store::Values(v) => v.clone(),
        };
        Image::from_pixels(self.window.width, self.window.height, px)
    }

    /// [`Film::image`], the film's values moved into it where it keeps values.
    pub fn into_image(self) -> Image {
        match self.store {
            Store::Values(v) => Image::from_pixels(self.window.width, self.window.height, v),
            Store::Sums(_) => self.image(),
        }
    }

    /// Per-pixel variance of the mean luminance (the squared standard error); infinite
    /// below two samples.
    pub fn variance_of_mean(&self) -> Vec<f64> {
        let pixels = match &self.store {
            Store::Sums(p) if self.samples >= 2 => p,
            _ => return vec![f64::INFINITY; self.len()],
        };
        let n = self.samples as f64;
        pixels.iter().map(|p| p.variance_of_mean(n)).collect()
    }

    /// Relative error of the image: the root-mean-square standard error of the pixel
    /// means divided by the image's mean luminance (infinite before two samples).
    /// Summed in blocks of pixels on the current rayon pool (the driver asks after
    /// every pass, between passes, when the other threads wait), the blocks' sums
    /// added in order, so the figure does not depend on the thread count.
    pub fn relative_error(&self) -> f64 {
        if self.samples < 2 {
            return f64::INFINITY;
        }
        let Store::Sums(pixels) = &self.store else {
            return f64::INFINITY;
        };
        let n = self.samples as f64;
        let blocks: Vec<(f64, f64)> = pixels
            .par_chunks(16_384)
            .map(|block| {
                block.iter().fold((0.0, 0.0), |(var, mean), p| {
                    let value = if p.weight > 0.0 {
                        luminance(&p.sum) / p.weight
                    } else {
                        0.0
                    };
                    (var + p.variance_of_mean(n), mean + value)
                })
            })
            .collect();
        let (var, mean) = blocks
            .iter()
            .fold((0.0, 0.0), |(v, m), &(bv, bm)| (v + bv, m + bm));
        let rms = (var / pixels.len() as f64).sqrt();
        let mean = mean / pixels.len() as f64;
        if mean > 0.0 {
            rms / mean
        } else if rms == 0.0 {
            0.0
        } else {
            f64::INFINITY
        }
    }

    /// Writes the film to `path` atomically, tagged with the scene's fingerprint. A film
    /// of values ([`Film::for_one_sample`]) has no sums to write: an error.
    pub fn save_checkpoint(&self, path: &Path, fingerprint: u64) -> std::io::Result<()> {
        let Store::Sums(pixels) = &self.store else {
            return Err(std::io::Error::other(
                "a one-sample film keeps pixel values, not the sums a checkpoint needs",
            ));
        };
        let mut out = Vec::with_capacity(HEADER + pixels.len() * PIXEL);
        out.extend_from_slice(MAGIC);
        let w = self.window;
        for v in [w.x, w.y, w.width, w.height, self.samples] {
            out.extend_from_slice(&v.to_le_bytes());
        }
        out.extend_from_slice(&fingerprint.to_le_bytes());
        for p in pixels {
            for v in [p.sum[0], p.sum[1], p.sum[2], p.sum_sq, p.weight] {
                out.extend_from_slice(&v.to_le_bytes());
            }
        }
        irradia_core::io::write_atomic(path, &out)
    }

    /// Reads a checkpoint written by [`Film::save_checkpoint`] for the same scene.
    pub fn load_checkpoint(path: &Path, fingerprint: u64) -> Result<Film, CheckpointError> {
        let p = path.display().to_string();
        let bytes = std::fs::read(path).map_err(|e| CheckpointError::Io {
            path: p.clone(),
            message: e.to_string(),
        })?;
        let bad = |m: &str| CheckpointError::Format {
            path: p.clone(),
            message: m.into(),
        };
        if bytes.len() < HEADER || &bytes[..16] != MAGIC {
            return Err(bad("wrong header"));
        }
        let u32_at = |o: usize| u32::from_le_bytes(bytes[o..o + 4].try_into().unwrap());
        let window = CropWindow {
            x: u32_at(16),
            y: u32_at(20),
            width: u32_at(24),
            height: u32_at(28),
        };
        let samples = u32_at(32);
        let fp = u64::from_le_bytes(bytes[36..44].try_into().unwrap());
        if fp != fingerprint {
            return Err(CheckpointError::Mismatch { path: p });
        }
        let mut film = Film::for_window(window).map_err(|e| bad(&e.to_string()))?;
        let n = film.len();
        if bytes.len() != HEADER + n * PIXEL {
            return Err(bad("truncated data"));
        }
        let Store::Sums(pixels) = &mut film.store else {
            unreachable!("for_window makes a film of sums")
        };
        for (i, px) in pixels.iter_mut().enumerate() {
            let o = HEADER + i * PIXEL;
            let f =
                |k: usize| f64::from_le_bytes(bytes[o + 8 * k..o + 8 * k + 8].try_into().unwrap());
            *px = FilmPixel {
                sum: [f(0), f(1), f(2)],
                sum_sq: f(3),
                weight: f(4),
            };
        }
        film.samples = samples;
        Ok(film)
    }
}

/// A fingerprint of what determines the image (the scene, the film's window and
/// filter, and the integrator's own parameters `integrator`), not the sample budget; a
/// checkpoint of another scene is refused with it.
pub fn fingerprint(scene: &Scene, integrator: &str) -> u64 {
    let s = &scene.settings;
    let text = format!(
        "{}x{}|{:?}|{:?}|{:?}|{}|{}|{}|{}|{:?}|{:?}|{:?}",
        s.width,
        s.height,
        s.background,
        scene.camera,
        scene
            .materials
            .iter()
            .map(|m| (m.emission, m.diffuse, m.specular, m.transmission))
            .collect::<Vec<_>>(),
        scene.objects.len(),
        scene.materials.len(),
        scene.lights.len(),
        integrator,
        scene.source,
        s.filter,
        s.crop,
    );
    text.bytes().fold(0xcbf2_9ce4_8422_2325u64, |h, b| {
        (h ^ b as u64).wrapping_mul(0x100_0000_01b3)
    })
}

#[inline]
pub(crate) fn luminance(s: &[f64; 3]) -> f64 {
    0.2126 * s[0] + 0.7152 * s[1] + 0.0722 * s[2]
}
