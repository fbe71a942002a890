//! The lecture's benchmark applications as triangle lists with a view: random triangles,
//! the Utah teapot, and a marching-cubes isosurface (the gyroid of PEERS.md). Triangle
//! `i` keeps id `i`: the serial draw order every parallel mode must reproduce.

use glam::Vec3;
use irradia_geometry::generators::random_triangles::{
    random_triangles, RandomTriangles, SizeDistribution,
};
use irradia_geometry::generators::{gyroid_mesh, MeshData};
use irradia_geometry::shapes::bezier::{teapot_patches, tessellate};
use irradia_raster::{Mesh, Pipeline, Triangle, ViewParams};

/// A workload by name and size.
#[derive(Clone, Debug, PartialEq)]
pub enum Workload {
    /// `count` random triangles in [-1,1]^3 (mean area 0.002).
    RandomTriangles { count: usize, seed: u64 },
    /// The teapot tessellated at `level` (level^2 * 2 triangles per patch, 32 patches).
    Teapot { level: u32 },
    /// The gyroid by marching cubes on an n^3 grid.
    MarchingCubes { n: u32 },
}

impl Workload {
    pub fn name(&self) -> &'static str {
        match self {
            Workload::RandomTriangles { .. } => "random-triangles",
            Workload::Teapot { .. } => "teapot",
            Workload::MarchingCubes { .. } => "marching-cubes",
        }
    }

    /// The workload called `name` with about `triangles` triangles.
    pub fn by_name(name: &str, triangles: usize) -> Option<Self> {
        let t = triangles.max(1) as f64;
        Some(match name {
            "random-triangles" => Workload::RandomTriangles {
                count: triangles,
                seed: 1,
            },
            "teapot" => Workload::Teapot {
                level: ((t / 64.0).sqrt().round() as u32).max(1),
            },
            // the gyroid makes about 19 n^2 triangles on an n^3 grid
            "marching-cubes" => Workload::MarchingCubes {
                n: ((t / 19.0).sqrt().round() as u32).max(4),
            },
            _ => return None,
        })
    }

    /// The triangles, each with a colour, in serial order.
    pub fn triangles(&self) -> Vec<Triangle> {
        let (positions, indices, center, radius) = match self {
            Workload::RandomTriangles { count, seed } => {
                let m = random_triangles(&RandomTriangles::new(
                    *count,
                    SizeDistribution::Constant(0.002),
                    *seed,
                ));
                (m.positions, m.indices, Vec3::ZERO, 1.8)
            }
            Workload::Teapot { level } => {
                let t = tessellate(&teapot_patches(), (*level).max(1));
                (t.positions, t.indices, Vec3::new(0.0, 0.0, 1.5), 3.8)
            }
            Workload::MarchingCubes { n } => {
                let MeshData { positions, indices } = gyroid_mesh((*n).max(4));
                (positions, indices, Vec3::ZERO, 1.8)
            }
        };
        let _ = (center, radius);
        let mut mesh = Mesh::new(positions, indices);
        mesh.colors = (0..mesh.positions.len())
            .map(|i| {
                let h = (i as u32).wrapping_mul(2_654_435_761);
                [
                    0.35 + 0.6 * ((h >> 8) & 255) as f32 / 255.0,
                    0.35 + 0.6 * ((h >> 16) & 255) as f32 / 255.0,
                    0.8,
                    1.0,
                ]
            })
            .collect();
        mesh.compute_vertex_normals();
        let mut tris = mesh.to_triangles();
        for (i, t) in tris.iter_mut().enumerate() {
            t.id = i as u32;
        }
        tris
    }

    /// A pipeline looking at the workload from a fixed viewpoint.
    pub fn pipeline(&self, width: u32, height: u32) -> Pipeline {
        let (eye, target, up) = match self {
            Workload::Teapot { .. } => {
                // frame the teapot's bounds, whatever axis its data calls up
                let t = tessellate(&teapot_patches(), 2);
                let (mut lo, mut hi) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
                for q in &t.positions {
                    lo = lo.min(*q);
                    hi = hi.max(*q);
                }
                let c = 0.5 * (lo + hi);
                let r = 0.5 * (hi - lo).length();
                let ext = hi - lo;
                let up = if ext.z < ext.x.min(ext.y) * 1.2 && ext.z <= ext.y {
                    Vec3::Z
                } else {
                    Vec3::Y
                };
                let side = if up == Vec3::Z {
                    Vec3::new(0.8, -0.55, 0.35)
                } else {
                    Vec3::new(0.8, 0.35, 0.55)
                };
                (c + side.normalize() * r * 2.3, c, up)
            }
            _ => (Vec3::new(1.5, 1.1, 1.9), Vec3::ZERO, Vec3::Y),
        };
        let mut p = Pipeline::new(width, height);
        p.view = ViewParams::look_at_perspective(
            eye,
            target,
            up,
            45.0,
            width as f32 / height as f32,
            0.1,
            100.0,
        );
        p
    }
}

