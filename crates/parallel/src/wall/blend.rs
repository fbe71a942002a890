//! Edge blending (Raskar et al. 1998, "The office of the future"; Majumder and Stevens
//! 2005): in an overlap, each projector's contribution ramps down towards its edge; the
//! ramps are normalised so that at every wall pixel the weights of the projectors that
//! cover it sum to one in linear light.

use super::config::WallConfig;

fn ramp(d: f32, overlap: u32) -> f32 {
    if overlap == 0 {
        return 1.0;
    }
    let t = (d / overlap as f32).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t) + 1e-6 // smoothstep, never exactly zero inside
}

/// Unnormalised attenuation of display `i` at its local pixel (x, y).
fn attenuation(c: &WallConfig, x: u32, y: u32) -> f32 {
    let dx = (x as f32 + 0.5).min(c.width as f32 - x as f32 - 0.5);
    let dy = (y as f32 + 0.5).min(c.height as f32 - y as f32 - 0.5);
    ramp(dx, c.overlap) * ramp(dy, c.overlap)
}

/// Blend weights of display `i` at each of its pixels (row-major, width x height).
pub fn weights(c: &WallConfig, i: usize) -> Vec<f32> {
    let (ox, oy) = c.origin(i);
    let mut out = Vec::with_capacity((c.width * c.height) as usize);
    for y in 0..c.height {
        for x in 0..c.width {
            let (wx, wy) = (ox + x, oy + y);
            let mut sum = 0.0;
            for j in 0..c.displays() {
                let (jx, jy) = c.origin(j);
                if wx >= jx && wx < jx + c.width && wy >= jy && wy < jy + c.height {
                    sum += attenuation(c, wx - jx, wy - jy);
                }
            }
            out.push(attenuation(c, x, y) / sum);
        }
    }
    out
}
