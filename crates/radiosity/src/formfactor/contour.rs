//! The closed-form differential-area-to-polygon form factor (the contour integral, by
//! Stokes' theorem; Lambert 1760, in Sillion and Puech, "Radiosity and Global
//! Illumination", 1994, eq. 4.17):
//!
//! `F_{dA→A} = (1/2π) Σ_k γ_k · n`, `γ_k = θ_k (R_k × R_{k+1}) / |R_k × R_{k+1}|`,
//!
//! where `R_k` runs from the point to the polygon's k-th corner and `θ_k` is the angle
//! between `R_k` and `R_{k+1}`. The polygon is first clipped to the half-space in
//! front of the point. The matrix method evaluates it at each element's centroid and
//! estimates visibility with a few rays to points of the receiving element.
//!
//! One point per element is accurate only while the other element is far away compared
//! with the elements' size: `F_{dA→A}` grows steeply towards a shared edge (its
//! derivative has a logarithmic singularity there), so for two perpendicular squares
//! sharing an edge the centroid value is 5% below the exact 0.20004 (lecture,
//! "perpendicular rectangles sharing an edge"). The row of an element that has a near
//! neighbour (closer than [`NEAR_FACTOR`] times the two diameters) is therefore
//! integrated over the element with a 3 x 3 Gauss rule (more where the element is
//! larger than its near neighbour), which is within 3e-5 of the
//! exact value for the shared-edge case (test
//! `formfactor_methods::edge_adjacent_elements_match_the_closed_form`). The whole row
//! uses the same points, so that it still sums to exactly 1 in a closed enclosure (the
//! contour formula at each point covers the point's whole hemisphere); visibility for
//! the far elements of such a row is still estimated from the centroid alone, and for
//! the near ones from every Gauss point (the pair's visibility rays shared out over the
//! points).

use super::{FormFactorMethod, FormFactors};
use crate::error::Result;
use crate::geom::Poly;
use crate::mesh::{Element, Mesh};
use crate::visibility::Visibility;
use glam::DVec3;

/// Form factor from a differential area at `x` with unit normal `n` to a polygon
/// (any closed loop of corners; only the part in front of `x` counts). The polygon
/// must face `x` for the result to be physical; the sign of the loop does not matter.
pub fn point_to_polygon(x: DVec3, n: DVec3, corners: &[DVec3]) -> f64 {
    let mut clipped: Vec<DVec3> = Vec::with_capacity(corners.len() + 2);
    clip_front(x, n, corners, &mut clipped);
    if clipped.len() < 3 {
        return 0.0;
    }
    let mut sum = 0.0;
    for k in 0..clipped.len() {
        let a = clipped[k] - x;
        let b = clipped[(k + 1) % clipped.len()] - x;
        let c = a.cross(b);
        let cl = c.length();
        if cl <= 1e-300 {
            continue;
        }
        let theta = cl.atan2(a.dot(b));
        sum += theta * c.dot(n) / cl;
    }
    (sum / (2.0 * std::f64::consts::PI)).abs()
}

/// Sutherland-Hodgman clip of a loop to `n · (p − x) >= 0`.
fn clip_front(x: DVec3, n: DVec3, poly: &[DVec3], out: &mut Vec<DVec3>) {
    let d = |p: DVec3| n.dot(p - x);
    for k in 0..poly.len() {
        let (a, b) = (poly[k], poly[(k + 1) % poly.len()]);
        let (da, db) = (d(a), d(b));
        if da >= 0.0 {
            out.push(a);
        }
        if (da >= 0.0) != (db >= 0.0) {
            let t = da / (da - db);
            out.push(a + (b - a) * t);
        }
    }
}

/// Whether the front of polygon `q` (normal `nq`, centroid `cq`) faces the point `x`.
#[inline]
pub fn faces(x: DVec3, cq: DVec3, nq: DVec3) -> bool {
    nq.dot(x - cq) > 0.0
}

/// Fraction of `k` x `k` Gauss points of `q` that `x` sees (1 when `k == 0`).
pub fn visible_fraction(
    vis: Option<&Visibility>,
    x: DVec3,
    nx: DVec3,
    q: &Poly,
    nq: DVec3,
    k: usize,
) -> f64 {
    let Some(vis) = vis else { return 1.0 };
    if k == 0 {
        return 1.0;
    }
    let side = (k as f64).sqrt().ceil().max(1.0) as usize;
    let pts = q.gauss_points(side);
    // Points of q behind x's plane are cut off by the contour formula already.
    let facing: Vec<_> = pts.iter().filter(|(p, _)| nx.dot(*p - x) > 0.0).collect();
    if facing.is_empty() {
        return 1.0;
    }
    let seen = facing
        .iter()
        .filter(|(p, _)| vis.visible(x, nx, *p, nq))
        .count();
    seen as f64 / facing.len() as f64
}

