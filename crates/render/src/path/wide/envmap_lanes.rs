//! The emitters at infinity for the W lanes at once: Mitsuba's `envmap`
//! ([`EnvmapSampler`]) looked up and importance sampled in SIMD lanes, and the constant
//! environment beside it, as Mitsuba 3's `llvm_ad_rgb` variant runs its `envmap` emitter
//! over vector lanes (Jakob et al., "Dr.Jit", SIGGRAPH 2022): the map's texels, cell
//! densities and alias tables are read by gathers
//! ([`gather`](irradia_geometry::packet::lanes::gather)), and everything else is lane
//! arithmetic.
//!
//! Each lane computes exactly what the scalar code computes, in its order, with selects
//! where it branches, so the results are the scalar ones bit for bit:
//! - a direction's map coordinates ([`EnvMap::uv_sin_theta`](irradia_scene::EnvMap)):
//!   the rotation into the map's frame, the polynomial arctangent
//!   ([`atan2`](irradia_geometry::packet::lanes::atan2), `irradia_core::atan2` in lanes);
//! - the bilinear lookup of the vertex grid (`EnvMap::eval_uv`: the grid cell, the four
//!   corner pixels, the weights) and the cell's density (`EnvmapSampler::pdf`), read from
//!   one record per grid vertex: the pixel's RGB and the density of the cell whose first
//!   corner it is, the wrapped column `W` stored so the lookup needs no wrap;
//! - a light sample: the cell drawn from the distribution's alias tables
//!   ([`AliasTable`]), its direction by the polynomial sine and cosine
//!   ([`sin_cos`](irradia_geometry::packet::lanes::sin_cos), `irradia_core::sin_cos` in
//!   lanes);
//! - the sum over the emitters at infinity with their choice probabilities
//!   (`LightSampler::environment_radiance_pdf`).

use super::gather::{checked, field};
use crate::path::alias::{AliasTable, ONE_MINUS_EPSILON};
use crate::path::envmap::EnvmapSampler;
use crate::path::lights::LightSampler;
use glam::Mat3;
use irradia_geometry::packet::lanes::{atan2, sin_cos, Fw, Mw, V3, W};
use std::f32::consts::PI;

/// A grid vertex's record: the pixel's RGB (unscaled) and the density `dist.pdf(i, j)`
/// of the cell `(i, j)` whose first corner it is (0 for the wrapped column and the last
/// row, which start no cell).
mod vtx {
    pub const RGB: usize = 0;
    pub const PDF: usize = 3;
    pub const LEN: usize = 4;
}

/// One environment map in the lanes' form.
pub(crate) struct EnvmapW {
    /// `(W + 1) x H` vertex records ([`vtx`]), row by row; column `W` repeats column 0.
    vertex: Vec<[f32; vtx::LEN]>,
    /// `W + 1`: records per row.
    stride: u32,
    /// `W` and `H - 1` (cells across and down) as `f32`, the last cell's column and
    /// row as `f32`, and `0.5 / W` (the half texel of `EnvMap::grid`).
    width: f32,
    rows: f32,
    last_column: f32,
    last_row: f32,
    half_texel: f32,
    /// The map's `scale` and its rotation from world to map (`to_world`'s transpose).
    scale: f32,
    to_map: Mat3,
    /// Whether the map has a density at all (`Piecewise2D::integral() > 0`).
    has_density: bool,
    /// The probability of choosing this emitter.
    probability: f32,
    /// The sampling distribution's alias tables ([`AliasTable`]): the marginal one over
    /// the `H - 1` rows of cells, and each row's over its `W` cells, row after row; a
    /// bin's threshold and its alias's bits.
    marginal_bins: Vec<[f32; 2]>,
    row_bins: Vec<[f32; 2]>,
    /// The map's rotation from map to world (`to_world`).
    to_world: Mat3,
}

