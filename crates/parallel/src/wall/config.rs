//! The wall file (TOML): the grid of projectors or panels and each one's response.
//!
//! ```toml
//! columns = 3          # displays across
//! rows = 2             # displays down
//! width = 320          # pixels of each display
//! height = 240
//! overlap = 32         # pixels shared by neighbouring projectors (0 for panels)
//! bezel = 0            # pixels of dark gap between neighbouring panels (0 for projectors)
//!
//! [[projector]]        # optional, row-major; missing ones are ideal (gamma 2.2, identity)
//! gamma = 2.4                                   # transfer: light ~ value^gamma
//! matrix = [[0.9, 0.1, 0.0], [0.05, 0.95, 0.0], [0.0, 0.05, 0.85]]  # linear RGB -> light
//! black = [0.01, 0.01, 0.012]                   # light emitted at value 0 (dark field)
//! vignetting = 0.25                             # brightness falls to 1 - v at the corners
//! ```
//! Every error names the file, and the line and field where TOML knows them.

use glam::{Mat3, Vec3};
use serde::Deserialize;
use std::path::Path;

#[derive(Clone, Debug, PartialEq)]
pub struct Projector {
    pub gamma: f32,
    /// Linear RGB of the frame buffer to emitted light (columns = primaries).
    pub matrix: Mat3,
    pub black: Vec3,
    /// Radial falloff: gain = 1 - vignetting * r^2, r = 1 at the corners.
    pub vignetting: f32,
}

impl Default for Projector {
    fn default() -> Self {
        Self {
            gamma: 2.2,
            matrix: Mat3::IDENTITY,
            black: Vec3::ZERO,
            vignetting: 0.0,
        }
    }
}

#[derive(Clone, Debug, PartialEq)]
pub struct WallConfig {
    pub columns: u32,
    pub rows: u32,
    pub width: u32,
    pub height: u32,
    pub overlap: u32,
    pub bezel: u32,
    /// Row-major, `columns * rows` entries.
    pub projectors: Vec<Projector>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawWall {
    columns: u32,
    rows: u32,
    width: u32,
    height: u32,
    #[serde(default)]
    overlap: u32,
    #[serde(default)]
    bezel: u32,
    #[serde(default)]
    projector: Vec<RawProjector>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawProjector {
    gamma: Option<f32>,
    matrix: Option<[[f32; 3]; 3]>,
    black: Option<[f32; 3]>,
    vignetting: Option<f32>,
}

impl WallConfig {
    pub fn load(path: &Path) -> Result<Self, String> {
        let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
        Self::parse(&text).map_err(|e| format!("{}: {e}", path.display()))
    }

    pub fn parse(text: &str) -> Result<Self, String> {
        let raw: RawWall = toml::from_str(text).map_err(|e| {
            let msg = e.message().to_string();
            match e.span() {
                Some(s) => {
                    let line = text[..s.start.min(text.len())].matches('\n').count() + 1;
                    format!("line {line}: {msg}")
                }
                None => msg,
            }
        })?;
        let field = |name: &str, ok: bool, what: &str| {
            if ok {
                Ok(())
            } else {
                Err(format!("field `{name}`: {what}"))
            }
        };
        field(
            "columns",
            (1..=64).contains(&raw.columns),
            "expected 1 to 64",
        )?;
        field("rows", (1..=64).contains(&raw.rows), "expected 1 to 64")?;
        field(
            "width",
            (8..=8192).contains(&raw.width),
            "expected 8 to 8192 pixels",
        )?;
        field(
            "height",
            (8..=8192).contains(&raw.height),
            "expected 8 to 8192 pixels",
        )?;
        field(
            "overlap",
            raw.overlap * 2 <= raw.width.min(raw.height),
            "must be at most half the display size",
        )?;
        field("bezel", raw.bezel <= 4096, "expected at most 4096 pixels")?;
        if raw.overlap > 0 && raw.bezel > 0 {
            return Err("fields `overlap` and `bezel`: a wall has either overlapping projectors or panels with bezels, not both".into());
        }
        let n = (raw.columns * raw.rows) as usize;
        if raw.projector.len() > n {
            return Err(format!(
                "[[projector]]: {} given for a {}x{} wall of {n}",
                raw.projector.len(),
                raw.columns,
                raw.rows
            ));
        }
        let mut projectors = Vec::with_capacity(n);
        for (i, p) in raw.projector.iter().enumerate() {
            let d = Projector::default();
            let gamma = p.gamma.unwrap_or(d.gamma);
            let name = |f: &str| {
                format!(
                    "projector {} (row {}, column {}) field `{f}`",
                    i + 1,
                    i as u32 / raw.columns + 1,
                    i as u32 % raw.columns + 1
                )
            };
            if !(gamma.is_finite() && (0.5..=5.0).contains(&gamma)) {
                return Err(format!("{}: {gamma} is not in 0.5..5", name("gamma")));
            }
            let matrix = p
                .matrix
                .map(|m| Mat3::from_cols_array_2d(&m).transpose())
                .unwrap_or(d.matrix);
            if !matrix.to_cols_array().iter().all(|v| v.is_finite())
                || matrix.determinant().abs() < 1e-4
            {
                return Err(format!("{}: must be finite and invertible", name("matrix")));
            }
            let black = p.black.map(Vec3::from).unwrap_or(d.black);
            if !black.is_finite() || black.min_element() < 0.0 || black.max_element() > 0.5 {
                return Err(format!("{}: each value must be in 0..0.5", name("black")));
            }
            let vignetting = p.vignetting.unwrap_or(d.vignetting);
            if !(vignetting.is_finite() && (0.0..0.9).contains(&vignetting)) {
                return Err(format!(
                    "{}: {vignetting} is not in 0..0.9",
                    name("vignetting")
                ));
            }
            projectors.push(Projector {
                gamma,
                matrix,
                black,
                vignetting,
            });
        }
        projectors.resize(n, Projector::default());
        Ok(WallConfig {
            columns: raw.columns,
            rows: raw.rows,
            width: raw.width,
            height: raw.height,
            overlap: raw.overlap,
            bezel: raw.bezel,
            projectors,
        })
    }

    /// Size of the whole wall in wall pixels.
    pub fn wall_size(&self) -> (u32, u32) {
        let w = self.columns * self.width - (self.columns - 1) * self.overlap
            + (self.columns - 1) * self.bezel;
        let h =
            self.rows * self.height - (self.rows - 1) * self.overlap + (self.rows - 1) * self.bezel;
        (w, h)
    }

    /// Top-left wall pixel of display `i` (row-major).
    pub fn origin(&self, i: usize) -> (u32, u32) {
        let (c, r) = (i as u32 % self.columns, i as u32 / self.columns);
        (
            c * (self.width - self.overlap + self.bezel),
            r * (self.height - self.overlap + self.bezel),
        )
    }

    pub fn displays(&self) -> usize {
        (self.columns * self.rows) as usize
    }
}
