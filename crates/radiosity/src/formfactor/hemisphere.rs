//! The hemisphere, by the Nusselt analogue (lecture, "Hemisphere"): the form factor from
//! a point to a surface is the fraction of the unit disk covered by the surface's
//! projection, first onto the unit hemisphere and then down onto its base. The disk is
//! cut into `resolution²` cells of equal area by the concentric map (Shirley and Chiu
//! 1997); through each cell's centre a ray goes out from the element's centroid (the
//! cell lifted onto the hemisphere) and the first element hit gains `1/resolution²`.

use super::{FormFactorMethod, FormFactors};
use crate::error::Result;
use crate::mesh::Mesh;
use crate::visibility::ElementTracer;
use glam::DVec3;
use std::f64::consts::FRAC_PI_4;

pub struct Hemisphere {
    pub resolution: usize,
}

/// Shirley-Chiu concentric map from [0,1]^2 to the unit disk (area preserving).
pub fn concentric_disk(u: f64, v: f64) -> (f64, f64) {
    let (a, b) = (2.0 * u - 1.0, 2.0 * v - 1.0);
    if a == 0.0 && b == 0.0 {
        return (0.0, 0.0);
    }
    let (r, phi) = if a.abs() > b.abs() {
        (a, FRAC_PI_4 * (b / a))
    } else {
        (b, 2.0 * FRAC_PI_4 - FRAC_PI_4 * (a / b))
    };
    (r * phi.cos(), r * phi.sin())
}

impl FormFactorMethod for Hemisphere {
    fn name(&self) -> &'static str {
        "hemisphere"
    }
    fn compute(
        &self,
        mesh: &Mesh,
        progress: Option<&(dyn Fn(usize) + Sync)>,
    ) -> Result<FormFactors> {
        let tracer = ElementTracer::new(mesh);
        let k = self.resolution.max(1);
        let w = 1.0 / (k * k) as f64;
        FormFactors::compute_rows(mesh.len(), progress, |i, row| {
            let e = &mesh.elements[i];
            let n = e.normal;
            let s = if n.x.abs() > 0.9 { DVec3::Y } else { DVec3::X }
                .cross(n)
                .normalize();
            let t = n.cross(s);
            for a in 0..k {
                for b in 0..k {
                    let (x, y) =
                        concentric_disk((a as f64 + 0.5) / k as f64, (b as f64 + 0.5) / k as f64);
                    let z = (1.0 - x * x - y * y).max(0.0).sqrt();
                    let dir = s * x + t * y + n * z;
                    // A ray that slips through the crack between two polygons (f32
                    // edges are not watertight across instances) is tried again with a
                    // direction nudged by 1e-6.
                    let hit = tracer
                        .nearest(e.centroid, n, dir)
                        .or_else(|| tracer.nearest(e.centroid, n, dir + (s + t * 0.7) * 1e-6));
                    if let Some(j) = hit {
                        // Back faces block the ray but pass no light.
                        if j != i && mesh.elements[j].normal.dot(dir) < 0.0 {
                            row[j] += w;
                        }
                    }
                }
            }
        })
    }
}
