//! Mitsuba 3's `sdfgrid`: a signed distance field sampled on a grid of `nx × ny × nz`
//! values spanning `[0, 1]³` of the shape's own frame (value `(i, j, k)` at
//! `(i / (nx - 1), j / (ny - 1), k / (nz - 1))`), interpolated trilinearly. The surface
//! is where the interpolated value is zero; the solid is where it is negative.
//!
//! Rays walk the cells that can hold the surface (a cell whose eight values do not all
//! have one strict sign; trilinear interpolation stays between its corner values) with
//! a 3D DDA (Amanatides and Woo 1987). Inside a cell the field along the ray is a cubic
//! in `t`; its roots are found exactly, in f64, by splitting the segment at the
//! cubic's turning points and bisecting each monotone piece that changes sign.
//!
//! Normals follow Mitsuba: the geometric normal is the gradient of the trilinear field
//! in the hit cell; the shading normal is either that (`analytic`) or Mitsuba's default
//! `smooth` normal (Hansson-Söderlund, Evans and Akenine-Möller, "Ray Tracing of Signed
//! Distance Function Grids", JCGT 2022: the normalised gradients of the eight cells
//! around the nearest grid point, extended to the hit point and blended trilinearly).
//! As in Mitsuba, the shape has no texture coordinates (uv is 0) and cannot be sampled
//! as an area emitter.
//!
//! The field is a closed solid (usable in CSG) when every value on the grid's boundary
//! is positive; otherwise the surface may end at the grid's faces and it is an open
//! surface.

use crate::shape::{Boundary, Hit, Shape, Span};
use crate::shapes::shape_error::ShapeError;
use glam::{DVec3, IVec3, Vec2, Vec3};
use irradia_core::{Aabb, Ray};

/// How the shading normal is computed (Mitsuba's `normals` parameter).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum SdfNormals {
    /// Blended gradients of the neighbouring cells: continuous across cells.
    #[default]
    Smooth,
    /// The gradient of the hit cell (equal to the geometric normal).
    Analytic,
}

/// The largest grid accepted, in values (256³).
pub const MAX_SDF_VALUES: usize = 1 << 24;

#[derive(Clone, Debug)]
pub struct SdfGrid {
    n: [usize; 3],
    values: Vec<f32>,
    /// Cells per axis (`n - 1`), as f64: grid coordinates are object coordinates × res.
    res: DVec3,
    /// Per cell: 0 all values positive, 1 all negative, 2 may hold the surface.
    cell_kind: Vec<u8>,
    /// The range of cells that may hold the surface, `[lo, hi)`.
    lo: IVec3,
    hi: IVec3,
    closed: bool,
    normals: SdfNormals,
}

/// A polynomial `c[0] + c[1] s + c[2] s² + c[3] s³`.
type Cubic = [f64; 4];

fn eval(c: &Cubic, s: f64) -> f64 {
    ((c[3] * s + c[2]) * s + c[1]) * s + c[0]
}

