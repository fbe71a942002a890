//! An independent reference for form factors with occlusion, shared by the radiosity
//! tests (`mod reference_quadrature;`). Nothing here calls the crate: the geometry
//! (rectangles), the visibility test (a segment against each blocker rectangle), the
//! Gauss-Legendre rule and the closed forms used to validate them are all written out
//! below, so a bug in the crate's ray caster, rasterizer, contour formula or quadrature
//! cannot leak into the reference.
//!
//! `F_ij = (1/A_i) ∫_{A_i} ∫_{A_j} V(x, y) cos θ_i cos θ_j / (π r²) dA_j dA_i`
//!
//! Outer integral (over the sender): composite Gauss-Legendre, `panels²` panels of
//! `points²` points. Inner integral (over the receiver, for each outer point x): a
//! `panels²` grid whose corners are tested for visibility; a panel whose four corners
//! agree and that holds no shadow corner (a blocker corner projected from x onto the
//! receiver's plane) is integrated with a 3 x 3 Gauss rule (visible) or skipped
//! (hidden); a panel cut by a shadow edge is cut into `leaf²` leaves, a leaf cut by the
//! edge is split in four `depth` times, and the smallest cells keep their visible part,
//! found from the segment test's margin (how far inside the blocker the segment passes)
//! at their corners. (A plain midpoint rule on the leaves would move a straight shadow
//! edge to the nearest leaf centres, a bias of order leaf size x edge length that does
//! not average out at a fixed point: 2e-4 at a point of the parallel scene.)
//! `occluded_form_factors.rs` checks the rule against closed forms: unoccluded 1e-6;
//! with a blocker, 5e-7 at points and 1e-7 over the parallel scene (exact shadows),
//! 5e-5 for a divider wall touching both planes.
#![allow(dead_code)]

use glam::DVec3;
use std::f64::consts::PI;

/// A rectangle: corners `o`, `o + u`, `o + u + v`, `o + v` (counter-clockwise seen from
/// the front), front normal along `u × v`. `u` and `v` must be perpendicular.
#[derive(Clone, Copy, Debug)]
pub struct Rect {
    pub o: DVec3,
    pub u: DVec3,
    pub v: DVec3,
}

impl Rect {
    pub fn new(o: DVec3, u: DVec3, v: DVec3) -> Self {
        assert!(
            u.dot(v).abs() <= 1e-12 * u.length() * v.length(),
            "a Rect needs perpendicular sides"
        );
        Self { o, u, v }
    }
    pub fn corners(&self) -> [DVec3; 4] {
        [
            self.o,
            self.o + self.u,
            self.o + self.u + self.v,
            self.o + self.v,
        ]
    }
    pub fn normal(&self) -> DVec3 {
        self.u.cross(self.v).normalize()
    }
    pub fn area(&self) -> f64 {
        self.u.cross(self.v).length()
    }
    /// The point at parameters `(s, t)` in [0, 1]².
    pub fn at(&self, s: f64, t: f64) -> DVec3 {
        self.o + self.u * s + self.v * t
    }
    /// The part `[s0, s1] x [t0, t1]` in parameter space.
    pub fn sub(&self, (s0, s1): (f64, f64), (t0, t1): (f64, f64)) -> Rect {
        Rect::new(self.at(s0, t0), self.u * (s1 - s0), self.v * (t1 - t0))
    }
    /// Parameters of a point of the rectangle's plane.
    pub fn params(&self, p: DVec3) -> (f64, f64) {
        let d = p - self.o;
        (
            d.dot(self.u) / self.u.length_squared(),
            d.dot(self.v) / self.v.length_squared(),
        )
    }
    /// Whether the open segment from `a` to `b` passes through the rectangle's interior.
    /// End points on the rectangle's plane do not count as blocked.
    pub fn blocks(&self, a: DVec3, b: DVec3) -> bool {
        self.margin(a, b) > 0.0
    }
    /// The segment test made continuous: with `t` where the line through `a` and `b`
    /// meets the rectangle's plane (0 at `a`, 1 at `b`) and `d` how far inside the
    /// rectangle's boundary it meets it, `min(d, t L, (1 − t) L)` (`L = |b − a|`):
    /// positive exactly where the open segment passes through the rectangle's interior
    /// (blocked), and along a shadow edge, including where the rectangle reaches the
    /// receiver's plane, a smooth function of `b`, so the rule below can place the edge
    /// inside a leaf.
    pub fn margin(&self, a: DVec3, b: DVec3) -> f64 {
        let n = self.u.cross(self.v);
        let (da, db) = (n.dot(a - self.o), n.dot(b - self.o));
        let len = (b - a).length();
        if (da - db).abs() <= 1e-15 * n.length() * len {
            return -len; // parallel to the plane: never blocked
        }
        let t = da / (da - db);
        let (s, w) = self.params(a + (b - a) * t);
        let (lu, lv) = (self.u.length(), self.v.length());
        (s * lu)
            .min((1.0 - s) * lu)
            .min(w * lv)
            .min((1.0 - w) * lv)
            .min(t * len)
            .min((1.0 - t) * len)
    }
}

