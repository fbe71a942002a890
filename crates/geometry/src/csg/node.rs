//! The CSG node: a `Shape` whose operands are placed shapes (`Instance`s) or other CSG
//! nodes, combined by spans (see `combine`). Operands are tested against the ray with
//! their bounds first, and only over the window of `t` that can still matter, so that
//! e.g. a difference never asks the subtracted solid about rays that miss the first.
//!
//! **Leaves** are the operands that are not CSG nodes, numbered depth first (the first
//! operand's leaves first). `Hit::leaf` and `Boundary::leaf` carry that number so a
//! scene can give each leaf its own material; [`Csg::leaf_paths`] says which operand
//! (by index at each level) each leaf is.

use super::ball::Ball;
use super::combine::combine;
use super::op::CsgOp;
use super::scratch::{with_buffers, Buffers};
use super::window::SlabRay;
use crate::instance::Instance;
use crate::shape::{Boundary, Hit, Shape, Span};
use crate::shapes::ShapeError;
use glam::Affine3A;
use irradia_core::{Aabb, Ray};
use std::sync::Arc;

/// One operand as given to [`Csg::new`].
#[derive(Clone, Debug)]
pub enum CsgOperand {
    /// A solid shape placed by a transform: one leaf.
    Shape(Instance),
    /// A CSG node placed by a transform (object to parent): its leaves.
    Node(Csg, Affine3A),
}

impl CsgOperand {
    /// A leaf: `shape` placed by the object-to-parent map `to_parent`.
    pub fn shape(shape: Arc<dyn Shape>, to_parent: Affine3A) -> Self {
        CsgOperand::Shape(Instance::new(shape, to_parent))
    }
    /// A nested node placed by `to_parent`.
    pub fn node(csg: Csg, to_parent: Affine3A) -> Self {
        CsgOperand::Node(csg, to_parent)
    }
}

impl From<Instance> for CsgOperand {
    fn from(i: Instance) -> Self {
        CsgOperand::Shape(i)
    }
}

impl From<Csg> for CsgOperand {
    fn from(c: Csg) -> Self {
        CsgOperand::Node(c, Affine3A::IDENTITY)
    }
}

#[derive(Clone, Debug)]
pub(super) struct Child {
    pub(super) instance: Instance,
    /// The node itself when the operand is a CSG node (`instance.shape` is it too), to
    /// find the surface at one of its boundaries (`resolve`).
    pub(super) node: Option<Arc<Csg>>,
    pub(super) leaf_offset: u32,
    bounds: Aabb,
    /// `instance.splits_surface()`, asked once.
    splits: bool,
}

/// A CSG node (union, intersection, difference or merge of solids): itself a solid.
#[derive(Clone, Debug)]
pub struct Csg {
    op: CsgOp,
    pub(super) children: Vec<Child>,
    leaf_paths: Vec<Vec<u32>>,
    bounds: Aabb,
    /// A union's or merge's bounding ball, when its operands are spheres placed by
    /// translations ([`Ball`]): tested before their boxes.
    ball: Option<Ball>,
}