impl SdfGrid {
    /// The grid of `n = [nx, ny, nz]` values, x fastest, then y, then z. Errors when a
    /// size is below 2, the count does not match, a value is not finite, the grid is
    /// larger than [`MAX_SDF_VALUES`] or no cell changes sign (there is no surface).
    pub fn new(n: [usize; 3], values: Vec<f32>, normals: SdfNormals) -> Result<Self, ShapeError> {
        if n.iter().any(|&k| k < 2) {
            return Err(ShapeError::OutOfRange {
                what: "sdfgrid",
                why: "the grid needs at least 2 values along each axis",
            });
        }
        let count = n[0].checked_mul(n[1]).and_then(|c| c.checked_mul(n[2]));
        if count.is_none_or(|c| c > MAX_SDF_VALUES) {
            return Err(ShapeError::OutOfRange {
                what: "sdfgrid",
                why: "the grid is larger than 256³ values",
            });
        }
        if count != Some(values.len()) {
            return Err(ShapeError::OutOfRange {
                what: "sdfgrid",
                why: "the number of values is not nx · ny · nz",
            });
        }
        if values.iter().any(|v| !v.is_finite()) {
            return Err(ShapeError::NotFinite {
                what: "an sdfgrid value",
            });
        }
        let cells = [n[0] - 1, n[1] - 1, n[2] - 1];
        let mut cell_kind = vec![0u8; cells[0] * cells[1] * cells[2]];
        let (mut lo, mut hi) = (IVec3::splat(i32::MAX), IVec3::splat(i32::MIN));
        let at = |x: usize, y: usize, z: usize| values[x + n[0] * (y + n[1] * z)];
        for z in 0..cells[2] {
            for y in 0..cells[1] {
                for x in 0..cells[0] {
                    let mut pos = true;
                    let mut neg = true;
                    for c in 0..8 {
                        let v = at(x + (c & 1), y + ((c >> 1) & 1), z + (c >> 2));
                        pos &= v > 0.0;
                        neg &= v < 0.0;
                    }
                    let kind = if pos {
                        0
                    } else if neg {
                        1
                    } else {
                        2
                    };
                    cell_kind[x + cells[0] * (y + cells[1] * z)] = kind;
                    if kind == 2 {
                        let c = IVec3::new(x as i32, y as i32, z as i32);
                        lo = lo.min(c);
                        hi = hi.max(c + IVec3::ONE);
                    }
                }
            }
        }
        if lo.x == i32::MAX {
            return Err(ShapeError::OutOfRange {
                what: "sdfgrid",
                why: "no cell changes sign: the grid holds no surface (the solid is where the values are negative)",
            });
        }
        let mut closed = true;
        for z in 0..n[2] {
            for y in 0..n[1] {
                for x in 0..n[0] {
                    let edge = x == 0
                        || y == 0
                        || z == 0
                        || x == n[0] - 1
                        || y == n[1] - 1
                        || z == n[2] - 1;
                    if edge && at(x, y, z) <= 0.0 {
                        closed = false;
                    }
                }
            }
        }
        Ok(Self {
            n,
            values,
            res: DVec3::new(cells[0] as f64, cells[1] as f64, cells[2] as f64),
            cell_kind,
            lo,
            hi,
            closed,
            normals,
        })
    }

    /// The grid sizes `[nx, ny, nz]`.
    pub fn dims(&self) -> [usize; 3] {
        self.n
    }

    /// Whether the field is positive on the whole boundary (a closed solid).
    pub fn is_closed(&self) -> bool {
        self.closed
    }

    #[inline]
    fn value(&self, x: i32, y: i32, z: i32) -> f64 {
        let x = x.clamp(0, self.n[0] as i32 - 1) as usize;
        let y = y.clamp(0, self.n[1] as i32 - 1) as usize;
        let z = z.clamp(0, self.n[2] as i32 - 1) as usize;
        self.values[x + self.n[0] * (y + self.n[1] * z)] as f64
    }

    /// The eight values of cell `c`, index bit 0 = x, bit 1 = y, bit 2 = z.
    fn corners(&self, c: IVec3) -> [f64; 8] {
        std::array::from_fn(|k| {
            let k = k as i32;
            self.value(c.x + (k & 1), c.y + ((k >> 1) & 1), c.z + (k >> 2))
        })
    }

    fn kind(&self, c: IVec3) -> u8 {
        let cx = self.n[0] - 1;
        let cy = self.n[1] - 1;
        self.cell_kind[c.x as usize + cx * (c.y as usize + cy * c.z as usize)]
    }

    /// The trilinear field at object point `p` (clamped to the grid).
    pub fn distance(&self, p: Vec3) -> f32 {
        let g = (p.as_dvec3() * self.res).clamp(DVec3::ZERO, self.res);
        let c = self.cell_of(g);
        let f = g - c.as_dvec3();
        trilinear(&self.corners(c), f) as f32
    }

    /// The cell holding grid point `g` (the last cell for points on the far faces).
    fn cell_of(&self, g: DVec3) -> IVec3 {
        let max = IVec3::new(
            self.n[0] as i32 - 2,
            self.n[1] as i32 - 2,
            self.n[2] as i32 - 2,
        );
        g.floor().as_ivec3().clamp(IVec3::ZERO, max)
    }

