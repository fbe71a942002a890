//! A tile's camera samples as one batch, made W at a time in lanes for the wide
//! path kernel ([`crate::path::wide`]).
//!
//! The driver asks for samples `first..first + m` of every pixel of a tile, pixel-major
//! ([`Cursor`]). One by one, each is [`camera_sample`]: the sampler's point and stream,
//! the pixel filter's warp, the camera's ray. [`CameraBatch::lanes`] makes W samples
//! at once, for every camera and filter: the W streams and points side by side
//! ([`Sampler::pixel_samples_lanes`]: W independent chains of integer hashing, instead of
//! one chain between two bounces of the kernel); the filter's warp (none for the default
//! box of one pixel, else lane by lane); for a pinhole camera the perspective projection
//! and the normalisation of the W directions in lanes
//! ([`CameraRays::pinhole_rays_lanes`]), inlined into the kernel's vector loop, for the others
//! (thin lens, orthographic) each lane's ray as [`camera_sample`] makes it. The filter's
//! weights ([`StartsW::weight`]: 1 for every box and tent, `f / density` for the
//! Gaussian, Mitsuba's default filter) go back to the driver, which applies them. Every sample
//! is the one [`camera_sample`] makes, bit for bit (tests below), so the image does not
//! change; this is the wavefront path tracer's batched camera-ray generation (Laine,
//! Karras, Aila, "Megakernels Considered Harmful: Wavefront Path Tracing on GPUs", HPG
//! 2013, section 4: a "new path" kernel that generates camera rays for many paths at
//! once).

// Lane loops index several arrays by the lane on purpose.
#![allow(clippy::needless_range_loop)]

use crate::driver::Tile;
use crate::filter::FilterSampler;
use crate::sampler::{camera_sample, Sampler};
use glam::Vec2;
use irradia_core::{Ray, Rng};
use irradia_geometry::packet::lanes::{Fw, V3, W};
use irradia_scene::camera::CameraRays;

/// The samples `first..first + m` of every pixel of a tile, made in lanes: sample `k`
/// of the batch is sample `first + k % m` of pixel `k / m` (row-major in the tile).
#[derive(Clone, Copy, Debug)]
pub struct CameraBatch<'a> {
    cam: &'a CameraRays,
    filter: &'a FilterSampler,
    sampler: Sampler,
    tile: Tile,
    first: u32,
    m: u32,
}

/// Up to W camera samples in lanes: ray origins and unit directions, each
/// sample's stream (already past its pixel jitter) and its filter weight.
#[derive(Clone, Debug)]
pub struct StartsW {
    pub origin: V3,
    pub dir: V3,
    pub rng: [Rng; W],
    pub weight: [f32; W],
}

impl<'a> CameraBatch<'a> {
    /// The batch of `m` samples a pixel from `first` (any camera, any filter).
    pub fn new(
        cam: &'a CameraRays,
        filter: &'a FilterSampler,
        sampler: Sampler,
        tile: Tile,
        first: u32,
        m: u32,
    ) -> Self {
        Self {
            cam,
            filter,
            sampler,
            tile,
            first,
            m,
        }
    }

    /// Whether every sample's filter weight is 1 (every box and tent filter; not the
    /// Gaussian), so the caller need not keep [`StartsW::weight`].
    pub fn unit_weights(&self) -> bool {
        self.filter.unit_weights()
    }

