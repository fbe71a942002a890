//! Planar polygons in f64 (DESIGN.md: form factors and radiosity sums in f64): the
//! patches and elements of the radiosity mesh are triangles or convex quadrilaterals.

use glam::DVec3;

/// A planar triangle (`n == 3`) or convex quadrilateral (`n == 4`), counter-clockwise
/// seen from the side its normal points to.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Poly {
    pub v: [DVec3; 4],
    pub n: u8,
}

impl Poly {
    pub fn tri(a: DVec3, b: DVec3, c: DVec3) -> Self {
        Self {
            v: [a, b, c, c],
            n: 3,
        }
    }
    pub fn quad(a: DVec3, b: DVec3, c: DVec3, d: DVec3) -> Self {
        Self {
            v: [a, b, c, d],
            n: 4,
        }
    }
    pub fn from_slice(p: &[DVec3]) -> Option<Self> {
        match p.len() {
            3 => Some(Self::tri(p[0], p[1], p[2])),
            4 => Some(Self::quad(p[0], p[1], p[2], p[3])),
            _ => None,
        }
    }
    #[inline]
    pub fn verts(&self) -> &[DVec3] {
        &self.v[..self.n as usize]
    }
    /// Newell's vector area: normal times area (exact for planar polygons).
    pub fn vector_area(&self) -> DVec3 {
        let vs = self.verts();
        let mut s = DVec3::ZERO;
        for i in 0..vs.len() {
            s += vs[i].cross(vs[(i + 1) % vs.len()]);
        }
        0.5 * s
    }
    pub fn area(&self) -> f64 {
        self.vector_area().length()
    }
    pub fn normal(&self) -> DVec3 {
        self.vector_area().normalize_or_zero()
    }
    /// Area centroid.
    pub fn centroid(&self) -> DVec3 {
        if self.n == 3 {
            return (self.v[0] + self.v[1] + self.v[2]) / 3.0;
        }
        let (a1, c1) = tri_ac(self.v[0], self.v[1], self.v[2]);
        let (a2, c2) = tri_ac(self.v[0], self.v[2], self.v[3]);
        if a1 + a2 <= 0.0 {
            return (self.v[0] + self.v[1] + self.v[2] + self.v[3]) / 4.0;
        }
        (c1 * a1 + c2 * a2) / (a1 + a2)
    }
    /// Longest distance between two vertices.
    pub fn diameter(&self) -> f64 {
        let vs = self.verts();
        let mut d: f64 = 0.0;
        for i in 0..vs.len() {
            for j in i + 1..vs.len() {
                d = d.max(vs[i].distance(vs[j]));
            }
        }
        d
    }
    /// Largest distance of a vertex from the plane through the first three (0 for
    /// triangles): how far a quadrilateral is from planar.
    pub fn non_planarity(&self) -> f64 {
        if self.n == 3 {
            return 0.0;
        }
        let n = (self.v[1] - self.v[0])
            .cross(self.v[2] - self.v[0])
            .normalize_or_zero();
        (self.v[3] - self.v[0]).dot(n).abs()
    }
    /// A point uniformly distributed over the area for `(u, w)` uniform in [0,1)^2.
    pub fn sample(&self, u: f64, w: f64) -> DVec3 {
        self.sample_split(self.split_fraction(), u, w)
    }
    /// The share of a quadrilateral's area in its first fan triangle `(v0, v1, v2)`
    /// (1 for triangles): what [`Poly::sample_split`] needs, computed once.
    pub fn split_fraction(&self) -> f64 {
        if self.n == 3 {
            return 1.0;
        }
        let a1 = tri_ac(self.v[0], self.v[1], self.v[2]).0;
        let a2 = tri_ac(self.v[0], self.v[2], self.v[3]).0;
        a1 / (a1 + a2)
    }
    /// [`Poly::sample`] with its [`Poly::split_fraction`] given.
    #[inline]
    pub fn sample_split(&self, split: f64, u: f64, w: f64) -> DVec3 {
        if self.n == 3 {
            return sample_tri(self.v[0], self.v[1], self.v[2], u, w);
        }
        if u < split {
            sample_tri(self.v[0], self.v[1], self.v[2], u / split, w)
        } else {
            sample_tri(
                self.v[0],
                self.v[2],
                self.v[3],
                (u - split) / (1.0 - split),
                w,
            )
        }
    }
    /// Splits into four children: quadrilaterals at edge midpoints and the centre,
    /// triangles at edge midpoints (three corner triangles and the middle one).
    pub fn split4(&self) -> [Poly; 4] {
        let m = |a: DVec3, b: DVec3| 0.5 * (a + b);
        let v = &self.v;
        if self.n == 3 {
            let (ab, bc, ca) = (m(v[0], v[1]), m(v[1], v[2]), m(v[2], v[0]));
            [
                Poly::tri(v[0], ab, ca),
                Poly::tri(ab, v[1], bc),
                Poly::tri(ca, bc, v[2]),
                Poly::tri(ab, bc, ca),
            ]
        } else {
            let (ab, bc, cd, da) = (m(v[0], v[1]), m(v[1], v[2]), m(v[2], v[3]), m(v[3], v[0]));
            let c = 0.25 * (v[0] + v[1] + v[2] + v[3]);
            [
                Poly::quad(v[0], ab, c, da),
                Poly::quad(ab, v[1], bc, c),
                Poly::quad(c, bc, v[2], cd),
                Poly::quad(da, c, cd, v[3]),
            ]
        }
    }
    /// Gauss-Legendre points and weights (weights sum to the area) with `k` points per
    /// direction: a k x k product rule on the bilinear map of a quadrilateral, or on the
    /// collapsed square (Duffy) for a triangle.
    pub fn gauss_points(&self, k: usize) -> Vec<(DVec3, f64)> {
        let (xs, ws) = gauss_legendre01(k);
        let mut out = Vec::with_capacity(k * k);
        let v = &self.v;
        for (i, &s) in xs.iter().enumerate() {
            for (j, &t) in xs.iter().enumerate() {
                let (p, jac) = if self.n == 3 {
                    // (s, t) -> a + s (b - a) + s t (c - b); Jacobian 2A s.
                    let p = v[0] + s * (v[1] - v[0]) + s * t * (v[2] - v[1]);
                    let jac = (v[1] - v[0]).cross(v[2] - v[1]).length() * s;
                    (p, jac)
                } else {
                    let p = v[0] * (1.0 - s) * (1.0 - t)
                        + v[1] * s * (1.0 - t)
                        + v[2] * s * t
                        + v[3] * (1.0 - s) * t;
                    let ds = (v[1] - v[0]) * (1.0 - t) + (v[2] - v[3]) * t;
                    let dt = (v[3] - v[0]) * (1.0 - s) + (v[2] - v[1]) * s;
                    (p, ds.cross(dt).length())
                };
                out.push((p, ws[i] * ws[j] * jac));
            }
        }
        out
    }
}

