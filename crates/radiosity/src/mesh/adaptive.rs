//! Adaptive subdivision where radiosity changes fast (Cohen et al. 1986, "adaptive
//! subdivision"): after a solve, an element whose radiosity differs from the average at
//! one of its corners by more than `tolerance` times the largest *reflected* radiosity
//! in the scene (`B − E`: a light's own emission, 100 times brighter than any wall in
//! the Cornell box, would otherwise hide every jump on the walls) is split into four;
//! the caller solves again on the finer mesh. The display mesh
//! (`weld`) removes the T-vertices this leaves between fine and coarse neighbours.

use crate::mesh::{weld, Element, Mesh};

/// Splits the elements with steep radiosity changes; returns the new mesh and how many
/// elements were split. Elements smaller than `min_area` are left alone.
pub fn refine(mesh: &Mesh, b: &[[f64; 3]], tolerance: f64, min_area: f64) -> (Mesh, usize) {
    let scale = mesh.scale();
    let display = weld::weld(&mesh.elements, b, scale);
    let bmax = b
        .iter()
        .enumerate()
        .flat_map(|(i, c)| {
            let e = mesh.emission(i);
            (0..3).map(move |k| c[k] - e[k])
        })
        .fold(0.0f64, f64::max)
        .max(1e-300);
    // Re-derive each element's corner ids by the same welding keys.
    let quantum = (scale * 1e-8).max(1e-300);
    let mut ids = std::collections::HashMap::with_capacity(display.positions.len());
    let key = |patch: u32, p: glam::DVec3| {
        let q = |x: f64| (x / quantum).round() as i64;
        (patch, q(p.x), q(p.y), q(p.z))
    };
    for (i, p) in display.positions.iter().enumerate() {
        ids.insert(key(display.patch[i], *p), i);
    }
    let mut out = Vec::with_capacity(mesh.elements.len());
    let mut split = 0;
    for (ei, e) in mesh.elements.iter().enumerate() {
        let steep = e.poly.verts().iter().any(|v| {
            let vi = ids[&key(e.patch, *v)];
            (0..3).any(|c| (display.radiosity[vi][c] - b[ei][c]).abs() > tolerance * bmax)
        });
        if steep && e.area > min_area {
            split += 1;
            for c in e.poly.split4() {
                out.push(Element::new(c, e.patch));
            }
        } else {
            out.push(*e);
        }
    }
    (Mesh::with_elements(mesh.patches.clone(), out), split)
}
