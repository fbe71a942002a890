//! A simulated photograph of the wall: every display's frame goes through its projector's
//! response (gamma, colour matrix, vignetting, black level) and the light of overlapping
//! projectors adds up; a camera calibrated to the common response turns light back into
//! the colour the wall was asked to show. Bezel gaps stay dark.

use super::color::{covering, vignette, Correction};
use super::config::WallConfig;
use glam::Vec3;

/// Light at each wall pixel (row-major over `c.wall_size()`) from the displays' frames
/// (`frames[i]` are drive values in [0, 1], row-major over one display).
pub fn light(c: &WallConfig, frames: &[Vec<Vec3>]) -> Vec<Vec3> {
    let (ww, wh) = c.wall_size();
    let mut out = vec![Vec3::ZERO; (ww * wh) as usize];
    for wy in 0..wh {
        for wx in 0..ww {
            let mut l = Vec3::ZERO;
            for (j, x, y) in covering(c, wx, wy) {
                let p = &c.projectors[j];
                let v = frames[j][(y * c.width + x) as usize];
                let lin = Vec3::new(v.x.powf(p.gamma), v.y.powf(p.gamma), v.z.powf(p.gamma));
                l += p.matrix * lin * vignette(p, c, x, y) + p.black;
            }
            out[(wy * ww + wx) as usize] = l;
        }
    }
    out
}

/// The photograph in the wall's linear colour (what the viewer sees, decoded through the
/// common response).
pub fn photograph(c: &WallConfig, corr: &Correction, frames: &[Vec<Vec3>]) -> Vec<Vec3> {
    let inv = corr.common.inverse();
    light(c, frames)
        .into_iter()
        .map(|l| inv * (l - corr.floor))
        .collect()
}