/// Area and centroid of the part of the unit square where `c + a ξ + b η <= 0`.
fn clipped_unit_square(c: f64, a: f64, b: f64) -> (f64, f64, f64) {
    let sq = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)];
    let f = |(x, y): (f64, f64)| c + a * x + b * y;
    let mut poly: Vec<(f64, f64)> = Vec::with_capacity(6);
    for k in 0..4 {
        let (p, q) = (sq[k], sq[(k + 1) % 4]);
        let (fp, fq) = (f(p), f(q));
        if fp <= 0.0 {
            poly.push(p);
        }
        if (fp <= 0.0) != (fq <= 0.0) {
            let t = fp / (fp - fq);
            poly.push((p.0 + (q.0 - p.0) * t, p.1 + (q.1 - p.1) * t));
        }
    }
    let (mut area, mut cx, mut cy) = (0.0, 0.0, 0.0);
    for k in 0..poly.len() {
        let (p, q) = (poly[k], poly[(k + 1) % poly.len()]);
        let cr = p.0 * q.1 - q.0 * p.1;
        area += cr;
        cx += (p.0 + q.0) * cr;
        cy += (p.1 + q.1) * cr;
    }
    if area.abs() < 1e-300 {
        return (0.0, 0.5, 0.5);
    }
    (0.5 * area, cx / (3.0 * area), cy / (3.0 * area))
}

/// Gauss-Legendre nodes and weights on [0, 1] (Newton on the Legendre polynomial; the
/// weights sum to 1).
pub fn gauss01(k: usize) -> Vec<(f64, f64)> {
    (0..k)
        .map(|i| {
            let mut x = (PI * (i as f64 + 0.75) / (k as f64 + 0.5)).cos();
            let mut dp = 1.0;
            for _ in 0..100 {
                // P_k(x) and P_k'(x) by the three-term recurrence.
                let (mut p0, mut p1) = (1.0, x);
                for n in 2..=k {
                    let p2 = ((2 * n - 1) as f64 * x * p1 - (n - 1) as f64 * p0) / n as f64;
                    p0 = p1;
                    p1 = p2;
                }
                let pk = if k == 1 { x } else { p1 };
                let pkm1 = if k == 1 { 1.0 } else { p0 };
                dp = k as f64 * (x * pk - pkm1) / (x * x - 1.0);
                let dx = pk / dp;
                x -= dx;
                if dx.abs() < 1e-15 {
                    break;
                }
            }
            let w = 2.0 / ((1.0 - x * x) * dp * dp);
            (0.5 * (1.0 - x), 0.5 * w)
        })
        .collect()
}

/// Sizes of the reference rule (see the module comment).
#[derive(Clone, Copy, Debug)]
pub struct Rule {
    /// Outer: panels per side of the sender and Gauss points per side of a panel.
    pub outer_panels: usize,
    pub outer_points: usize,
    /// Inner: panels per side of the receiver, midpoint leaves per side of a cut panel.
    pub inner_panels: usize,
    pub leaf: usize,
    /// Times a leaf cut by a shadow edge is split in four before the affine fit.
    pub depth: usize,
}

impl Default for Rule {
    fn default() -> Self {
        Self {
            outer_panels: 8,
            outer_points: 4,
            inner_panels: 32,
            leaf: 8,
            depth: 3,
        }
    }
}

/// The point-to-area kernel `cos θ_x cos θ_y / (π r²)` per unit receiver area (0 where
/// either side faces away).
#[inline]
fn kernel(x: DVec3, nx: DVec3, y: DVec3, ny: DVec3) -> f64 {
    let d = y - x;
    let r2 = d.length_squared();
    let (cx, cy) = (nx.dot(d), -ny.dot(d));
    if cx <= 0.0 || cy <= 0.0 {
        return 0.0;
    }
    cx * cy / (PI * r2 * r2)
}