impl Csg {
    /// Combines `operands` left to right with `op`. Errors when there are none or one
    /// of them is not a solid.
    pub fn new(op: CsgOp, operands: Vec<CsgOperand>) -> Result<Self, ShapeError> {
        if operands.is_empty() {
            return Err(ShapeError::NoOperands { op: op.name() });
        }
        let mut children = Vec::with_capacity(operands.len());
        let mut leaf_paths = Vec::new();
        for (i, operand) in operands.into_iter().enumerate() {
            let leaf_offset = leaf_paths.len() as u32;
            let (instance, node) = match operand {
                CsgOperand::Shape(inst) => {
                    if !inst.shape.is_solid() {
                        return Err(ShapeError::NotSolid {
                            kind: inst.shape.kind(),
                        });
                    }
                    leaf_paths.push(vec![i as u32]);
                    (inst, None)
                }
                CsgOperand::Node(csg, to_parent) => {
                    for p in &csg.leaf_paths {
                        let mut path = vec![i as u32];
                        path.extend_from_slice(p);
                        leaf_paths.push(path);
                    }
                    let node = Arc::new(csg);
                    (Instance::new(node.clone(), to_parent), Some(node))
                }
            };
            // An untransformed operand keeps its own bounds: Instance widens a
            // half-infinite box (a plane's) to the infinite one.
            let bounds = if *instance.to_world() == Affine3A::IDENTITY {
                instance.shape.bounds()
            } else {
                instance.bounds()
            };
            children.push(Child {
                bounds,
                splits: instance.splits_surface(),
                instance,
                node,
                leaf_offset,
            });
        }
        let bounds = match op {
            CsgOp::Union | CsgOp::Merge => {
                children.iter().fold(Aabb::EMPTY, |b, c| b.union(c.bounds))
            }
            CsgOp::Intersection => children
                .iter()
                .fold(Aabb::INFINITE, |b, c| b.intersection(c.bounds)),
            CsgOp::Difference => children[0].bounds,
        };
        let ball = match op {
            CsgOp::Union | CsgOp::Merge if bounds.is_finite() => Ball::around(
                bounds.center(),
                children.iter().map(|c| {
                    let sphere = match c.node {
                        None => c.instance.shape.as_sphere().map(|s| (s.center, s.radius)),
                        Some(_) => None,
                    };
                    (sphere, c.instance.to_world())
                }),
            ),
            _ => None,
        };
        Ok(Self {
            op,
            children,
            leaf_paths,
            bounds,
            ball,
        })
    }

    pub fn union(operands: Vec<CsgOperand>) -> Result<Self, ShapeError> {
        Self::new(CsgOp::Union, operands)
    }
    pub fn intersection(operands: Vec<CsgOperand>) -> Result<Self, ShapeError> {
        Self::new(CsgOp::Intersection, operands)
    }
    pub fn difference(operands: Vec<CsgOperand>) -> Result<Self, ShapeError> {
        Self::new(CsgOp::Difference, operands)
    }
    pub fn merge(operands: Vec<CsgOperand>) -> Result<Self, ShapeError> {
        Self::new(CsgOp::Merge, operands)
    }

    pub fn op(&self) -> CsgOp {
        self.op
    }

    /// How many leaves (non-CSG operands, at any depth) the tree has.
    pub fn leaf_count(&self) -> u32 {
        self.leaf_paths.len() as u32
    }

    /// For each leaf, in depth-first order (the numbering of `Hit::leaf`), the operand
    /// index at each level from this node down: `[1, 0]` is the first operand of this
    /// node's second operand.
    pub fn leaf_paths(&self) -> &[Vec<u32>] {
        &self.leaf_paths
    }

    /// The operand's spans that overlap `[lo, hi]`, leaves renumbered, into `out`.
    /// `bounds_known` says the caller has already found the operand's bounds to
    /// overlap `[lo, hi]` (the same test, so it is not repeated).
    ///
    /// With `SURFACES` false only the parameters are computed ([`Shape::spans_t`]), and
    /// each boundary is named so that its surface can be found afterwards
    /// (`resolve`): a leaf operand's boundaries get `prim` = their place in the leaf's
    /// own list (enter of span `i` is `2i`, its exit `2i + 1`), `leaf` 0 (before the
    /// renumbering) and the normal's `x` 1, which `combine` negates wherever it would
    /// negate the real normal, so that its sign says whether to.
    #[inline]
    #[allow(clippy::too_many_arguments)]
    fn operand_spans<const SURFACES: bool>(
        &self,
        c: &Child,
        ray: &Ray,
        slab: &SlabRay,
        lo: f32,
        hi: f32,
        bounds_known: bool,
        out: &mut Vec<Span>,
    ) {
        out.clear();
        if !bounds_known && !slab.overlaps(&c.bounds, lo, hi) {
            return;
        }
        // A leaf's parameter-only boundaries are named by their place in its own list
        // (before any is dropped), for `resolve`.
        let name = !SURFACES && c.node.is_none();
        if SURFACES {
            c.instance.spans(ray, out);
        } else {
            c.instance.spans_t(ray, out);
        }
        // Keep the spans that overlap the window, named and with leaves renumbered,
        // in place (one pass).
        let mut kept = 0;
        for i in 0..out.len() {
            let mut s = out[i];
            if s.exit.t >= lo && s.enter.t <= hi {
                if name {
                    for (k, b) in [&mut s.enter, &mut s.exit].into_iter().enumerate() {
                        b.prim = (2 * i + k) as u32;
                        b.leaf = 0;
                        // Only `x`: `y` and `uv` are the leaf's
                        // ([`Shape::span_boundary_of`]).
                        b.normal.x = 1.0;
                    }
                }
                s.enter.leaf += c.leaf_offset;
                s.exit.leaf += c.leaf_offset;
                out[kept] = s;
                kept += 1;
            }
        }
        out.truncate(kept);
    }