    /// Trilinear field at object point `p`, clamping outside the grid (as Mitsuba's
    /// texture lookups do).
    fn field(&self, p: DVec3) -> f64 {
        let g = (p * self.res).clamp(DVec3::ZERO, self.res);
        let c = self.cell_of(g);
        trilinear(&self.corners(c), g - c.as_dvec3())
    }

    /// Mitsuba's `voxel_grad`: the gradient (object units) of cell `c`'s trilinear
    /// field, evaluated along lines through `p`: `(F(x0 + h, y, z) - F(x0, y, z)) / h`.
    fn voxel_grad(&self, p: DVec3, c: IVec3) -> DVec3 {
        let h = DVec3::ONE / self.res;
        let p0 = c.as_dvec3() * h;
        let mut g = DVec3::ZERO;
        for axis in 0..3 {
            let (mut a, mut b) = (p, p);
            a[axis] = p0[axis] + h[axis];
            b[axis] = p0[axis];
            g[axis] = (self.field(a) - self.field(b)) / h[axis];
        }
        g
    }

    /// The analytic gradient at `p` (Mitsuba's `sdf_grad`: the cell holding `p`).
    fn gradient(&self, p: DVec3) -> DVec3 {
        let g = (p * self.res).clamp(DVec3::ZERO, self.res);
        self.voxel_grad(p, self.cell_of(g))
    }

    /// Mitsuba's smooth shading normal at `p` (object space, unnormalised).
    fn smooth_normal(&self, p: DVec3) -> DVec3 {
        let scaled = p * self.res;
        let v000 = scaled.round().as_ivec3() - IVec3::ONE;
        let mut n = [DVec3::ZERO; 8];
        let mut valid = [false; 8];
        for (k, (nk, vk)) in n.iter_mut().zip(valid.iter_mut()).enumerate() {
            let k = k as i32;
            let c = v000 + IVec3::new(k & 1, (k >> 1) & 1, k >> 2);
            *vk = c.cmpge(IVec3::ZERO).all();
            if *vk {
                *nk = self.voxel_grad(p, c).normalize_or_zero();
            }
        }
        let v111 = v000 + IVec3::ONE;
        let mut w = scaled - v111.as_dvec3() + DVec3::splat(0.5);
        // An axis whose lower (upper) four cells are all outside the grid takes the
        // other side's weight fully.
        for axis in 0..3 {
            let bit = 1 << axis;
            let low = (0..8).filter(|k| k & bit == 0).all(|k| !valid[k]);
            let high = (0..8).filter(|k| k & bit != 0).all(|k| !valid[k]);
            if low {
                w[axis] = 1.0;
            }
            if high {
                w[axis] = 0.0;
            }
        }
        let mut out = DVec3::ZERO;
        for (k, nk) in n.iter().enumerate() {
            let wx = if k & 1 == 0 { 1.0 - w.x } else { w.x };
            let wy = if k & 2 == 0 { 1.0 - w.y } else { w.y };
            let wz = if k & 4 == 0 { 1.0 - w.z } else { w.z };
            out += *nk * (wx * wy * wz);
        }
        out
    }

    /// The cubic of the field along `go + gd (t0 + s)` (grid coordinates) in cell `c`.
    fn cubic(&self, c: IVec3, go: DVec3, gd: DVec3, t0: f64) -> Cubic {
        let start = go + gd * t0 - c.as_dvec3();
        let v = self.corners(c);
        let mut out = [0.0; 4];
        for (k, vk) in v.iter().enumerate() {
            // Each weight is a product of three linear factors (1 - x) or x.
            let mut p: Cubic = [*vk, 0.0, 0.0, 0.0];
            for axis in 0..3 {
                let (a, b) = if k & (1 << axis) != 0 {
                    (start[axis], gd[axis])
                } else {
                    (1.0 - start[axis], -gd[axis])
                };
                p = [
                    p[0] * a,
                    p[1] * a + p[0] * b,
                    p[2] * a + p[1] * b,
                    p[3] * a + p[2] * b,
                ];
            }
            for i in 0..4 {
                out[i] += p[i];
            }
        }
        out
    }

