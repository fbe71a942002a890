//! Parametric surfaces `p(u, v) = (x(u, v), y(u, v), z(u, v))` over a rectangle of
//! `(u, v)`, each coordinate an expression (see `crate::expr`).
//!
//! Summary / public API:
//! - `ParametricSurface::parse(["cos(u)*sin(v)", "cos(v)", "sin(u)*sin(v)"],
//!   (0.0, 2.0 * PI), (0.0, PI), (64, 32)) -> Result<_, ParametricError>`: sources for x, y,
//!   z over the variables `u, v`, the u and v ranges, and the grid resolution (cells
//!   along u and v, 1..=4096 each). `ParametricSurface::new` takes parsed `Expr`s.
//! - A `Shape` (not a solid: no CSG spans); hits report `uv` normalised to [0, 1]²
//!   over the parameter rectangle, and the exact normal `∂p/∂u × ∂p/∂v` (the user's
//!   orientation) as shading normal.
//!
//! Method (documented choice): the surface is **tessellated** into a uniform grid of
//! triangles held in a `TriangleMesh` (BVH + watertight triangle test). Within the grid
//! neighbouring cells share vertices, so there are no cracks; where the parameter
//! rectangle's edges meet in space (a periodic seam like `u = 0` and `u = 2π` of a sphere,
//! or a pole where a whole edge maps to one point) the boundary vertices are snapped to
//! bit-identical positions (within 1e-6 of the surface's size), so the watertight test
//! leaves no gap there either, and triangles collapsed to a line are dropped. At a hit
//! the parameters are refined by Gauss-Newton on `|p(u, v) - hit|²` from the
//! interpolated ones, and the normal is evaluated exactly there from forward-mode
//! derivatives (dual numbers). The price is the geometric deviation of the flat triangles,
//! measured at build time ([`ParametricSurface::max_deviation`]), which shrinks as
//! `1 / resolution²`.

// `!(a < b)` comparisons are deliberate: they are also true when a value is NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use crate::expr::{Expr, ExprError};
use crate::mesh::{MeshError, TriangleMesh};
use crate::shape::{Facets, Hit, Shape, Span};
use glam::{DVec3, Vec2, Vec3};
use irradia_core::{Aabb, Ray};
use std::collections::HashMap;

/// Why a parametric surface could not be built.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ParametricError {
    #[error("{coordinate}(u, v): {error}")]
    Expr {
        coordinate: &'static str,
        error: ExprError,
    },
    #[error("the {which} range must be finite with min < max, got [{min}, {max}]")]
    BadRange {
        which: &'static str,
        min: f64,
        max: f64,
    },
    #[error("the resolution must be 1..=4096 cells along u and v, got {0} x {1}")]
    BadResolution(u32, u32),
    #[error("the surface is not finite at u = {u}, v = {v}")]
    NotFinite { u: f64, v: f64 },
    #[error("tessellation: {0}")]
    Mesh(#[from] MeshError),
}

/// The map `(u, v) -> p` and its derivatives.
#[derive(Clone, Debug)]
struct Mapping {
    coords: [Expr; 3],
    u_range: (f64, f64),
    v_range: (f64, f64),
    /// Size of the surface (its bounding-box diagonal), for relative tolerances.
    scale: f64,
}

#[derive(Clone, Debug)]
pub struct ParametricSurface {
    map: Mapping,
    resolution: (u32, u32),
    mesh: TriangleMesh,
    max_deviation: f32,
}

const NAMES: [&str; 3] = ["x", "y", "z"];

impl ParametricSurface {
    /// Parses the x, y and z expressions over `u, v`.
    pub fn parse(
        sources: [&str; 3],
        u_range: (f64, f64),
        v_range: (f64, f64),
        resolution: (u32, u32),
    ) -> Result<Self, ParametricError> {
        let mut exprs = Vec::with_capacity(3);
        for (k, src) in sources.iter().enumerate() {
            exprs.push(
                Expr::parse(src, &["u", "v"]).map_err(|error| ParametricError::Expr {
                    coordinate: NAMES[k],
                    error,
                })?,
            );
        }
        let [x, y, z]: [Expr; 3] = exprs.try_into().expect("three expressions");
        Self::new([x, y, z], u_range, v_range, resolution)
    }

    /// From parsed expressions over exactly the variables `u, v`.
    pub fn new(
        coords: [Expr; 3],
        u_range: (f64, f64),
        v_range: (f64, f64),
        resolution: (u32, u32),
    ) -> Result<Self, ParametricError> {
        for (k, e) in coords.iter().enumerate() {
            if e.variables() != ["u", "v"] {
                return Err(ParametricError::Expr {
                    coordinate: NAMES[k],
                    error: ExprError::new(1, "the expression must be over the variables u, v"),
                });
            }
        }
        for (which, (min, max)) in [("u", u_range), ("v", v_range)] {
            if !(min.is_finite() && max.is_finite() && min < max) {
                return Err(ParametricError::BadRange { which, min, max });
            }
        }
        let (nu, nv) = resolution;
        if !(1..=4096).contains(&nu) || !(1..=4096).contains(&nv) {
            return Err(ParametricError::BadResolution(nu, nv));
        }
        let mut map = Mapping {
            coords,
            u_range,
            v_range,
            scale: 1.0,
        };
        let (mesh, max_deviation) = map.tessellate(resolution)?;
        Ok(Self {
            map,
            resolution,
            mesh,
            max_deviation,
        })
    }

