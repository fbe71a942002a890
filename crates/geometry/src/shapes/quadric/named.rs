//! Constructors for quadrics: the general one from its ten coefficients, the named ones
//! in a canonical frame (axis of symmetry along `y`), clipping, and the capped cylinder
//! and cone between two points (POV-Ray's `cylinder` and `cone`).

// `!(x > 0.0)` is deliberate: it is also true for NaN, which must be refused too.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use super::{HalfSpace, Quadric, QuadricForm, QuadricKind};
use crate::shapes::shape_error::{finite, positive, ShapeError};
use glam::{DAffine3, DMat3, DVec3, Vec3};
use irradia_core::Affine3A;

const UNBOUNDED: (DVec3, DVec3) = (DVec3::splat(f64::NEG_INFINITY), DVec3::splat(f64::INFINITY));

fn general(form: QuadricForm, kind: QuadricKind) -> Quadric {
    Quadric::from_parts(form, Vec::new(), kind, DAffine3::IDENTITY, UNBOUNDED)
}

impl Quadric {
    /// The general quadric from POV-Ray's ten coefficients `[A, B, C, D, E, F, G, H, I,
    /// J]` of `A x² + B y² + C z² + D xy + E xz + F yz + G x + H y + I z + J = 0`. The
    /// solid is where the left side is `≤ 0`. Errors on non-finite coefficients or when
    /// every quadratic and linear coefficient is zero.
    pub fn new(coefficients: [f64; 10]) -> Result<Self, ShapeError> {
        finite("quadric coefficient", &coefficients)?;
        if coefficients[..9].iter().all(|&c| c == 0.0) {
            return Err(ShapeError::NotASurface);
        }
        Ok(general(
            QuadricForm::from_coefficients(coefficients),
            QuadricKind::General,
        ))
    }

    /// An ellipsoid with the given centre and semi-axes along x, y, z.
    pub fn ellipsoid(center: Vec3, radii: Vec3) -> Result<Self, ShapeError> {
        finite("ellipsoid center", &center.as_dvec3().to_array())?;
        for r in radii.to_array() {
            positive("ellipsoid radius", r as f64)?;
        }
        let r = radii.as_dvec3();
        let inv2 = DVec3::ONE / (r * r);
        let c = center.as_dvec3();
        let form = QuadricForm {
            a: DMat3::from_diagonal(inv2),
            b: -2.0 * inv2 * c,
            c: (c * c * inv2).element_sum() - 1.0,
        };
        Ok(Quadric::from_parts(
            form,
            Vec::new(),
            QuadricKind::Ellipsoid { radii: r },
            DAffine3::from_translation(-c),
            (c - r, c + r),
        ))
    }

    /// The infinite solid cylinder `x² + z² ≤ r²` around the `y` axis.
    pub fn cylinder(radius: f32) -> Result<Self, ShapeError> {
        positive("cylinder radius", radius as f64)?;
        let r = radius as f64;
        let mut k = [0.0; 10];
        (k[0], k[2], k[9]) = (1.0, 1.0, -r * r);
        Ok(Quadric::from_parts(
            QuadricForm::from_coefficients(k),
            Vec::new(),
            QuadricKind::Cylinder { radius: r },
            DAffine3::IDENTITY,
            (
                DVec3::new(-r, f64::NEG_INFINITY, -r),
                DVec3::new(r, f64::INFINITY, r),
            ),
        ))
    }

    /// The infinite double cone `x² + z² ≤ (slope·y)²` around the `y` axis, apex at the
    /// origin; `slope` is the tangent of the half-angle.
    pub fn cone(slope: f32) -> Result<Self, ShapeError> {
        positive("cone slope", slope as f64)?;
        let s = slope as f64;
        let mut k = [0.0; 10];
        (k[0], k[1], k[2]) = (1.0, -s * s, 1.0);
        Ok(general(
            QuadricForm::from_coefficients(k),
            QuadricKind::Cone { slope: s },
        ))
    }

    /// The paraboloid `y = k (x² + z²)`, open upwards for `k > 0`; the solid is the
    /// inside of the bowl.
    pub fn paraboloid(curvature: f32) -> Result<Self, ShapeError> {
        positive("paraboloid curvature", curvature as f64)?;
        let c = curvature as f64;
        let mut k = [0.0; 10];
        (k[0], k[2], k[7]) = (c, c, -1.0);
        Ok(general(
            QuadricForm::from_coefficients(k),
            QuadricKind::Paraboloid { curvature: c },
        ))
    }

