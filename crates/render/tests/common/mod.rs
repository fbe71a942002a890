//! Scenes built in code for the render tests (no file loader needed).
#![allow(dead_code)]

use glam::{Affine3A, Vec3};
use irradia_core::Rgb;
use irradia_geometry::shapes::Sphere;
use irradia_geometry::Instance;
use irradia_scene::{
    Camera, FovAxis, Light, Material, Object, Projection, RenderSettings, Scene, Texture,
};
use std::sync::Arc;

pub fn camera(eye: Vec3, look_at: Vec3, fov: f32) -> Camera {
    Camera {
        eye,
        look_at,
        up: Vec3::Y,
        projection: Projection::Perspective {
            fov_degrees: fov,
            axis: FovAxis::Horizontal,
        },
        near_clip: 0.0,
    }
}

pub fn settings(width: u32, height: u32) -> RenderSettings {
    RenderSettings {
        width,
        height,
        ..RenderSettings::default()
    }
}

pub fn diffuse(name: &str, c: Rgb, kd: f32) -> Material {
    Material {
        name: name.into(),
        color: Texture::Solid(c),
        ambient: 0.0,
        diffuse: kd,
        specular: 0.0,
        ..Material::default()
    }
}

/// One sphere object per (centre, radius, material index, name).
pub fn spheres(list: &[(Vec3, f32, u32, &str)]) -> (Vec<Object>, Vec<Instance>) {
    let mut objects = Vec::new();
    let mut instances = Vec::new();
    for &(c, r, m, name) in list {
        objects.push(Object {
            name: name.into(),
            material: m,
            leaf_materials: Vec::new(),
        });
        instances.push(Instance::new(
            Arc::new(Sphere::new(Vec3::ZERO, 1.0)),
            Affine3A::from_scale_rotation_translation(Vec3::splat(r), glam::Quat::IDENTITY, c),
        ));
    }
    (objects, instances)
}

/// A small showcase: a ground sphere, a mirror, a glass ball, a point light and a rect
/// area light (soft shadows, so random numbers matter).
pub fn showcase(width: u32, height: u32) -> Scene {
    let mut s = settings(width, height);
    s.background = Rgb::new(0.2, 0.3, 0.5);
    let ground = Material {
        name: "ground".into(),
        color: Texture::Checker {
            a: Rgb::new(0.9, 0.9, 0.9),
            b: Rgb::new(0.2, 0.2, 0.2),
            scale: 1.0,
        },
        ambient: 0.1,
        diffuse: 0.8,
        ..Material::default()
    };
    let mirror = Material {
        name: "mirror".into(),
        color: Texture::Solid(Rgb::WHITE),
        ambient: 0.0,
        diffuse: 0.1,
        specular: 0.8,
        shininess: 60.0,
        reflection: Rgb::splat(0.8),
        ..Material::default()
    };
    let glass = Material {
        name: "glass".into(),
        color: Texture::Solid(Rgb::WHITE),
        ambient: 0.0,
        diffuse: 0.0,
        specular: 0.8,
        shininess: 100.0,
        reflection: Rgb::splat(1.0),
        transmission: 1.0,
        filter_color: Some(Rgb::new(0.9, 1.0, 0.9)),
        ior: 1.5,
        fresnel: true,
        ..Material::default()
    };
    let (objects, instances) = spheres(&[
        (Vec3::new(0.0, -1000.0, 0.0), 1000.0, 0, "ground"),
        (Vec3::new(1.0, 1.0, 0.0), 1.0, 1, "mirror"),
        (Vec3::new(-1.2, 0.8, 1.0), 0.8, 2, "glass"),
    ]);
    let lights = vec![
        Light::Point {
            position: Vec3::new(-3.0, 6.0, 4.0),
            intensity: Rgb::splat(30.0),
        },
        Light::Rect {
            corner: Vec3::new(2.0, 5.0, 2.0),
            edge_u: Vec3::new(1.0, 0.0, 0.0),
            edge_v: Vec3::new(0.0, 0.0, 1.0),
            radiance: Rgb::splat(4.0),
            samples: 4,
        },
    ];
    Scene::new(
        camera(Vec3::new(0.0, 2.0, 6.0), Vec3::new(0.0, 0.8, 0.0), 60.0),
        s,
        vec![ground, mirror, glass],
        lights,
        objects,
        instances,
    )
}
