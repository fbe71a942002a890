//! The plane `n·p = d` as a solid half-space (lecture: "Planes"): the side the normal
//! points away from is inside, as in POV-Ray's `plane { n, d }`. The ray parameter is
//! `t = (d - n·o) / (n·dir)`, computed in f64 with the hit point projected back onto
//! the plane. A plane whose normal is an axis (the ground, `y = 0`) reads the one
//! coordinate that matters (see [`Plane::num_den`]).

// `!(x > 0.0)` is deliberate: it is also true for NaN, which must be refused too.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use crate::shape::{Boundary, Hit, Shape, Span};
use crate::shapes::shape_error::{finite, ShapeError};
use glam::{DVec3, Vec2, Vec3};
use irradia_core::{Aabb, Frame, Ray};

/// The half-space `normal · p ≤ offset`; its surface is the plane `normal · p = offset`.
#[derive(Clone, Debug)]
pub struct Plane {
    normal: DVec3,
    offset: f64,
    frame: Frame,
    /// The axis the normal lies along (`normal` is `±` that unit axis), if it does.
    axis: Option<usize>,
}

impl Plane {
    /// `normal` need not be unit length; it is normalised and `offset` is the signed
    /// distance of the plane from the origin along the unit normal (POV-Ray's meaning).
    pub fn new(normal: Vec3, offset: f32) -> Result<Self, ShapeError> {
        finite("plane normal", &normal.as_dvec3().to_array())?;
        finite("plane offset", &[offset as f64])?;
        let n = normal.as_dvec3();
        let len = n.length();
        if !(len > 0.0) {
            return Err(ShapeError::ZeroVector {
                what: "plane normal",
            });
        }
        let normal = n / len;
        Ok(Self {
            normal,
            offset: offset as f64,
            frame: Frame::from_normal(normal.as_vec3()),
            axis: unit_axis(normal),
        })
    }

    pub fn normal(&self) -> Vec3 {
        self.normal.as_vec3()
    }
    pub fn offset(&self) -> f32 {
        self.offset as f32
    }

    /// The crossing's parameter in `(0, t_max)` (f64), or `None`. Crossings outside
    /// are refused before the point is projected: a ray leaving the plane behind it
    /// (half of all rays on average) costs one division.
    #[inline]
    fn crossing_t(&self, ray: &Ray, t_max: f32) -> Option<f64> {
        let (num, den) = self.num_den(ray);
        let t = num / den;
        (t > 0.0 && t < t_max as f64).then_some(t)
    }

    /// `(d - n·o, n·dir)` in f64, the crossing's parameter being their quotient. For
    /// a normal along an axis only that coordinate is read: the other two products are
    /// `±0`, which leave a sum unchanged except for the sign of a zero, so `num` is the
    /// same number and `den` differs at most in the sign of a zero `den`, where the
    /// quotient is infinite or NaN and no crossing is reported either way (for a ray
    /// with finite components, as rays are). It also loads one 4-byte coordinate of
    /// each vector, not the 8-byte pair on which helper `csg6`'s profile found 57% of
    /// `occluded`'s samples (a store-forwarding stall, by the look of it).
    #[inline]
    fn num_den(&self, ray: &Ray) -> (f64, f64) {
        match self.axis {
            Some(a) => {
                let n = self.normal[a];
                let o = ray.origin.as_ref()[a] as f64;
                let d = ray.dir.as_ref()[a] as f64;
                (self.offset - n * o, n * d)
            }
            None => {
                let (o, d) = (ray.origin.as_dvec3(), ray.dir.as_dvec3());
                (self.offset - self.normal.dot(o), self.normal.dot(d))
            }
        }
    }

    /// The hit at crossing `t` ([`Self::crossing_t`]): the point projected onto the
    /// plane, as `plane_crossing` does, its uv and error bound.
    #[inline]
    fn hit_at(&self, ray: &Ray, t: f64) -> Hit {
        let (o, d) = (ray.origin.as_dvec3(), ray.dir.as_dvec3());
        let p = o + d * t;
        let p = p - self.normal * (self.normal.dot(p) - self.offset);
        let point = p.as_vec3();
        let mut h = Hit::new(t as f32, point, self.normal.as_vec3(), self.uv(point));
        h.error = plane_point_error(p, self.normal, self.offset);
        h
    }

    fn uv(&self, p: Vec3) -> Vec2 {
        Vec2::new(p.dot(self.frame.s), p.dot(self.frame.t))
    }
}

/// The axis `n` (unit) lies along, if it is `±` a unit axis.
fn unit_axis(n: DVec3) -> Option<usize> {
    (0..3).find(|&a| n[a].abs() == 1.0 && (0..3).all(|b| b == a || n[b] == 0.0))
}

/// Where the line `o + t d` meets the plane `n·p = offset` (`n` unit), in f64: the
/// parameter and the point projected onto the plane. `None` when parallel.
#[inline]
pub(crate) fn plane_crossing(n: DVec3, offset: f64, o: DVec3, d: DVec3) -> Option<(f64, DVec3)> {
    let den = n.dot(d);
    if den == 0.0 {
        return None;
    }
    let t = (offset - n.dot(o)) / den;
    let p = o + d * t;
    Some((t, p - n * (n.dot(p) - offset)))
}

