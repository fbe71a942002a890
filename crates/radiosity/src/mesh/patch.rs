//! Patches: the input polygons of a radiosity scene with their reflectance and emission
//! (lecture, "Radiosity": objects broken into flat, perfectly diffuse patches).

use crate::error::{RadiosityError, Result};
use crate::geom::Poly;
use glam::DVec3;

/// An input polygon as the user (or a built-in scene) gives it.
#[derive(Clone, Debug)]
pub struct PatchSpec {
    /// For messages: "floor", "tall block side 2", "scene.toml object 3 face 5".
    pub name: String,
    /// Corners (3 or more, planar or nearly so), counter-clockwise seen from the front.
    pub corners: Vec<DVec3>,
    /// Diffuse reflectance per RGB channel, each in [0, 1).
    pub reflectance: [f64; 3],
    /// Emitted radiosity (W/m^2, or any consistent unit) per channel.
    pub emission: [f64; 3],
}

/// A validated planar patch: a triangle or convex quadrilateral.
#[derive(Clone, Debug)]
pub struct Patch {
    pub name: String,
    pub poly: Poly,
    pub reflectance: [f64; 3],
    pub emission: [f64; 3],
    /// Index of the `PatchSpec` this patch came from (polygons with more than four
    /// corners, and non-planar quadrilaterals, become several patches).
    pub source: u32,
}

impl Patch {
    pub fn area(&self) -> f64 {
        self.poly.area()
    }
    pub fn is_emitter(&self) -> bool {
        self.emission.iter().any(|&e| e > 0.0)
    }
}

/// Relative tolerance on planarity: a quadrilateral whose fourth corner is further than
/// this times its diameter from the plane of the first three is cut into two triangles.
pub const PLANARITY_TOLERANCE: f64 = 1e-6;

/// Checks the specs and turns them into planar patches. Errors name the patch and say
/// what to change: reflectance at or above 1 (the radiosity equation has no convergent
/// solution), negative or non-finite values, fewer than three corners, zero area.
pub fn validate(specs: &[PatchSpec]) -> Result<Vec<Patch>> {
    let mut out = Vec::with_capacity(specs.len());
    for (si, s) in specs.iter().enumerate() {
        let what = |m: String| RadiosityError::Input(format!("patch {} ('{}'): {}", si, s.name, m));
        for (c, &r) in ["red", "green", "blue"].iter().zip(&s.reflectance) {
            if !r.is_finite() || r < 0.0 {
                return Err(what(format!(
                    "{c} reflectance {r} is not a number in [0, 1)"
                )));
            }
            if r >= 1.0 {
                return Err(what(format!(
                    "{c} reflectance {r} is at or above 1: such a surface reflects at least all the light it \
                     receives and the radiosity equation has no finite solution; use a reflectance below 1 \
                     (real materials stay below about 0.95)"
                )));
            }
        }
        for (c, &e) in ["red", "green", "blue"].iter().zip(&s.emission) {
            if !e.is_finite() || e < 0.0 {
                return Err(what(format!(
                    "{c} emission {e} must be finite and not negative"
                )));
            }
        }
        if s.corners.len() < 3 {
            return Err(what(format!(
                "has {} corners; a patch needs at least 3",
                s.corners.len()
            )));
        }
        if s.corners.iter().any(|c| !c.is_finite()) {
            return Err(what("a corner is not a finite number".into()));
        }
        // Fan-triangulate polygons with more than four corners; keep quads when planar.
        let polys: Vec<Poly> = match s.corners.len() {
            3 => vec![Poly::tri(s.corners[0], s.corners[1], s.corners[2])],
            4 => {
                let q = Poly::quad(s.corners[0], s.corners[1], s.corners[2], s.corners[3]);
                if q.non_planarity() > PLANARITY_TOLERANCE * q.diameter() || !is_convex_quad(&q) {
                    vec![
                        Poly::tri(q.v[0], q.v[1], q.v[2]),
                        Poly::tri(q.v[0], q.v[2], q.v[3]),
                    ]
                } else {
                    vec![q]
                }
            }
            _ => (1..s.corners.len() - 1)
                .map(|i| Poly::tri(s.corners[0], s.corners[i], s.corners[i + 1]))
                .collect(),
        };
        let total: f64 = polys.iter().map(|p| p.area()).sum();
        let scale = s.corners.iter().map(|c| c.length()).fold(1e-300, f64::max);
        if total <= 1e-12 * scale * scale {
            return Err(what(format!(
                "has zero area ({total:e}); its corners are coincident or collinear. Remove it or fix its corners"
            )));
        }
        for p in polys {
            if p.area() <= 1e-12 * scale * scale {
                continue; // a sliver of a fan; the rest of the polygon carries the area
            }
            out.push(Patch {
                name: s.name.clone(),
                poly: p,
                reflectance: s.reflectance,
                emission: s.emission,
                source: si as u32,
            });
        }
    }
    if out.is_empty() {
        return Err(RadiosityError::Input("the scene has no patches".into()));
    }
    if !out.iter().any(|p| p.is_emitter()) {
        return Err(RadiosityError::Input(
            "no patch emits light, so every radiosity is 0; give at least one patch an emission"
                .into(),
        ));
    }
    Ok(out)
}

fn is_convex_quad(q: &Poly) -> bool {
    let n = q.vector_area();
    (0..4).all(|i| {
        let a = q.v[i];
        let b = q.v[(i + 1) % 4];
        let c = q.v[(i + 2) % 4];
        (b - a).cross(c - b).dot(n) > 0.0
    })
}

/// A convenience for tests and built-in scenes.
pub fn spec(name: &str, corners: &[DVec3], reflectance: [f64; 3], emission: [f64; 3]) -> PatchSpec {
    PatchSpec {
        name: name.to_string(),
        corners: corners.to_vec(),
        reflectance,
        emission,
    }
}