    /// The node's spans that overlap `[lo, hi]` (exact inside the window), in `b.acc`;
    /// with `SURFACES` false, only their parameters (see `operand_spans`).
    fn collect<const SURFACES: bool>(&self, ray: &Ray, lo: f32, hi: f32, b: &mut Buffers) {
        b.acc.clear();
        let slab = SlabRay::new(ray);
        let narrowing = matches!(self.op, CsgOp::Intersection | CsgOp::Difference);
        // An intersection tests every operand's bounds first (over the whole window,
        // so the first operand's test need not be repeated).
        let first_known = self.op == CsgOp::Intersection;
        if first_known
            && !self
                .children
                .iter()
                .all(|c| slab.overlaps(&c.bounds, lo, hi))
        {
            return;
        }
        let (mut lo, mut hi) = (lo, hi);
        let mut children = self.children.iter();
        let first = children.next().expect("a CSG node has operands");
        self.operand_spans::<SURFACES>(first, ray, &slab, lo, hi, first_known, &mut b.acc);
        for c in children {
            if narrowing {
                // Nothing outside the current result can come back in.
                match (b.acc.first(), b.acc.last()) {
                    (Some(f), Some(l)) => {
                        lo = lo.max(f.enter.t);
                        hi = hi.min(l.exit.t);
                    }
                    _ => return,
                }
            }
            self.operand_spans::<SURFACES>(c, ray, &slab, lo, hi, false, &mut b.operand);
            if b.operand.is_empty() {
                if self.op == CsgOp::Intersection {
                    b.acc.clear();
                    return;
                }
                continue;
            }
            if b.acc.is_empty() && !narrowing {
                std::mem::swap(&mut b.acc, &mut b.operand);
                continue;
            }
            b.tmp.clear();
            combine(self.op, &b.acc, &b.operand, &mut b.tmp);
            std::mem::swap(&mut b.acc, &mut b.tmp);
        }
    }

    /// The first boundary with `0 < t < t_max` of the combined spans, with its surface
    /// (normal, uv, primitive, leaf). The spans are combined by their parameters alone
    /// and the surface is computed for that one boundary only (`resolve`): the same
    /// boundary, bit for bit, as combining spans with every surface computed.
    fn first_boundary(&self, ray: &Ray, t_max: f32) -> Option<Boundary> {
        with_buffers(|b| {
            self.collect::<false>(ray, 0.0, t_max, b);
            let e = b
                .acc
                .iter()
                .flat_map(|s| [s.enter, s.exit])
                .find(|e| e.t > 0.0 && e.t < t_max)?;
            Some(self.resolve(ray, &e, &mut b.tmp))
        })
    }

    /// Whether the combined spans have a boundary with `0 < t < t_max` (no surfaces).
    fn any_boundary(&self, ray: &Ray, t_max: f32) -> bool {
        with_buffers(|b| {
            self.collect::<false>(ray, 0.0, t_max, b);
            b.acc
                .iter()
                .flat_map(|s| [s.enter.t, s.exit.t])
                .any(|t| t > 0.0 && t < t_max)
        })
    }