    /// The point at parameters `(u, v)`.
    pub fn point(&self, u: f64, v: f64) -> DVec3 {
        self.map.point(u, v)
    }

    /// Point and partial derivatives `∂p/∂u`, `∂p/∂v` (forward-mode dual numbers).
    pub fn derivatives(&self, u: f64, v: f64) -> (DVec3, DVec3, DVec3) {
        self.map.derivatives(u, v)
    }

    /// Unit normal `∂p/∂u × ∂p/∂v` at `(u, v)`; where it vanishes (a pole) the limit
    /// is taken by stepping towards the centre of the parameter rectangle.
    pub fn normal(&self, u: f64, v: f64) -> DVec3 {
        self.map.normal(u, v)
    }

    pub fn mesh(&self) -> &TriangleMesh {
        &self.mesh
    }

    pub fn resolution(&self) -> (u32, u32) {
        self.resolution
    }

    /// Largest distance measured between a triangle's centre and the surface point at
    /// the same parameters.
    pub fn max_deviation(&self) -> f32 {
        self.max_deviation
    }
}

impl Mapping {
    /// The point at parameters `(u, v)`.
    pub fn point(&self, u: f64, v: f64) -> DVec3 {
        DVec3::new(
            self.coords[0].eval(&[u, v]),
            self.coords[1].eval(&[u, v]),
            self.coords[2].eval(&[u, v]),
        )
    }

    /// Point and partial derivatives `∂p/∂u`, `∂p/∂v` (forward-mode dual numbers).
    pub fn derivatives(&self, u: f64, v: f64) -> (DVec3, DVec3, DVec3) {
        let mut p = DVec3::ZERO;
        let mut du = DVec3::ZERO;
        let mut dv = DVec3::ZERO;
        for k in 0..3 {
            let (val, g) = self.coords[k].eval_gradient(&[u, v]);
            p[k] = val;
            du[k] = g[0];
            dv[k] = g[1];
        }
        (p, du, dv)
    }

    /// Unit normal `∂p/∂u × ∂p/∂v` at `(u, v)`; where it vanishes (a pole, a cusp) the
    /// limit is taken by stepping towards the centre of the parameter rectangle.
    pub fn normal(&self, u: f64, v: f64) -> DVec3 {
        let (uc, vc) = (
            0.5 * (self.u_range.0 + self.u_range.1),
            0.5 * (self.v_range.0 + self.v_range.1),
        );
        let scale = self.scale;
        for step in [0.0, 1e-7, 1e-5, 1e-3, 1e-2] {
            let (uu, vv) = (u + (uc - u) * step, v + (vc - v) * step);
            let (_, du, dv) = self.derivatives(uu, vv);
            let n = du.cross(dv);
            let (ru, rv) = (
                self.u_range.1 - self.u_range.0,
                self.v_range.1 - self.v_range.0,
            );
            // Relative to the size of the surface per unit parameter.
            if n.length() > 1e-9 * scale * scale / (ru * rv) && n.is_finite() {
                return n.normalize();
            }
        }
        DVec3::Y
    }

    fn param(&self, s: f64, t: f64) -> (f64, f64) {
        (
            self.u_range.0 + (self.u_range.1 - self.u_range.0) * s,
            self.v_range.0 + (self.v_range.1 - self.v_range.0) * t,
        )
    }