/// An error bound for a point that was projected onto a plane in f64 and rounded to
/// f32: the f64 residual's rounding plus half an f32 ulp per coordinate.
#[inline]
pub(crate) fn plane_point_error(p: DVec3, n: DVec3, offset: f64) -> f32 {
    let residual =
        (n.dot(p) - offset).abs() + 8.0 * f64::EPSILON * (n.abs().dot(p.abs()) + offset.abs());
    (p.abs().max_element() * f32::EPSILON as f64 + residual) as f32
}

impl Shape for Plane {
    fn kind(&self) -> &'static str {
        "plane"
    }

    fn bounds(&self) -> Aabb {
        // An axis-aligned half-space is bounded on one side; others are not bounded.
        let n = self.normal;
        for axis in 0..3 {
            if n[axis].abs() == 1.0 {
                let mut b = Aabb::INFINITE;
                let v = (self.offset * n[axis]) as f32;
                if n[axis] > 0.0 {
                    b.max[axis] = v;
                } else {
                    b.min[axis] = v;
                }
                return b;
            }
        }
        Aabb::INFINITE
    }

    fn intersect(&self, ray: &Ray, t_max: f32) -> Option<Hit> {
        self.crossing_t(ray, t_max).map(|t| self.hit_at(ray, t))
    }

    fn splits_surface(&self) -> bool {
        true
    }

    #[inline]
    fn nearest_t(&self, ray: &Ray, t_max: f32) -> Option<f64> {
        self.crossing_t(ray, t_max)
    }

    fn surface_at(&self, ray: &Ray, t: f64, _uv: bool) -> Hit {
        self.hit_at(ray, t)
    }

    /// `t = num / den` in `(0, t_max)` decided without the division: `num` and `den`
    /// of one sign and `|num| < t_max |den|` (a parallel ray, `den = 0`, is never
    /// blocked; an infinite `t_max` accepts every crossing ahead).
    fn occluded(&self, ray: &Ray, t_max: f32) -> bool {
        let (num, den) = self.num_den(ray);
        num * den > 0.0 && num.abs() < t_max as f64 * den.abs()
    }

    fn is_solid(&self) -> bool {
        true
    }

    fn spans(&self, ray: &Ray, out: &mut Vec<Span>) {
        let (o, d) = (ray.origin.as_dvec3(), ray.dir.as_dvec3());
        match plane_crossing(self.normal, self.offset, o, d) {
            None => {
                if self.normal.dot(o) <= self.offset {
                    out.push(Span {
                        enter: Boundary::NEG_INFINITY,
                        exit: Boundary::INFINITY,
                    });
                }
            }
            Some((t, p)) => {
                let b = Boundary::new(t as f32, self.normal.as_vec3(), self.uv(p.as_vec3()));
                out.push(if self.normal.dot(d) > 0.0 {
                    Span {
                        enter: Boundary::NEG_INFINITY,
                        exit: b,
                    }
                } else {
                    Span {
                        enter: b,
                        exit: Boundary::INFINITY,
                    }
                });
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use irradia_core::Rng;

    /// The plane as it was before the axis path: every product of `n·o` and `n·d`.
    fn general(p: &Plane) -> Plane {
        Plane {
            axis: None,
            ..p.clone()
        }
    }

    /// A coordinate that is often exactly `±0` or equal to the offset.
    fn coordinate(rng: &mut Rng, offset: f32) -> f32 {
        match (rng.next_f32() * 6.0) as u32 {
            0 => 0.0,
            1 => -0.0,
            2 => offset,
            _ => rng.next_f32() * 8.0 - 4.0,
        }
    }

    #[test]
    fn axis_planes_cross_where_the_general_plane_does_bit_for_bit() {
        let mut rng = Rng::new(11, 5);
        let mut crossings = 0;
        for (normal, offset) in [
            (Vec3::Y, 0.0),
            (Vec3::Y, -0.0),
            (-Vec3::Y, 1.5),
            (Vec3::X, -2.0),
            (-Vec3::Z, 0.25),
            (Vec3::Z * 3.0, 1.0),
        ] {
            let axis = Plane::new(normal, offset).unwrap();
            assert!(axis.axis.is_some(), "{normal}");
            let plain = general(&axis);
            for _ in 0..20_000 {
                let mut c = || coordinate(&mut rng, offset);
                let ray = Ray::new(Vec3::new(c(), c(), c()), Vec3::new(c(), c(), c()));
                let t_max = if rng.next_f32() < 0.5 {
                    f32::INFINITY
                } else {
                    3.0
                };
                let want = plain.crossing_t(&ray, t_max);
                let got = axis.crossing_t(&ray, t_max);
                assert_eq!(want.map(f64::to_bits), got.map(f64::to_bits), "{ray:?}");
                crossings += want.is_some() as u32;
                assert_eq!(
                    plain.occluded(&ray, t_max),
                    axis.occluded(&ray, t_max),
                    "{ray:?}"
                );
            }
        }
        assert!(crossings > 20_000, "{crossings} crossings");
    }

    #[test]
    fn only_axis_normals_take_the_axis_path() {
        assert_eq!(Plane::new(Vec3::Y, 0.0).unwrap().axis, Some(1));
        assert_eq!(Plane::new(-Vec3::X * 2.0, 0.0).unwrap().axis, Some(0));
        assert_eq!(
            Plane::new(Vec3::new(0.0, 1.0, 1e-6), 0.0).unwrap().axis,
            None
        );
        assert_eq!(Plane::new(Vec3::ONE, 0.0).unwrap().axis, None);
    }
}
