//! Quadrics `pᵀA p + bᵀp + c = 0` (lecture: "Quadrics"), solved in f64, optionally
//! clipped by half-spaces (planes or a box).
//!
//! - [`form`]: the quadratic form, the stable ray-quadric roots, Newton polish.
//! - [`clip`]: half-spaces and the interval a ray keeps inside them.
//! - [`named`]: constructors (ellipsoid, cylinder, cone, paraboloid, hyperboloids,
//!   capped cylinder and cone between two points, clipping, transforming).
//! - [`facets`]: polygons for the bounded named quadrics.
//!
//! As a solid the quadric is `Q ≤ 0`. Clipped by half-spaces it is *capped*: the solid
//! is `{Q ≤ 0} ∩ half-spaces`, so the parts of the clipping planes inside the quadric
//! are surface too (POV-Ray's capped `cylinder`). [`Quadric::open`] instead keeps only
//! the quadric surface inside the clipping region, which is not a solid.

pub mod clip;
mod facets;
pub mod form;
mod named;

pub use clip::HalfSpace;
pub use form::QuadricForm;

use crate::shape::{Boundary, Hit, Shape, Span};
use clip::{clip_interval, NO_PLANE};
use glam::{DAffine3, DVec3, Vec2, Vec3};
use irradia_core::{Aabb, Ray};

/// Which quadric this is, for names, texture coordinates and facets. The canonical
/// (local) frame has the axis of symmetry along `y`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum QuadricKind {
    General,
    /// `(x/rx)² + (y/ry)² + (z/rz)² = 1` in the local frame.
    Ellipsoid {
        radii: DVec3,
    },
    /// `x² + z² = r²`, infinite along `y`.
    Cylinder {
        radius: f64,
    },
    /// `x² + z² = (slope·y)²`, apex at the origin.
    Cone {
        slope: f64,
    },
    /// `y = k (x² + z²)`.
    Paraboloid {
        curvature: f64,
    },
    /// `(x² + z²)/a² - y²/c² = 1`.
    HyperboloidOneSheet {
        a: f64,
        c: f64,
    },
    /// `(x² + z²)/a² - y²/c² = -1`.
    HyperboloidTwoSheets {
        a: f64,
        c: f64,
    },
    /// A cylinder of `radius` from local `y = 0` to `y = height`, with both caps.
    CappedCylinder {
        radius: f64,
        height: f64,
    },
    /// A cone frustum from radius `r0` at local `y = 0` to `r1` at `y = height`, capped.
    CappedCone {
        r0: f64,
        r1: f64,
        height: f64,
    },
}

/// A quadric surface or solid. Build it with the constructors in [`named`] (re-exported
/// as methods: `Quadric::new`, `Quadric::ellipsoid`, `Quadric::capped_cylinder`, ...).
#[derive(Clone, Debug)]
pub struct Quadric {
    form: QuadricForm,
    clip: Vec<HalfSpace>,
    /// True: the solid `Q ≤ 0` ∩ clip (caps are surface). False: the open surface.
    solid: bool,
    kind: QuadricKind,
    /// Object space to the canonical frame of `kind` (texture coordinates, facets).
    to_local: DAffine3,
    /// Bounds known from construction (named shapes, clipping boxes), object space.
    known_bounds: (DVec3, DVec3),
    bounds: Aabb,
    /// The centre of the bounds when they are finite: rays are solved from the point
    /// nearest it (see `QuadricForm::inside_intervals_near`).
    centre: Option<DVec3>,
}

/// One end of an inside interval: its parameter and which surface it lies on.
#[derive(Clone, Copy, Debug)]
struct End {
    t: f64,
    /// `SURFACE`, a clip plane index, or `NO_PLANE` for an end at infinity.
    side: u32,
}

const SURFACE: u32 = u32::MAX - 1;

impl End {
    /// A parameter-only boundary at this end that carries the end itself through CSG
    /// (see [`Shape::span_boundary_of`]): the f64 parameter's bits in `uv` (high word
    /// in `x`), and the side in the size of the normal's `y` (0 for the quadric
    /// surface, `i + 1` for clip plane `i`; exact in f32 for any plane count a quadric
    /// has). An end at infinity needs no side (it is never asked for a surface).
    #[inline]
    fn carried(self) -> Boundary {
        let bits = self.t.to_bits();
        let code = if self.side == SURFACE || self.side == NO_PLANE {
            0.0
        } else {
            (self.side + 1) as f32
        };
        Boundary::new(
            self.t as f32,
            Vec3::new(0.0, code, 0.0),
            Vec2::new(
                f32::from_bits((bits >> 32) as u32),
                f32::from_bits(bits as u32),
            ),
        )
    }

