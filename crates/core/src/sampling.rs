//! Deterministic random numbers and the standard warps from the unit square.
//!
//! Every sample stream is seeded from what it belongs to (pixel, sample index, pass),
//! never from a thread, so an image does not depend on the thread count or tile order.

use glam::{Vec2, Vec3};
use std::f32::consts::{FRAC_1_PI, PI};

/// PCG32 (O'Neill 2014, "PCG: A Family of Simple Fast Space-Efficient Statistically Good
/// Algorithms for Random Number Generation"), XSH-RR output.
#[derive(Clone, Debug)]
pub struct Rng {
    state: u64,
    inc: u64,
}

impl Rng {
    /// A stream for `seed` on sequence `stream`.
    pub fn new(seed: u64, stream: u64) -> Self {
        let mut r = Rng {
            state: 0,
            inc: (stream << 1) | 1,
        };
        r.next_u32();
        r.state = r.state.wrapping_add(seed);
        r.next_u32();
        r
    }

    /// A stream for one pixel sample: the same for any thread or tile order.
    #[inline]
    pub fn for_pixel(x: u32, y: u32, sample: u32, pass: u32) -> Self {
        let key = hash64(((y as u64) << 32) | x as u64);
        Rng::new(hash64(key ^ ((sample as u64) << 20) ^ pass as u64), key)
    }

    /// [`Rng::for_pixel`] and then [`Rng::next_2d`] for `N` samples at once (pixel
    /// `(x[i], y[i])`, sample `sample[i]`, one `pass`): the streams past those two
    /// numbers, and the numbers (`u[0][i]`, `u[1][i]`). The same arithmetic as `N`
    /// calls, written as loops over the samples, so that a caller compiled for wide
    /// vectors (the path kernel's AVX2) runs the `N` hash chains side by side instead
    /// of one after the other.
    #[inline(always)]
    pub fn for_pixels_2d<const N: usize>(
        x: &[u32; N],
        y: &[u32; N],
        sample: &[u32; N],
        pass: u32,
    ) -> ([Rng; N], [[f32; N]; 2]) {
        let mut state = [0u64; N];
        let mut inc = [0u64; N];
        for i in 0..N {
            let key = hash64(((y[i] as u64) << 32) | x[i] as u64);
            let seed = hash64(key ^ ((sample[i] as u64) << 20) ^ pass as u64);
            inc[i] = (key << 1) | 1;
            // `new`: a step from state 0 (to `inc`), the seed added, a step.
            state[i] = pcg_step(inc[i].wrapping_add(seed), inc[i]);
        }
        let mut u = [[0.0; N]; 2];
        for u in &mut u {
            for i in 0..N {
                let old = state[i];
                state[i] = pcg_step(old, inc[i]);
                u[i] = unit_f32(pcg_output(old));
            }
        }
        let rngs = std::array::from_fn(|i| Rng {
            state: state[i],
            inc: inc[i],
        });
        (rngs, u)
    }

    /// `K` calls of [`Rng::next_f32`] on each stream `rngs[i]` whose bit `i` of `take`
    /// is set (`N <= 32`), the numbers of call `k` in `u[k][i]`; the other streams stay
    /// as they are (their numbers mean nothing). The same arithmetic as the calls,
    /// written as loops over the streams, so that a caller compiled for wide vectors
    /// (the path kernel) steps the `N` generators side by side.
    #[inline(always)]
    pub fn next_f32_lanes<const N: usize, const K: usize>(
        rngs: &mut [Rng; N],
        take: u32,
    ) -> [[f32; N]; K] {
        assert!(N <= 32);
        let mut state: [u64; N] = std::array::from_fn(|i| rngs[i].state);
        let inc: [u64; N] = std::array::from_fn(|i| rngs[i].inc);
        let mut u = [[0.0; N]; K];
        for u in &mut u {
            for i in 0..N {
                let old = state[i];
                u[i] = unit_f32(pcg_output(old));
                state[i] = if take >> i & 1 != 0 {
                    pcg_step(old, inc[i])
                } else {
                    old
                };
            }
        }
        for (r, s) in rngs.iter_mut().zip(state) {
            r.state = s;
        }
        u
    }

    #[inline]
    pub fn next_u32(&mut self) -> u32 {
        let old = self.state;
        self.state = pcg_step(old, self.inc);
        pcg_output(old)
    }

