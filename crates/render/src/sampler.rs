//! Where in a pixel each camera sample goes, and the random stream it goes on with:
//! the one sampler of every integrator ([`Sampler`]), followed by the pixel filter's
//! warp ([`crate::filter`]) in [`camera_sample`].
//!
//! - [`Sampler::Stratified`] (the Whitted tracer): one sample goes through the pixel
//!   centre (as POV-Ray without anti-aliasing); more samples use correlated
//!   multi-jittered sampling (Kensler, "Correlated Multi-Jittered Sampling", Pixar
//!   Technical Memo 13-01, 2013): stratified in 2D on an m x n grid and in each axis
//!   alone, for a sample count known in advance.
//! - [`Sampler::Independent`] (the path tracer, Mitsuba's `independent` sampler):
//!   uniform jitter drawn first from the sample's own stream, for renders whose sample
//!   count is not known in advance (time and error budgets); `seed` selects an
//!   independent family of streams.
//!
//! Both are seeded from (pixel, sample index), so images do not depend on threads,
//! tiles, passes or crop windows.

use crate::filter::FilterSampler;
use glam::Vec2;
use irradia_core::sampling::hash64;
use irradia_core::{Ray, Rng};
use irradia_geometry::packet::lanes::W;
use irradia_scene::camera::CameraRays;

/// Stream tag of the independent sampler's samples.
const INDEPENDENT_STREAM: u32 = 0x9a7b;

/// How the samples of a pixel are placed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Sampler {
    /// `spp` correlated multi-jittered samples (the pixel centre when `spp <= 1`).
    Stratified { spp: u32 },
    /// Uniform jitter from stream family `seed`.
    Independent { seed: u32 },
}

impl Sampler {
    /// Offset in `[0,1)²` of sample `i` of pixel (x, y), and the random stream the
    /// sample's rays use (already past the jitter).
    #[inline(always)]
    pub fn pixel_sample(&self, x: u32, y: u32, i: u32) -> (Vec2, Rng) {
        match *self {
            Sampler::Stratified { spp } => stratified(x, y, i.min(spp.max(1) - 1), spp),
            Sampler::Independent { seed } => {
                let mut rng =
                    Rng::for_pixel(x, y, i, INDEPENDENT_STREAM ^ seed.wrapping_mul(0x9e37_79b9));
                let j = rng.next_2d();
                (j, rng)
            }
        }
    }

    /// [`Sampler::pixel_sample`] of eight samples at once (pixel `(x[i], y[i])`, sample
    /// `i[i]`): the offsets' coordinates in lanes and the streams, each exactly the
    /// one-by-one sample's. The independent sampler's streams are made side by side
    /// ([`Rng::for_pixels_2d`]); the stratified sampler's one by one.
    #[inline(always)]
    pub fn pixel_samples8(
        &self,
        x: &[u32; 8],
        y: &[u32; 8],
        i: &[u32; 8],
    ) -> ([Rng; 8], [[f32; 8]; 2]) {
        match *self {
            Sampler::Independent { seed } => {
                Rng::for_pixels_2d(x, y, i, INDEPENDENT_STREAM ^ seed.wrapping_mul(0x9e37_79b9))
            }
            Sampler::Stratified { .. } => {
                let mut u = [[0.0; 8]; 2];
                let rngs = std::array::from_fn(|k| {
                    let (v, rng) = self.pixel_sample(x[k], y[k], i[k]);
                    (u[0][k], u[1][k]) = (v.x, v.y);
                    rng
                });
                (rngs, u)
            }
        }
    }

    /// [`Sampler::pixel_samples8`] over the path kernel's `W` lanes, eight at a time.
    #[inline(always)]
    pub fn pixel_samples_lanes(
        &self,
        x: &[u32; W],
        y: &[u32; W],
        i: &[u32; W],
    ) -> ([Rng; W], [[f32; W]; 2]) {
        const { assert!(W.is_multiple_of(8)) };
        let mut u = [[0.0; W]; 2];
        let mut rngs: [Rng; W] = std::array::from_fn(|_| Rng::new(0, 0));
        for h in 0..W / 8 {
            let r = h * 8..h * 8 + 8;
            let (rr, uu) = self.pixel_samples8(
                x[r.clone()].try_into().unwrap(),
                y[r.clone()].try_into().unwrap(),
                i[r.clone()].try_into().unwrap(),
            );
            for (k, g) in rr.into_iter().enumerate() {
                rngs[h * 8 + k] = g;
                u[0][h * 8 + k] = uu[0][k];
                u[1][h * 8 + k] = uu[1][k];
            }
        }
        (rngs, u)
    }
}

/// A camera sample: the ray, its random stream and its filter weight.
#[derive(Clone, Debug)]
pub struct CameraSample {
    pub ray: Ray,
    pub rng: Rng,
    pub weight: f32,
}

