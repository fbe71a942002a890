//! The progressive film of the path tracer: per-pixel sums of samples and of squared
//! luminance in f64, so that the mean, a per-pixel variance estimate and the error of
//! the whole image are known at any time, and a checkpoint of it can be written and
//! resumed.

use irradia_core::{Image, ImageError, Rgb};
use std::path::Path;

const MAGIC: &[u8; 16] = b"IRRADIA-FILM-v1\n";

/// Accumulated samples. Every pixel holds the same number of samples.
#[derive(Clone, Debug, PartialEq)]
pub struct Film {
    width: u32,
    height: u32,
    samples: u32,
    sum: Vec<[f64; 3]>,
    sum_sq: Vec<f64>,
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
    /// An empty film; the size is checked before allocating.
    pub fn new(width: u32, height: u32) -> Result<Self, ImageError> {
        let n = irradia_core::image::check_size(width, height, 32)?;
        Ok(Self {
            width,
            height,
            samples: 0,
            sum: vec![[0.0; 3]; n],
            sum_sq: vec![0.0; n],
        })
    }

    pub fn width(&self) -> u32 {
        self.width
    }
    pub fn height(&self) -> u32 {
        self.height
    }
    /// Samples per pixel accumulated so far.
    pub fn samples(&self) -> u32 {
        self.samples
    }

    /// Rows of (sum, sum of squared luminance) for parallel accumulation.
    pub(crate) fn rows_mut(
        &mut self,
    ) -> impl rayon::iter::IndexedParallelIterator<Item = (&mut [[f64; 3]], &mut [f64])> {
        use rayon::prelude::*;
        let w = self.width as usize;
        self.sum
            .par_chunks_mut(w)
            .zip(self.sum_sq.par_chunks_mut(w))
    }

    pub(crate) fn finish_pass(&mut self, samples: u32) {
        self.samples += samples;
    }

    /// The mean of the samples (black before the first sample).
    pub fn image(&self) -> Image {
        let k = if self.samples > 0 {
            1.0 / self.samples as f64
        } else {
            0.0
        };
        let px = self
            .sum
            .iter()
            .map(|s| Rgb::new((s[0] * k) as f32, (s[1] * k) as f32, (s[2] * k) as f32))
            .collect();
        Image::from_pixels(self.width, self.height, px)
    }

    /// Per-pixel variance of the mean luminance (the squared standard error).
    pub fn variance_of_mean(&self) -> Vec<f64> {
        let n = self.samples as f64;
        if self.samples < 2 {
            return vec![f64::INFINITY; self.sum.len()];
        }
        self.sum
            .iter()
            .zip(&self.sum_sq)
            .map(|(s, &s2)| {
                let mean = luminance(s) / n;
                let var = ((s2 / n - mean * mean) * n / (n - 1.0)).max(0.0);
                var / n
            })
            .collect()
    }

    /// Relative error of the image: the root-mean-square standard error of the pixel
    /// means divided by the image's mean luminance (infinite before two samples).
    pub fn relative_error(&self) -> f64 {
        if self.samples < 2 {
            return f64::INFINITY;
        }
        let var = self.variance_of_mean();
        let rms = (var.iter().sum::<f64>() / var.len() as f64).sqrt();
        let mean = self.sum.iter().map(luminance).sum::<f64>()
            / (self.sum.len() as f64 * self.samples as f64);
        if mean > 0.0 {
            rms / mean
        } else if rms == 0.0 {
            0.0
        } else {
            f64::INFINITY
        }
    }

    /// Writes the film to `path` atomically, tagged with the scene's fingerprint.
    pub fn save_checkpoint(&self, path: &Path, fingerprint: u64) -> std::io::Result<()> {
        let mut out = Vec::with_capacity(40 + self.sum.len() * 32);
        out.extend_from_slice(MAGIC);
        for v in [self.width, self.height, self.samples] {
            out.extend_from_slice(&v.to_le_bytes());
        }
        out.extend_from_slice(&fingerprint.to_le_bytes());
        for (s, s2) in self.sum.iter().zip(&self.sum_sq) {
            for v in s {
                out.extend_from_slice(&v.to_le_bytes());
            }
            out.extend_from_slice(&s2.to_le_bytes());
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
        if bytes.len() < 36 || &bytes[..16] != MAGIC {
            return Err(bad("wrong header"));
        }
        let u32_at = |o: usize| u32::from_le_bytes(bytes[o..o + 4].try_into().unwrap());
        let (width, height, samples) = (u32_at(16), u32_at(20), u32_at(24));
        let fp = u64::from_le_bytes(bytes[28..36].try_into().unwrap());
        if fp != fingerprint {
            return Err(CheckpointError::Mismatch { path: p });
        }
        let mut film = Film::new(width, height).map_err(|e| bad(&e.to_string()))?;
        let n = film.sum.len();
        if bytes.len() != 36 + n * 32 {
            return Err(bad("truncated data"));
        }
        for i in 0..n {
            let o = 36 + i * 32;
            let f =
                |k: usize| f64::from_le_bytes(bytes[o + 8 * k..o + 8 * k + 8].try_into().unwrap());
            film.sum[i] = [f(0), f(1), f(2)];
            film.sum_sq[i] = f(3);
        }
        film.samples = samples;
        Ok(film)
    }
}

#[inline]
pub(crate) fn luminance(s: &[f64; 3]) -> f64 {
    0.2126 * s[0] + 0.7152 * s[1] + 0.0722 * s[2]
}
