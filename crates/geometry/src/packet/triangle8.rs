//! Eight world-space triangles tested against one ray at once: the Möller-Trumbore
//! test (Möller and Trumbore, "Fast, Minimum Storage Ray/Triangle Intersection",
//! JGT 2(1), 1997) in the form with a precomputed geometric normal that Embree uses
//! for its triangle leaves (Wald et al., "Embree: A Kernel Framework for Efficient CPU
//! Ray Tracing", SIGGRAPH 2014).
//!
//! For a ray `o + t d` and a triangle `v0 + b1 e1 + b2 e2` (`e1 = v1 - v0`,
//! `e2 = v2 - v0`, `n = e1 × e2`), Cramer's rule with `s = o - v0`, `r = d × s` and
//! `den = d · n` gives
//!
//! ```text
//! b1 = (e2 · r) / den,   b2 = -(e1 · r) / den,   t = -(s · n) / den.
//! ```
//!
//! The numerators are compared against `|den|` after taking the sign of `den` into
//! them, so nothing is divided until a lane is known to be hit. With AVX2 and FMA
//! (detected at run time) a packet is one 8-lane test; otherwise two 4-lane SSE tests
//! (x86_64 baseline) or a scalar loop. All paths compute the same products and sums
//! (the FMA path rounds fewer times), so they agree except within rounding of an edge.
//!
//! The test is not watertight: a ray through an edge shared by two triangles can,
//! with a probability of the order of the rounding error, slip between them. The path
//! tracer's estimate is unaffected at any measurable level; Mitsuba's and Embree's
//! default triangle tests behave the same way.

use super::simd_build::has_avx2;
use glam::Vec3;

/// Lanes of a packet.
pub const LANES: usize = 8;

/// Up to eight triangles, structure of arrays (`[axis][lane]`), 32-byte aligned.
/// Missing lanes hold a degenerate triangle (all zeros) that no ray hits.
#[derive(Clone, Copy, Debug)]
#[repr(C, align(32))]
pub struct TrianglePacket {
    v0: [[f32; LANES]; 3],
    e1: [[f32; LANES]; 3],
    e2: [[f32; LANES]; 3],
    n: [[f32; LANES]; 3],
}

/// A hit inside a packet: the lane, the ray parameter and the barycentrics of
/// `v1` and `v2`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PacketHit {
    pub lane: usize,
    pub t: f32,
    pub b1: f32,
    pub b2: f32,
}

/// Per-lane results of a test: sign-corrected numerators of `b1`, `b2`, `t` and
/// `|den|`.
type Lanes = [[f32; LANES]; 4];

impl TrianglePacket {
    /// Packs up to eight triangles (corners `v0, v1, v2`).
    pub fn new(tris: &[[Vec3; 3]]) -> Self {
        assert!(tris.len() <= LANES);
        let mut p = TrianglePacket {
            v0: [[0.0; LANES]; 3],
            e1: [[0.0; LANES]; 3],
            e2: [[0.0; LANES]; 3],
            n: [[0.0; LANES]; 3],
        };
        for (lane, t) in tris.iter().enumerate() {
            let (e1, e2) = (t[1] - t[0], t[2] - t[0]);
            let n = e1.cross(e2);
            for axis in 0..3 {
                p.v0[axis][lane] = t[0][axis];
                p.e1[axis][lane] = e1[axis];
                p.e2[axis][lane] = e2[axis];
                p.n[axis][lane] = n[axis];
            }
        }
        p
    }