    /// Walks the cells along the ray over `[t_start, t_end]` and reports each sign
    /// change of the field, in order, as `(t, entering)`, until `visit` returns false.
    /// `inside` is the state at `t_start`.
    fn walk(
        &self,
        ray: &Ray,
        t_start: f64,
        t_end: f64,
        mut inside: bool,
        mut visit: impl FnMut(f64, bool, IVec3) -> bool,
    ) {
        let go = ray.origin.as_dvec3() * self.res;
        let gd = ray.dir.as_dvec3() * self.res;
        let mid = go + gd * t_start;
        let mut cell = mid.floor().as_ivec3().clamp(self.lo, self.hi - IVec3::ONE);
        let step = IVec3::new(
            if gd.x >= 0.0 { 1 } else { -1 },
            if gd.y >= 0.0 { 1 } else { -1 },
            if gd.z >= 0.0 { 1 } else { -1 },
        );
        let next_t = |cell: IVec3, axis: usize| -> f64 {
            if gd[axis] == 0.0 {
                return f64::INFINITY;
            }
            let edge = cell[axis] + if step[axis] > 0 { 1 } else { 0 };
            (edge as f64 - go[axis]) / gd[axis]
        };
        let mut t = t_start;
        while t < t_end {
            let tn = (0..3)
                .map(|a| next_t(cell, a))
                .fold(f64::INFINITY, f64::min);
            let seg_end = tn.min(t_end).max(t);
            match self.kind(cell) {
                0 => {
                    if inside && !visit(t, false, cell) {
                        return;
                    }
                    inside = false;
                }
                1 => {
                    if !inside && !visit(t, true, cell) {
                        return;
                    }
                    inside = true;
                }
                _ => {
                    let c = self.cubic(cell, go, gd, t);
                    let len = seg_end - t;
                    let mut cuts = vec![0.0];
                    // Turning points: roots of 3 c3 s² + 2 c2 s + c1 inside (0, len).
                    let (a, b, cc) = (3.0 * c[3], 2.0 * c[2], c[1]);
                    if a != 0.0 {
                        let disc = b * b - 4.0 * a * cc;
                        if disc >= 0.0 {
                            let q = -0.5 * (b + b.signum() * disc.sqrt());
                            let mut r = [q / a, if q != 0.0 { cc / q } else { 0.0 }];
                            r.sort_by(f64::total_cmp);
                            cuts.extend(r.iter().copied().filter(|&s| s > 0.0 && s < len));
                        }
                    } else if b != 0.0 {
                        let s = -cc / b;
                        if s > 0.0 && s < len {
                            cuts.push(s);
                        }
                    }
                    cuts.push(len);
                    for w in cuts.windows(2) {
                        let (s0, s1) = (w[0], w[1]);
                        let in1 = eval(&c, s1) < 0.0;
                        if in1 != inside {
                            // Bisect on the monotone piece for the sign change.
                            let (mut a, mut b) = (s0, s1);
                            for _ in 0..60 {
                                let m = 0.5 * (a + b);
                                if m <= a || m >= b {
                                    break;
                                }
                                if (eval(&c, m) < 0.0) == inside {
                                    a = m;
                                } else {
                                    b = m;
                                }
                            }
                            inside = in1;
                            if !visit(t + 0.5 * (a + b), in1, cell) {
                                return;
                            }
                        }
                    }
                }
            }
            if tn >= t_end {
                return;
            }
            // Step into the next cell along the axis whose face comes first.
            let axis = (0..3)
                .min_by(|&a, &b| next_t(cell, a).total_cmp(&next_t(cell, b)))
                .unwrap_or(0);
            cell[axis] += step[axis];
            if cell[axis] < self.lo[axis] || cell[axis] >= self.hi[axis] {
                return;
            }
            t = tn.max(t);
        }
    }

