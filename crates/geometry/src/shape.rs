//! The `Shape` interface: intersection, bounds, and spans for CSG.

use crate::mesh::{AttributePoint, MeshAttributes, TriangleMesh};
use glam::{Vec2, Vec3};
use irradia_core::{Aabb, Ray};

/// A ray-surface intersection, in the coordinate frame of the ray that was passed in.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    /// Ray parameter (in units of `ray.dir`, which need not be unit length).
    pub t: f32,
    /// The hit point.
    pub point: Vec3,
    /// Unit geometric normal. For closed shapes it points out of the solid; for open
    /// surfaces (polygons, patches) it is the surface's own orientation. It is never
    /// flipped towards the ray: integrators decide which side they are on.
    pub normal: Vec3,
    /// Unit shading normal (interpolated vertex normals on meshes); equals `normal`
    /// for analytic shapes.
    pub shading_normal: Vec3,
    /// Surface parameterisation, for textures (its derivatives, when an integrator
    /// needs them: [`Shape::uv_derivatives`]).
    pub uv: Vec2,
    /// Primitive index inside the shape (triangle of a mesh, patch of a Bézier surface).
    pub prim: u32,
    /// Which CSG leaf was hit (depth-first numbering); 0 for shapes that are not CSG.
    pub leaf: u32,
    /// An absolute bound on the error of `point`; secondary rays are pushed off the
    /// surface by at least this much (see `irradia_core::offset_ray_origin`).
    pub error: f32,
}

/// What ray casting reports of a hit (Open3D's `RaycastingScene.cast_rays`): the
/// fields of [`Hit`] of the same names.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CastHit {
    pub t: f32,
    pub prim: u32,
    pub uv: Vec2,
    pub normal: Vec3,
}

impl From<&Hit> for CastHit {
    #[inline]
    fn from(h: &Hit) -> Self {
        Self {
            t: h.t,
            prim: h.prim,
            uv: h.uv,
            normal: h.normal,
        }
    }
}

impl Hit {
    /// A hit with the shading normal equal to the geometric one and no error.
    pub fn new(t: f32, point: Vec3, normal: Vec3, uv: Vec2) -> Self {
        Self {
            t,
            point,
            normal,
            shading_normal: normal,
            uv,
            prim: 0,
            leaf: 0,
            error: 0.0,
        }
    }
}

/// One end of a span: where a ray enters or leaves a solid.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Boundary {
    /// Ray parameter; `-inf` / `+inf` when the ray is inside for ever on that side.
    pub t: f32,
    /// Unit normal pointing out of the solid at this point (meaningless at infinity).
    pub normal: Vec3,
    pub uv: Vec2,
    pub prim: u32,
    pub leaf: u32,
}

impl Boundary {
    pub fn new(t: f32, normal: Vec3, uv: Vec2) -> Self {
        Self {
            t,
            normal,
            uv,
            prim: 0,
            leaf: 0,
        }
    }
    pub const NEG_INFINITY: Boundary = Boundary {
        t: f32::NEG_INFINITY,
        normal: Vec3::ZERO,
        uv: Vec2::ZERO,
        prim: 0,
        leaf: 0,
    };
    pub const INFINITY: Boundary = Boundary {
        t: f32::INFINITY,
        normal: Vec3::ZERO,
        uv: Vec2::ZERO,
        prim: 0,
        leaf: 0,
    };
}

/// A parameter interval `[enter.t, exit.t]` in which the ray is inside a solid.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Span {
    pub enter: Boundary,
    pub exit: Boundary,
}

/// A surface approximated by planar polygons, in object space: for radiosity meshing
/// and for the rasterizer. Faces wind counter-clockwise seen from the side their
/// normal points to (out of solids).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Facets {
    pub vertices: Vec<Vec3>,
    /// Each face is a loop of indices into `vertices` (3 or more, planar).
    pub faces: Vec<Vec<u32>>,
    /// Optional per-vertex unit normals for smooth shading (empty when flat).
    pub normals: Vec<Vec3>,
}

/// A surface or solid that rays can hit.
///
/// Rays passed in may have non-unit directions; `t` is in units of `ray.dir`.
/// Only hits with `0 < t < t_max` count.
pub trait Shape: Send + Sync + std::fmt::Debug {
    /// A short name for statistics and error messages ("sphere", "quadric", ...).
    fn kind(&self) -> &'static str;

    /// Object-space bounds. Unbounded shapes (a plane, an unclipped cylinder) return
    /// a box with infinite coordinates.
    fn bounds(&self) -> Aabb;

    /// The nearest hit with `0 < t < t_max`.
    fn intersect(&self, ray: &Ray, t_max: f32) -> Option<Hit>;