/// `F_{dA(x) → recv}` with visibility: the differential area at `x` with unit normal
/// `nx` to the front of `recv`, blocked by `blockers`.
pub fn point_to_rect(x: DVec3, nx: DVec3, recv: &Rect, blockers: &[Rect], rule: Rule) -> f64 {
    let p = rule.inner_panels;
    let ny = recv.normal();
    let jac = recv.area();
    let h = 1.0 / p as f64;
    let visible = |y: DVec3| !blockers.iter().any(|b| b.blocks(x, y));
    // Blocked where positive (the largest margin over the blockers).
    let margin = |y: DVec3| {
        blockers
            .iter()
            .map(|b| b.margin(x, y))
            .fold(f64::NEG_INFINITY, f64::max)
    };
    // Visibility at the panel corners.
    let mut corner = vec![true; (p + 1) * (p + 1)];
    if !blockers.is_empty() {
        for j in 0..=p {
            for i in 0..=p {
                corner[j * (p + 1) + i] = visible(recv.at(i as f64 * h, j as f64 * h));
            }
        }
    }
    // Panels holding a corner of a blocker's shadow on the receiver's plane.
    let mut cut = vec![false; p * p];
    let plane = ny.dot(recv.o);
    for b in blockers {
        for c in b.corners() {
            let den = ny.dot(c - x);
            if den.abs() < 1e-300 {
                continue;
            }
            let t = (plane - ny.dot(x)) / den;
            if t <= 1.0 {
                continue; // the blocker corner is not between x and the plane
            }
            let (s, w) = recv.params(x + (c - x) * t);
            if (0.0..1.0).contains(&s) && (0.0..1.0).contains(&w) {
                let (i, j) = ((s * p as f64) as usize, (w * p as f64) as usize);
                cut[j.min(p - 1) * p + i.min(p - 1)] = true;
            }
        }
    }
    let g3 = gauss01(3);
    let mut sum = 0.0;
    for j in 0..p {
        for i in 0..p {
            let c = [
                corner[j * (p + 1) + i],
                corner[j * (p + 1) + i + 1],
                corner[(j + 1) * (p + 1) + i],
                corner[(j + 1) * (p + 1) + i + 1],
            ];
            let (s0, t0) = (i as f64 * h, j as f64 * h);
            if !cut[j * p + i] && c.iter().all(|&v| v) {
                for &(a, wa) in &g3 {
                    for &(b, wb) in &g3 {
                        let y = recv.at(s0 + a * h, t0 + b * h);
                        sum += wa * wb * h * h * kernel(x, nx, y, ny);
                    }
                }
            } else if cut[j * p + i] || c.iter().any(|&v| v) {
                // A leaf grid with the visibility margin at its corners: a leaf whose
                // corners agree is visible or hidden as a whole (midpoint rule); a leaf
                // cut by a shadow edge keeps the part where the margin, fitted by an
                // affine function of the four corners, says visible, the kernel taken at
                // that part's centroid.
                let l = rule.leaf;
                let hl = h / l as f64;
                let mut m = vec![0.0; (l + 1) * (l + 1)];
                for b in 0..=l {
                    for a in 0..=l {
                        m[b * (l + 1) + a] =
                            margin(recv.at(s0 + a as f64 * hl, t0 + b as f64 * hl));
                    }
                }
                for b in 0..l {
                    for a in 0..l {
                        let m00 = m[b * (l + 1) + a];
                        let m10 = m[b * (l + 1) + a + 1];
                        let m01 = m[(b + 1) * (l + 1) + a];
                        let m11 = m[(b + 1) * (l + 1) + a + 1];
                        let (sa, tb) = (s0 + a as f64 * hl, t0 + b as f64 * hl);
                        sum += leaf_cell(
                            &|s, t| recv.at(s, t),
                            &margin,
                            &|y| kernel(x, nx, y, ny),
                            (sa, tb, hl),
                            [m00, m10, m01, m11],
                            rule.depth,
                        );
                    }
                }
            }
        }
    }
    sum * jac
}

