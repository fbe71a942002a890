//! The hemicube drawn by the software rasterizer: its error against the exact
//! point-to-polygon form factor at the centroids (what one hemicube per element
//! approximates) falls as the resolution grows.

use irradia_radiosity::formfactor::contour::point_to_polygon;
use irradia_radiosity::formfactor::{self, Method, Params};
use irradia_radiosity::mesh::{Mesh, MeshOptions};
use irradia_radiosity::scenes;

#[test]
fn hemicube_converges_to_the_centroid_form_factors() {
    // An empty closed box: no occlusion, so the contour integral at each centroid is
    // exactly what the hemicube estimates.
    let mesh = Mesh::build(
        &scenes::closed_box(1.0, [0.5; 3], [1.0; 3]),
        MeshOptions {
            max_element_area: Some(0.25 * 1.000001),
            ..Default::default()
        },
    )
    .unwrap();
    let n = mesh.len();
    let mut exact = vec![0.0; n * n];
    for (i, ei) in mesh.elements.iter().enumerate() {
        for (j, ej) in mesh.elements.iter().enumerate() {
            if i != j {
                exact[i * n + j] =
                    point_to_polygon(ei.centroid, ei.normal, ej.poly.verts()).max(0.0);
            }
        }
    }
    let mut errors = Vec::new();
    for r in [8usize, 32, 128, 512] {
        let hc = formfactor::method(
            Method::Hemicube,
            Params {
                hemicube_resolution: r,
                ..Default::default()
            },
        )
        .compute(&mesh, None)
        .unwrap();
        let e =
            hc.f.iter()
                .zip(&exact)
                .map(|(a, b)| (a - b).abs())
                .fold(0.0, f64::max);
        println!("hemicube {r:>4}: max error {e:.3e}");
        errors.push(e);
    }
    for w in errors.windows(2) {
        assert!(w[1] < w[0] * 0.6, "hemicube error did not fall: {errors:?}");
    }
    assert!(errors[3] < 2e-3, "{errors:?}");
}