    /// Uniform in [0, 1).
    #[inline]
    pub fn next_f32(&mut self) -> f32 {
        unit_f32(self.next_u32())
    }

    /// A point uniform in the cube [-0.5, 0.5)³ (x, y, z drawn in that order): random
    /// directions, offsets and positions for tests and scene generators.
    #[inline]
    pub fn next_centered_vec3(&mut self) -> Vec3 {
        let x = self.next_f32() - 0.5;
        let y = self.next_f32() - 0.5;
        let z = self.next_f32() - 0.5;
        Vec3::new(x, y, z)
    }

    /// Uniform in [0, 1) with 53 bits.
    #[inline]
    pub fn next_f64(&mut self) -> f64 {
        let hi = (self.next_u32() as u64) << 21;
        let lo = (self.next_u32() >> 11) as u64;
        (hi | lo) as f64 * (1.0 / 9_007_199_254_740_992.0)
    }

    #[inline]
    pub fn next_2d(&mut self) -> Vec2 {
        Vec2::new(self.next_f32(), self.next_f32())
    }

    /// Uniform integer in `0..n` (n > 0).
    #[inline]
    pub fn below(&mut self, n: u32) -> u32 {
        ((self.next_u32() as u64 * n as u64) >> 32) as u32
    }
}

/// PCG32's state transition (an LCG step).
#[inline(always)]
fn pcg_step(state: u64, inc: u64) -> u64 {
    state
        .wrapping_mul(6_364_136_223_846_793_005)
        .wrapping_add(inc)
}

/// PCG32's XSH-RR output of the state before a step.
#[inline(always)]
fn pcg_output(old: u64) -> u32 {
    let xorshifted = (((old >> 18) ^ old) >> 27) as u32;
    let rot = (old >> 59) as u32;
    xorshifted.rotate_right(rot)
}

/// The top 24 bits of `v` as a uniform number in [0, 1).
#[inline(always)]
fn unit_f32(v: u32) -> f32 {
    (v >> 8) as f32 * (1.0 / 16_777_216.0)
}

