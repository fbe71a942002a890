//! An object placed in the world: a shape and an affine transform. Rays are carried
//! into object space (the direction is not renormalised, so `t` is shared).

use crate::csg::window::SlabRay;
use crate::mesh::AttributePoint;
use crate::shape::{Boundary, CastHit, Hit, Shape, Span};
use glam::{Affine3A, Mat3A, Vec3};
use irradia_core::{Aabb, Ray};
use std::sync::Arc;

#[derive(Clone, Debug)]
pub struct Instance {
    pub shape: Arc<dyn Shape>,
    to_world: Affine3A,
    to_object: Affine3A,
    /// Inverse transpose of the linear part: carries normals to world space.
    normal_to_world: Mat3A,
    /// Largest stretch of the linear part, to scale error bounds.
    max_scale: f32,
    identity: bool,
    bounds: Aabb,
    /// The shape's own (object-space) bounds where a rotation or shear makes the world
    /// box looser than they are: see [`Self::may_meet`].
    cull_bounds: Option<Aabb>,
}

impl Instance {
    /// Places `shape` with the object-to-world map `to_world`, which must be invertible.
    pub fn new(shape: Arc<dyn Shape>, to_world: Affine3A) -> Self {
        let to_object = to_world.inverse();
        let normal_to_world = to_object.matrix3.transpose();
        let m = to_world.matrix3;
        let max_scale = m
            .x_axis
            .length()
            .max(m.y_axis.length())
            .max(m.z_axis.length())
            * 3f32.sqrt();
        let own = shape.bounds();
        let bounds = own.transformed(&to_world);
        // Only a linear part with off-diagonal terms (a rotation, a shear) turns the
        // box: under a scale and a translation the world box is as tight as the own.
        let turned = m.x_axis.y != 0.0
            || m.x_axis.z != 0.0
            || m.y_axis.x != 0.0
            || m.y_axis.z != 0.0
            || m.z_axis.x != 0.0
            || m.z_axis.y != 0.0;
        let cull_bounds = (turned && own.is_finite() && !own.is_empty()).then_some(own);
        Self {
            shape,
            to_world,
            to_object,
            normal_to_world,
            max_scale,
            identity: to_world == Affine3A::IDENTITY,
            bounds,
            cull_bounds,
        }
    }

    pub fn untransformed(shape: Arc<dyn Shape>) -> Self {
        Self::new(shape, Affine3A::IDENTITY)
    }

    #[inline]
    pub fn to_world(&self) -> &Affine3A {
        &self.to_world
    }
    #[inline]
    pub fn to_object(&self) -> &Affine3A {
        &self.to_object
    }

    /// Whether the object-to-world map is the identity (object space is world space).
    #[inline]
    pub fn is_identity(&self) -> bool {
        self.identity
    }

    /// World-space bounds.
    #[inline]
    pub fn bounds(&self) -> Aabb {
        self.bounds
    }

    /// Whether the object-space ray `object_ray` may meet the shape's own bounds for
    /// some `t` in `[0, t_max]` (always true where they are not kept). A scan over
    /// objects tests their world boxes; a rotated shape's world box is the box around
    /// its own box turned, larger than it (the `csg` scene's Steinmetz solid: twice the
    /// camera rays, and three times the shadow rays, of its own box), so the
    /// rays that reach a placed shape are tested again against its own box, in object
    /// space, before the shape is asked. The test is the CSG operands' (`SlabRay`,
    /// widened by a few ulps): conservative, so it drops only rays that miss.
    #[inline]
    fn may_meet(&self, object_ray: &Ray, t_max: f32) -> bool {
        match &self.cull_bounds {
            Some(b) => SlabRay::new(object_ray).overlaps(b, 0.0, t_max),
            None => true,
        }
    }

    #[inline]
    pub(crate) fn object_ray(&self, ray: &Ray) -> Ray {
        Ray::new(
            self.to_object.transform_point3(ray.origin),
            self.to_object.transform_vector3(ray.dir),
        )
    }

    /// `(dp/du, dp/dv)` in world space at world-space hit `hit` of this instance
    /// ([`Shape::uv_derivatives`] carried by the transform).
    pub fn uv_derivatives(&self, hit: &Hit) -> (Vec3, Vec3) {
        if self.identity {
            return self.shape.uv_derivatives_at(hit);
        }
        let mut object_hit = *hit;
        object_hit.point = self.to_object.transform_point3(hit.point);
        let (du, dv) = self.shape.uv_derivatives_at(&object_hit);
        (
            self.to_world.transform_vector3(du),
            self.to_world.transform_vector3(dv),
        )
    }

