//! Shared helpers for the radiosity tests (included with `mod common;`).
#![allow(dead_code)]

use irradia_radiosity::mesh::{Mesh, MeshOptions};
use irradia_radiosity::scenes;

/// The furnace: a closed unit cube, every wall emitting 1 and reflecting 0.5, cut into
/// `per_side`² elements per wall.
pub fn furnace(per_side: usize) -> Mesh {
    let area = 1.0 / (per_side * per_side) as f64 * 1.000001;
    Mesh::build(
        &scenes::closed_box(1.0, [0.5, 0.4, 0.3], [1.0, 1.0, 1.0]),
        MeshOptions {
            max_element_area: Some(area),
            ..Default::default()
        },
    )
    .unwrap()
}

pub fn furnace_expected() -> [f64; 3] {
    [2.0, 1.0 / 0.6, 1.0 / 0.7]
}

/// A closed cube with a block standing inside (occlusion) and a light in the ceiling.
pub fn box_with_block(area: f64) -> Mesh {
    Mesh::build(
        &scenes::closed_box_with_block([0.6, 0.5, 0.4]),
        MeshOptions {
            max_element_area: Some(area),
            ..Default::default()
        },
    )
    .unwrap()
}
