//! Small scenes built in code for the path tracer's statistical tests.
#![allow(dead_code)]

pub mod wide;

use glam::{Affine3A, Vec3};
use irradia_core::Rgb;
use irradia_geometry::shapes::Sphere;
use irradia_geometry::Instance;
use irradia_scene::{
    Camera, FovAxis, Integrator, Material, Object, Projection, RenderSettings, Scene, Texture,
};
use std::sync::Arc;

pub fn diffuse(albedo: f32, emission: f32) -> Material {
    Material {
        color: Texture::Solid(Rgb::WHITE),
        ambient: 0.0,
        diffuse: albedo,
        emission: Rgb::splat(emission),
        ..Material::default()
    }
}

pub fn settings(w: u32, h: u32, max_depth: u32, background: Rgb) -> RenderSettings {
    RenderSettings {
        width: w,
        height: h,
        max_depth,
        spp: 1,
        background,
        integrator: Integrator::Path,
        ..RenderSettings::default()
    }
}

pub fn camera(eye: Vec3, look_at: Vec3, fov: f32) -> Camera {
    Camera {
        eye,
        look_at,
        up: Vec3::Y,
        projection: Projection::Perspective {
            fov_degrees: fov,
            axis: FovAxis::Vertical,
        },
        near_clip: 0.0,
    }
}

/// Clear glass of index `ior` (the lecture's transmission with Fresnel weights).
pub fn clear_glass(ior: f32) -> Material {
    Material {
        diffuse: 0.0,
        transmission: 1.0,
        ior,
        fresnel: true,
        ..diffuse(0.0, 0.0)
    }
}

pub fn object(name: &str, material: u32) -> Object {
    Object {
        name: name.into(),
        material,
        leaf_materials: vec![],
    }
}

/// The inside of a closed ellipsoid (a sphere stretched by its transform, which also
/// exercises the area Jacobian of light sampling) with reflectance `rho` and uniform
/// two-sided emission `e`, seen from inside.
pub fn furnace_sphere(rho: f32, e: f32) -> Scene {
    let shape = Arc::new(Sphere::new(Vec3::ZERO, 2.0));
    let inst = Instance::new(shape, Affine3A::from_scale(Vec3::new(1.0, 1.5, 1.0)));
    Scene::new(
        camera(Vec3::new(0.3, -0.2, 0.1), Vec3::new(1.0, 0.0, -1.0), 90.0),
        settings(16, 12, 200, Rgb::BLACK),
        vec![Material {
            emission_two_sided: true,
            ..diffuse(rho, e)
        }],
        vec![],
        vec![object("shell", 0)],
        vec![inst],
    )
}

/// A white (albedo 1) diffuse sphere in a uniform environment.
pub fn white_sphere_in_environment(env: f32) -> Scene {
    let shape = Arc::new(Sphere::new(Vec3::ZERO, 1.0));
    Scene::new(
        camera(Vec3::new(0.0, 0.0, 4.0), Vec3::ZERO, 35.0),
        settings(16, 12, 400, Rgb::splat(env)),
        vec![diffuse(1.0, 0.0)],
        vec![],
        vec![object("ball", 0)],
        vec![Instance::untransformed(shape)],
    )
}

/// A small room (the inside of a big sphere), a glossy ball, a glass ball and a
/// spherical emitter: every kind of lobe and MIS on an emissive object.
pub fn small_room() -> Scene {
    let room = Instance::untransformed(Arc::new(Sphere::new(Vec3::ZERO, 5.0)));
    let ball = Instance::untransformed(Arc::new(Sphere::new(Vec3::new(-1.0, -0.5, 0.0), 1.0)));
    let glass = Instance::untransformed(Arc::new(Sphere::new(Vec3::new(1.2, -0.8, 0.5), 0.7)));
    let lamp = Instance::untransformed(Arc::new(Sphere::new(Vec3::new(0.0, 3.0, 0.0), 0.5)));
    let glossy = Material {
        specular: 0.4,
        shininess: 30.0,
        ..diffuse(0.5, 0.0)
    };
    let clear = clear_glass(1.5);
    Scene::new(
        camera(Vec3::new(0.0, 0.0, 4.5), Vec3::new(0.0, -0.3, 0.0), 60.0),
        settings(16, 12, 8, Rgb::BLACK),
        vec![diffuse(0.6, 0.0), glossy, clear, diffuse(0.0, 8.0)],
        vec![],
        vec![
            object("room", 0),
            object("ball", 1),
            object("glass", 2),
            object("lamp", 3),
        ],
        vec![room, ball, glass, lamp],
    )
}