    /// POV-Ray's union: the nearest hit of any operand. Operands that split their
    /// hits ([`Shape::splits_surface`]) give their parameter first and only the
    /// winner's surface is computed: the same hit as the nearest of whole hits.
    fn nearest_operand_hit(&self, ray: &Ray, t_max: f32) -> Option<Hit> {
        let mut best: Option<Hit> = None;
        let mut param = None;
        let mut t_max = t_max;
        let slab = SlabRay::new(ray);
        for c in &self.children {
            if !slab.overlaps(&c.bounds, 0.0, t_max) {
                continue;
            }
            if c.splits {
                if let Some(t) = c.instance.nearest_t(ray, t_max) {
                    t_max = t as f32;
                    param = Some((c, t));
                }
            } else if let Some(mut h) = c.instance.intersect(ray, t_max) {
                h.leaf += c.leaf_offset;
                t_max = h.t;
                best = Some(h);
                param = None;
            }
        }
        match param {
            Some((c, t)) => {
                let mut h = c.instance.surface_at(ray, t, true);
                h.leaf += c.leaf_offset;
                Some(h)
            }
            None => best,
        }
    }
}

/// The hit at a span boundary. The point is `o + t d` evaluated in f64 from the f32
/// parameter; its error bound covers rounding `t` to f32 and the point to f32, and the
/// rounding of the ray carried into an operand's object space (a few ulps of `o` and
/// of `t d`, Instance's own bound).
fn hit_at(ray: &Ray, b: &Boundary) -> Hit {
    let p = (ray.origin.as_dvec3() + ray.dir.as_dvec3() * b.t as f64).as_vec3();
    let mut h = Hit::new(b.t, p, b.normal, b.uv);
    h.prim = b.prim;
    h.leaf = b.leaf;
    h.error = (ray.origin.abs().max_element()
        + (ray.dir * b.t).abs().max_element()
        + p.abs().max_element())
        * 4.0
        * f32::EPSILON;
    h
}

impl Shape for Csg {
    fn take_warnings(&self) -> Vec<String> {
        self.children
            .iter()
            .flat_map(|c| c.instance.shape.take_warnings())
            .collect()
    }

    fn kind(&self) -> &'static str {
        "csg"
    }

    fn bounds(&self) -> Aabb {
        self.bounds
    }

    fn intersect(&self, ray: &Ray, t_max: f32) -> Option<Hit> {
        if self.ball.is_some_and(|b| !b.may_meet(ray)) {
            return None;
        }
        if self.op == CsgOp::Union {
            return self.nearest_operand_hit(ray, t_max);
        }
        let b = self.first_boundary(ray, t_max)?;
        Some(hit_at(ray, &b))
    }

    fn occluded(&self, ray: &Ray, t_max: f32) -> bool {
        if self.ball.is_some_and(|b| !b.may_meet(ray)) {
            return false;
        }
        if self.op == CsgOp::Union {
            let slab = SlabRay::new(ray);
            return self
                .children
                .iter()
                .any(|c| slab.overlaps(&c.bounds, 0.0, t_max) && c.instance.occluded(ray, t_max));
        }
        self.any_boundary(ray, t_max)
    }

    fn is_solid(&self) -> bool {
        true
    }

    fn spans(&self, ray: &Ray, out: &mut Vec<Span>) {
        with_buffers(|b| {
            self.collect::<true>(ray, f32::NEG_INFINITY, f32::INFINITY, b);
            out.extend_from_slice(&b.acc);
        })
    }

    /// The spans' parameters, each boundary named as `operand_spans` says (its `prim`
    /// and the sign of its normal's `x` are this node's, for `resolve`).
    fn spans_t(&self, ray: &Ray, out: &mut Vec<Span>) {
        with_buffers(|b| {
            self.collect::<false>(ray, f32::NEG_INFINITY, f32::INFINITY, b);
            out.extend_from_slice(&b.acc);
        })
    }
}