fn tri_ac(a: DVec3, b: DVec3, c: DVec3) -> (f64, DVec3) {
    (0.5 * (b - a).cross(c - a).length(), (a + b + c) / 3.0)
}

fn sample_tri(a: DVec3, b: DVec3, c: DVec3, u: f64, w: f64) -> DVec3 {
    let su = u.sqrt();
    a * (1.0 - su) + b * (su * (1.0 - w)) + c * (su * w)
}

/// Gauss-Legendre nodes and weights on [0, 1] (Golub-Welsch free: Newton on P_k).
pub fn gauss_legendre01(k: usize) -> (Vec<f64>, Vec<f64>) {
    let k = k.max(1);
    let mut xs = vec![0.0; k];
    let mut ws = vec![0.0; k];
    for i in 0..k {
        let mut x = (std::f64::consts::PI * (i as f64 + 0.75) / (k as f64 + 0.5)).cos();
        let mut dp = 0.0;
        for _ in 0..100 {
            let (mut p0, mut p1) = (1.0, x);
            if k == 1 {
                p1 = x;
                p0 = 1.0;
            } else {
                for n in 2..=k {
                    let p2 = ((2 * n - 1) as f64 * x * p1 - (n - 1) as f64 * p0) / n as f64;
                    p0 = p1;
                    p1 = p2;
                }
            }
            // p1 = P_k(x), p0 = P_{k-1}(x)
            dp = k as f64 * (x * p1 - p0) / (x * x - 1.0);
            let dx = p1 / dp;
            x -= dx;
            if dx.abs() < 1e-15 {
                break;
            }
        }
        xs[i] = 0.5 * (1.0 - x);
        ws[i] = 1.0 / ((1.0 - x * x) * dp * dp);
    }
    (xs, ws)
}

/// Ray-polygon intersection (Möller-Trumbore on the fan triangles), in f64.
/// Returns `t` with `t_min < t < t_max`.
pub fn intersect_poly(p: &Poly, o: DVec3, d: DVec3, t_min: f64, t_max: f64) -> Option<f64> {
    let tris: &[(usize, usize, usize)] = if p.n == 3 {
        &[(0, 1, 2)]
    } else {
        &[(0, 1, 2), (0, 2, 3)]
    };
    for &(a, b, c) in tris {
        let (v0, v1, v2) = (p.v[a], p.v[b], p.v[c]);
        let e1 = v1 - v0;
        let e2 = v2 - v0;
        let pv = d.cross(e2);
        let det = e1.dot(pv);
        if det.abs() < 1e-300 {
            continue;
        }
        let inv = 1.0 / det;
        let tv = o - v0;
        let u = tv.dot(pv) * inv;
        if !(0.0..=1.0).contains(&u) {
            continue;
        }
        let qv = tv.cross(e1);
        let v = d.dot(qv) * inv;
        if v < 0.0 || u + v > 1.0 {
            continue;
        }
        let t = e2.dot(qv) * inv;
        if t > t_min && t < t_max {
            return Some(t);
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gauss_integrates_polynomials_exactly() {
        let (x, w) = gauss_legendre01(5);
        let s: f64 = x.iter().zip(&w).map(|(x, w)| w * x.powi(9)).sum();
        assert!((s - 0.1).abs() < 1e-14, "{s}");
    }

    #[test]
    fn gauss_weights_sum_to_area() {
        let t = Poly::tri(DVec3::ZERO, DVec3::X * 2.0, DVec3::Y * 3.0);
        let s: f64 = t.gauss_points(4).iter().map(|p| p.1).sum();
        assert!((s - 3.0).abs() < 1e-12);
        let q = Poly::quad(
            DVec3::ZERO,
            DVec3::X * 2.0,
            DVec3::new(3.0, 1.0, 0.0),
            DVec3::Y,
        );
        let s: f64 = q.gauss_points(4).iter().map(|p| p.1).sum();
        assert!((s - q.area()).abs() < 1e-12);
    }

    #[test]
    fn split_keeps_area() {
        let q = Poly::quad(
            DVec3::ZERO,
            DVec3::X * 2.0,
            DVec3::new(3.0, 1.0, 0.0),
            DVec3::Y,
        );
        let s: f64 = q.split4().iter().map(|c| c.area()).sum();
        assert!((s - q.area()).abs() < 1e-12);
        let t = Poly::tri(DVec3::ZERO, DVec3::X * 2.0, DVec3::Y * 3.0);
        let s: f64 = t.split4().iter().map(|c| c.area()).sum();
        assert!((s - 3.0).abs() < 1e-12);
    }
}