    /// The end that [`Self::carried`] put in `b` (its normal possibly negated).
    #[inline]
    fn from_carried(b: &Boundary) -> Self {
        let bits = ((b.uv.x.to_bits() as u64) << 32) | b.uv.y.to_bits() as u64;
        let t = f64::from_bits(bits);
        let code = b.normal.y.abs() as u32;
        let side = if !t.is_finite() {
            NO_PLANE
        } else if code == 0 {
            SURFACE
        } else {
            code - 1
        };
        End { t, side }
    }
}

impl Quadric {
    pub(crate) fn from_parts(
        form: QuadricForm,
        clip: Vec<HalfSpace>,
        kind: QuadricKind,
        to_local: DAffine3,
        known_bounds: (DVec3, DVec3),
    ) -> Self {
        let mut q = Self {
            form,
            clip,
            solid: true,
            kind,
            to_local,
            known_bounds,
            bounds: Aabb::INFINITE,
            centre: None,
        };
        q.update_bounds();
        q
    }

    /// The quadratic form (the surface is `form.value(p) = 0`).
    pub fn form(&self) -> &QuadricForm {
        &self.form
    }
    /// The clipping half-spaces (empty when unclipped).
    pub fn clip_planes(&self) -> &[HalfSpace] {
        &self.clip
    }
    pub fn quadric_kind(&self) -> QuadricKind {
        self.kind
    }
    /// The map from object space to the canonical frame of [`QuadricKind`].
    pub fn to_local(&self) -> &DAffine3 {
        &self.to_local
    }

    pub(crate) fn update_bounds(&mut self) {
        self.bounds = self.compute_bounds();
        self.centre = self
            .bounds
            .is_finite()
            .then(|| self.bounds.center().as_dvec3());
    }

    /// The f64 parameter intervals of the unclipped solid `Q ≤ 0` along `o + t d`, as
    /// intersection uses them (solved near the bounds' centre when bounded).
    #[inline]
    pub fn line_intervals(&self, o: DVec3, d: DVec3) -> form::LineIntervals {
        match self.centre {
            Some(c) => self.form.inside_intervals_near(o, d, c),
            None => self.form.inside_intervals(o, d),
        }
    }

    fn compute_bounds(&self) -> Aabb {
        let (mut lo, mut hi) = self.known_bounds;
        if let Some((a, b)) = self.form.ellipsoid_bounds() {
            lo = lo.max(a);
            hi = hi.min(b);
        }
        if lo.cmpgt(hi).any() {
            return Aabb::EMPTY;
        }
        // Round outwards so the f32 box contains the f64 one.
        let pad = |v: DVec3| v.abs() * 1e-6 + DVec3::splat(1e-30);
        Aabb::new((lo - pad(lo)).as_vec3(), (hi + pad(hi)).as_vec3())
    }

    /// The ends of the inside intervals of the (clipped) solid along `o + t d`.
    #[inline]
    fn solid_spans(&self, o: DVec3, d: DVec3, out: &mut [(End, End); 2]) -> usize {
        let iv = self.line_intervals(o, d);
        let end = |t: f64, side: u32| End {
            t,
            side: if t.is_finite() { side } else { NO_PLANE },
        };
        let mut n = 0;
        if self.clip.is_empty() {
            for &(t0, t1) in iv.as_slice() {
                out[n] = (end(t0, SURFACE), end(t1, SURFACE));
                n += 1;
            }
            return n;
        }
        if iv.len == 0 {
            return 0;
        }
        let Some(c) = clip_interval(&self.clip, o, d) else {
            return 0;
        };
        for &(t0, t1) in iv.as_slice() {
            // Ties go to the quadric surface: deterministic, and either is correct.
            let a = if t0 >= c.t_in {
                end(t0, SURFACE)
            } else {
                end(c.t_in, c.plane_in)
            };
            let b = if t1 <= c.t_out {
                end(t1, SURFACE)
            } else {
                end(c.t_out, c.plane_out)
            };
            if a.t <= b.t {
                out[n] = (a, b);
                n += 1;
            }
        }
        n
    }