    fn tessellate(
        &mut self,
        resolution: (u32, u32),
    ) -> Result<(TriangleMesh, f32), ParametricError> {
        let (nu, nv) = (resolution.0 as usize, resolution.1 as usize);
        let mut positions = Vec::with_capacity((nu + 1) * (nv + 1));
        let mut uvs = Vec::with_capacity(positions.capacity());
        for i in 0..=nu {
            for j in 0..=nv {
                let (s, t) = (i as f64 / nu as f64, j as f64 / nv as f64);
                let (u, v) = self.param(s, t);
                let p = self.point(u, v);
                if !p.is_finite() {
                    return Err(ParametricError::NotFinite { u, v });
                }
                positions.push(p);
                uvs.push(Vec2::new(s as f32, t as f32));
            }
        }
        let idx = |i: usize, j: usize| i * (nv + 1) + j;
        // Snap boundary vertices that meet in space to one bit-identical position.
        let (lo, hi) = positions.iter().fold(
            (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
            |(lo, hi), p| (lo.min(*p), hi.max(*p)),
        );
        self.scale = (hi - lo).length().max(1e-300);
        let eps = 1e-6 * self.scale;
        let mut positions: Vec<Vec3> = positions.iter().map(|p| p.as_vec3()).collect();
        let boundary: Vec<usize> = (0..=nu)
            .flat_map(|i| (0..=nv).map(move |j| (i, j)))
            .filter(|&(i, j)| i == 0 || i == nu || j == 0 || j == nv)
            .map(|(i, j)| idx(i, j))
            .collect();
        let cell = |p: Vec3| {
            let q = (p.as_dvec3() / eps).floor();
            (q.x as i64, q.y as i64, q.z as i64)
        };
        let mut grid: HashMap<(i64, i64, i64), Vec<usize>> = HashMap::new();
        for &b in &boundary {
            let p = positions[b];
            let c = cell(p);
            let mut snapped = None;
            'search: for dx in -1..=1 {
                for dy in -1..=1 {
                    for dz in -1..=1 {
                        let key = (
                            c.0.saturating_add(dx),
                            c.1.saturating_add(dy),
                            c.2.saturating_add(dz),
                        );
                        if let Some(list) = grid.get(&key) {
                            for &o in list {
                                if (positions[o] - p).length() as f64 <= eps {
                                    snapped = Some(positions[o]);
                                    break 'search;
                                }
                            }
                        }
                    }
                }
            }
            match snapped {
                Some(q) => positions[b] = q,
                None => grid.entry(c).or_default().push(b),
            }
        }
        let mut normals = Vec::with_capacity(positions.len());
        for i in 0..=nu {
            for j in 0..=nv {
                let (u, v) = self.param(i as f64 / nu as f64, j as f64 / nv as f64);
                normals.push(self.normal(u, v).as_vec3());
            }
        }
        let mut indices = Vec::with_capacity(2 * nu * nv);
        let mut deviation = 0.0f64;
        for i in 0..nu {
            for j in 0..nv {
                for tri in [
                    [idx(i, j), idx(i + 1, j), idx(i + 1, j + 1)],
                    [idx(i, j), idx(i + 1, j + 1), idx(i, j + 1)],
                ] {
                    let [a, b, c] = tri.map(|k| positions[k]);
                    if a == b || b == c || a == c {
                        continue;
                    }
                    let centre = (a.as_dvec3() + b.as_dvec3() + c.as_dvec3()) / 3.0;
                    let st = (uvs[tri[0]] + uvs[tri[1]] + uvs[tri[2]]) / 3.0;
                    let (u, v) = self.param(st.x as f64, st.y as f64);
                    deviation = deviation.max((self.point(u, v) - centre).length());
                    indices.push(tri.map(|k| k as u32));
                }
            }
        }
        let mesh = TriangleMesh::new(positions, indices, Some(normals), Some(uvs))?;
        Ok((mesh, deviation as f32))
    }

    /// Gauss-Newton on `|p(u, v) - target|²` from `(u, v)`, clamped to the rectangle;
    /// steps that do not reduce the distance are rejected.
    fn refine(&self, target: DVec3, mut u: f64, mut v: f64) -> (f64, f64) {
        let mut dist = (self.point(u, v) - target).length_squared();
        for _ in 0..4 {
            let (p, du, dv) = self.derivatives(u, v);
            let r = target - p;
            let (a, b, c) = (du.dot(du), du.dot(dv), dv.dot(dv));
            let det = a * c - b * b;
            if !(det.abs() > 1e-12 * (a * c).max(f64::MIN_POSITIVE)) {
                break;
            }
            let (ru, rv) = (du.dot(r), dv.dot(r));
            let nu = (u + (c * ru - b * rv) / det).clamp(self.u_range.0, self.u_range.1);
            let nv = (v + (a * rv - b * ru) / det).clamp(self.v_range.0, self.v_range.1);
            let nd = (self.point(nu, nv) - target).length_squared();
            if !(nd < dist) {
                break;
            }
            (u, v, dist) = (nu, nv, nd);
        }
        (u, v)
    }
}

impl Shape for ParametricSurface {
    fn kind(&self) -> &'static str {
        "parametric"
    }

    fn bounds(&self) -> Aabb {
        self.mesh.bounds()
    }

    fn intersect(&self, ray: &Ray, t_max: f32) -> Option<Hit> {
        let mut h = self.mesh.intersect(ray, t_max)?;
        let m = &self.map;
        let (u, v) = m.param(h.uv.x as f64, h.uv.y as f64);
        let (u, v) = m.refine(h.point.as_dvec3(), u, v);
        let n = m.normal(u, v).as_vec3();
        if n.is_finite() {
            h.shading_normal = if n.dot(h.normal) < 0.0 { -n } else { n };
        }
        h.uv = Vec2::new(
            ((u - m.u_range.0) / (m.u_range.1 - m.u_range.0)) as f32,
            ((v - m.v_range.0) / (m.v_range.1 - m.v_range.0)) as f32,
        );
        h.prim = 0;
        Some(h)
    }

    fn occluded(&self, ray: &Ray, t_max: f32) -> bool {
        self.mesh.occluded(ray, t_max)
    }

    fn is_solid(&self) -> bool {
        false
    }

    fn spans(&self, _ray: &Ray, _out: &mut Vec<Span>) {}

    fn facets(&self, _detail: u32) -> Option<Facets> {
        self.mesh.facets(0)
    }
}
