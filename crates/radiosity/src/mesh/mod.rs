//! The radiosity mesh: patches (input polygons) and the elements they are cut into.
//!
//! - `patch`: validation of the input polygons (reflectance, area, planarity);
//! - `subdivide`: uniform patch/element substructuring to a maximum element area;
//! - `contact`: splitting patches along the edges of patches that stand on them
//!   (discontinuity-conforming meshing at contact lines);
//! - `adaptive`: splitting elements where the solved radiosity changes fast;
//! - `weld`: the display mesh, with shared vertices and no T-vertex cracks.

pub mod adaptive;
pub mod contact;
pub mod patch;
pub mod subdivide;
pub mod weld;

pub use patch::{spec, validate, Patch, PatchSpec};

use crate::error::{RadiosityError, Result};
use crate::geom::Poly;
use glam::DVec3;

/// One element: the unit the form factors and solvers work on.
#[derive(Clone, Copy, Debug)]
pub struct Element {
    pub poly: Poly,
    /// Index of the patch it belongs to.
    pub patch: u32,
    pub area: f64,
    pub centroid: DVec3,
    pub normal: DVec3,
}

impl Element {
    pub fn new(poly: Poly, patch: u32) -> Self {
        Self {
            poly,
            patch,
            area: poly.area(),
            centroid: poly.centroid(),
            normal: poly.normal(),
        }
    }
}

/// Patches and their elements.
#[derive(Clone, Debug)]
pub struct Mesh {
    pub patches: Vec<Patch>,
    pub elements: Vec<Element>,
}

/// How finely to cut patches into elements.
#[derive(Clone, Copy, Debug)]
pub struct MeshOptions {
    /// Largest element area (scene units squared). `None`: one element per patch.
    pub max_element_area: Option<f64>,
    /// Refuse to build more elements than this (memory guard).
    pub max_elements: usize,
}

impl Default for MeshOptions {
    fn default() -> Self {
        Self {
            max_element_area: None,
            max_elements: 5_000_000,
        }
    }
}

impl Mesh {
    /// Validates the patches, splits them along contact lines (`contact`) and
    /// substructures them into elements.
    pub fn build(specs: &[PatchSpec], opts: MeshOptions) -> Result<Mesh> {
        let patches = validate(specs)?;
        let scale = patch_scale(&patches);
        let patches = contact::split_at_contacts(patches, scale);
        Self::from_patches(patches, opts)
    }

    pub fn from_patches(patches: Vec<Patch>, opts: MeshOptions) -> Result<Mesh> {
        let max_area = opts.max_element_area.unwrap_or(f64::INFINITY);
        if max_area.is_nan() || max_area <= 0.0 {
            return Err(RadiosityError::Input(format!(
                "--max-element-area must be positive (got {max_area})"
            )));
        }
        let sizes: Vec<(usize, usize)> = patches
            .iter()
            .map(|p| subdivide::grid_size(&p.poly, max_area))
            .collect();
        let count: usize = patches
            .iter()
            .zip(&sizes)
            .map(|(p, &s)| subdivide::element_count(&p.poly, s))
            .sum();
        if count > opts.max_elements {
            let total: f64 = patches.iter().map(|p| p.area()).sum();
            return Err(RadiosityError::Input(format!(
                "--max-element-area {max_area} would make {count} elements, more than the limit of {}; \
                 use a larger area (about {:.4e} gives that many)",
                opts.max_elements,
                total / opts.max_elements as f64
            )));
        }
        let mut elements = Vec::with_capacity(count);
        for (pi, (p, &s)) in patches.iter().zip(&sizes).enumerate() {
            for e in subdivide::subdivide(&p.poly, s) {
                elements.push(Element::new(e, pi as u32));
            }
        }
        Ok(Mesh { patches, elements })
    }

    /// A mesh with the given elements (adaptive refinement, hierarchical leaves).
    pub fn with_elements(patches: Vec<Patch>, elements: Vec<Element>) -> Mesh {
        Mesh { patches, elements }
    }

    pub fn len(&self) -> usize {
        self.elements.len()
    }
    pub fn is_empty(&self) -> bool {
        self.elements.is_empty()
    }
    pub fn reflectance(&self, i: usize) -> [f64; 3] {
        self.patches[self.elements[i].patch as usize].reflectance
    }
    pub fn emission(&self, i: usize) -> [f64; 3] {
        self.patches[self.elements[i].patch as usize].emission
    }
    pub fn total_area(&self) -> f64 {
        self.elements.iter().map(|e| e.area).sum()
    }
    /// Diameter of the scene's bounding box (scales ray offsets).
    pub fn scale(&self) -> f64 {
        patch_scale(&self.patches)
    }
}

/// Diameter of the bounding box of the patches.
fn patch_scale(patches: &[Patch]) -> f64 {
    let mut lo = DVec3::splat(f64::INFINITY);
    let mut hi = DVec3::splat(f64::NEG_INFINITY);
    for p in patches {
        for v in p.poly.verts() {
            lo = lo.min(*v);
            hi = hi.max(*v);
        }
    }
    (hi - lo).length()
}
