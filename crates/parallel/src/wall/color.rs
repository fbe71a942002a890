//! Colour matching, vignetting and dark-field compensation (Majumder, He, Towles, Welch
//! 2000, "Achieving color uniformity across multi-projector displays"): every projector
//! is driven so that the wall shows `floor + M * c` for the wanted linear colour `c`,
//! where `M` is a common gamut inside every projector's gamut (the mean primaries, pulled
//! towards grey until each projector can make them), `floor` is the darkest level every
//! pixel can reach (the dark field where overlapping black levels add up), and `M` is
//! scaled so the dimmest (vignetted, blended) pixel can still reach white.

use super::config::{Projector, WallConfig};
use glam::{Mat3, Vec3};

/// Gain of a projector's vignetting at its local pixel.
pub fn vignette(p: &Projector, c: &WallConfig, x: u32, y: u32) -> f32 {
    let u = (x as f32 + 0.5) / c.width as f32 * 2.0 - 1.0;
    let v = (y as f32 + 0.5) / c.height as f32 * 2.0 - 1.0;
    1.0 - p.vignetting * 0.5 * (u * u + v * v)
}

/// Displays covering wall pixel (wx, wy) with their local pixel.
pub fn covering(c: &WallConfig, wx: u32, wy: u32) -> impl Iterator<Item = (usize, u32, u32)> + '_ {
    (0..c.displays()).filter_map(move |j| {
        let (ox, oy) = c.origin(j);
        (wx >= ox && wx < ox + c.width && wy >= oy && wy < oy + c.height)
            .then(|| (j, wx - ox, wy - oy))
    })
}

/// Sum of the black levels at a wall pixel.
pub fn black_at(c: &WallConfig, wx: u32, wy: u32) -> Vec3 {
    covering(c, wx, wy)
        .map(|(j, _, _)| c.projectors[j].black)
        .sum()
}

/// The common response every projector is driven to reproduce.
#[derive(Clone, Debug)]
pub struct Correction {
    /// Linear colour to light, common to the wall.
    pub common: Mat3,
    pub floor: Vec3,
}

impl Correction {
    /// Plans the correction for a wall with blend weights `weights[i]` per display.
    pub fn plan(c: &WallConfig, weights: &[Vec<f32>]) -> Self {
        let n = c.displays();
        let inv: Vec<Mat3> = c.projectors.iter().map(|p| p.matrix.inverse()).collect();
        let mean = c
            .projectors
            .iter()
            .map(|p| p.matrix)
            .fold(Mat3::ZERO, |a, m| a + m)
            * (1.0 / n as f32);
        // Common gamut: pull the mean primaries towards grey until every projector can make them.
        let grey = Mat3::from_cols(
            Vec3::splat(1.0 / 3.0),
            Vec3::splat(1.0 / 3.0),
            Vec3::splat(1.0 / 3.0),
        );
        let mut gamut = mean;
        for k in 0..=20 {
            let lambda = 1.0 - k as f32 * 0.05;
            gamut = mean * (Mat3::IDENTITY * lambda + grey * (1.0 - lambda));
            if inv
                .iter()
                .all(|m| (*m * gamut).to_cols_array().iter().all(|&v| v >= -1e-6))
            {
                break;
            }
        }
        // Dark field: the floor must be reachable everywhere (M_p^-1 (floor - B) >= 0).
        let mut floor = Vec3::ZERO;
        let (ww, wh) = c.wall_size();
        let mut blacks: Vec<Vec3> = Vec::new();
        for wy in 0..wh {
            for wx in 0..ww {
                let b = black_at(c, wx, wy);
                if covering(c, wx, wy).next().is_some() && !blacks.contains(&b) {
                    blacks.push(b);
                }
            }
        }
        for b in &blacks {
            floor = floor.max(*b);
        }
        let step = gamut * Vec3::ONE * 0.002;
        for _ in 0..500 {
            let ok = blacks.iter().all(|b| {
                inv.iter()
                    .all(|m| (*m * (floor - *b)).min_element() >= -1e-7)
            });
            if ok {
                break;
            }
            floor += step;
        }
        // Brightness: the largest scale every pixel of every projector can reach at white.
        let mut scale = f32::INFINITY;
        for i in 0..n {
            let p = &c.projectors[i];
            let (ox, oy) = c.origin(i);
            for y in 0..c.height {
                for x in 0..c.width {
                    let w = weights[i][(y * c.width + x) as usize];
                    let g = vignette(p, c, x, y);
                    let a = inv[i] * (w * (floor - black_at(c, ox + x, oy + y))) / g;
                    let b = inv[i] * (w * (gamut * Vec3::ONE)) / g;
                    for k in 0..3 {
                        if b[k] > 1e-9 {
                            scale = scale.min((1.0 - a[k]) / b[k]);
                        }
                    }
                }
            }
        }
        Correction {
            common: gamut * scale.max(0.0),
            floor,
        }
    }

    /// The value (before the projector's gamma) display `i` must show at its local pixel
    /// (x, y) for the wall to show linear colour `want` there.
    pub fn drive(&self, c: &WallConfig, i: usize, x: u32, y: u32, weight: f32, want: Vec3) -> Vec3 {
        let p = &c.projectors[i];
        let (ox, oy) = c.origin(i);
        let target = self.floor + self.common * want.clamp(Vec3::ZERO, Vec3::ONE);
        let light = weight * (target - black_at(c, ox + x, oy + y)) / vignette(p, c, x, y);
        let lin = (p.matrix.inverse() * light).clamp(Vec3::ZERO, Vec3::ONE);
        Vec3::new(
            lin.x.powf(1.0 / p.gamma),
            lin.y.powf(1.0 / p.gamma),
            lin.z.powf(1.0 / p.gamma),
        )
    }
}