    /// The 8-lane test: the mask of lanes hit with `0 < t < t_max`, and with `out`
    /// filled when the mask is not empty.
    ///
    /// # Safety
    /// The CPU must support AVX2 and FMA ([`has_avx2`]).
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma")]
    #[inline]
    pub unsafe fn test_avx2(&self, o: Vec3, d: Vec3, t_max: f32, out: &mut Lanes) -> u32 {
        use std::arch::x86_64::*;
        let ld = |a: &[f32; LANES]| _mm256_load_ps(a.as_ptr());
        let (dx, dy, dz) = (
            _mm256_set1_ps(d.x),
            _mm256_set1_ps(d.y),
            _mm256_set1_ps(d.z),
        );
        let sx = _mm256_sub_ps(_mm256_set1_ps(o.x), ld(&self.v0[0]));
        let sy = _mm256_sub_ps(_mm256_set1_ps(o.y), ld(&self.v0[1]));
        let sz = _mm256_sub_ps(_mm256_set1_ps(o.z), ld(&self.v0[2]));
        // r = d × s
        let rx = _mm256_fmsub_ps(dy, sz, _mm256_mul_ps(dz, sy));
        let ry = _mm256_fmsub_ps(dz, sx, _mm256_mul_ps(dx, sz));
        let rz = _mm256_fmsub_ps(dx, sy, _mm256_mul_ps(dy, sx));
        let dot = |ax: __m256, ay: __m256, az: __m256, b: &[[f32; LANES]; 3]| {
            _mm256_fmadd_ps(
                az,
                ld(&b[2]),
                _mm256_fmadd_ps(ay, ld(&b[1]), _mm256_mul_ps(ax, ld(&b[0]))),
            )
        };
        let neg = _mm256_set1_ps(-0.0);
        let den = dot(dx, dy, dz, &self.n);
        let sign = _mm256_and_ps(den, neg);
        let abs_den = _mm256_xor_ps(den, sign);
        let u = _mm256_xor_ps(dot(rx, ry, rz, &self.e2), sign);
        let v = _mm256_xor_ps(dot(rx, ry, rz, &self.e1), _mm256_xor_ps(sign, neg));
        let t = _mm256_xor_ps(dot(sx, sy, sz, &self.n), _mm256_xor_ps(sign, neg));
        let zero = _mm256_setzero_ps();
        let ok = _mm256_and_ps(
            _mm256_and_ps(
                _mm256_cmp_ps::<_CMP_GE_OQ>(u, zero),
                _mm256_cmp_ps::<_CMP_GE_OQ>(v, zero),
            ),
            _mm256_and_ps(
                _mm256_cmp_ps::<_CMP_LE_OQ>(_mm256_add_ps(u, v), abs_den),
                _mm256_and_ps(
                    _mm256_cmp_ps::<_CMP_GT_OQ>(t, zero),
                    _mm256_cmp_ps::<_CMP_LT_OQ>(t, _mm256_mul_ps(abs_den, _mm256_set1_ps(t_max))),
                ),
            ),
        );
        let mask = _mm256_movemask_ps(_mm256_and_ps(
            ok,
            _mm256_cmp_ps::<_CMP_GT_OQ>(abs_den, zero),
        )) as u32;
        if mask != 0 {
            _mm256_storeu_ps(out[0].as_mut_ptr(), u);
            _mm256_storeu_ps(out[1].as_mut_ptr(), v);
            _mm256_storeu_ps(out[2].as_mut_ptr(), t);
            _mm256_storeu_ps(out[3].as_mut_ptr(), abs_den);
        }
        mask
    }

