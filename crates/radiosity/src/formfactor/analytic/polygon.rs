//! The "analytic" matrix method: the inner integral of the form-factor integral in
//! closed form (the contour formula, point to polygon) and the outer integral over the
//! sending element by Gauss-Legendre quadrature:
//!
//! `F_ij = (1/A_i) Σ_g w_g F_{dA(x_g) → A_j}`.
//!
//! Without occluders this is exact up to the quadrature error of a smooth integrand
//! (and a logarithmic edge singularity for elements that share an edge). Visibility,
//! when asked for, is the fraction of rays from each Gauss point to points of `j`.

use crate::error::Result;
use crate::formfactor::contour::{faces, point_to_polygon, visible_fraction};
use crate::formfactor::{FormFactorMethod, FormFactors};
use crate::mesh::Mesh;
use crate::visibility::Visibility;

pub struct AnalyticPolygon {
    pub gauss_points: usize,
    pub visibility_samples: usize,
}

impl FormFactorMethod for AnalyticPolygon {
    fn name(&self) -> &'static str {
        "analytic"
    }
    fn compute(
        &self,
        mesh: &Mesh,
        progress: Option<&(dyn Fn(usize) + Sync)>,
    ) -> Result<FormFactors> {
        let vis = (self.visibility_samples > 0).then(|| Visibility::new(mesh));
        let els = &mesh.elements;
        let k = self.gauss_points.max(1);
        FormFactors::compute_rows(els.len(), progress, |i, row| {
            let ei = &els[i];
            let pts = ei.poly.gauss_points(k);
            for (j, ej) in els.iter().enumerate() {
                if i == j
                    || ej.normal.dot(ei.normal) > 1.0 - 1e-12
                        && (ej.centroid - ei.centroid).dot(ei.normal).abs() < 1e-12 * mesh.scale()
                {
                    continue; // coplanar: sees nothing of each other
                }
                let mut s = 0.0;
                for (x, w) in &pts {
                    if !faces(*x, ej.centroid, ej.normal) {
                        continue;
                    }
                    let f = point_to_polygon(*x, ei.normal, ej.poly.verts());
                    if f > 0.0 {
                        s += w
                            * f
                            * visible_fraction(
                                vis.as_ref(),
                                *x,
                                ei.normal,
                                &ej.poly,
                                ej.normal,
                                self.visibility_samples,
                            );
                    }
                }
                row[j] = s / ei.area;
            }
        })
    }
}
