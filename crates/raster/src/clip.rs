//! Homogeneous clipping (Sutherland and Hodgman 1974, done in clip space as in Blinn
//! and Newell 1978) against the near and far planes and a guard band around the screen.
//!
//! Triangles that stay inside the guard band are not clipped at the screen edges: the
//! rasterizer only visits pixels inside the screen, and its fixed-point edge functions
//! have room for the whole guard band. So the x/y planes cut only triangles that reach
//! far beyond the screen, and clipping never moves a vertex of an ordinary triangle.
//!
//! An edge crossing a plane is always cut by interpolating from its inside end to its
//! outside end, so two triangles sharing that edge produce the same new vertex bit for
//! bit and stay watertight.

use crate::screen::VARYINGS;
use glam::Vec4;

/// How far (in pixels) the guard band reaches beyond each edge of the screen.
pub const GUARD_BAND_PX: f32 = 8192.0;

/// A vertex in clip space with its attributes.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct ClipVertex {
    pub pos: Vec4,
    pub var: [f32; VARYINGS],
}

/// The most vertices a triangle can have after clipping by six planes.
pub const MAX_CLIPPED: usize = 9;

/// A convex polygon with at most [`MAX_CLIPPED`] vertices, on the stack.
#[derive(Clone, Copy, Debug)]
pub struct ClipPolygon {
    pub len: usize,
    pub v: [ClipVertex; MAX_CLIPPED],
}

/// The six clip planes for one screen size.
#[derive(Clone, Copy, Debug)]
pub struct ClipPlanes {
    /// Guard band half-extent in NDC units (> 1).
    gx: f32,
    gy: f32,
}

impl ClipPlanes {
    pub fn new(width: u32, height: u32) -> Self {
        Self {
            gx: 1.0 + 2.0 * GUARD_BAND_PX / width.max(1) as f32,
            gy: 1.0 + 2.0 * GUARD_BAND_PX / height.max(1) as f32,
        }
    }

    /// Signed distance-like value of `p` to plane `k`; inside when >= 0.
    #[inline(always)]
    fn dist(&self, k: usize, p: Vec4) -> f32 {
        match k {
            0 => p.z,       // near: z_ndc >= 0
            1 => p.w - p.z, // far: z_ndc <= 1
            2 => p.x + self.gx * p.w,
            3 => self.gx * p.w - p.x,
            4 => p.y + self.gy * p.w,
            _ => self.gy * p.w - p.y,
        }
    }

    /// One bit per plane that `p` is outside of.
    #[inline(always)]
    pub fn outcode(&self, p: Vec4) -> u8 {
        let mut code = 0u8;
        for k in 0..6 {
            if self.dist(k, p) < 0.0 {
                code |= 1 << k;
            }
        }
        code
    }

    /// Clips triangle `t` by the planes in `planes` (a mask of outcode bits; the
    /// union of the vertices' outcodes). The result may be empty.
    pub fn clip(&self, t: [&ClipVertex; 3], planes: u8) -> ClipPolygon {
        let mut cur = ClipPolygon {
            len: 3,
            v: [ClipVertex::default(); MAX_CLIPPED],
        };
        cur.v[0] = *t[0];
        cur.v[1] = *t[1];
        cur.v[2] = *t[2];
        for k in 0..6 {
            if planes & (1 << k) == 0 {
                continue;
            }
            let mut next = ClipPolygon {
                len: 0,
                v: [ClipVertex::default(); MAX_CLIPPED],
            };
            for i in 0..cur.len {
                let a = &cur.v[i];
                let b = &cur.v[(i + 1) % cur.len];
                let da = self.dist(k, a.pos);
                let db = self.dist(k, b.pos);
                let a_in = da >= 0.0;
                let b_in = db >= 0.0;
                if a_in {
                    push(&mut next, *a);
                }
                if a_in != b_in {
                    // Always from the inside end, so shared edges cut identically.
                    let (inside, outside, di, d_o) =
                        if a_in { (a, b, da, db) } else { (b, a, db, da) };
                    push(&mut next, lerp(inside, outside, di / (di - d_o)));
                }
            }
            cur = next;
            if cur.len < 3 {
                cur.len = 0;
                return cur;
            }
        }
        cur
    }
}

#[inline]
fn push(p: &mut ClipPolygon, v: ClipVertex) {
    if p.len < MAX_CLIPPED {
        p.v[p.len] = v;
        p.len += 1;
    }
}

#[inline]
fn lerp(a: &ClipVertex, b: &ClipVertex, t: f32) -> ClipVertex {
    let var: [f32; VARYINGS] = std::array::from_fn(|i| a.var[i] + t * (b.var[i] - a.var[i]));
    ClipVertex {
        pos: a.pos + t * (b.pos - a.pos),
        var,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cv(x: f32, y: f32, z: f32, w: f32) -> ClipVertex {
        ClipVertex {
            pos: Vec4::new(x, y, z, w),
            var: [x; VARYINGS],
        }
    }

    #[test]
    fn near_plane_cuts_one_corner_into_a_quad() {
        let planes = ClipPlanes::new(100, 100);
        let a = cv(0.0, 0.0, -1.0, 1.0);
        let b = cv(1.0, 0.0, 0.5, 1.0);
        let c = cv(0.0, 1.0, 0.5, 1.0);
        let code = planes.outcode(a.pos) | planes.outcode(b.pos) | planes.outcode(c.pos);
        assert_eq!(code, 1);
        let p = planes.clip([&a, &b, &c], code);
        assert_eq!(p.len, 4);
        for v in &p.v[..p.len] {
            assert!(v.pos.z >= -1e-6, "{v:?}");
        }
        // The cut on edge a-b is where z crosses 0: t = 1/1.5 from a.
        assert!(p
            .v
            .iter()
            .take(p.len)
            .any(|v| (v.pos.x - 2.0 / 3.0).abs() < 1e-6 && v.pos.z.abs() < 1e-6));
    }

    #[test]
    fn shared_edge_cut_is_identical_in_both_directions() {
        let planes = ClipPlanes::new(100, 100);
        let a = cv(0.3, 0.1, -0.7, 1.3);
        let b = cv(-0.2, 0.4, 0.9, 1.1);
        let c = cv(0.5, 0.5, 0.5, 1.0);
        let key = |p: &ClipPolygon| {
            let mut k: Vec<[u32; 4]> = p.v[..p.len]
                .iter()
                .map(|v| v.pos.to_array().map(f32::to_bits))
                .collect();
            k.sort();
            k
        };
        // The same triangle with the opposite winding walks edge a-b as b-a.
        assert_eq!(
            key(&planes.clip([&a, &b, &c], 1)),
            key(&planes.clip([&b, &a, &c], 1))
        );
    }
}