    /// The hyperboloid of one sheet `(x² + z²)/a² - y²/c² = 1` (waist radius `a`); the
    /// solid is the part around the axis.
    pub fn hyperboloid_one_sheet(a: f32, c: f32) -> Result<Self, ShapeError> {
        positive("hyperboloid radius", a as f64)?;
        positive("hyperboloid height scale", c as f64)?;
        let (a, c) = (a as f64, c as f64);
        let mut k = [0.0; 10];
        (k[0], k[1], k[2], k[9]) = (1.0 / (a * a), -1.0 / (c * c), 1.0 / (a * a), -1.0);
        Ok(general(
            QuadricForm::from_coefficients(k),
            QuadricKind::HyperboloidOneSheet { a, c },
        ))
    }

    /// The hyperboloid of two sheets `(x² + z²)/a² - y²/c² = -1` (vertices at
    /// `y = ±c`); the solid is the inside of both cups.
    pub fn hyperboloid_two_sheets(a: f32, c: f32) -> Result<Self, ShapeError> {
        positive("hyperboloid radius", a as f64)?;
        positive("hyperboloid height scale", c as f64)?;
        let (a, c) = (a as f64, c as f64);
        let mut k = [0.0; 10];
        (k[0], k[1], k[2], k[9]) = (1.0 / (a * a), -1.0 / (c * c), 1.0 / (a * a), 1.0);
        Ok(general(
            QuadricForm::from_coefficients(k),
            QuadricKind::HyperboloidTwoSheets { a, c },
        ))
    }

    /// Clips by the half-space `normal · p ≤ offset` (what is kept). The result is
    /// capped: a solid whose surface includes the part of the plane inside the quadric.
    pub fn clipped_by_plane(mut self, normal: Vec3, offset: f32) -> Result<Self, ShapeError> {
        finite(
            "clipping plane",
            &[normal.x as f64, normal.y as f64, normal.z as f64],
        )?;
        finite("clipping plane offset", &[offset as f64])?;
        let h = HalfSpace::new(normal.as_dvec3(), offset as f64).ok_or(ShapeError::ZeroVector {
            what: "clipping plane normal",
        })?;
        self.clip.push(h);
        self.update_bounds();
        Ok(self)
    }

    /// Clips by the box `[min, max]` (six half-spaces), capped like `clipped_by_plane`.
    pub fn clipped_by_box(mut self, min: Vec3, max: Vec3) -> Result<Self, ShapeError> {
        finite(
            "clipping box",
            &[min.x, min.y, min.z, max.x, max.y, max.z].map(|v| v as f64),
        )?;
        if min.cmpge(max).any() {
            return Err(ShapeError::OutOfRange {
                what: "clipping box",
                why: "min must be below max on every axis",
            });
        }
        let (lo, hi) = (min.as_dvec3(), max.as_dvec3());
        for axis in [DVec3::X, DVec3::Y, DVec3::Z] {
            self.clip.push(HalfSpace {
                normal: -axis,
                offset: -lo.dot(axis),
            });
            self.clip.push(HalfSpace {
                normal: axis,
                offset: hi.dot(axis),
            });
        }
        self.known_bounds = (self.known_bounds.0.max(lo), self.known_bounds.1.min(hi));
        self.update_bounds();
        Ok(self)
    }

    /// Only the quadric surface inside the clipping region, without caps: an open
    /// surface (not a solid, so not usable in CSG), e.g. a tube.
    pub fn open(mut self) -> Self {
        self.solid = false;
        self
    }

    /// The same quadric after the object-to-world map `to_world` (applied exactly to
    /// the coefficients). Errors when the map is not invertible or not finite.
    pub fn transformed(&self, to_world: &Affine3A) -> Result<Self, ShapeError> {
        let m = to_daffine(to_world);
        let det = m.matrix3.determinant();
        if !(det.is_finite() && det != 0.0 && m.translation.is_finite()) {
            return Err(ShapeError::OutOfRange {
                what: "quadric transform",
                why: "the matrix must be finite and invertible",
            });
        }
        let (lo, hi) = self.known_bounds;
        let known = if lo.is_finite() && hi.is_finite() {
            let b = irradia_core::Aabb::new(lo.as_vec3(), hi.as_vec3()).transformed(to_world);
            (b.min.as_dvec3(), b.max.as_dvec3())
        } else {
            UNBOUNDED
        };
        let mut q = Quadric::from_parts(
            self.form.transformed(&m),
            self.clip.iter().map(|h| h.transformed(&m)).collect(),
            self.kind,
            self.to_local * m.inverse(),
            known,
        );
        q.solid = self.solid;
        Ok(q)
    }