    /// The same test four lanes at a time with SSE (x86_64 baseline).
    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    fn test_sse(&self, o: Vec3, d: Vec3, t_max: f32, out: &mut Lanes) -> u32 {
        use std::arch::x86_64::*;
        let mut mask = 0;
        for half in 0..2 {
            let k = 4 * half;
            // SAFETY: SSE2 is part of the x86_64 baseline; lanes k..k+4 lie in the
            // arrays (unaligned loads and stores).
            unsafe {
                let ld = |a: &[f32; LANES]| _mm_loadu_ps(a.as_ptr().add(k));
                let (dx, dy, dz) = (_mm_set1_ps(d.x), _mm_set1_ps(d.y), _mm_set1_ps(d.z));
                let sx = _mm_sub_ps(_mm_set1_ps(o.x), ld(&self.v0[0]));
                let sy = _mm_sub_ps(_mm_set1_ps(o.y), ld(&self.v0[1]));
                let sz = _mm_sub_ps(_mm_set1_ps(o.z), ld(&self.v0[2]));
                let rx = _mm_sub_ps(_mm_mul_ps(dy, sz), _mm_mul_ps(dz, sy));
                let ry = _mm_sub_ps(_mm_mul_ps(dz, sx), _mm_mul_ps(dx, sz));
                let rz = _mm_sub_ps(_mm_mul_ps(dx, sy), _mm_mul_ps(dy, sx));
                let dot = |ax: __m128, ay: __m128, az: __m128, b: &[[f32; LANES]; 3]| {
                    _mm_add_ps(
                        _mm_add_ps(_mm_mul_ps(ax, ld(&b[0])), _mm_mul_ps(ay, ld(&b[1]))),
                        _mm_mul_ps(az, ld(&b[2])),
                    )
                };
                let neg = _mm_set1_ps(-0.0);
                let den = dot(dx, dy, dz, &self.n);
                let sign = _mm_and_ps(den, neg);
                let abs_den = _mm_xor_ps(den, sign);
                let u = _mm_xor_ps(dot(rx, ry, rz, &self.e2), sign);
                let v = _mm_xor_ps(dot(rx, ry, rz, &self.e1), _mm_xor_ps(sign, neg));
                let t = _mm_xor_ps(dot(sx, sy, sz, &self.n), _mm_xor_ps(sign, neg));
                let zero = _mm_setzero_ps();
                let ok = _mm_and_ps(
                    _mm_and_ps(_mm_cmpge_ps(u, zero), _mm_cmpge_ps(v, zero)),
                    _mm_and_ps(
                        _mm_cmple_ps(_mm_add_ps(u, v), abs_den),
                        _mm_and_ps(
                            _mm_cmpgt_ps(t, zero),
                            _mm_cmplt_ps(t, _mm_mul_ps(abs_den, _mm_set1_ps(t_max))),
                        ),
                    ),
                );
                let m = _mm_movemask_ps(_mm_and_ps(ok, _mm_cmpgt_ps(abs_den, zero))) as u32;
                if m != 0 {
                    _mm_storeu_ps(out[0].as_mut_ptr().add(k), u);
                    _mm_storeu_ps(out[1].as_mut_ptr().add(k), v);
                    _mm_storeu_ps(out[2].as_mut_ptr().add(k), t);
                    _mm_storeu_ps(out[3].as_mut_ptr().add(k), abs_den);
                }
                mask |= m << k;
            }
        }
        mask
    }

    /// The same test one lane at a time (targets without SSE, and the tests' oracle).
    pub fn test_scalar(&self, o: Vec3, d: Vec3, t_max: f32, out: &mut Lanes) -> u32 {
        let mut mask = 0;
        for lane in 0..LANES {
            let g = |a: &[[f32; LANES]; 3]| Vec3::new(a[0][lane], a[1][lane], a[2][lane]);
            let (v0, e1, e2, n) = (g(&self.v0), g(&self.e1), g(&self.e2), g(&self.n));
            let s = o - v0;
            let r = d.cross(s);
            let den = d.dot(n);
            let sgn = if den.is_sign_negative() { -1.0 } else { 1.0 };
            let (u, v, t, a) = (
                e2.dot(r) * sgn,
                -e1.dot(r) * sgn,
                -s.dot(n) * sgn,
                den.abs(),
            );
            if a > 0.0 && u >= 0.0 && v >= 0.0 && u + v <= a && t > 0.0 && t < a * t_max {
                mask |= 1 << lane;
            }
            out[0][lane] = u;
            out[1][lane] = v;
            out[2][lane] = t;
            out[3][lane] = a;
        }
        mask
    }