    /// The number of samples: `m` for every pixel of the tile.
    pub fn len(&self) -> usize {
        (self.tile.w * self.tile.h * self.m) as usize
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// A cursor at the batch's sample 0.
    pub fn cursor(&self) -> Cursor {
        Cursor::new(self.tile, self.m as usize)
    }

    /// Sample `k` one by one, as [`camera_sample`] makes it (but for its filter weight).
    pub fn sample(&self, k: usize) -> (Ray, Rng) {
        let (x, y, s) = self.cursor().at(k);
        let cs = camera_sample(self.cam, self.filter, self.sampler, x, y, self.first + s);
        (cs.ray, cs.rng)
    }

    /// Samples `k..k + n` in lanes `0..n` (`0 < n <= W`), `k` being where `cursor`
    /// stands (it moves on by `n`); lanes `n..` repeat lane 0. Each lane is
    /// [`Self::sample`] bit for bit.
    #[inline(always)]
    pub fn lanes(&self, cursor: &mut Cursor, n: usize) -> StartsW {
        let (px, py, s) = self.lane_pixels(cursor, n);
        // The streams and points: W independent hash chains side by side.
        let (mut rng, u) = self.sampler.pixel_samples_lanes(&px, &py, &s);
        // `camera_sample`: the filter's warp (the unit box leaves `u` as it is).
        let (mut ox, mut oy) = (Fw(u[0]), Fw(u[1]));
        let mut weight = [1.0f32; W];
        if !self.filter.is_unit_box() {
            for i in 0..W {
                let (o, w) = self.filter.warp(Vec2::new(u[0][i], u[1][i]));
                (ox.0[i], oy.0[i], weight[i]) = (o.x, o.y, w);
            }
        }
        let x = Fw(std::array::from_fn(|i| px[i] as f32)) + ox;
        let y = Fw(std::array::from_fn(|i| py[i] as f32)) + oy;
        if self.cam.is_pinhole() {
            let (origin, dir) = self.cam.pinhole_rays_lanes(x, y);
            return StartsW {
                origin,
                dir,
                rng,
                weight,
            };
        }
        // Thin lens (its aperture point drawn next from the sample's stream) and
        // orthographic cameras: lane by lane.
        let (mut origin, mut dir) = (V3::ZERO, V3::ZERO);
        for i in 0..W {
            let ray = if self.cam.needs_lens_sample() {
                let lens = rng[i].next_2d();
                self.cam.ray_lens(x.0[i], y.0[i], lens)
            } else {
                self.cam.ray(x.0[i], y.0[i])
            };
            origin.set_lane(i, ray.origin);
            dir.set_lane(i, ray.dir);
        }
        StartsW {
            origin,
            dir,
            rng,
            weight,
        }
    }

    /// The pixels and sample indices of samples `k..k + n` (`0 < n <= W`), `k` being
    /// where `cursor` stands (it moves on by `n`); lanes `n..` repeat lane 0.
    #[inline(always)]
    fn lane_pixels(&self, cursor: &mut Cursor, n: usize) -> ([u32; W], [u32; W], [u32; W]) {
        debug_assert!(n > 0 && n <= W);
        let (mut px, mut py, mut s) = ([0u32; W], [0u32; W], [0u32; W]);
        let k = cursor.k;
        for i in 0..n {
            let (x, y, j) = cursor.at(k + i);
            (px[i], py[i], s[i]) = (x, y, self.first + j);
        }
        for i in n..W {
            (px[i], py[i], s[i]) = (px[0], py[0], s[0]);
        }
        (px, py, s)
    }
}

/// Pixel and sample of the `k`-th sample of a tile's batch (pixel-major, `m` samples
/// a pixel): found by stepping from the previous one when asked in order (the kernel
/// and the driver always ask so), by division otherwise. A one-sample render asks for
/// a million of these, and three integer divisions a sample showed in its profile.
#[derive(Clone, Copy, Debug)]
pub struct Cursor {
    t: Tile,
    m: u32,
    /// The next `k` in order and its (x, y, sample).
    k: usize,
    at: (u32, u32, u32),
}

impl Cursor {
    pub fn new(t: Tile, m: usize) -> Self {
        Self {
            t,
            m: m as u32,
            k: 0,
            at: (t.x0, t.y0, 0),
        }
    }