    /// A solid cylinder of `radius` from `a` to `b`, closed by flat caps (POV-Ray's
    /// `cylinder { a, b, radius }`).
    pub fn capped_cylinder(a: Vec3, b: Vec3, radius: f32) -> Result<Self, ShapeError> {
        Self::capped_cone(a, radius, b, radius)
    }

    /// A solid cone frustum from radius `radius_a` at `a` to `radius_b` at `b`, closed by
    /// flat caps (POV-Ray's `cone { a, ra, b, rb }`). One radius may be zero (a pointed
    /// cone); equal radii give a cylinder.
    pub fn capped_cone(a: Vec3, radius_a: f32, b: Vec3, radius_b: f32) -> Result<Self, ShapeError> {
        finite(
            "cone end",
            &[a, b].map(|v| v.as_dvec3().to_array()).concat(),
        )?;
        finite("cone radius", &[radius_a as f64, radius_b as f64])?;
        let (ra, rb) = (radius_a as f64, radius_b as f64);
        if ra < 0.0 || rb < 0.0 {
            return Err(ShapeError::NotPositive {
                what: "cone radius",
                value: ra.min(rb),
            });
        }
        if ra == 0.0 && rb == 0.0 {
            return Err(ShapeError::NotPositive {
                what: "cone radius",
                value: 0.0,
            });
        }
        let (pa, pb) = (a.as_dvec3(), b.as_dvec3());
        let axis = pb - pa;
        let h = axis.length();
        if !(h > 0.0) {
            return Err(ShapeError::Coincident {
                what: if ra == rb {
                    "cylinder ends"
                } else {
                    "cone ends"
                },
            });
        }
        let y = axis / h;
        // A right-handed orthonormal frame (x, y, z) with y along the axis.
        let helper = if y.x.abs() < 0.9 { DVec3::X } else { DVec3::Z };
        let z = helper.cross(y).normalize();
        let x = y.cross(z);
        let local_to_object = DAffine3::from_mat3_translation(DMat3::from_cols(x, y, z), pa);
        // Local: x² + z² - (ra + k y)² with k = (rb - ra)/h.
        let k = (rb - ra) / h;
        let mut c = [0.0; 10];
        (c[0], c[1], c[2], c[7], c[9]) = (1.0, -k * k, 1.0, -2.0 * ra * k, -ra * ra);
        let local = QuadricForm::from_coefficients(c);
        let clip = [
            HalfSpace {
                normal: -DVec3::Y,
                offset: 0.0,
            },
            HalfSpace {
                normal: DVec3::Y,
                offset: h,
            },
        ];
        // Exact bounds: each end disc extends r·√(1 - yᵢ²) along axis i.
        let ext = |r: f64| (DVec3::ONE - y * y).max(DVec3::ZERO).map(f64::sqrt) * r;
        let lo = (pa - ext(ra)).min(pb - ext(rb));
        let hi = (pa + ext(ra)).max(pb + ext(rb));
        let kind = if ra == rb {
            QuadricKind::CappedCylinder {
                radius: ra,
                height: h,
            }
        } else {
            QuadricKind::CappedCone {
                r0: ra,
                r1: rb,
                height: h,
            }
        };
        Ok(Quadric::from_parts(
            local.transformed(&local_to_object),
            clip.iter()
                .map(|p| p.transformed(&local_to_object))
                .collect(),
            kind,
            local_to_object.inverse(),
            (lo, hi),
        ))
    }
}

pub(crate) fn to_daffine(m: &Affine3A) -> DAffine3 {
    DAffine3::from_mat3_translation(
        DMat3::from_cols(
            Vec3::from(m.matrix3.x_axis).as_dvec3(),
            Vec3::from(m.matrix3.y_axis).as_dvec3(),
            Vec3::from(m.matrix3.z_axis).as_dvec3(),
        ),
        Vec3::from(m.translation).as_dvec3(),
    )
}