    /// Where world-space hit `hit` lies on the shape's attributes
    /// ([`Shape::attribute_point`]).
    pub fn attribute_point(&self, hit: &Hit) -> Option<AttributePoint<'_>> {
        if self.identity {
            return self.shape.attribute_point(hit);
        }
        let mut object_hit = *hit;
        object_hit.point = self.to_object.transform_point3(hit.point);
        self.shape.attribute_point(&object_hit)
    }

    /// Nearest hit in world space.
    pub fn intersect(&self, ray: &Ray, t_max: f32) -> Option<Hit> {
        if self.identity {
            return self.shape.intersect(ray, t_max);
        }
        let r = self.object_ray(ray);
        if !self.may_meet(&r, t_max) {
            return None;
        }
        let h = self.shape.intersect(&r, t_max)?;
        Some(self.hit_to_world(ray, h))
    }

    /// Whether the shape splits its nearest hit ([`Shape::splits_surface`]).
    #[inline]
    pub fn splits_surface(&self) -> bool {
        self.shape.splits_surface()
    }

    /// The parameter of [`Self::intersect`]'s hit ([`Shape::nearest_t`]; `t` is
    /// shared by world and object space), finished by [`Self::surface_at`].
    #[inline]
    pub fn nearest_t(&self, ray: &Ray, t_max: f32) -> Option<f64> {
        if self.identity {
            return self.shape.nearest_t(ray, t_max);
        }
        let r = self.object_ray(ray);
        if !self.may_meet(&r, t_max) {
            return None;
        }
        self.shape.nearest_t(&r, t_max)
    }

    /// The world hit at the parameter [`Self::nearest_t`] gave for `ray`: the hit of
    /// [`Self::intersect`], bit for bit (its uv only with `uv`: [`Shape::surface_at`]).
    pub fn surface_at(&self, ray: &Ray, t: f64, uv: bool) -> Hit {
        if self.identity {
            return self.shape.surface_at(ray, t, uv);
        }
        let h = self.shape.surface_at(&self.object_ray(ray), t, uv);
        self.hit_to_world(ray, h)
    }

    /// An object-space hit `h` of world ray `ray` carried to world space.
    #[inline]
    fn hit_to_world(&self, ray: &Ray, mut h: Hit) -> Hit {
        h.point = ray.at(h.t);
        h.normal = self
            .normal_to_world
            .mul_vec3a(h.normal.into())
            .normalize()
            .into();
        h.shading_normal = self
            .normal_to_world
            .mul_vec3a(h.shading_normal.into())
            .normalize()
            .into();
        // The world point is recomputed from t: its error is that of t times |dir|,
        // bounded by the object-space error stretched by the transform, plus rounding.
        h.error = h.error * self.max_scale
            + (ray.origin.abs().max_element() + (ray.dir * h.t).abs().max_element())
                * 4.0
                * f32::EPSILON;
        h
    }

    /// [`Self::intersect`] as ray casting reports it ([`Shape::intersect_cast`]): the
    /// normal carried to world space as there, `t`, primitive and uv as they are.
    pub fn intersect_cast(&self, ray: &Ray, t_max: f32) -> Option<CastHit> {
        if self.identity {
            return self.shape.intersect_cast(ray, t_max);
        }
        let mut h = self.shape.intersect_cast(&self.object_ray(ray), t_max)?;
        h.normal = self.cast_normal_to_world(h.normal);
        Some(h)
    }

    /// An object-space normal of a cast hit carried to world space (unit length).
    #[inline]
    pub(crate) fn cast_normal_to_world(&self, n: Vec3) -> Vec3 {
        self.normal_to_world.mul_vec3a(n.into()).normalize().into()
    }

    #[inline]
    pub fn occluded(&self, ray: &Ray, t_max: f32) -> bool {
        if self.identity {
            return self.shape.occluded(ray, t_max);
        }
        self.occluded_transformed(ray, t_max)
    }

    /// [`Self::occluded`] of a placed shape, kept out of line. Inlined into a caller's
    /// loop over objects (the Whitted tracer's shadow scan), the ray's carry into object
    /// space was hoisted in front of the loop: the ray's six lanes were reloaded there
    /// as 16-byte loads straddling the separate stores that had just written the shadow
    /// ray, a store-forwarding stall on every shadow ray (~10% of `Whitted::trace`'s
    /// samples, `perf annotate`), even in scenes where no object is transformed.
    #[inline(never)]
    fn occluded_transformed(&self, ray: &Ray, t_max: f32) -> bool {
        let r = self.object_ray(ray);
        self.may_meet(&r, t_max) && self.shape.occluded(&r, t_max)
    }

    /// Spans in world space (parameters are shared; normals are carried to world space).
    pub fn spans(&self, ray: &Ray, out: &mut Vec<Span>) {
        if self.identity {
            return self.shape.spans(ray, out);
        }
        let start = out.len();
        self.shape.spans(&self.object_ray(ray), out);
        for s in &mut out[start..] {
            for b in [&mut s.enter, &mut s.exit] {
                b.normal = self.carry_boundary_normal(b.t, b.normal);
            }
        }
    }

    /// [`Shape::span_boundary_of`] in world space: boundary `index` of [`Self::spans`]'
    /// list, its normal carried to world space as there.
    pub(crate) fn span_boundary_of(
        &self,
        ray: &Ray,
        index: u32,
        param: &Boundary,
        scratch: &mut Vec<Span>,
    ) -> Option<Boundary> {
        if self.identity {
            return self.shape.span_boundary_of(ray, index, param, scratch);
        }
        let mut b = self
            .shape
            .span_boundary_of(&self.object_ray(ray), index, param, scratch)?;
        b.normal = self.carry_boundary_normal(b.t, b.normal);
        Some(b)
    }

    /// [`Shape::spans_t`] in world space: the spans' parameters only (they are shared
    /// with object space, so nothing is carried).
    #[inline]
    pub fn spans_t(&self, ray: &Ray, out: &mut Vec<Span>) {
        if self.identity {
            return self.shape.spans_t(ray, out);
        }
        self.shape.spans_t(&self.object_ray(ray), out);
    }

    /// The world ray carried into object space, as [`Self::spans`] carries it (the
    /// same ray when the map is the identity).
    #[inline]
    pub(crate) fn ray_to_object(&self, ray: &Ray) -> Ray {
        if self.identity {
            *ray
        } else {
            self.object_ray(ray)
        }
    }

    /// An object-space boundary normal at parameter `t` carried to world space, as
    /// [`Self::spans`] carries it (unchanged at infinite `t` or under the identity).
    #[inline]
    pub(crate) fn carry_boundary_normal(&self, t: f32, n: Vec3) -> Vec3 {
        if self.identity || !t.is_finite() {
            n
        } else {
            Vec3::from(self.normal_to_world.mul_vec3a(n.into())).normalize()
        }
    }
}