    /// The ray's parameter interval inside the box of cells that may hold the surface.
    fn clip(&self, ray: &Ray) -> Option<(f64, f64)> {
        let lo = self.lo.as_dvec3() / self.res;
        let hi = self.hi.as_dvec3() / self.res;
        let o = ray.origin.as_dvec3();
        let d = ray.dir.as_dvec3();
        let (mut t0, mut t1) = (f64::NEG_INFINITY, f64::INFINITY);
        for axis in 0..3 {
            if d[axis] == 0.0 {
                if o[axis] < lo[axis] || o[axis] > hi[axis] {
                    return None;
                }
                continue;
            }
            let (a, b) = (
                (lo[axis] - o[axis]) / d[axis],
                (hi[axis] - o[axis]) / d[axis],
            );
            t0 = t0.max(a.min(b));
            t1 = t1.min(a.max(b));
        }
        (t0 <= t1 && t0.is_finite() && t1.is_finite()).then_some((t0, t1))
    }

    fn outward(&self, p: DVec3) -> DVec3 {
        let g = self.gradient(p);
        if g.length_squared() > 0.0 {
            g.normalize()
        } else {
            DVec3::Z
        }
    }
}

fn trilinear(v: &[f64; 8], f: DVec3) -> f64 {
    let lerp = |a: f64, b: f64, t: f64| a + (b - a) * t;
    let x00 = lerp(v[0], v[1], f.x);
    let x10 = lerp(v[2], v[3], f.x);
    let x01 = lerp(v[4], v[5], f.x);
    let x11 = lerp(v[6], v[7], f.x);
    lerp(lerp(x00, x10, f.y), lerp(x01, x11, f.y), f.z)
}

impl Shape for SdfGrid {
    fn kind(&self) -> &'static str {
        "sdfgrid"
    }

    fn bounds(&self) -> Aabb {
        let lo = self.lo.as_dvec3() / self.res;
        let hi = self.hi.as_dvec3() / self.res;
        Aabb::new(
            (lo - DVec3::splat(1e-6)).as_vec3(),
            (hi + DVec3::splat(1e-6)).as_vec3(),
        )
    }

    fn intersect(&self, ray: &Ray, t_max: f32) -> Option<Hit> {
        let (t0, t1) = self.clip(ray)?;
        let (ts, te) = (t0.max(0.0), t1.min(t_max as f64));
        if ts >= te {
            return None;
        }
        let o = ray.origin.as_dvec3();
        let d = ray.dir.as_dvec3();
        let inside = self.field(o + d * ts) < 0.0;
        let mut found = None;
        self.walk(ray, ts, te, inside, |t, _, _| {
            if t > 0.0 && t < t_max as f64 {
                found = Some(t);
                false
            } else {
                true
            }
        });
        let t = found?;
        let p = o + d * t;
        let n = self.outward(p);
        let shading = match self.normals {
            SdfNormals::Analytic => n,
            SdfNormals::Smooth => {
                let s = self.smooth_normal(p);
                if s.length_squared() > 0.0 {
                    s.normalize()
                } else {
                    n
                }
            }
        };
        let mut h = Hit::new(t as f32, p.as_vec3(), n.as_vec3(), Vec2::ZERO);
        h.shading_normal = shading.as_vec3();
        h.error = ((o.abs().max_element() + (d * t).abs().max_element())
            * 8.0
            * f32::EPSILON as f64) as f32;
        Some(h)
    }

    fn is_solid(&self) -> bool {
        self.closed
    }

    fn spans(&self, ray: &Ray, out: &mut Vec<Span>) {
        if !self.closed {
            return;
        }
        let Some((t0, t1)) = self.clip(ray) else {
            return;
        };
        let o = ray.origin.as_dvec3();
        let d = ray.dir.as_dvec3();
        let boundary =
            |t: f64| Boundary::new(t as f32, self.outward(o + d * t).as_vec3(), Vec2::ZERO);
        let mut enter: Option<f64> = None;
        self.walk(ray, t0, t1, false, |t, entering, _| {
            if entering {
                enter = Some(t);
            } else if let Some(e) = enter.take() {
                out.push(Span {
                    enter: boundary(e),
                    exit: boundary(t),
                });
            }
            true
        });
        // A closed field is positive where the walk ends, so no span stays open; keep
        // the output well formed if rounding says otherwise.
        if let Some(e) = enter {
            out.push(Span {
                enter: boundary(e),
                exit: boundary(t1),
            });
        }
    }
}
