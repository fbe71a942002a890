//! Tests of the light selection: the probability of picking each light, by power and uniformly.

use super::*;
use irradia_scene::{Camera, FovAxis, Projection, RenderSettings};

/// Two point lights of intensity 1 and 3 seen from the origin: the probability of
/// choosing each, read from the delta sample's pdf.
fn pick_probabilities(selection: LightSelection) -> Vec<f32> {
    let camera = Camera {
        eye: Vec3::Z,
        look_at: Vec3::ZERO,
        up: Vec3::Y,
        projection: Projection::Perspective {
            fov_degrees: 45.0,
            axis: FovAxis::Vertical,
        },
        near_clip: 0.0,
    };
    let settings = RenderSettings {
        light_selection: selection,
        ..RenderSettings::default()
    };
    let light = |x: f32, i: f32| Light::Point {
        position: Vec3::new(x, 1.0, 0.0),
        intensity: Rgb::splat(i),
    };
    let scene = Scene::new(
        camera,
        settings,
        vec![],
        vec![light(-1.0, 1.0), light(1.0, 3.0)],
        vec![],
        vec![],
    );
    let lights = LightSampler::new(&scene);
    [0.1, 0.9]
        .iter()
        .map(|&u| {
            let s = lights
                .sample(&scene, Vec3::ZERO, u, Vec2::splat(0.5))
                .unwrap();
            assert!(s.delta);
            s.pdf
        })
        .collect()
}

#[test]
fn power_selection_follows_intensity() {
    let p = pick_probabilities(LightSelection::Power);
    assert!(
        (p[0] - 0.25).abs() < 1e-6 && (p[1] - 0.75).abs() < 1e-6,
        "{p:?}"
    );
}

#[test]
fn uniform_selection_is_mitsubas() {
    let p = pick_probabilities(LightSelection::Uniform);
    assert!(
        (p[0] - 0.5).abs() < 1e-6 && (p[1] - 0.5).abs() < 1e-6,
        "{p:?}"
    );
}