/// SplitMix64 finaliser: a strong 64-bit mix for seeding.
#[inline]
pub fn hash64(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// Uniform point on the unit disk, Shirley-Chiu concentric map.
pub fn concentric_disk(u: Vec2) -> Vec2 {
    let o = 2.0 * u - Vec2::ONE;
    if o.x == 0.0 && o.y == 0.0 {
        return Vec2::ZERO;
    }
    let (r, theta) = if o.x.abs() > o.y.abs() {
        (o.x, PI / 4.0 * (o.y / o.x))
    } else {
        (o.y, PI / 2.0 - PI / 4.0 * (o.x / o.y))
    };
    r * Vec2::new(theta.cos(), theta.sin())
}

/// Cosine-weighted direction on the +z hemisphere; density `cos(theta) / pi`.
pub fn cosine_hemisphere(u: Vec2) -> Vec3 {
    let d = concentric_disk(u);
    let z = (1.0 - d.length_squared()).max(0.0).sqrt();
    Vec3::new(d.x, d.y, z)
}

#[inline]
pub fn cosine_hemisphere_pdf(cos_theta: f32) -> f32 {
    cos_theta.max(0.0) * FRAC_1_PI
}

/// Uniform direction on the unit sphere; density `1 / (4 pi)`.
pub fn uniform_sphere(u: Vec2) -> Vec3 {
    let z = 1.0 - 2.0 * u.x;
    let r = (1.0 - z * z).max(0.0).sqrt();
    let phi = 2.0 * PI * u.y;
    Vec3::new(r * phi.cos(), r * phi.sin(), z)
}

/// Uniform direction on the +z hemisphere; density `1 / (2 pi)`.
pub fn uniform_hemisphere(u: Vec2) -> Vec3 {
    let z = u.x;
    let r = (1.0 - z * z).max(0.0).sqrt();
    let phi = 2.0 * PI * u.y;
    Vec3::new(r * phi.cos(), r * phi.sin(), z)
}

/// Uniform barycentric coordinates on a triangle (b1, b2); b0 = 1 - b1 - b2.
pub fn uniform_triangle(u: Vec2) -> Vec2 {
    let s = u.x.sqrt();
    Vec2::new(1.0 - s, u.y * s)
}

/// The radical inverse in base 2 (van der Corput), for low-discrepancy sequences.
#[inline]
pub fn radical_inverse_base2(i: u32) -> f32 {
    (i.reverse_bits() >> 8) as f32 * (1.0 / 16_777_216.0)
}

/// The radical inverse of `i` in a prime `base` (Halton sequences).
pub fn radical_inverse(mut i: u64, base: u64) -> f64 {
    let inv = 1.0 / base as f64;
    let (mut f, mut r) = (inv, 0.0);
    while i > 0 {
        r += f * (i % base) as f64;
        i /= base;
        f *= inv;
    }
    r
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rng_is_uniform_enough() {
        let mut r = Rng::new(7, 3);
        let n = 100_000;
        let mut bins = [0u32; 10];
        for _ in 0..n {
            let v = r.next_f32();
            assert!((0.0..1.0).contains(&v));
            bins[(v * 10.0) as usize] += 1;
        }
        for b in bins {
            assert!((b as f32 - n as f32 / 10.0).abs() < 500.0, "{bins:?}");
        }
    }

    /// `for_pixels_2d` is `for_pixel` then `next_2d`, sample by sample: the numbers
    /// and the streams after them. (The sample index shifted by 21 in place of 20
    /// fails it: tried.)
    #[test]
    fn pixel_streams_in_lanes_are_the_one_by_one_streams() {
        let mut r = Rng::new(1, 2);
        for pass in [0u32, 7, 0x9a7b ^ 0x1234_5678] {
            let x: [u32; 8] = std::array::from_fn(|_| r.next_u32() % 4096);
            let y: [u32; 8] = std::array::from_fn(|i| if i == 3 { x[3] } else { r.next_u32() });
            let s: [u32; 8] = std::array::from_fn(|i| [0, 1, 63, 1 << 20][i % 4]);
            let (rngs, u) = Rng::for_pixels_2d(&x, &y, &s, pass);
            for i in 0..8 {
                let mut want = Rng::for_pixel(x[i], y[i], s[i], pass);
                let j = want.next_2d();
                assert_eq!((u[0][i], u[1][i]), (j.x, j.y));
                let mut got = rngs[i].clone();
                for _ in 0..3 {
                    assert_eq!(got.next_u32(), want.next_u32());
                }
            }
        }
    }

    /// `next_f32_lanes` is `K` calls of `next_f32` on the streams it takes, and leaves
    /// the others as they were.
    #[test]
    fn numbers_in_lanes_are_the_one_by_one_numbers() {
        let mut rngs: [Rng; 16] = std::array::from_fn(|i| Rng::for_pixel(i as u32, 5, 3, 1));
        for take in [0xffff_u32, 0, 0b1010_0110_0001_1001, 1 << 15] {
            let mut want = rngs.clone();
            let u: [[f32; 16]; 6] = Rng::next_f32_lanes(&mut rngs, take);
            for i in 0..16 {
                if take >> i & 1 != 0 {
                    for u in &u {
                        assert_eq!(u[i], want[i].next_f32());
                    }
                }
                assert_eq!(rngs[i].clone().next_u32(), want[i].next_u32(), "stream {i}");
            }
        }
    }

    #[test]
    fn pixel_streams_differ_and_repeat() {
        let a: Vec<u32> = (0..4)
            .map(|_| 0)
            .scan(Rng::for_pixel(3, 4, 0, 0), |r, _| Some(r.next_u32()))
            .collect();
        let b: Vec<u32> = (0..4)
            .map(|_| 0)
            .scan(Rng::for_pixel(3, 4, 0, 0), |r, _| Some(r.next_u32()))
            .collect();
        let c: Vec<u32> = (0..4)
            .map(|_| 0)
            .scan(Rng::for_pixel(4, 3, 0, 0), |r, _| Some(r.next_u32()))
            .collect();
        assert_eq!(a, b);
        assert_ne!(a, c);
    }

    #[test]
    fn warps_land_where_they_should() {
        let mut r = Rng::new(1, 1);
        for _ in 0..1000 {
            let u = r.next_2d();
            assert!(concentric_disk(u).length() <= 1.0 + 1e-6);
            let d = cosine_hemisphere(u);
            assert!(d.z >= 0.0 && (d.length() - 1.0).abs() < 1e-4);
            assert!((uniform_sphere(u).length() - 1.0).abs() < 1e-4);
        }
    }
}