/// One leaf `[s, s + h] x [t, t + h]` of a panel cut by a shadow edge, its margins at
/// the corners `m` (00, 10, 01, 11): whole (midpoint rule) where they agree, else split
/// in four `depth` times and, at the bottom, the visible part of the affine fit of the
/// margins, the kernel taken at that part's centroid.
fn leaf_cell(
    at: &dyn Fn(f64, f64) -> DVec3,
    margin: &dyn Fn(DVec3) -> f64,
    kernel: &dyn Fn(DVec3) -> f64,
    (s, t, h): (f64, f64, f64),
    m: [f64; 4],
    depth: usize,
) -> f64 {
    if m.iter().all(|&v| v <= 0.0) {
        return h * h * kernel(at(s + 0.5 * h, t + 0.5 * h));
    }
    if m.iter().all(|&v| v > 0.0) {
        return 0.0;
    }
    let [m00, m10, m01, m11] = m;
    if depth == 0 {
        let da = 0.5 * (m10 + m11 - m00 - m01);
        let db = 0.5 * (m01 + m11 - m00 - m10);
        let c0 = 0.25 * (m00 + m10 + m01 + m11) - 0.5 * (da + db);
        let (frac, cx, cy) = clipped_unit_square(c0, da, db);
        return h * h * frac * kernel(at(s + cx * h, t + cy * h));
    }
    let g = 0.5 * h;
    let mm = |a: f64, b: f64| margin(at(s + a * h, t + b * h));
    let (b0, l0, c, r0, t1) = (
        mm(0.5, 0.0),
        mm(0.0, 0.5),
        mm(0.5, 0.5),
        mm(1.0, 0.5),
        mm(0.5, 1.0),
    );
    leaf_cell(at, margin, kernel, (s, t, g), [m00, b0, l0, c], depth - 1)
        + leaf_cell(
            at,
            margin,
            kernel,
            (s + g, t, g),
            [b0, m10, c, r0],
            depth - 1,
        )
        + leaf_cell(
            at,
            margin,
            kernel,
            (s, t + g, g),
            [l0, c, m01, t1],
            depth - 1,
        )
        + leaf_cell(
            at,
            margin,
            kernel,
            (s + g, t + g, g),
            [c, r0, t1, m11],
            depth - 1,
        )
}

/// `F_{send → recv}` with visibility (the area-to-area form factor, sender's front to
/// receiver's front).
pub fn rect_to_rect(send: &Rect, recv: &Rect, blockers: &[Rect], rule: Rule) -> f64 {
    let n = send.normal();
    let g = gauss01(rule.outer_points);
    let h = 1.0 / rule.outer_panels as f64;
    let mut sum = 0.0;
    for j in 0..rule.outer_panels {
        for i in 0..rule.outer_panels {
            for &(a, wa) in &g {
                for &(b, wb) in &g {
                    let x = send.at((i as f64 + a) * h, (j as f64 + b) * h);
                    sum += wa * wb * h * h * point_to_rect(x, n, recv, blockers, rule);
                }
            }
        }
    }
    sum
}

// ---- Closed forms (written out here, independent of the crate's catalogue) ----

/// Differential area to a parallel rectangle `[0, a] x [0, b]` at distance `c`, the
/// area's normal through the corner (odd in `a` and in `b`, so signed corners add up).
pub fn corner_parallel(a: f64, b: f64, c: f64) -> f64 {
    let (x, y) = (a / c, b / c);
    let (sx, sy) = ((1.0 + x * x).sqrt(), (1.0 + y * y).sqrt());
    (x / sx * (y / sx).atan() + y / sy * (x / sy).atan()) / (2.0 * PI)
}

/// Differential area at `(px, py)` on the plane `z = 0` (normal +z) to the rectangle
/// `[x0, x1] x [y0, y1]` of the plane `z = c` facing it, by superposition of corners.
pub fn point_parallel(px: f64, py: f64, (x0, x1): (f64, f64), (y0, y1): (f64, f64), c: f64) -> f64 {
    let f = |x: f64, y: f64| corner_parallel(x - px, y - py, c);
    f(x1, y1) - f(x0, y1) - f(x1, y0) + f(x0, y0)
}

/// Two directly opposed parallel `a x b` rectangles at distance `c` (Siegel and Howell;
/// the lecture's "parallel rectangles").
pub fn opposed_rectangles(a: f64, b: f64, c: f64) -> f64 {
    let (x, y) = (a / c, b / c);
    let (x2, y2) = (x * x, y * y);
    let t = 0.5 * ((1.0 + x2) * (1.0 + y2) / (1.0 + x2 + y2)).ln()
        + x * (1.0 + y2).sqrt() * (x / (1.0 + y2).sqrt()).atan()
        + y * (1.0 + x2).sqrt() * (y / (1.0 + x2).sqrt()).atan()
        - x * x.atan()
        - y * y.atan();
    2.0 * t / (PI * x * y)
}