impl EnvmapW {
    pub(crate) fn new(sampler: &EnvmapSampler, probability: f32) -> Self {
        let map = &sampler.map;
        let (w, h) = (map.image.width(), map.image.height());
        let dist = sampler.distribution();
        let bins = |t: &AliasTable| -> Vec<[f32; 2]> {
            t.bins()
                .iter()
                .map(|b| [b.q, f32::from_bits(b.alias)])
                .collect()
        };
        let marginal_bins = bins(dist.marginal().alias());
        let row_bins = dist.rows().iter().flat_map(|r| bins(r.alias())).collect();
        let mut vertex = Vec::with_capacity((w as usize + 1) * h as usize);
        for y in 0..h {
            for x in 0..=w {
                let c = map.vertex(x, y);
                let pdf = if x < w && y + 1 < h {
                    dist.pdf(x as usize, y as usize)
                } else {
                    0.0
                };
                vertex.push([c.r, c.g, c.b, pdf]);
            }
        }
        Self {
            vertex,
            stride: w + 1,
            width: w as f32,
            rows: (h - 1) as f32,
            last_column: (w - 1) as f32,
            last_row: (h - 2) as f32,
            half_texel: 0.5 / w as f32,
            scale: map.scale,
            to_map: map.to_world.transpose(),
            has_density: dist.integral() > 0.0,
            probability,
            marginal_bins,
            row_bins,
            to_world: map.to_world,
        }
    }

    /// `EnvMap::uv_sin_theta` in every lane: the map's `(u, v)` of world direction `dir`
    /// and its `sin θ`.
    #[inline(always)]
    fn uv_sin_theta(&self, dir: V3) -> (Fw, Fw, Fw) {
        let d = mat_mul(&self.to_map, dir).normalize();
        let u = atan2(d.x, -d.z) * (0.5 / PI);
        let u = u.lt(0.0).select(u + 1.0, u);
        let sin_theta = (d.x * d.x + d.z * d.z).sqrt();
        let theta = atan2(sin_theta, d.y);
        (u.min(1.0 - f32::EPSILON), clamp_unit(theta / PI), sin_theta)
    }

    /// `EnvMap::grid` and `EnvMap::cell` of map coordinates `(u, v)`: the index of the
    /// cell's first vertex record and the bilinear weights `fx`, `fy` of `eval_uv`.
    #[inline(always)]
    fn cell(&self, u: Fw, v: Fw) -> ([u32; W], Fw, Fw) {
        // `(u - ½/W).rem_euclid(1)`: `u` is in [0, 1) (or NaN), so `%` leaves it as it is.
        let x = u - self.half_texel;
        let s = x.lt(0.0).select(x + 1.0, x);
        let t = clamp_unit(v);
        let (xs, ys) = (s * self.width, t * self.rows);
        let (i, fi) = truncate_to(xs, self.last_column);
        let (j, fj) = truncate_to(ys, self.last_row);
        let fx = clamp_unit(xs - fi);
        let fy = clamp_unit(ys - fj);
        let idx = std::array::from_fn(|k| j[k] * self.stride + i[k]);
        (idx, fx, fy)
    }

    /// `EnvMap::eval_uv`'s bilinear interpolation of the cell at `idx` with weights
    /// `fx`, `fy`, times the scale, and the cell's density `dist.pdf(i, j)`.
    #[inline(always)]
    fn bilinear(&self, idx: &[u32; W], fx: Fw, fy: Fw) -> (V3, Fw) {
        let s = self.stride;
        let i10: [u32; W] = std::array::from_fn(|k| idx[k] + 1);
        let i01: [u32; W] = std::array::from_fn(|k| idx[k] + s);
        let i11: [u32; W] = std::array::from_fn(|k| idx[k] + s + 1);
        // The largest of the four: in bounds, so are the others.
        checked(&self.vertex[..], &i11);
        let corners = [idx, &i10, &i01, &i11];
        let (gx, gy) = (1.0 - fx, 1.0 - fy);
        // (No closure: it would not inherit the kernel's target features.)
        let l = V3::new(
            self.channel(corners, 0, (fx, gx), (fy, gy)),
            self.channel(corners, 1, (fx, gx), (fy, gy)),
            self.channel(corners, 2, (fx, gx), (fy, gy)),
        );
        (l, field(&self.vertex[..], idx, vtx::PDF))
    }