/// Pairs whose centroids are closer than this times the sum of the two diameters are
/// integrated with [`NEAR_GAUSS_POINTS`]² points over the element instead of one.
pub const NEAR_FACTOR: f64 = 1.0;
/// Gauss points per direction over the element for rows with near pairs (scaled up
/// by the ratio of the element's diameter to its smallest near neighbour's).
pub const NEAR_GAUSS_POINTS: usize = 3;
/// At most this many Gauss points per direction.
pub const MAX_GAUSS_POINTS: usize = 8;

/// Whether two polygons are near enough that one point per element is not accurate.
#[inline]
pub fn is_near(ci: DVec3, di: f64, cj: DVec3, dj: f64) -> bool {
    ci.distance_squared(cj) < (NEAR_FACTOR * (di + dj)).powi(2)
}

/// The contour formula at element centroids (Gauss points for rows with near pairs).
pub struct Contour {
    pub visibility_samples: usize,
}

/// Whether element `j` faces element `i` and vice versa (by centroids).
fn facing_pair(ei: &Element, ej: &Element) -> bool {
    faces(ei.centroid, ej.centroid, ej.normal) && faces(ej.centroid, ei.centroid, ei.normal)
}

impl FormFactorMethod for Contour {
    fn name(&self) -> &'static str {
        "contour"
    }
    fn compute(
        &self,
        mesh: &Mesh,
        progress: Option<&(dyn Fn(usize) + Sync)>,
    ) -> Result<FormFactors> {
        let vis = (self.visibility_samples > 0).then(|| Visibility::new(mesh));
        let els = &mesh.elements;
        let diameters: Vec<f64> = els.iter().map(|e| e.poly.diameter()).collect();
        let k = self.visibility_samples;
        FormFactors::compute_rows(els.len(), progress, |i, row| {
            let ei = &els[i];
            let near = |j: usize| is_near(ei.centroid, diameters[i], els[j].centroid, diameters[j]);
            // The smallest near neighbour: the rule needs more points when the element
            // is large compared with what it sees up close.
            let nearest = (0..els.len())
                .filter(|&j| j != i && facing_pair(ei, &els[j]) && near(j))
                .map(|j| diameters[j])
                .fold(f64::INFINITY, f64::min);
            if nearest == f64::INFINITY {
                for (j, ej) in els.iter().enumerate() {
                    if i == j || !facing_pair(ei, ej) {
                        continue;
                    }
                    let f = point_to_polygon(ei.centroid, ei.normal, ej.poly.verts());
                    if f > 0.0 {
                        row[j] = f * visible_fraction(
                            vis.as_ref(),
                            ei.centroid,
                            ei.normal,
                            &ej.poly,
                            ej.normal,
                            k,
                        );
                    }
                }
                return;
            }
            let points = (NEAR_GAUSS_POINTS as f64 * diameters[i] / nearest)
                .ceil()
                .clamp(NEAR_GAUSS_POINTS as f64, MAX_GAUSS_POINTS as f64);
            let pts = ei.poly.gauss_points(points as usize);
            // Near pairs: the visibility rays are shared out over the Gauss points.
            let k_point = k.div_ceil(pts.len()).max(usize::from(k > 0));
            for (j, ej) in els.iter().enumerate() {
                if i == j || !faces(ei.centroid, ej.centroid, ej.normal) && !near(j) {
                    continue;
                }
                let near_j = near(j);
                let mut s = 0.0;
                for (x, w) in &pts {
                    if !faces(*x, ej.centroid, ej.normal) {
                        continue;
                    }
                    let f = point_to_polygon(*x, ei.normal, ej.poly.verts());
                    if f > 0.0 {
                        s += w
                            * f
                            * if near_j {
                                visible_fraction(
                                    vis.as_ref(),
                                    *x,
                                    ei.normal,
                                    &ej.poly,
                                    ej.normal,
                                    k_point,
                                )
                            } else {
                                1.0
                            };
                    }
                }
                if s > 0.0 && !near_j {
                    s *= visible_fraction(
                        vis.as_ref(),
                        ei.centroid,
                        ei.normal,
                        &ej.poly,
                        ej.normal,
                        k,
                    );
                }
                row[j] = s / ei.area;
            }
        })
    }
}