    /// The portable test (SSE on x86_64).
    #[inline(always)]
    pub fn test(&self, o: Vec3, d: Vec3, t_max: f32, out: &mut Lanes) -> u32 {
        #[cfg(target_arch = "x86_64")]
        {
            self.test_sse(o, d, t_max, out)
        }
        #[cfg(not(target_arch = "x86_64"))]
        {
            self.test_scalar(o, d, t_max, out)
        }
    }
}

/// The nearest hit among the lanes of `mask` (results of a test) with `t < t_max`.
#[inline(always)]
pub fn nearest_lane(mut mask: u32, v: &Lanes, t_max: f32) -> Option<PacketHit> {
    let mut best: Option<PacketHit> = None;
    let mut t_max = t_max;
    while mask != 0 {
        let lane = mask.trailing_zeros() as usize;
        mask &= mask - 1;
        let inv = 1.0 / v[3][lane];
        let t = v[2][lane] * inv;
        if t < t_max {
            t_max = t;
            best = Some(PacketHit {
                lane,
                t,
                b1: v[0][lane] * inv,
                b2: v[1][lane] * inv,
            });
        }
    }
    best
}

/// Generates the nearest-hit and any-hit loops over a slice of packets with the test
/// `$test`, so the AVX2 variant is compiled with its target features throughout.
macro_rules! packet_loops {
    ($nearest:ident, $any:ident, $test:ident $(, #[$attr:meta])*) => {
        $(#[$attr])*
        /// The nearest hit with `0 < t < t_max` among `packets`: (packet index, hit).
        pub fn $nearest(
            packets: &[TrianglePacket],
            o: Vec3,
            d: Vec3,
            t_max: f32,
        ) -> Option<(usize, PacketHit)> {
            let mut best = None;
            let mut t_max = t_max;
            let mut lanes = [[0f32; LANES]; 4];
            for (k, p) in packets.iter().enumerate() {
                #[allow(unused_unsafe)]
                let mask = unsafe { p.$test(o, d, t_max, &mut lanes) };
                if mask != 0 {
                    if let Some(h) = nearest_lane(mask, &lanes, t_max) {
                        t_max = h.t;
                        best = Some((k, h));
                    }
                }
            }
            best
        }

        $(#[$attr])*
        /// Whether any triangle of `packets` is hit with `0 < t < t_max`.
        pub fn $any(packets: &[TrianglePacket], o: Vec3, d: Vec3, t_max: f32) -> bool {
            let mut lanes = [[0f32; LANES]; 4];
            #[allow(unused_unsafe)]
            packets
                .iter()
                .any(|p| unsafe { p.$test(o, d, t_max, &mut lanes) } != 0)
        }
    };
}

packet_loops!(nearest_portable, any_portable, test);

#[cfg(target_arch = "x86_64")]
mod avx2 {
    use super::*;
    packet_loops!(
        nearest_avx2,
        any_avx2,
        test_avx2,
        #[target_feature(enable = "avx2,fma")]
    );
}

/// The nearest hit with `0 < t < t_max` among `packets`: (packet index, hit).
#[inline]
pub fn nearest(
    packets: &[TrianglePacket],
    o: Vec3,
    d: Vec3,
    t_max: f32,
) -> Option<(usize, PacketHit)> {
    #[cfg(target_arch = "x86_64")]
    if has_avx2() {
        // SAFETY: the CPU supports AVX2 and FMA.
        return unsafe { avx2::nearest_avx2(packets, o, d, t_max) };
    }
    nearest_portable(packets, o, d, t_max)
}

/// Whether any triangle of `packets` is hit with `0 < t < t_max`.
#[inline]
pub fn any(packets: &[TrianglePacket], o: Vec3, d: Vec3, t_max: f32) -> bool {
    #[cfg(target_arch = "x86_64")]
    if has_avx2() {
        // SAFETY: the CPU supports AVX2 and FMA.
        return unsafe { avx2::any_avx2(packets, o, d, t_max) };
    }
    any_portable(packets, o, d, t_max)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tris() -> Vec<[Vec3; 3]> {
        vec![
            [
                Vec3::new(-1.0, -1.0, 2.0),
                Vec3::new(1.0, -1.0, 2.0),
                Vec3::new(0.0, 1.0, 2.0),
            ],
            [
                Vec3::new(-1.0, -1.0, 1.0),
                Vec3::new(0.0, 1.0, 1.0),
                Vec3::new(1.0, -1.0, 1.0),
            ],
            [
                Vec3::new(5.0, 5.0, 1.0),
                Vec3::new(6.0, 5.0, 1.0),
                Vec3::new(5.0, 6.0, 1.0),
            ],
        ]
    }

    #[test]
    fn finds_the_nearest_triangle_and_its_barycentrics() {
        let t = tris();
        let p = [TrianglePacket::new(&t)];
        let (o, d) = (Vec3::new(0.1, 0.0, -1.0), Vec3::Z);
        let (k, h) = nearest(&p, o, d, 10.0).unwrap();
        assert_eq!((k, h.lane), (0, 1));
        assert!((h.t - 2.0).abs() < 1e-6);
        let [a, b, c] = t[1];
        let q = a * (1.0 - h.b1 - h.b2) + b * h.b1 + c * h.b2;
        assert!((q - (o + d * h.t)).length() < 1e-6, "{q}");
        // t_max excludes farther hits; hits behind the origin never count; empty
        // lanes (all-zero triangles) are never hit.
        assert!(nearest(&p, o, d, 1.5).is_none());
        assert!(!any(&p, o, -d, 10.0));
        assert!(!any(&p, Vec3::ZERO, Vec3::X, 10.0));
        assert!(any(&p, o, d, 3.0));
    }

    #[test]
    fn simd_paths_agree_with_the_scalar_test_on_random_rays() {
        let mut rng = irradia_core::Rng::new(7, 1);
        let mut v = || Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * 2.0 - 1.0;
        let tris: Vec<[Vec3; 3]> = (0..8).map(|_| [v(), v(), v()]).collect();
        let mut rng = irradia_core::Rng::new(8, 1);
        let p = TrianglePacket::new(&tris);
        let (mut a, mut b) = ([[0f32; LANES]; 4], [[0f32; LANES]; 4]);
        let mut hits = 0;
        for i in 0..2000 {
            // Aim at a point in (or, barycentrics past 1, just beside) a triangle.
            let [p0, p1, p2] = tris[i % 8];
            let (b1, b2) = (rng.next_f32() * 0.7, rng.next_f32() * 0.7);
            let o = Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * 6.0 - 3.0;
            let d = p0 + (p1 - p0) * b1 + (p2 - p0) * b2 - o;
            let m_scalar = p.test_scalar(o, d, 10.0, &mut a);
            let m = p.test(o, d, 10.0, &mut b);
            assert_eq!(m, m_scalar);
            #[cfg(target_arch = "x86_64")]
            if has_avx2() {
                // SAFETY: checked above.
                let m_avx = unsafe { p.test_avx2(o, d, 10.0, &mut b) };
                // FMA rounds differently: allow a lane to differ only at an edge.
                for lane in 0..LANES {
                    if (m_avx ^ m_scalar) & (1 << lane) != 0 {
                        let edge = [a[0][lane], a[1][lane], a[3][lane] - a[0][lane] - a[1][lane]]
                            .iter()
                            .any(|e| e.abs() <= 1e-5 * a[3][lane]);
                        assert!(edge, "lane {lane} differs away from an edge");
                    }
                }
            }
            hits += m_scalar.count_ones();
        }
        assert!(hits > 1000, "too few hits ({hits}) to test anything");
    }
}