    /// The nearest end with `0 < t < t_max` on the surface that a ray sees.
    #[inline]
    fn nearest(&self, o: DVec3, d: DVec3, t_max: f64) -> Option<End> {
        let ok = |e: &End| e.t > 0.0 && e.t < t_max && e.side != NO_PLANE;
        if self.solid {
            let mut spans = [(End { t: 0.0, side: 0 }, End { t: 0.0, side: 0 }); 2];
            let n = self.solid_spans(o, d, &mut spans);
            spans[..n]
                .iter()
                .flat_map(|(a, b)| [*a, *b])
                .find(|e| ok(e))
        } else {
            let iv = self.line_intervals(o, d);
            let c = if self.clip.is_empty() {
                None
            } else {
                Some(clip_interval(&self.clip, o, d)?)
            };
            iv.as_slice()
                .iter()
                .flat_map(|&(a, b)| [a, b])
                .filter(|t| t.is_finite())
                .filter(|&t| match c {
                    Some(c) => t >= c.t_in && t <= c.t_out,
                    None => true,
                })
                .map(|t| End { t, side: SURFACE })
                .find(|e| ok(e))
        }
    }

    /// Normal (unit, out of the solid) at `p` on `side`.
    #[inline]
    fn normal_at(&self, p: DVec3, side: u32, d: DVec3) -> DVec3 {
        if side == SURFACE {
            let g = self.form.gradient(p);
            let len = g.length();
            if len > 0.0 && len.is_finite() {
                g / len
            } else {
                // A singular point (a cone's apex): any normal facing the ray will do.
                -d.normalize()
            }
        } else {
            self.clip[side as usize].normal
        }
    }

    /// Texture coordinates, computed in f32 (accurate enough for textures), the angle
    /// by the sphere's polynomial `atan2` (error below 2e-5 rad, several times cheaper
    /// than libm's; this runs for both ends of every span).
    fn uv_at(&self, p: DVec3, side: u32) -> Vec2 {
        use std::f32::consts::{PI, TAU};
        let l = self.to_local.transform_point3(p).as_vec3();
        let angle = || 0.5 + irradia_core::atan2(l.z, l.x) / TAU;
        match self.kind {
            QuadricKind::Ellipsoid { radii } => {
                let u = (l / radii.as_vec3()).normalize_or_zero();
                Vec2::new(angle(), u.y.clamp(-1.0, 1.0).acos() / PI)
            }
            QuadricKind::CappedCylinder { height, .. } | QuadricKind::CappedCone { height, .. }
                if side == SURFACE =>
            {
                Vec2::new(angle(), l.y / height as f32)
            }
            QuadricKind::CappedCylinder { radius, .. } => {
                let r = radius as f32;
                Vec2::new(0.5 + l.x / (2.0 * r), 0.5 + l.z / (2.0 * r))
            }
            QuadricKind::CappedCone { r0, r1, .. } => {
                let r = r0.max(r1) as f32;
                Vec2::new(0.5 + l.x / (2.0 * r), 0.5 + l.z / (2.0 * r))
            }
            _ => Vec2::new(angle(), l.y),
        }
    }

    fn boundary(&self, o: DVec3, d: DVec3, e: End) -> Boundary {
        if e.side == NO_PLANE {
            return Boundary::new(e.t as f32, Vec3::ZERO, Vec2::ZERO);
        }
        let p = o + d * e.t;
        let mut b = Boundary::new(
            e.t as f32,
            self.normal_at(p, e.side, d).as_vec3(),
            self.uv_at(p, e.side),
        );
        b.prim = prim_of(e.side);
        b
    }

    fn hit(&self, o: DVec3, d: DVec3, e: End) -> Hit {
        let p = o + d * e.t;
        let n = self.normal_at(p, e.side, d);
        let mut h = Hit::new(e.t as f32, p.as_vec3(), n.as_vec3(), self.uv_at(p, e.side));
        h.prim = prim_of(e.side);
        // Distance from the f64 point to the true surface (residual plus its rounding
        // error, over the gradient), plus rounding the point to f32 (half an ulp per
        // coordinate, at most eps·max|p| in length).
        let surface_err = if e.side == SURFACE {
            let g = self.form.gradient(p).length();
            (self.form.value(p).abs() + self.form.value_error(p)) / g
        } else {
            let h = &self.clip[e.side as usize];
            (h.normal.dot(p) - h.offset).abs()
                + 8.0 * f64::EPSILON * (h.normal.abs().dot(p.abs()) + h.offset.abs())
        };
        let err = p.abs().max_element() * f32::EPSILON as f64
            + if surface_err.is_finite() {
                surface_err
            } else {
                0.0
            };
        h.error = err as f32;
        h
    }
}

