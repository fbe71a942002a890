//! Cameras: perspective (look-at, field of view, near clip), thin lens and orthographic,
//! with Mitsuba 3's definitions (plugins `perspective`, `thinlens`, `orthographic`).
//!
//! Irradia is right-handed with +y up; an unrotated camera looks down -z. The one place
//! that turns a field of view and its axis into image-plane extents is
//! [`FovAxis::half_extents`]: the tracers, the rasterizer and radiosity's display all
//! ask it.

use glam::{Vec2, Vec3};
use irradia_core::{sampling, Ray};
use irradia_geometry::packet::lanes::{Fw, V3};

/// Which image axis the field of view spans (Mitsuba's `fov_axis`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FovAxis {
    /// The image width (Mitsuba's `x`).
    Horizontal,
    /// The image height (Mitsuba's `y`).
    Vertical,
    /// The image diagonal.
    Diagonal,
    /// The smaller of the two image axes (`x` when width < height).
    Smaller,
    /// The larger of the two image axes (`y` when width < height).
    Larger,
}

impl FovAxis {
    /// Half extents `(tan(fov_x / 2), tan(fov_y / 2))` of the image plane at distance 1
    /// for a full field of view of `fov_degrees` across this axis of a `width` x `height`
    /// image (square pixels).
    pub fn half_extents(self, fov_degrees: f32, width: u32, height: u32) -> Vec2 {
        let t = (fov_degrees.to_radians() * 0.5).tan();
        let (w, h) = (width as f32, height as f32);
        let aspect = w / h;
        let horizontal = match self {
            FovAxis::Horizontal => true,
            FovAxis::Vertical => false,
            FovAxis::Smaller => width <= height,
            FovAxis::Larger => width > height,
            FovAxis::Diagonal => {
                let d = (w * w + h * h).sqrt();
                return Vec2::new(t * w / d, t * h / d);
            }
        };
        if horizontal {
            Vec2::new(t, t / aspect)
        } else {
            Vec2::new(t * aspect, t)
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Projection {
    /// Pinhole with the full field of view in degrees across `axis` (Mitsuba's
    /// `perspective`).
    Perspective { fov_degrees: f32, axis: FovAxis },
    /// A thin lens of radius `aperture_radius` focused at distance `focus_distance`
    /// along the view axis (Mitsuba's `thinlens`): points on the plane of focus image
    /// sharp, others blur into the circle of confusion.
    ThinLens {
        fov_degrees: f32,
        axis: FovAxis,
        aperture_radius: f32,
        focus_distance: f32,
    },
    /// Parallel rays; `height` is the world-space height of the view (the width follows
    /// from the image's aspect ratio).
    Orthographic { height: f32 },
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    pub eye: Vec3,
    pub look_at: Vec3,
    pub up: Vec3,
    pub projection: Projection,
    /// Distance along the view axis before which nothing is seen (Mitsuba's `near_clip`;
    /// rays start on that plane). 0 in Irradia's scenes unless given.
    pub near_clip: f32,
}

impl Camera {
    /// A camera with no near clip.
    pub fn new(eye: Vec3, look_at: Vec3, up: Vec3, projection: Projection) -> Self {
        Self {
            eye,
            look_at,
            up,
            projection,
            near_clip: 0.0,
        }
    }

    /// Half extents of the image plane for a `width` x `height` image: at distance 1
    /// (`tan` of the half angles) for perspective and thin-lens cameras, in world units
    /// for orthographic ones.
    pub fn half_extents(&self, width: u32, height: u32) -> Vec2 {
        match self.projection {
            Projection::Perspective { fov_degrees, axis }
            | Projection::ThinLens {
                fov_degrees, axis, ..
            } => axis.half_extents(fov_degrees, width, height),
            Projection::Orthographic { height: h } => {
                Vec2::new(0.5 * h * (width as f32 / height as f32), 0.5 * h)
            }
        }
    }

    /// The full vertical field of view in radians for a `width` x `height` image, or
    /// `None` for an orthographic camera (what a rasterizer's projection matrix takes).
    pub fn fov_y_radians(&self, width: u32, height: u32) -> Option<f32> {
        match self.projection {
            Projection::Orthographic { .. } => None,
            _ => Some(2.0 * self.half_extents(width, height).y.atan()),
        }
    }

    /// The camera's basis and image-plane extents for an image of `width` x `height`.
    pub fn rays(&self, width: u32, height: u32) -> CameraRays {
        let forward = (self.look_at - self.eye).normalize();
        let right = forward.cross(self.up).normalize();
        let up = right.cross(forward);
        let (kind, lens) = match self.projection {
            Projection::Perspective { .. } => (Kind::Pinhole, Vec2::ZERO),
            Projection::ThinLens {
                aperture_radius,
                focus_distance,
                ..
            } => (Kind::ThinLens, Vec2::new(aperture_radius, focus_distance)),
            Projection::Orthographic { .. } => (Kind::Orthographic, Vec2::ZERO),
        };
        CameraRays {
            origin: self.eye,
            right,
            up,
            forward,
            half: self.half_extents(width, height),
            kind,
            aperture_radius: lens.x,
            focus_distance: lens.y,
            near_clip: self.near_clip,
            width: width as f32,
            height: height as f32,
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kind {
    Pinhole,
    ThinLens,
    Orthographic,
}

/// A camera prepared for one image size: generates primary rays.
#[derive(Clone, Copy, Debug)]
pub struct CameraRays {
    origin: Vec3,
    /// Unit basis: right, up, forward.
    right: Vec3,
    up: Vec3,
    forward: Vec3,
    /// Half extents of the image plane at distance 1 (perspective) or in world units.
    half: Vec2,
    kind: Kind,
    aperture_radius: f32,
    focus_distance: f32,
    near_clip: f32,
    width: f32,
    height: f32,
}

impl CameraRays {
    /// The primary ray through image position `(x, y)` in pixels (continuous: the centre
    /// of pixel (i, j) is (i + 0.5, j + 0.5)), y down, through the centre of the lens.
    /// Directions are unit length.
    #[inline(always)]
    pub fn ray(&self, x: f32, y: f32) -> Ray {
        self.ray_lens(x, y, Vec2::splat(0.5))
    }

    /// Whether rays depend on a lens sample (a thin lens with a non-zero aperture).
    #[inline]
    pub fn needs_lens_sample(&self) -> bool {
        self.kind == Kind::ThinLens && self.aperture_radius > 0.0
    }

    /// The primary ray through image position `(x, y)` and the point of the aperture
    /// that `lens` (in the unit square) maps to by the concentric disk warp (Shirley and
    /// Chiu 1997); `lens` matters only for a thin lens. Mitsuba's `thinlens`: the ray
    /// leaves the aperture point towards the point of the plane of focus that the
    /// pinhole ray through `(x, y)` meets.
    #[inline(always)]
    pub fn ray_lens(&self, x: f32, y: f32, lens: Vec2) -> Ray {
        let sx = (2.0 * x / self.width - 1.0) * self.half.x;
        let sy = (1.0 - 2.0 * y / self.height) * self.half.y;
        let (origin, dir) = match self.kind {
            Kind::Orthographic => (self.origin + self.right * sx + self.up * sy, self.forward),
            Kind::Pinhole => (
                self.origin,
                (self.forward + self.right * sx + self.up * sy).normalize(),
            ),
            Kind::ThinLens => {
                let plane = self.forward + self.right * sx + self.up * sy;
                let a = sampling::concentric_disk(lens) * self.aperture_radius;
                let aperture = self.origin + self.right * a.x + self.up * a.y;
                let focus = self.origin + plane * self.focus_distance;
                (aperture, (focus - aperture).normalize())
            }
        };
        if self.near_clip > 0.0 {
            // Start on the near plane: along `dir` until the view-axis distance is
            // `near_clip` (Mitsuba moves its ray origins the same way).
            let t = self.near_clip / dir.dot(self.forward);
            return Ray::new(origin + dir * t, dir);
        }
        Ray::new(origin, dir)
    }

    /// Whether this is a pinhole (perspective) camera, the one [`Self::pinhole_rays_lanes`]
    /// makes rays for.
    #[inline]
    pub fn is_pinhole(&self) -> bool {
        self.kind == Kind::Pinhole
    }

    /// W pinhole rays at once, through image positions `(x, y)` in pixels (one
    /// per lane): origins and unit directions, each lane computed as [`Self::ray`]
    /// computes its ray, in the same operations and order (so bit for bit the same:
    /// `tests::pinhole_lanes_are_the_scalar_rays`). For a pinhole camera only
    /// ([`Self::is_pinhole`]). `#[inline(always)]` so that it runs in the vector
    /// width of the kernel that calls it (the wide path kernel's AVX-512 or AVX2).
    #[inline(always)]
    pub fn pinhole_rays_lanes(&self, x: Fw, y: Fw) -> (V3, V3) {
        debug_assert!(self.is_pinhole());
        let sx = (2.0 * x / self.width - 1.0) * self.half.x;
        let sy = (1.0 - 2.0 * y / self.height) * self.half.y;
        let v = |a: Vec3| V3::new(Fw::splat(a.x), Fw::splat(a.y), Fw::splat(a.z));
        // `forward + right * sx + up * sy`, component by component as glam sums it.
        let dir = v(self.forward)
            .add(v(self.right).scale(sx))
            .add(v(self.up).scale(sy))
            .normalize();
        let origin = v(self.origin);
        if self.near_clip > 0.0 {
            let t = self.near_clip / dir.dot(v(self.forward));
            return (origin.add(dir.scale(t)), dir);
        }
        (origin, dir)
    }

    pub fn forward(&self) -> Vec3 {
        self.forward
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use irradia_geometry::packet::lanes::W;

    fn camera(projection: Projection) -> Camera {
        Camera::new(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, Vec3::Y, projection)
    }

    /// Every lane of `pinhole_rays_lanes` is the scalar `ray` bit for bit, with and
    /// without a near clip, over odd positions and camera frames. (Summing the
    /// direction in another order, `forward + (right * sx + up * sy)`, fails it:
    /// tried.)
    #[test]
    fn pinhole_lanes_are_the_scalar_rays() {
        let mut rng = irradia_core::Rng::new(3, 7);
        for case in 0..40 {
            let mut c = Camera::new(
                Vec3::new(rng.next_f32() * 8.0 - 4.0, 1.3, 5.0 + rng.next_f32()),
                Vec3::new(0.2, rng.next_f32() - 0.5, -0.7),
                Vec3::new(0.1 * rng.next_f32(), 1.0, 0.0),
                Projection::Perspective {
                    fov_degrees: 20.0 + 100.0 * rng.next_f32(),
                    axis: [FovAxis::Horizontal, FovAxis::Diagonal][case % 2],
                },
            );
            c.near_clip = if case % 3 == 0 {
                0.0
            } else {
                0.01 + rng.next_f32()
            };
            let (w, h) = (317 + case as u32, 211);
            let r = c.rays(w, h);
            assert!(r.is_pinhole());
            let (mut x, mut y) = (Fw::ZERO, Fw::ZERO);
            for lane in 0..W {
                x.0[lane] = rng.next_f32() * w as f32;
                y.0[lane] = rng.next_f32() * h as f32;
            }
            let (o, d) = r.pinhole_rays_lanes(x, y);
            for lane in 0..W {
                let want = r.ray(x.0[lane], y.0[lane]);
                assert_eq!(
                    o.lane(lane).to_array(),
                    want.origin.to_array(),
                    "case {case}"
                );
                assert_eq!(d.lane(lane).to_array(), want.dir.to_array(), "case {case}");
            }
        }
    }

    #[test]
    fn centre_ray_looks_at_target_and_fov_spans_the_axis() {
        let cam = camera(Projection::Perspective {
            fov_degrees: 90.0,
            axis: FovAxis::Horizontal,
        });
        let r = cam.rays(200, 100);
        assert!((r.ray(100.0, 50.0).dir - -Vec3::Z).length() < 1e-6);
        let edge = r.ray(200.0, 50.0).dir;
        assert!(
            (edge.x - edge.z.abs()).abs() < 1e-5,
            "45 degrees to the right edge: {edge}"
        );
        let top = r.ray(100.0, 0.0).dir;
        assert!(top.y > 0.0);
    }

    #[test]
    fn every_fov_axis_spans_its_own_extent() {
        let t = 1.0f32; // tan(45°)
        let (w, h) = (300u32, 200u32);
        let d = ((w * w + h * h) as f32).sqrt();
        let cases = [
            (FovAxis::Horizontal, Vec2::new(t, t * 2.0 / 3.0)),
            (FovAxis::Vertical, Vec2::new(t * 1.5, t)),
            (FovAxis::Smaller, Vec2::new(t * 1.5, t)),
            (FovAxis::Larger, Vec2::new(t, t * 2.0 / 3.0)),
            (FovAxis::Diagonal, Vec2::new(300.0 / d, 200.0 / d)),
        ];
        for (axis, want) in cases {
            let got = axis.half_extents(90.0, w, h);
            assert!((got - want).length() < 1e-6, "{axis:?}: {got} vs {want}");
        }
        // Portrait: smaller is the width, larger the height.
        assert!((FovAxis::Smaller.half_extents(90.0, 200, 300).x - 1.0).abs() < 1e-6);
        assert!((FovAxis::Larger.half_extents(90.0, 200, 300).y - 1.0).abs() < 1e-6);
    }

    #[test]
    fn near_clip_moves_origins_onto_the_near_plane() {
        let mut cam = camera(Projection::Perspective {
            fov_degrees: 60.0,
            axis: FovAxis::Horizontal,
        });
        cam.near_clip = 2.0;
        let r = cam.rays(64, 48);
        for (x, y) in [(0.0, 0.0), (32.0, 24.0), (60.5, 3.5)] {
            let ray = r.ray(x, y);
            let along = (ray.origin - cam.eye).dot(-Vec3::Z);
            assert!((along - 2.0).abs() < 1e-5, "{along}");
            // Still on the pinhole ray.
            assert!((ray.origin - cam.eye).normalize().dot(ray.dir) > 1.0 - 1e-6);
        }
    }
}