    /// Whether the shape's nearest hit comes in two steps that save work: its
    /// parameter ([`Self::nearest_t`]) and then, for the one hit a closest-hit scan
    /// over several objects keeps, its surface ([`Self::surface_at`]). The scan then
    /// computes one surface, the winner's, instead of one for every object that was
    /// the nearest so far (a ray seen past a sphere onto a floor: the floor's point,
    /// normal and uv thrown away); Wald et al. 2001, "Interactive Rendering with
    /// Coherent Ray Tracing", §3: intersection first, shading data for the final hit
    /// only. The sphere and the plane say yes; other shapes are asked for whole hits.
    fn splits_surface(&self) -> bool {
        false
    }

    /// The exact (f64) parameter of the hit [`Self::intersect`] gives, whose `Hit::t`
    /// is its f32 rounding: `Some` exactly when `intersect` finds a hit.
    fn nearest_t(&self, ray: &Ray, t_max: f32) -> Option<f64> {
        self.intersect(ray, t_max).map(|h| h.t as f64)
    }

    /// The hit at the parameter `t` that [`Self::nearest_t`] gave for `ray`: bit for
    /// bit the hit [`Self::intersect`] gives, except that with `uv` false the caller
    /// says it will not read the hit's texture coordinates, which the shape may then
    /// leave zero (the sphere's cost two arctangents, a twelfth of a Whitted tracer's
    /// time on a scene of untextured spheres). The default finds the hit again by
    /// `intersect`: the nearest hit in `(0, t_max)`, where there is one, is the nearest
    /// of all.
    fn surface_at(&self, ray: &Ray, t: f64, uv: bool) -> Hit {
        let _ = (t, uv);
        self.intersect(ray, f32::INFINITY)
            .expect("surface_at: asked for a ray that hits nothing")
    }

    /// The nearest hit as ray casting reports it (`t`, primitive, uv, geometric
    /// normal): the same values as [`Self::intersect`]'s, which this default takes
    /// them from. A shape overrides it where those four come cheaper than a whole
    /// [`Hit`] (a triangle mesh: straight from the leaf that was hit).
    fn intersect_cast(&self, ray: &Ray, t_max: f32) -> Option<CastHit> {
        self.intersect(ray, t_max).map(|h| CastHit::from(&h))
    }

    /// The shape as a triangle mesh, when it is one (`None` for every other shape): lets
    /// a caller that traces many rays against a scene of one mesh call the mesh's own
    /// closest-hit routine directly, with no dynamic call per ray (see
    /// [`crate::Accel::sole_mesh`]), and a renderer bake its triangles and interpolate
    /// its vertex normals as the mesh's hits do (the path tracer's flat scene).
    fn as_triangle_mesh(&self) -> Option<&TriangleMesh> {
        None
    }

    /// The shape as a sphere, when it is one (`None` for every other shape): lets the
    /// path tracer's wide kernel intersect W rays with it at once, with the
    /// sphere's own centre, radius and arithmetic.
    fn as_sphere(&self) -> Option<&crate::shapes::Sphere> {
        None
    }

    /// The partial derivatives `(dp/du, dp/dv)` of the surface point with respect to its
    /// texture coordinates at the hit with object-space point `p`, `uv` and primitive
    /// `prim` (Mitsuba's `dp_du`, `dp_dv`): the tangent frame of anisotropic BSDFs and of
    /// normal and bump maps. Asked only by integrators that need it, so hits stay lean.
    /// Zero where the shape has no parameterisation (the frame about the normal is then
    /// arbitrary).
    fn uv_derivatives(&self, p: Vec3, uv: Vec2, prim: u32) -> (Vec3, Vec3) {
        let _ = (p, uv, prim);
        (Vec3::ZERO, Vec3::ZERO)
    }

    /// The named per-vertex and per-face values the shape carries (a triangle mesh's
    /// attributes, Mitsuba's `Mesh::add_attribute`), for checking what the
    /// `mesh_attribute` texture reads; `None` for shapes without them.
    fn attributes(&self) -> Option<&MeshAttributes> {
        None
    }