    /// One colour channel `c` of [`EnvmapW::bilinear`]: the corners `(i, j)`,
    /// `(i + 1, j)`, `(i, j + 1)`, `(i + 1, j + 1)` weighted as `eval_uv` weighs them
    /// (`(fx, 1 - fx)`, `(fy, 1 - fy)`), times the scale.
    #[inline(always)]
    fn channel(
        &self,
        corners: [&[u32; W]; 4],
        c: usize,
        (fx, gx): (Fw, Fw),
        (fy, gy): (Fw, Fw),
    ) -> Fw {
        let t = &self.vertex[..];
        let at = vtx::RGB + c;
        let top = field(t, corners[0], at) * gx + field(t, corners[1], at) * fx;
        let bottom = field(t, corners[2], at) * gx + field(t, corners[3], at) * fx;
        (top * gy + bottom * fy) * self.scale
    }

    /// `EnvmapSampler::pdf_uv`: the cell's density `p` turned into solid angle at
    /// `sin θ`, 0 for a black map or at the poles.
    #[inline(always)]
    fn solid_angle(&self, p: Fw, sin_theta: Fw) -> Fw {
        if !self.has_density {
            return Fw::ZERO;
        }
        let pdf = p / (Fw::splat(2.0 * PI * PI) * sin_theta);
        sin_theta.le(0.0).select(Fw::ZERO, pdf)
    }

    /// `EnvmapSampler::radiance_pdf(dir, true)` in every lane: the radiance arriving
    /// from world direction `dir` and the density with which `sample` produces `dir`.
    #[inline(always)]
    pub(crate) fn radiance_pdf(&self, dir: V3) -> (V3, Fw) {
        let (u, v, sin_theta) = self.uv_sin_theta(dir);
        let (idx, fx, fy) = self.cell(u, v);
        let (radiance, p) = self.bilinear(&idx, fx, fy);
        (radiance, self.solid_angle(p, sin_theta))
    }

    /// `EnvmapSampler::sample(u)` in the lanes of `lanes`: those that got a direction,
    /// the direction, the radiance arriving from it and its solid-angle density. The cell
    /// is drawn from the alias tables as the scalar `Piecewise2D::sample` draws it: two
    /// reads of the marginal table, then two of the drawn row's.
    #[inline(always)]
    pub(crate) fn sample(&self, u: [Fw; 2], lanes: Mw) -> (Mw, V3, V3, Fw) {
        if !self.has_density {
            return (Mw::FALSE, V3::ZERO, V3::ZERO, Fw::ZERO);
        }
        let (cells, rows) = (self.stride - 1, self.marginal_bins.len() as u32);
        // `Piecewise2D::sample`: the row by the marginal table, then the cell in it.
        let (v, j) = sample_1d(&self.marginal_bins, &[0; W], rows, u[1]);
        let start: [u32; W] = std::array::from_fn(|k| j[k] * cells);
        let (x, i) = sample_1d(&self.row_bins, &start, cells, u[0]);
        // `EnvMap::uv_of_grid`: `x + ½/W` is in [0, 2), so `rem_euclid(1)` subtracts 1
        // at most (exactly).
        let y = x + self.half_texel;
        let uu = y.ge(1.0).select(y - 1.0, y);
        // `EnvMap::direction_sin_theta`, with its polynomial sines and cosines.
        let (phi, theta) = (Fw::splat(2.0 * PI) * uu, Fw::splat(PI) * v);
        let ((sp, cp), (st, ct)) = (sin_cos(phi), sin_cos(theta));
        let wi = mat_mul(&self.to_world, V3::new(sp * st, ct, -cp * st)).normalize();
        let idx: [u32; W] = std::array::from_fn(|k| j[k] * self.stride + i[k]);
        checked(&self.vertex[..], &idx);
        let p = field(&self.vertex[..], &idx, vtx::PDF);
        let ok = lanes & !(st.le(0.0) | p.le(0.0));
        // `EnvMap::eval_uv` at the sampled point.
        let (cell, fx, fy) = self.cell(uu, v);
        let (radiance, _) = self.bilinear(&cell, fx, fy);
        let pdf = p / (Fw::splat(2.0 * PI * PI) * st);
        (ok, wi, radiance, pdf)
    }
}

