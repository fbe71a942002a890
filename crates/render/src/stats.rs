//! Ray statistics in the manner of POV-Ray's "Render Statistics": rays by type, the
//! deepest level reached, and rays cut off by weight (adaptive depth control) or depth.
//!
//! Each tile counts into its own `Stats` (plain integers, no atomics in the hot path);
//! the tiles' counters are merged when the image is done.

use serde::{Deserialize, Serialize};
use std::fmt;

#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct Stats {
    pub width: u32,
    pub height: u32,
    /// Pixels rendered.
    pub pixels: u64,
    /// Camera samples (primary rays): pixels times samples per pixel, plus adaptive ones.
    pub samples: u64,
    pub camera_rays: u64,
    pub reflected_rays: u64,
    pub refracted_rays: u64,
    /// Shadow (feeler) rays towards light sources, and how many found the light fully
    /// blocked.
    pub shadow_rays: u64,
    pub shadow_blocked: u64,
    /// Rays that reached no object (they return the background).
    pub missed: u64,
    /// Secondary rays not traced because their weight fell below `min_weight`.
    pub cut_by_weight: u64,
    /// Secondary rays not traced because they would exceed `max_depth`.
    pub cut_by_depth: u64,
    /// Deepest level traced (camera rays are level 1), and the limit.
    pub max_level_reached: u32,
    pub max_level: u32,
    /// Pixels refined by adaptive supersampling.
    pub refined_pixels: u64,
}

impl Stats {
    /// Every ray traced: camera, reflected, refracted and shadow rays.
    pub fn total_rays(&self) -> u64 {
        self.camera_rays + self.reflected_rays + self.refracted_rays + self.shadow_rays
    }

    /// Adds another tile's (or thread's) counters into this one.
    pub fn merge(&mut self, o: &Stats) {
        self.pixels += o.pixels;
        self.samples += o.samples;
        self.camera_rays += o.camera_rays;
        self.reflected_rays += o.reflected_rays;
        self.refracted_rays += o.refracted_rays;
        self.shadow_rays += o.shadow_rays;
        self.shadow_blocked += o.shadow_blocked;
        self.missed += o.missed;
        self.cut_by_weight += o.cut_by_weight;
        self.cut_by_depth += o.cut_by_depth;
        self.max_level_reached = self.max_level_reached.max(o.max_level_reached);
        self.refined_pixels += o.refined_pixels;
    }

    #[inline]
    pub(crate) fn reached(&mut self, level: u32) {
        if level > self.max_level_reached {
            self.max_level_reached = level;
        }
    }
}

impl fmt::Display for Stats {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let line = "-".repeat(60);
        writeln!(f, "Render Statistics")?;
        writeln!(f, "Image Resolution {} x {}", self.width, self.height)?;
        writeln!(f, "{line}")?;
        let spp = if self.pixels > 0 {
            self.samples as f64 / self.pixels as f64
        } else {
            0.0
        };
        writeln!(
            f,
            "Pixels:  {:>12}   Samples: {:>12}   Smpls/Pxl: {spp:.2}",
            self.pixels, self.samples
        )?;
        writeln!(
            f,
            "Rays:    {:>12}   Max Level: {}/{}",
            self.total_rays(),
            self.max_level_reached,
            self.max_level
        )?;
        writeln!(f, "{line}")?;
        writeln!(f, "Camera Rays:       {:>12}", self.camera_rays)?;
        writeln!(f, "Reflected Rays:    {:>12}", self.reflected_rays)?;
        writeln!(f, "Refracted Rays:    {:>12}", self.refracted_rays)?;
        writeln!(
            f,
            "Shadow Ray Tests:  {:>12}   Blocked: {:>12}",
            self.shadow_rays, self.shadow_blocked
        )?;
        writeln!(f, "Rays Missed:       {:>12}", self.missed)?;
        writeln!(f, "Cut by Weight:     {:>12}", self.cut_by_weight)?;
        writeln!(f, "Cut by Depth:      {:>12}", self.cut_by_depth)?;
        if self.refined_pixels > 0 {
            writeln!(f, "Refined Pixels:    {:>12}", self.refined_pixels)?;
        }
        write!(f, "{line}")
    }
}