    /// Where object-space hit `hit` lies for attribute lookups (the triangle, its
    /// corners and barycentric coordinates); `None` for shapes without attributes.
    /// Shapes made of other placed shapes (a [`crate::ShapeGroup`]) find the member
    /// from the hit's `leaf`.
    fn attribute_point(&self, hit: &Hit) -> Option<AttributePoint<'_>> {
        let _ = hit;
        None
    }

    /// [`Shape::uv_derivatives`] at an object-space hit; shapes made of other placed
    /// shapes (a [`crate::ShapeGroup`]) find the member from the hit's `leaf`.
    fn uv_derivatives_at(&self, hit: &Hit) -> (Vec3, Vec3) {
        self.uv_derivatives(hit.point, hit.uv, hit.prim)
    }

    /// Whether any hit with `0 < t < t_max` exists (shadow rays). Shapes may override
    /// this with something cheaper than finding the nearest hit.
    fn occluded(&self, ray: &Ray, t_max: f32) -> bool {
        self.intersect(ray, t_max).is_some()
    }

    /// True for shapes that bound a solid, and so can take part in CSG.
    fn is_solid(&self) -> bool;

    /// Appends, in increasing `t` over the whole line (negative `t` too), the spans in
    /// which the ray is inside the solid (Roth 1982, "Ray casting for modeling solids").
    /// Shapes that are not solid append nothing.
    fn spans(&self, ray: &Ray, out: &mut Vec<Span>);

    /// [`Shape::spans`] for a caller that needs only where the boundaries are: the same
    /// spans, with the same `t`s in the same order, but each boundary's `normal`, `uv`
    /// and `prim` may be left unset. CSG combines spans by `t` alone and shades only the
    /// one boundary that wins (or none, for a shadow ray), so shapes whose surface costs
    /// more than their roots (a normal, an `atan2` for uv) override this to skip it.
    fn spans_t(&self, ray: &Ray, out: &mut Vec<Span>) {
        self.spans(ray, out)
    }

    /// Boundary `index` of the list [`Shape::spans`] appends along `ray` (the enter of
    /// span `index / 2` when `index` is even, else its exit), bit for bit, or `None`
    /// when the list is shorter. CSG asks it for the one boundary a ray reports, after
    /// combining spans by their parameters alone (`csg::resolve`). The default computes
    /// the whole list into `scratch`; shapes whose surface costs more than their roots
    /// (a normal, an `atan2` for uv) override it to compute that boundary's alone.
    fn span_boundary(&self, ray: &Ray, index: u32, scratch: &mut Vec<Span>) -> Option<Boundary> {
        scratch.clear();
        self.spans(ray, scratch);
        let s = scratch.get((index / 2) as usize)?;
        Some(if index % 2 == 0 { s.enter } else { s.exit })
    }

    /// [`Shape::span_boundary`] for a boundary that [`Shape::spans_t`] gave: `param` is
    /// boundary `index` of the list `spans_t` appended along the same `ray`, as CSG
    /// carried it (`t`, `uv` and the size of the normal's `y` as `spans_t` set them:
    /// CSG renames `prim` and `leaf`, sets the normal's `x` and may negate the normal).
    /// The answer is `span_boundary`'s, bit for bit. The default asks `span_boundary`;
    /// a shape whose `spans_t` keeps in those fields what its surface needs (the
    /// quadric: its f64 parameter and which surface) overrides it so as not to solve
    /// the ray again.
    fn span_boundary_of(
        &self,
        ray: &Ray,
        index: u32,
        param: &Boundary,
        scratch: &mut Vec<Span>,
    ) -> Option<Boundary> {
        let _ = param;
        self.span_boundary(ray, index, scratch)
    }

    /// The surface as planar polygons. `detail` sets how finely curved surfaces are cut
    /// (about `detail` segments around a full turn); flat shapes ignore it. `None` for
    /// shapes that cannot be faceted (unbounded ones).
    fn facets(&self, detail: u32) -> Option<Facets> {
        let _ = detail;
        None
    }

    /// True when [`Shape::facets`] is the surface itself, not an approximation: every
    /// face is planar and convex, the faces together are exactly the surface, and a hit
    /// on them is a hit on the shape (polygons, boxes, convex polyhedra). A renderer may
    /// then intersect the facets instead of the shape (the path tracer's flat scene).
    fn facets_exact(&self) -> bool {
        false
    }

    /// Surface area in object space, for shapes that can be sampled as emitters
    /// (the path tracer's next-event estimation and instant radiosity).
    fn area(&self) -> Option<f32> {
        None
    }

    /// A point uniformly distributed by area on the surface (object space) and its unit
    /// normal (outward), from `u` in the unit square. `None` when unsupported; such
    /// emitters are then found only by rays that hit them.
    fn sample_surface(&self, u: glam::Vec2) -> Option<(Vec3, Vec3)> {
        let _ = u;
        None
    }

    /// Warnings the shape gathered while rays were cast (for example an implicit
    /// surface whose given Lipschitz bound proved too small), each returned once, for
    /// the renderer to print after a render.
    fn take_warnings(&self) -> Vec<String> {
        Vec::new()
    }
}