/// `Piecewise1D::sample(u)` in every lane, lane `k` drawing from the alias table of
/// `n` cells whose bins start at `bins[start[k]]` ([`AliasTable::sample`] with the same
/// `f32` operations): the point of [0, 1) and its cell.
#[inline(always)]
fn sample_1d(bins: &[[f32; 2]], start: &[u32; W], n: u32, u: Fw) -> (Fw, [u32; W]) {
    let x = u * n as f32;
    let k = x.map(f32::floor);
    let f = (x - k).min(Fw::splat(ONE_MINUS_EPSILON));
    let own_bin: [u32; W] = std::array::from_fn(|l| (k.0[l] as u32).min(n - 1));
    let at: [u32; W] = std::array::from_fn(|l| start[l] + own_bin[l]);
    checked(bins, &at);
    let (q, alias) = (field(bins, &at, 0), field(bins, &at, 1));
    let own = f.lt(q);
    let i: [u32; W] = own.select_u32(own_bin, alias.0.map(f32::to_bits));
    let du = own.select(
        (f / q).min(Fw::splat(ONE_MINUS_EPSILON)),
        ((f - q) / (1.0 - q)).min(Fw::splat(ONE_MINUS_EPSILON)),
    );
    let du = du.min(Fw::splat(1.0 - f32::EPSILON));
    let fi = Fw(std::array::from_fn(|l| i[l] as f32));
    ((fi + du) / n as f32, i)
}

/// Every emitter at infinity of a scene in the lanes' form: the constant environment
/// (the background and Mitsuba's `constant` emitters, one radiance) and the maps.
pub(crate) struct EnvironmentW {
    /// The constant environment's radiance and its share of the light density,
    /// `probability / 4π` (zeros without one).
    constant: [f32; 3],
    constant_pdf: f32,
    maps: Vec<EnvmapW>,
}

impl EnvironmentW {
    pub(crate) fn new(lights: &LightSampler) -> Self {
        let (constant, constant_pdf, maps) = lights.environment_parts();
        Self {
            constant: [constant.r, constant.g, constant.b],
            constant_pdf,
            maps: maps
                .into_iter()
                .map(|(s, probability)| EnvmapW::new(s, probability))
                .collect(),
        }
    }

    /// The environment maps, in `LightSampler::environment_parts`' order.
    pub(crate) fn maps(&self) -> &[EnvmapW] {
        &self.maps
    }

    /// `LightSampler::environment_radiance_pdf(dir, true)` in every lane, bit for bit:
    /// the radiance a ray travelling along `dir` sees when it leaves the scene, and the
    /// density with which light sampling produces `dir`.
    #[inline(always)]
    pub(crate) fn radiance_pdf(&self, dir: V3) -> (V3, Fw) {
        let [r, g, b] = self.constant;
        let mut l = V3::new(Fw::splat(r), Fw::splat(g), Fw::splat(b));
        let mut pdf = Fw::splat(self.constant_pdf);
        for m in &self.maps {
            let (li, p) = m.radiance_pdf(dir);
            l = l.add(li);
            pdf = pdf + Fw::splat(m.probability) * p;
        }
        (l, pdf)
    }
}