/// A softly lit room (no caustics, a large lamp) with diffuse and glossy surfaces: low
/// variance paths through next-event estimation, MIS and Russian roulette.
pub fn soft_room() -> Scene {
    let room = Instance::untransformed(Arc::new(Sphere::new(Vec3::ZERO, 5.0)));
    let ball = Instance::untransformed(Arc::new(Sphere::new(Vec3::new(-1.0, -0.5, 0.0), 1.0)));
    let ball2 = Instance::untransformed(Arc::new(Sphere::new(Vec3::new(1.2, -0.8, 0.5), 0.7)));
    let lamp = Instance::untransformed(Arc::new(Sphere::new(Vec3::new(0.0, 3.0, 0.0), 1.2)));
    let glossy = Material {
        specular: 0.3,
        shininess: 10.0,
        ..diffuse(0.5, 0.0)
    };
    Scene::new(
        camera(Vec3::new(0.0, 0.0, 4.5), Vec3::new(0.0, -0.3, 0.0), 60.0),
        settings(16, 12, 8, Rgb::BLACK),
        vec![
            diffuse(0.6, 0.0),
            glossy,
            diffuse(0.8, 0.0),
            diffuse(0.0, 2.0),
        ],
        vec![],
        vec![
            object("room", 0),
            object("ball", 1),
            object("ball2", 2),
            object("lamp", 3),
        ],
        vec![room, ball, ball2, lamp],
    )
}

/// Which vertex normals [`uv_sphere_mesh`] gets.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SphereNormals {
    /// Given: the sphere's outward normals.
    Outward,
    /// Given, pointing into the sphere (they turn the geometric normal inwards).
    Inward,
    /// None given: the mesh averages its faces' normals.
    Computed,
    /// Flat: every triangle its own corners, each given the face's normal (what
    /// ignoring the vertex normals would shade with).
    Faceted,
}

/// A coarse unit sphere as a triangle mesh of `rings` bands of `segments` quads
/// (wound counter-clockwise seen from outside; the pole quads are triangles plus a
/// degenerate one), with smooth vertex normals: with few triangles the interpolated
/// normals are far from the faces' normals.
pub fn uv_sphere_mesh(
    rings: u32,
    segments: u32,
    normals: SphereNormals,
) -> irradia_geometry::TriangleMesh {
    use std::f32::consts::PI;
    let mut positions = Vec::new();
    for i in 0..=rings {
        let theta = PI * i as f32 / rings as f32;
        for j in 0..segments {
            let phi = 2.0 * PI * j as f32 / segments as f32;
            positions.push(Vec3::new(
                theta.sin() * phi.cos(),
                theta.cos(),
                theta.sin() * phi.sin(),
            ));
        }
    }
    let at = |i: u32, j: u32| i * segments + j % segments;
    let mut indices = Vec::new();
    for i in 0..rings {
        for j in 0..segments {
            let (a, b, c, d) = (at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
            indices.push([a, c, b]);
            indices.push([a, d, c]);
        }
    }
    // Outward winding: the face normal of a band triangle points away from the centre.
    let [a, b, c] = indices[2].map(|i| positions[i as usize]);
    assert!((b - a).cross(c - a).dot(a + b + c) > 0.0, "winding");
    let given = match normals {
        SphereNormals::Outward => Some(positions.clone()),
        SphereNormals::Inward => Some(positions.iter().map(|p| -*p).collect()),
        SphereNormals::Computed => None,
        SphereNormals::Faceted => {
            let corners: Vec<Vec3> = indices
                .iter()
                .flat_map(|t| t.map(|i| positions[i as usize]))
                .collect();
            let normals = corners
                .chunks(3)
                .flat_map(|c| [(c[1] - c[0]).cross(c[2] - c[0]).normalize_or(Vec3::Y); 3])
                .collect();
            let indices = (0..indices.len() as u32)
                .map(|k| [3 * k, 3 * k + 1, 3 * k + 2])
                .collect();
            return irradia_geometry::TriangleMesh::new(corners, indices, Some(normals), None)
                .unwrap();
        }
    };
    irradia_geometry::TriangleMesh::new(positions, indices, given, None).unwrap()
}
