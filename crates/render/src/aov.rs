//! Arbitrary output variables: images of what the camera rays found rather than the
//! light they brought back. Float images keep raw values; [`Aov::display`] maps them
//! to [0, 1] for PNG.

use crate::integrator::AovSample;
use irradia_core::{Image, Rgb};
use std::fmt;
use std::str::FromStr;

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Aov {
    /// Distance from the camera to the first hit (infinite on the background).
    Depth,
    /// World-space shading normal at the first hit, components in [-1, 1].
    Normal,
    /// Index of the first object hit (its position in the scene), -1 on the background.
    ObjectId,
    /// Deepest level of the pixel's ray tree (1 = the camera ray only, 0 = nothing).
    RayDepth,
}

impl Aov {
    pub const ALL: [Aov; 4] = [Aov::Depth, Aov::Normal, Aov::ObjectId, Aov::RayDepth];

    pub fn name(self) -> &'static str {
        match self {
            Aov::Depth => "depth",
            Aov::Normal => "normal",
            Aov::ObjectId => "object-id",
            Aov::RayDepth => "ray-depth",
        }
    }

    /// The raw value of this variable for one sample, as a colour.
    pub fn value(self, s: &AovSample) -> Rgb {
        match self {
            Aov::Depth => Rgb::splat(s.depth),
            Aov::Normal => Rgb::new(s.normal.x, s.normal.y, s.normal.z),
            Aov::ObjectId => Rgb::splat(s.object as f32),
            Aov::RayDepth => Rgb::splat(s.ray_depth as f32),
        }
    }

    /// The raw image mapped to [0, 1] for an 8-bit file: depth as grey from near (white)
    /// to the farthest finite depth (dark), background black; normals as `(n + 1) / 2`;
    /// object ids and ray depths divided by their maximum.
    pub fn display(self, raw: &Image) -> Image {
        let px = raw.pixels();
        let finite_max = |f: &dyn Fn(&Rgb) -> f32| {
            px.iter()
                .map(f)
                .filter(|v| v.is_finite())
                .fold(0.0f32, f32::max)
        };
        let out: Vec<Rgb> = match self {
            Aov::Depth => {
                let far = finite_max(&|c| c.r).max(f32::MIN_POSITIVE);
                px.iter()
                    .map(|c| {
                        if c.r.is_finite() {
                            Rgb::splat(1.0 - 0.9 * (c.r / far))
                        } else {
                            Rgb::BLACK
                        }
                    })
                    .collect()
            }
            Aov::Normal => px
                .iter()
                .map(|c| {
                    if c.is_black() {
                        Rgb::BLACK
                    } else {
                        c.map(|v| 0.5 * (v + 1.0))
                    }
                })
                .collect(),
            Aov::ObjectId => {
                let top = finite_max(&|c| c.r).max(0.0) + 1.0;
                px.iter().map(|c| Rgb::splat((c.r + 1.0) / top)).collect()
            }
            Aov::RayDepth => {
                let top = finite_max(&|c| c.r).max(1.0);
                px.iter().map(|c| Rgb::splat(c.r / top)).collect()
            }
        };
        Image::from_pixels(raw.width(), raw.height(), out)
    }
}

impl fmt::Display for Aov {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Aov {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        Aov::ALL
            .into_iter()
            .find(|a| a.name() == s)
            .ok_or_else(|| format!("unknown AOV '{s}' (use depth, normal, object-id or ray-depth)"))
    }
}