    /// The (x, y, sample within the batch) of sample `k`.
    #[inline]
    pub fn at(&mut self, k: usize) -> (u32, u32, u32) {
        if k != self.k {
            let (p, s) = (k / self.m as usize, (k % self.m as usize) as u32);
            let w = self.t.w as usize;
            self.at = (self.t.x0 + (p % w) as u32, self.t.y0 + (p / w) as u32, s);
        }
        let here = self.at;
        // Step to k + 1: the next sample, else the next pixel, else the next row.
        let (mut x, mut y, mut s) = here;
        s += 1;
        if s == self.m {
            s = 0;
            x += 1;
            if x == self.t.x0 + self.t.w {
                x = self.t.x0;
                y += 1;
            }
        }
        self.k = k + 1;
        self.at = (x, y, s);
        here
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;
    use irradia_scene::camera::{Camera, FovAxis, Projection};
    use irradia_scene::PixelFilter;

    fn camera(projection: Projection, near_clip: f32) -> CameraRays {
        let mut c = Camera::new(
            Vec3::new(0.3, 1.1, 4.0),
            Vec3::new(-0.2, 0.4, 0.0),
            Vec3::Y,
            projection,
        );
        c.near_clip = near_clip;
        c.rays(97, 61)
    }

    const PINHOLE: Projection = Projection::Perspective {
        fov_degrees: 39.3,
        axis: FovAxis::Horizontal,
    };

    /// Every lane of `lanes` is the one-by-one sample bit for bit (ray, stream: its
    /// next numbers, and filter weight), for each camera
    /// (pinhole with and without a near clip, thin lens, orthographic) and filter (the
    /// unit box, a wider box, tent, Gaussian), over tiles, batch sizes, first samples,
    /// samplers and partial groups. (A thin lens whose lanes skip the aperture draw, a
    /// warp left out of the lanes, or weights of another sample fail it: tried.)
    #[test]
    fn lanes_are_the_one_by_one_samples() {
        let cameras = [
            camera(PINHOLE, 0.0),
            camera(PINHOLE, 0.05),
            camera(
                Projection::ThinLens {
                    fov_degrees: 39.3,
                    axis: FovAxis::Horizontal,
                    aperture_radius: 0.1,
                    focus_distance: 3.5,
                },
                0.0,
            ),
            camera(Projection::Orthographic { height: 2.0 }, 0.0),
        ];
        let filters = [
            PixelFilter::Box { radius: 0.5 },
            PixelFilter::Box { radius: 0.75 },
            PixelFilter::Tent { radius: 1.0 },
            PixelFilter::Gaussian { stddev: 0.5 },
        ];
        let mut checked = 0;
        let mut weighted = 0;
        for (case, cam) in cameras.iter().enumerate() {
            for pf in filters {
                let filter = FilterSampler::new(pf);
                for (tile, first, m, sampler) in [
                    (
                        Tile {
                            x0: 0,
                            y0: 0,
                            w: 5,
                            h: 3,
                        },
                        0,
                        1,
                        Sampler::Independent { seed: 0 },
                    ),
                    (
                        Tile {
                            x0: 32,
                            y0: 17,
                            w: 7,
                            h: 4,
                        },
                        3,
                        2,
                        Sampler::Independent { seed: 9 },
                    ),
                    (
                        Tile {
                            x0: 90,
                            y0: 60,
                            w: 7,
                            h: 1,
                        },
                        7,
                        16,
                        Sampler::Independent { seed: 1 },
                    ),
                    (
                        Tile {
                            x0: 11,
                            y0: 2,
                            w: 3,
                            h: 3,
                        },
                        1,
                        5,
                        Sampler::Stratified { spp: 16 },
                    ),
                ] {
                    let batch = CameraBatch::new(cam, &filter, sampler, tile, first, m);
                    let mut cursor = batch.cursor();
                    let mut k = 0;
                    while k < batch.len() {
                        let n = (batch.len() - k).min(W);
                        let got = batch.lanes(&mut cursor, n);
                        for lane in 0..n {
                            let (ray, mut rng) = batch.sample(k + lane);
                            let cs = {
                                let mut c = batch.cursor();
                                let (x, y, s) = c.at(k + lane);
                                camera_sample(cam, &filter, sampler, x, y, first + s)
                            };
                            let what = format!("camera {case} {pf:?} {tile:?} k {}", k + lane);
                            assert_eq!(got.weight[lane].to_bits(), cs.weight.to_bits(), "{what}");
                            assert_eq!(
                                batch.unit_weights(),
                                !matches!(pf, PixelFilter::Gaussian { .. })
                            );
                            if batch.unit_weights() {
                                assert_eq!(cs.weight, 1.0, "{what}");
                            } else if cs.weight != 1.0 {
                                weighted += 1;
                            }
                            assert_eq!(ray.origin, cs.ray.origin);
                            assert_eq!(ray.dir, cs.ray.dir);
                            assert_eq!(got.origin.lane(lane), ray.origin, "{what}");
                            assert_eq!(got.dir.lane(lane), ray.dir, "{what}");
                            let mut lane_rng = got.rng[lane].clone();
                            for _ in 0..4 {
                                assert_eq!(lane_rng.next_u32(), rng.next_u32(), "{what}");
                            }
                            checked += 1;
                        }
                        k += n;
                    }
                }
            }
        }
        assert!(checked > 3000 && weighted > 500, "{checked} {weighted}");
    }

    /// The cursor stepping in order agrees with division.
    #[test]
    fn cursor_steps_as_it_divides() {
        let t = Tile {
            x0: 4,
            y0: 8,
            w: 3,
            h: 2,
        };
        let mut stepping = Cursor::new(t, 5);
        for k in 0..30 {
            let (p, s) = (k / 5, (k % 5) as u32);
            let want = (4 + (p % 3) as u32, 8 + (p / 3) as u32, s);
            assert_eq!(stepping.at(k), want);
            assert_eq!(Cursor::new(t, 5).at(k), want);
        }
    }
}