/// A scene's objects as raster triangles, for `irradia parallel --workload SCENE`.
#[derive(Clone, Debug, Default)]
pub struct SceneTriangles {
    /// In object order (the serial draw order), ids `0..n`.
    pub triangles: Vec<Triangle>,
    /// Names of the objects that have no facets (unbounded planes, CSG, implicit
    /// surfaces) and so are left out.
    pub skipped: Vec<String>,
}

/// Segments around a full turn when curved shapes are cut into facets.
pub const SCENE_FACET_DETAIL: u32 = 48;

/// The scene's objects cut into facets (`Shape::facets`), moved to world space, each
/// vertex coloured by its object's material texture there.
pub fn scene_triangles(scene: &irradia_scene::Scene) -> SceneTriangles {
    let mut out = SceneTriangles::default();
    for (obj, inst) in scene.objects.iter().zip(scene.accel.instances()) {
        let Some(f) = inst.shape.facets(SCENE_FACET_DETAIL) else {
            out.skipped.push(obj.name.clone());
            continue;
        };
        let mut mesh = Mesh::from_facets(&f);
        let to_world = *inst.to_world();
        let normal_matrix = inst.to_object().matrix3.transpose();
        for q in &mut mesh.positions {
            *q = to_world.transform_point3(*q);
        }
        if mesh.normals.len() == mesh.positions.len() {
            for n in &mut mesh.normals {
                *n = (normal_matrix * *n).normalize_or_zero();
            }
        } else {
            mesh.normals.clear(); // flat: face normals
        }
        let mat = &scene.materials[obj.material as usize];
        mesh.colors = mesh
            .positions
            .iter()
            .map(|q| {
                let c = mat.color.eval(*q, glam::Vec2::ZERO) * mat.diffuse + mat.emission;
                [c.r, c.g, c.b, 1.0]
            })
            .collect();
        out.triangles.extend(mesh.to_triangles());
    }
    for (i, t) in out.triangles.iter_mut().enumerate() {
        t.id = i as u32;
    }
    out
}

/// A pipeline with the scene's camera, image size and lights (area lights as the
/// rasterizer approximates them; no shadows), Phong shading per pixel.
pub fn scene_pipeline(scene: &irradia_scene::Scene) -> Pipeline {
    let (w, h) = (scene.settings.width, scene.settings.height);
    let mut p = Pipeline::new(w, h);
    let r = scene_radius(scene);
    let dist = (scene.camera.look_at - scene.camera.eye).length().max(1e-3);
    p.view = ViewParams::from_camera(
        &scene.camera,
        w,
        h,
        (dist * 1e-3).min(r * 1e-3).max(1e-4),
        dist + 4.0 * r,
    );
    let used: Vec<f32> = scene
        .objects
        .iter()
        .map(|o| scene.materials[o.material as usize].ambient)
        .collect();
    let ambient = used.iter().sum::<f32>() / used.len().max(1) as f32;
    p.lights =
        irradia_raster::Lights::from_scene(&scene.lights, scene.settings.ambient_light * ambient);
    if scene.lights.is_empty() {
        // Scenes lit only by emitting objects (for the path tracer): a headlight and a
        // dim ambient term, so that the rasterizer shows their shapes and colours.
        let forward = (scene.camera.look_at - scene.camera.eye).normalize_or_zero();
        p.lights = irradia_raster::Lights {
            ambient: irradia_core::Rgb::splat(0.15),
            lights: vec![irradia_raster::lighting::RasterLight::Directional {
                direction: forward,
                color: irradia_core::Rgb::splat(0.85),
            }],
        };
    }
    p.shading = irradia_raster::Shading::Phong;
    p
}

/// Radius of the finite part of the scene around the camera's target.
fn scene_radius(scene: &irradia_scene::Scene) -> f32 {
    let mut r: f32 = 1.0;
    for inst in scene.accel.instances() {
        let b = inst.bounds();
        if b.min.is_finite() && b.max.is_finite() {
            r = r
                .max((b.min - scene.camera.look_at).length())
                .max((b.max - scene.camera.look_at).length());
        }
    }
    r
}