/// `m * v` in every lane, in `glam`'s order (`x_axis * v.x + y_axis * v.y + z_axis * v.z`).
#[inline(always)]
fn mat_mul(m: &Mat3, v: V3) -> V3 {
    let row = |k: usize| {
        Fw::splat(m.x_axis[k]) * v.x + Fw::splat(m.y_axis[k]) * v.y + Fw::splat(m.z_axis[k]) * v.z
    };
    V3::new(row(0), row(1), row(2))
}

/// `f32::clamp(0, 1)` in every lane (a NaN stays NaN).
#[inline(always)]
fn clamp_unit(x: Fw) -> Fw {
    let x = x.lt(0.0).select(Fw::ZERO, x);
    x.gt(1.0).select(Fw::splat(1.0), x)
}

/// `(x as u32).min(top)` for an integer `top`, as integers and as `f32`: negative and
/// NaN lanes give 0 (as the saturating cast does).
#[inline(always)]
fn truncate_to(x: Fw, top: f32) -> ([u32; W], Fw) {
    let x = x.ge(0.0).select(x, Fw::ZERO).min(top);
    // SAFETY: every lane is finite and in [0, top], which fits an i32.
    let i: [u32; W] = std::array::from_fn(|k| unsafe { x.0[k].to_int_unchecked::<i32>() } as u32);
    let f = Fw(std::array::from_fn(|k| i[k] as i32 as f32));
    (i, f)
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;
    use irradia_core::{Image, Rgb, Rng};
    use irradia_scene::EnvMap;
    use std::path::PathBuf;
    use std::sync::Arc;

    /// A 16 x 8 map with a bright spot and a black row, turned.
    fn sampler() -> EnvmapSampler {
        let mut image = Image::filled(16, 8, Rgb::splat(0.2)).unwrap();
        for y in 0..8 {
            for x in 0..16 {
                image.set(
                    x,
                    y,
                    Rgb::new(0.1 + 0.07 * x as f32, 0.3, 0.05 + 0.2 * y as f32),
                );
            }
        }
        image.set(5, 2, Rgb::new(30.0, 20.0, 4.0));
        image.set(15, 6, Rgb::new(0.5, 3.0, 6.0));
        for x in 0..16 {
            image.set(x, 4, Rgb::BLACK);
        }
        EnvmapSampler::new(Arc::new(EnvMap {
            image: Arc::new(image),
            scale: 1.3,
            to_world: Mat3::from_rotation_x(0.4) * Mat3::from_rotation_y(-1.1),
            path: PathBuf::new(),
        }))
    }

    /// Directions of every kind: random, along the axes and the map's poles and seam
    /// (in the map's frame), and degenerate.
    fn directions(map: &EnvMap) -> Vec<Vec3> {
        let mut rng = Rng::new(21, 22);
        let mut dirs: Vec<Vec3> = (0..3000)
            .map(|_| {
                let v = Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) - 0.5;
                v * (0.1 + 10.0 * rng.next_f32())
            })
            .collect();
        for d in [
            Vec3::X,
            Vec3::Y,
            Vec3::Z,
            -Vec3::X,
            -Vec3::Y,
            -Vec3::Z,
            Vec3::new(0.0, 1.0, -1e-9),
            Vec3::new(1e-9, -1.0, 0.0),
            Vec3::new(-1e-7, 0.3, -1.0),
            Vec3::new(1e-7, 0.3, -1.0),
        ] {
            dirs.push(map.to_world * d);
            dirs.push(d);
        }
        // Texel centres and cell corners of the map.
        for k in 0..200 {
            let uv = glam::Vec2::new((k % 17) as f32 / 16.0, (k / 17) as f32 / 11.0);
            dirs.push(map.direction(uv.min(glam::Vec2::splat(1.0 - f32::EPSILON))));
        }
        dirs
    }

    /// The lanes' light samples equal the scalar `sample`'s bit for bit (direction,
    /// radiance, density, and the lanes without one), at random numbers and at the
    /// edges of the unit square.
    #[test]
    fn lanes_equal_the_scalar_sample() {
        let s = sampler();
        let m = EnvmapW::new(&s, 1.0);
        let mut rng = Rng::new(31, 32);
        let edge = [0.0, 0.5, 1.0 - f32::EPSILON / 2.0, 0.999_9, 1e-7];
        let (mut some, mut none) = (0, 0);
        for round in 0..2000 {
            let mut u = [Fw::ZERO; 2];
            for k in 0..W {
                let e = |i: usize| edge[(round + i) % edge.len()];
                u[0].0[k] = if round < 20 && k < 4 {
                    e(k)
                } else {
                    rng.next_f32()
                };
                u[1].0[k] = if round < 20 && k >= 2 {
                    e(k + 1)
                } else {
                    rng.next_f32()
                };
            }
            let (ok, wi, li, pdf) = m.sample(u, Mw::TRUE);
            for k in 0..W {
                let uk = glam::Vec2::new(u[0].0[k], u[1].0[k]);
                match s.sample(uk) {
                    Some(want) => {
                        some += 1;
                        assert!(ok.get(k), "a sample at {uk}");
                        assert_eq!(
                            wi.lane(k).to_array().map(f32::to_bits),
                            want.wi.to_array().map(f32::to_bits),
                            "{uk}"
                        );
                        let got = li.lane(k);
                        assert_eq!(
                            [got.x, got.y, got.z].map(f32::to_bits),
                            [want.radiance.r, want.radiance.g, want.radiance.b].map(f32::to_bits),
                            "{uk}"
                        );
                        assert_eq!(pdf.0[k].to_bits(), want.pdf.to_bits(), "{uk}");
                    }
                    None => {
                        none += 1;
                        assert!(!ok.get(k), "no sample at {uk}");
                    }
                }
            }
        }
        assert!(some > 10_000, "{some} samples, {none} without");
    }

    /// The lanes' radiance and density of every direction equal the scalar
    /// `radiance_pdf`'s bit for bit, for the map alone and with a constant environment.
    #[test]
    fn lanes_equal_the_scalar_lookup_and_density() {
        let s = sampler();
        let probability = 0.7;
        let m = EnvmapW::new(&s, probability);
        let env = EnvironmentW {
            constant: [0.1, 0.2, 0.3],
            constant_pdf: 0.3 / (4.0 * PI),
            maps: vec![EnvmapW::new(&s, probability)],
        };
        let dirs = directions(&s.map);
        for chunk in dirs.chunks(W) {
            let mut d = V3::ZERO;
            for k in 0..W {
                d.set_lane(k, chunk[k % chunk.len()]);
            }
            let (l, p) = m.radiance_pdf(d);
            let (l2, p2) = env.radiance_pdf(d);
            for k in 0..W {
                let dir = d.lane(k);
                let (want, want_p) = s.radiance_pdf(dir, true);
                let got = l.lane(k);
                assert_eq!(
                    [got.x, got.y, got.z].map(f32::to_bits),
                    [want.r, want.g, want.b].map(f32::to_bits),
                    "radiance along {dir}"
                );
                assert_eq!(p.0[k].to_bits(), want_p.to_bits(), "density along {dir}");
                let want2 = Rgb::new(0.1, 0.2, 0.3) + want;
                let got2 = l2.lane(k);
                assert_eq!(
                    [got2.x, got2.y, got2.z].map(f32::to_bits),
                    [want2.r, want2.g, want2.b].map(f32::to_bits)
                );
                let want_p2 = 0.3 / (4.0 * PI) + probability * want_p;
                assert_eq!(p2.0[k].to_bits(), want_p2.to_bits());
            }
        }
    }
}