#[inline]
fn prim_of(side: u32) -> u32 {
    if side == SURFACE {
        0
    } else {
        side + 1
    }
}

impl Shape for Quadric {
    fn kind(&self) -> &'static str {
        match self.kind {
            QuadricKind::General => "quadric",
            QuadricKind::Ellipsoid { .. } => "ellipsoid",
            QuadricKind::Cylinder { .. } | QuadricKind::CappedCylinder { .. } => "cylinder",
            QuadricKind::Cone { .. } | QuadricKind::CappedCone { .. } => "cone",
            QuadricKind::Paraboloid { .. } => "paraboloid",
            QuadricKind::HyperboloidOneSheet { .. } => "hyperboloid of one sheet",
            QuadricKind::HyperboloidTwoSheets { .. } => "hyperboloid of two sheets",
        }
    }

    fn bounds(&self) -> Aabb {
        self.bounds
    }

    fn intersect(&self, ray: &Ray, t_max: f32) -> Option<Hit> {
        let (o, d) = (ray.origin.as_dvec3(), ray.dir.as_dvec3());
        let e = self.nearest(o, d, t_max as f64)?;
        Some(self.hit(o, d, e))
    }

    fn occluded(&self, ray: &Ray, t_max: f32) -> bool {
        self.nearest(ray.origin.as_dvec3(), ray.dir.as_dvec3(), t_max as f64)
            .is_some()
    }

    fn is_solid(&self) -> bool {
        self.solid
    }

    fn spans(&self, ray: &Ray, out: &mut Vec<Span>) {
        if !self.solid {
            return;
        }
        let (o, d) = (ray.origin.as_dvec3(), ray.dir.as_dvec3());
        let mut spans = [(End { t: 0.0, side: 0 }, End { t: 0.0, side: 0 }); 2];
        let n = self.solid_spans(o, d, &mut spans);
        for &(a, b) in &spans[..n] {
            out.push(Span {
                enter: self.boundary(o, d, a),
                exit: self.boundary(o, d, b),
            });
        }
    }

    /// One boundary of [`Self::spans`]: the same ends, and the surface (normal, uv) at
    /// the one asked for alone.
    fn span_boundary(&self, ray: &Ray, index: u32, _: &mut Vec<Span>) -> Option<Boundary> {
        if !self.solid {
            return None;
        }
        let (o, d) = (ray.origin.as_dvec3(), ray.dir.as_dvec3());
        let mut spans = [(End { t: 0.0, side: 0 }, End { t: 0.0, side: 0 }); 2];
        let n = self.solid_spans(o, d, &mut spans);
        let &(a, b) = spans[..n].get((index / 2) as usize)?;
        Some(self.boundary(o, d, if index % 2 == 0 { a } else { b }))
    }

    /// [`Self::span_boundary`] from the end that [`Self::spans_t`] carried in `param`:
    /// the same end (its f64 parameter and side), so the same boundary, without
    /// solving the ray again (13% of the Steinmetz solid's solves were these: helper
    /// `csg6`'s profile, docs/benchmarks.md).
    fn span_boundary_of(
        &self,
        ray: &Ray,
        index: u32,
        param: &Boundary,
        scratch: &mut Vec<Span>,
    ) -> Option<Boundary> {
        let _ = (index, scratch);
        if !self.solid {
            return None;
        }
        let e = End::from_carried(param);
        debug_assert_eq!((e.t as f32).to_bits(), param.t.to_bits());
        let (o, d) = (ray.origin.as_dvec3(), ray.dir.as_dvec3());
        Some(self.boundary(o, d, e))
    }

    /// [`Self::spans`]' ends without their normals and uv (no gradient, no `atan2`),
    /// each carrying its end ([`End::carried`]) for [`Self::span_boundary_of`].
    fn spans_t(&self, ray: &Ray, out: &mut Vec<Span>) {
        if !self.solid {
            return;
        }
        let (o, d) = (ray.origin.as_dvec3(), ray.dir.as_dvec3());
        let mut spans = [(End { t: 0.0, side: 0 }, End { t: 0.0, side: 0 }); 2];
        let n = self.solid_spans(o, d, &mut spans);
        let at = |e: End| e.carried();
        for &(a, b) in &spans[..n] {
            out.push(Span {
                enter: at(a),
                exit: at(b),
            });
        }
    }

    fn facets(&self, detail: u32) -> Option<crate::shape::Facets> {
        facets::facets(self, detail)
    }
}