/// Sample `i` of pixel (x, y) (of the whole image, whatever the crop window): placed by
/// `sampler`, moved about the pixel centre by `filter`.
#[inline(always)]
pub fn camera_sample(
    cam: &CameraRays,
    filter: &FilterSampler,
    sampler: Sampler,
    x: u32,
    y: u32,
    i: u32,
) -> CameraSample {
    let (u, mut rng) = sampler.pixel_sample(x, y, i);
    let (o, weight) = filter.warp(u);
    // A thin lens draws its aperture point next from the sample's stream; pinhole and
    // orthographic cameras draw none, so their streams are unchanged.
    let ray = if cam.needs_lens_sample() {
        let lens = rng.next_2d();
        cam.ray_lens(x as f32 + o.x, y as f32 + o.y, lens)
    } else {
        cam.ray(x as f32 + o.x, y as f32 + o.y)
    };
    CameraSample { ray, rng, weight }
}

/// The camera ray through the centre of pixel (x, y) and its stream: the sample of a
/// one-sample stratified render, whatever the pixel filter (the centre stays the
/// centre); what object-parallel ray casting traces.
pub fn centre_sample(cam: &CameraRays, x: u32, y: u32) -> (Ray, Rng) {
    let (o, rng) = stratified(x, y, 0, 1);
    (cam.ray(x as f32 + o.x, y as f32 + o.y), rng)
}

/// Kensler's hash-based permutation of `0..l`: element `i` of a random permutation
/// chosen by `p`, with no memory.
fn permute(mut i: u32, l: u32, p: u32) -> u32 {
    let mut w = l - 1;
    w |= w >> 1;
    w |= w >> 2;
    w |= w >> 4;
    w |= w >> 8;
    w |= w >> 16;
    loop {
        i ^= p;
        i = i.wrapping_mul(0xe170_893d);
        i ^= p >> 16;
        i ^= (i & w) >> 4;
        i ^= p >> 8;
        i = i.wrapping_mul(0x0929_eb3f);
        i ^= p >> 23;
        i ^= (i & w) >> 1;
        i = i.wrapping_mul(1 | p >> 27);
        i = i.wrapping_mul(0x6935_fa69);
        i ^= (i & w) >> 11;
        i = i.wrapping_mul(0x74dc_b303);
        i ^= (i & w) >> 2;
        i = i.wrapping_mul(0x9e50_1cc3);
        i ^= (i & w) >> 2;
        i = i.wrapping_mul(0xc860_a3df);
        i &= w;
        i ^= i >> 5;
        if i < l {
            break;
        }
    }
    (i.wrapping_add(p)) % l
}

/// Offset in `[0,1)²` of sample `s` of `n` in pixel (x, y) by correlated multi-jittered
/// sampling, and the random stream the sample's rays use.
#[inline]
pub fn stratified(x: u32, y: u32, s: u32, n: u32) -> (Vec2, Rng) {
    let mut rng = Rng::for_pixel(x, y, s, 0);
    if n <= 1 {
        return (Vec2::splat(0.5), rng);
    }
    let p = hash64(((y as u64) << 32) | x as u64) as u32;
    let m = (n as f32).sqrt().ceil() as u32;
    let rows = n.div_ceil(m);
    let s = permute(s, n, p.wrapping_mul(0x5163_3e2d));
    let (sx, sy) = (s % m, s / m);
    let px = permute(sx, m, p.wrapping_mul(0xa511_e9b3));
    let py = permute(sy, rows, p.wrapping_mul(0x63d8_3595));
    let jx = rng.next_f32();
    let jy = rng.next_f32();
    let u = (sx as f32 + (py as f32 + jx) / rows as f32) / m as f32;
    let v = (sy as f32 + (px as f32 + jy) / m as f32) / rows as f32;
    (Vec2::new(u.min(0.999_999_9), v.min(0.999_999_9)), rng)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_sample_is_the_pixel_centre() {
        assert_eq!(stratified(3, 9, 0, 1).0, Vec2::splat(0.5));
    }

    #[test]
    fn samples_are_stratified_in_each_axis() {
        for &n in &[4u32, 9, 16, 5, 7, 12] {
            let m = (n as f32).sqrt().ceil() as u32;
            let rows = n.div_ceil(m);
            let mut cols_hit = vec![0u32; m as usize];
            let mut rows_hit = vec![0u32; rows as usize];
            for s in 0..n {
                let (o, _) = stratified(11, 4, s, n);
                assert!((0.0..1.0).contains(&o.x) && (0.0..1.0).contains(&o.y));
                cols_hit[(o.x * m as f32) as usize] += 1;
                rows_hit[(o.y * rows as f32) as usize] += 1;
            }
            // Each column and row of the m x rows grid gets at most its share.
            assert!(
                cols_hit.iter().all(|&c| c <= rows),
                "n={n} cols {cols_hit:?}"
            );
            assert!(rows_hit.iter().all(|&c| c <= m), "n={n} rows {rows_hit:?}");
        }
    }

    #[test]
    fn permutation_is_a_bijection() {
        for l in [1u32, 2, 5, 16, 33] {
            let mut seen = vec![false; l as usize];
            for i in 0..l {
                let j = permute(i, l, 0xdead_beef) as usize;
                assert!(!seen[j]);
                seen[j] = true;
            }
        }
    }
}