/// Semi-analytic reference for a sender on `z = 0` (normal +z) and a receiver and
/// blockers that are axis-aligned rectangles parallel to it, the receiver facing down at
/// height `c`, each blocker at a height strictly between: from each outer Gauss point the
/// visible part of the receiver is the receiver minus the blockers' shadows, which are
/// rectangles (a central projection between parallel planes scales). With one blocker
/// the inner integral is therefore exact: `F(receiver) − F(shadow ∩ receiver)`.
pub struct ParallelBox {
    pub x: (f64, f64),
    pub y: (f64, f64),
    pub z: f64,
}

/// The exact point-to-receiver factor from `(px, py, 0)` (normal +z) with the receiver
/// partly hidden by `blocker`: `F(receiver) − F(shadow ∩ receiver)`, the shadow being the
/// blocker scaled about the point by `recv.z / blocker.z`.
pub fn point_parallel_shadowed(
    px: f64,
    py: f64,
    recv: &ParallelBox,
    blocker: Option<&ParallelBox>,
) -> f64 {
    let open = point_parallel(px, py, recv.x, recv.y, recv.z);
    let Some(bl) = blocker else {
        return open;
    };
    assert!(bl.z > 0.0 && bl.z < recv.z);
    let k = recv.z / bl.z;
    let sx = (
        (px + (bl.x.0 - px) * k).max(recv.x.0),
        (px + (bl.x.1 - px) * k).min(recv.x.1),
    );
    let sy = (
        (py + (bl.y.0 - py) * k).max(recv.y.0),
        (py + (bl.y.1 - py) * k).min(recv.y.1),
    );
    if sx.0 < sx.1 && sy.0 < sy.1 {
        open - point_parallel(px, py, sx, sy, recv.z)
    } else {
        open
    }
}

pub fn parallel_semi_analytic(
    send: ((f64, f64), (f64, f64)),
    recv: &ParallelBox,
    blocker: Option<&ParallelBox>,
    panels: usize,
    points: usize,
) -> f64 {
    let ((sx0, sx1), (sy0, sy1)) = send;
    let g = gauss01(points);
    let (hx, hy) = ((sx1 - sx0) / panels as f64, (sy1 - sy0) / panels as f64);
    let mut sum = 0.0;
    for j in 0..panels {
        for i in 0..panels {
            for &(a, wa) in &g {
                for &(b, wb) in &g {
                    let px = sx0 + (i as f64 + a) * hx;
                    let py = sy0 + (j as f64 + b) * hy;
                    let f = point_parallel_shadowed(px, py, recv, blocker);
                    sum += wa * wb * hx * hy * f;
                }
            }
        }
    }
    sum / ((sx1 - sx0) * (sy1 - sy0))
}

/// The lecture's perpendicular rectangles with a common edge of length `l`: sender
/// `w x l` on the floor, receiver `h x l` on the wall (Siegel and Howell).
pub fn perpendicular_common_edge(w: f64, h: f64, l: f64) -> f64 {
    let (hh, ww) = (h / l, w / l);
    let (h2, w2) = (hh * hh, ww * ww);
    let s = (h2 + w2).sqrt();
    let t = ww * (1.0 / ww).atan() + hh * (1.0 / hh).atan() - s * (1.0 / s).atan();
    let l1 = ((1.0 + w2) * (1.0 + h2) / (1.0 + w2 + h2)).ln();
    let l2 = w2 * (w2 * (1.0 + w2 + h2) / ((1.0 + w2) * (w2 + h2))).ln();
    let l3 = h2 * (h2 * (1.0 + h2 + w2) / ((1.0 + h2) * (h2 + w2))).ln();
    (t + 0.25 * (l1 + l2 + l3)) / (PI * ww)
}

/// Floor strip `x in [0, w]` to the wall strip `z in [z0, z1]` (both of length `l`,
/// the wall at `x = 0`): form-factor algebra on the common-edge case, since the exchange
/// integral `A_1 F_12` is additive over the receiver.
pub fn perpendicular_with_gap(w: f64, (z0, z1): (f64, f64), l: f64) -> f64 {
    let g = |h: f64| {
        if h <= 0.0 {
            0.0
        } else {
            w * l * perpendicular_common_edge(w, h, l)
        }
    };
    (g(z1) - g(z0)) / (w * l)
}
