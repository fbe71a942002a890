//! The wall job of `irradia wall`, the same on threads ([`crate::comm::LocalComm`]) and
//! under `mpirun` (`MpiComm`): two frames, the corrected one and the naive one for
//! comparison. In each, every rank renders and corrects its own display and waits at the
//! frame barrier; then every rank writes its own display's image (`display-R-C.png`, the
//! projector's drive values) and rank 0, the display rank, gathers the frames and writes
//! the simulated photographs (`photo.png`, `photo-uncorrected.png`).
//!
//! Files are written atomically. A rank that cannot write its file fails with a
//! [`WallError`] naming it; under MPI the caller then ends the whole job (the other
//! ranks would otherwise wait for it at the next frame).

use super::{frame_and_own_with, WallConfig, WallRendering, WallSource};
use crate::comm::{Comm, CommError};
use glam::Vec3;
use irradia_core::{Image, Rgb};
use std::path::{Path, PathBuf};
use thiserror::Error;

/// Why a wall job failed on one rank.
#[derive(Debug, Error)]
pub enum WallError {
    #[error(transparent)]
    Comm(#[from] CommError),
    #[error("rank {rank}: {message}")]
    Write { rank: usize, message: String },
}

impl WallError {
    /// The rank at fault.
    pub fn culprit(&self) -> Option<usize> {
        match self {
            WallError::Comm(e) => e.culprit(),
            WallError::Write { rank, .. } => Some(*rank),
        }
    }
}

/// The file of display `i` (row `i / columns`, column `i % columns`, from 0).
pub fn display_file(c: &WallConfig, i: usize) -> String {
    format!(
        "display-{}-{}.png",
        i as u32 / c.columns,
        i as u32 % c.columns
    )
}

/// Writes `px` (`w` x `h`, row-major) as an image. `drive = true`: the values are
/// projector drive values, stored as they are (the PNG's 8-bit values are the drive
/// levels, `round(255 v)`); otherwise linear colour, encoded by the image writer (sRGB).
pub fn save(path: &Path, w: u32, h: u32, px: &[Vec3], drive: bool) -> Result<(), String> {
    let pixels = px
        .iter()
        .map(|v| {
            let v = v.clamp(Vec3::ZERO, Vec3::ONE);
            if drive {
                // The writer encodes linear light with the sRGB curve: pass it the value
                // that encodes to the drive level, so the file's 8-bit value is
                // round(255 * drive).
                let d = irradia_core::color::srgb_to_linear;
                Rgb::new(d(v.x), d(v.y), d(v.z))
            } else {
                Rgb::new(v.x, v.y, v.z)
            }
        })
        .collect();
    irradia_core::io::save(&Image::from_pixels(w, h, pixels), path).map_err(|e| e.to_string())
}

/// Runs the wall job on `comm` (one rank per display) and writes into `dir` (which must
/// exist). Returns the files this rank wrote.
pub fn run<C: Comm>(
    comm: &C,
    c: &WallConfig,
    src: &WallSource,
    dir: &Path,
) -> Result<Vec<PathBuf>, WallError> {
    run_with(comm, c, src, dir, WallRendering::PerDisplay)
}

/// [`run`] with a choice of how the displays' images are rendered.
pub fn run_with<C: Comm>(
    comm: &C,
    c: &WallConfig,
    src: &WallSource,
    dir: &Path,
    rendering: WallRendering,
) -> Result<Vec<PathBuf>, WallError> {
    let rank = comm.rank();
    let write = |name: &str, w: u32, h: u32, px: &[Vec3], drive: bool| {
        let path = dir.join(name);
        save(&path, w, h, px, drive).map_err(|message| WallError::Write { rank, message })?;
        Ok::<PathBuf, WallError>(path)
    };
    let (ww, wh) = c.wall_size();
    let mut written = Vec::new();
    for corrected in [true, false] {
        let (own, gathered) = frame_and_own_with(comm, c, src, corrected, rendering)?;
        if corrected {
            written.push(write(
                &display_file(c, rank),
                c.width,
                c.height,
                &own,
                true,
            )?);
        }
        if let Some(f) = gathered {
            let name = if corrected {
                "photo.png"
            } else {
                "photo-uncorrected.png"
            };
            written.push(write(name, ww, wh, &f.photo, false)?);
        }
    }
    Ok(written)
}
