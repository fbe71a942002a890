//! The lecture's benchmark applications as triangle lists with a view: random triangles,
//! the Utah teapot, and a marching-cubes isosurface (the gyroid of PEERS.md). Triangle
//! `i` keeps id `i`: the serial draw order every parallel mode must reproduce.

use crate::tessellate::uv::triangle_uvs;
use crate::tessellate::{
    object_region, plane_of, plane_view, tessellate_plane, tessellate_solid, PlaneDetail,
    Tessellation,
};
use glam::Vec3;
use irradia_core::{Aabb, Rgb};
use irradia_geometry::generators::random_triangles::{
    random_triangles, RandomTriangles, SizeDistribution,
};
use irradia_geometry::generators::{gyroid_mesh, MeshData};
use irradia_geometry::shapes::bezier::{teapot_patches, tessellate};
use irradia_geometry::Instance;
use irradia_raster::{Mesh, Pipeline, Triangle, Vertex, ViewParams};
use irradia_scene::{Material, Texture};

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
    /// In object order (the serial draw order), ids `0..n`; each triangle's material is
    /// its object's (or CSG leaf's) index into `Scene::materials`, the table of
    /// [`scene_pipeline`].
    pub triangles: Vec<Triangle>,
    /// Per scene object, its triangles' range in `triangles` (empty when skipped).
    pub objects: Vec<std::ops::Range<usize>>,
    /// Names of the objects that could not be made into triangles (open surfaces
    /// without facets, solids with no surface at the tessellation's resolution).
    pub skipped: Vec<String>,
}

impl SceneTriangles {
    /// Whether some triangle's material (in `pipeline`'s table) lets light through,
    /// so that the image depends on the order of the transparent surfaces (sort-last
    /// depth compositing cannot draw it).
    pub fn has_transparency(&self, pipeline: &Pipeline) -> bool {
        self.triangles.iter().any(|t| {
            pipeline
                .materials
                .get(t.material as usize)
                .unwrap_or(&pipeline.material)
                .is_transparent()
        })
    }
}

/// Segments around a full turn when curved shapes are cut into facets.
pub const SCENE_FACET_DETAIL: u32 = 48;

/// [`scene_triangles_with`] at the default resolution.
pub fn scene_triangles(scene: &irradia_scene::Scene) -> SceneTriangles {
    scene_triangles_with(scene, &Tessellation::default())
}

/// The scene's objects as world-space triangles, coloured by their material's texture:
/// objects with facets (`Shape::facets`) as they are, planes cut to the view of
/// [`scene_pipeline`], other solids (CSG, implicit surfaces, unbounded quadrics) by
/// marching cubes (see [`crate::tessellate`]). Checkered surfaces take one colour per
/// triangle (at its centre, or its plane cell's), solid colours one per vertex; image
/// textures take white vertices and, at every corner, the shape's own texture
/// coordinates ([`crate::tessellate::uv`]), and the pipeline looks the image up per
/// fragment (its texture table, [`scene_pipeline`]).
pub fn scene_triangles_with(scene: &irradia_scene::Scene, opts: &Tessellation) -> SceneTriangles {
    let pipeline = scene_pipeline(scene);
    let view = plane_view(pipeline.view.view, pipeline.view.proj, pipeline.height);
    let detail = |m: &Material| PlaneDetail {
        max_cell_px: opts.plane_cell_pixels(pipeline.height),
        checker: match m.color {
            Texture::Checker { scale, .. } => Some(scale),
            _ => None,
        },
    };
    let region = finite_region(scene);
    let mut out = SceneTriangles::default();
    for (obj, inst) in scene.objects.iter().zip(scene.accel.instances()) {
        let first = out.triangles.len();
        out.objects.push(first..first);
        let to_world = *inst.to_world();
        let normal_matrix = inst.to_object().matrix3.transpose();
        let mut mesh = WorldMesh::default();
        if let Some(mut f) = inst.shape.facets(SCENE_FACET_DETAIL) {
            if matches!(
                scene.materials[obj.material as usize].color,
                Texture::Image { .. }
            ) {
                fan_from_centres(&mut f);
            }
            let m = Mesh::from_facets(&f);
            mesh.positions = m
                .positions
                .iter()
                .map(|q| to_world.transform_point3(*q))
                .collect();
            if m.normals.len() == m.positions.len() {
                mesh.normals = m
                    .normals
                    .iter()
                    .map(|n| (normal_matrix * *n).normalize_or_zero())
                    .collect();
            }
            mesh.indices = m.indices;
        } else if inst.shape.kind() == "plane" {
            let Some((p, n)) = plane_of(inst.shape.as_ref()) else {
                out.skipped.push(obj.name.clone());
                continue;
            };
            let mat = &scene.materials[obj.material as usize];
            let n = (normal_matrix * n).normalize_or_zero();
            let pm = tessellate_plane(to_world.transform_point3(p), n, &view, detail(mat));
            mesh.normals = vec![n; pm.positions.len()];
            mesh.positions = pm.positions;
            mesh.indices = pm.indices;
            mesh.colour_points = pm.cell_centres;
            mesh.colour_sizes = pm.cell_sizes;
        } else {
            let bounds = object_region(&inst.shape.bounds(), &region, inst.to_object());
            let solid = tessellate_solid(inst.shape.as_ref(), &bounds, opts.resolution);
            let Some(sm) = solid.filter(|m| !m.indices.is_empty()) else {
                out.skipped.push(obj.name.clone());
                continue;
            };
            mesh.positions = sm
                .positions
                .iter()
                .map(|q| to_world.transform_point3(*q))
                .collect();
            mesh.normals = sm
                .normals
                .iter()
                .map(|n| (normal_matrix * *n).normalize_or_zero())
                .collect();
            mesh.indices = sm.indices;
            mesh.materials = sm
                .leaves
                .iter()
                .map(|&l| obj.material_for_leaf(l))
                .collect();
        }
        mesh.append_to(&mut out.triangles, scene, obj.material, inst);
        if let Some(r) = out.objects.last_mut() {
            r.end = out.triangles.len();
        }
    }
    for (i, t) in out.triangles.iter_mut().enumerate() {
        t.id = i as u32;
    }
    out
}

/// Cuts every convex face of five or more corners (a disk, a cylinder's cap) into a fan
/// around its centroid instead of a fan from its first corner: texture coordinates
/// that are not affine over the face (a disk's angle and radius) are then fitted over
/// narrow wedges ([`crate::tessellate::uv`]) instead of over slivers spanning it.
fn fan_from_centres(f: &mut irradia_geometry::Facets) {
    let faces = std::mem::take(&mut f.faces);
    let smooth = f.normals.len() == f.vertices.len();
    for face in faces {
        let p: Vec<Vec3> = face.iter().map(|&i| f.vertices[i as usize]).collect();
        // Newell's normal, then every turn the same way round it.
        let mut n = Vec3::ZERO;
        for k in 0..p.len() {
            let (a, b) = (p[k], p[(k + 1) % p.len()]);
            n += Vec3::new(
                (a.y - b.y) * (a.z + b.z),
                (a.z - b.z) * (a.x + b.x),
                (a.x - b.x) * (a.y + b.y),
            );
        }
        let convex = (0..p.len()).all(|k| {
            let (a, b, c) = (p[k], p[(k + 1) % p.len()], p[(k + 2) % p.len()]);
            (b - a).cross(c - b).dot(n) >= -1e-6 * n.length_squared()
        });
        if face.len() < 5 || !convex || n == Vec3::ZERO {
            f.faces.push(face);
            continue;
        }
        let c = f.vertices.len() as u32;
        f.vertices.push(p.iter().sum::<Vec3>() / p.len() as f32);
        if smooth {
            let m: Vec3 = face.iter().map(|&i| f.normals[i as usize]).sum();
            f.normals.push(m.normalize_or_zero());
        }
        for k in 0..face.len() {
            f.faces.push(vec![c, face[k], face[(k + 1) % face.len()]]);
        }
    }
}

/// One object's triangles in world space before they become raster triangles.
#[derive(Default)]
struct WorldMesh {
    positions: Vec<Vec3>,
    /// Per vertex, or empty for face normals.
    normals: Vec<Vec3>,
    indices: Vec<[u32; 3]>,
    /// Per triangle (CSG leaves), or empty for the object's material.
    materials: Vec<u32>,
    /// Per triangle, where its one colour is taken (plane cells), or empty.
    colour_points: Vec<Vec3>,
    /// Per triangle with a colour point, the side of the cell it stands for.
    colour_sizes: Vec<f32>,
}

impl WorldMesh {
    fn append_to(
        &self,
        out: &mut Vec<Triangle>,
        scene: &irradia_scene::Scene,
        material: u32,
        instance: &Instance,
    ) {
        for (k, idx) in self.indices.iter().enumerate() {
            let p = idx.map(|i| self.positions[i as usize]);
            let face = (p[1] - p[0]).cross(p[2] - p[0]).normalize_or_zero();
            let m = self.materials.get(k).copied().unwrap_or(material);
            let tex = &scene.materials[m as usize].color;
            // An image is looked up per fragment by the pipeline: white vertices with
            // the surface's texture coordinates.
            let uvs = match tex {
                Texture::Image { .. } => {
                    Some(triangle_uvs(instance, p).unwrap_or([glam::Vec2::ZERO; 3]))
                }
                _ => None,
            };
            let rgba = |q: Vec3| {
                let c = tex.eval(q, glam::Vec2::ZERO);
                [c.r, c.g, c.b, 1.0]
            };
            // A texture that varies takes one colour per triangle, so that checks stay
            // sharp-edged (along the triangle edges) instead of blending across them.
            let flat = match (self.colour_points.get(k), tex) {
                // A cell larger than a check covers as much of either colour: their
                // mean (what the checks average to once they are smaller than pixels).
                (Some(_), Texture::Checker { a, b, scale })
                    if self.colour_sizes.get(k).is_some_and(|s| *s > 1.01 * scale) =>
                {
                    let c = (*a + *b) * 0.5;
                    Some([c.r, c.g, c.b, 1.0])
                }
                (_, Texture::Image { .. }) => Some([1.0; 4]),
                (Some(c), _) => Some(rgba(*c)),
                (None, Texture::Solid(_)) => None,
                (None, _) => Some(rgba((p[0] + p[1] + p[2]) / 3.0)),
            };
            let v = |j: usize| Vertex {
                position: p[j],
                normal: if self.normals.is_empty() {
                    face
                } else {
                    self.normals[idx[j] as usize]
                },
                color: flat.unwrap_or_else(|| rgba(p[j])),
                uv: uvs.map_or(glam::Vec2::ZERO, |u| u[j]),
            };
            out.push(Triangle {
                v: [v(0), v(1), v(2)],
                id: 0,
                material: m,
            });
        }
    }
}

/// The raster material of a scene material: the Whitted tracer's Phong model (`r·v`
/// highlights, the material's ambient, diffuse and specular coefficients, emission;
/// POV-Ray's finish model without distance falloff of point and spot lights). The
/// texture colour comes in as the vertex colour (image textures: through the
/// pipeline's texture table, set by [`scene_pipeline`]).
///
/// Transmission maps to the pipeline's transparent pass: `dst = local + k_t * filter *
/// dst`, the tracer's `local + k_t * filter * (refracted ray)` without refraction's
/// bending (or Fresnel's angle dependence); the filter is the material's
/// `filter_color`, or the surface colour at the fragment. POV-Ray materials scale
/// their ambient and diffuse terms by the opacity `1 - luminance(k_t * filter)` as the
/// tracer does (with the texture's mean colour when the filter is the surface's).
pub fn raster_material(m: &Material) -> irradia_raster::Material {
    let opacity = if m.model == irradia_scene::ShadingModel::PovRay && m.transmission > 0.0 {
        let filter = m.filter_color.unwrap_or_else(|| mean_colour(&m.color));
        (1.0 - (filter * m.transmission).luminance()).clamp(0.0, 1.0)
    } else {
        1.0
    };
    irradia_raster::Material {
        diffuse: Rgb::splat(m.diffuse * opacity),
        specular: Rgb::splat(m.specular),
        shininess: m.shininess,
        two_sided: true,
        ambient: Some(Rgb::splat(m.ambient * opacity)),
        emission: m.emission,
        highlight: irradia_raster::lighting::Highlight::Phong,
        distance_falloff: m.model != irradia_scene::ShadingModel::PovRay,
        texture: None,
        transmission: m.transmission.max(0.0),
        filter: m.filter_color,
    }
}

/// A texture's average colour.
fn mean_colour(t: &Texture) -> Rgb {
    match t {
        Texture::Solid(c) => *c,
        Texture::Checker { a, b, .. } => (*a + *b) * 0.5,
        Texture::Image { image, .. } => image.mean(),
    }
}

/// A pipeline with the scene's camera, image size, lights (area lights as the
/// rasterizer approximates them; no shadows), materials (one table entry per scene
/// material, [`raster_material`]) and image textures (one table entry per material
/// with an image), Phong shading per pixel. With an unbounded object
/// in the scene the far plane is pushed out to 1000 times the scene's size, so that
/// planes reach almost to the horizon.
pub fn scene_pipeline(scene: &irradia_scene::Scene) -> Pipeline {
    let (w, h) = (scene.settings.width, scene.settings.height);
    let mut p = Pipeline::new(w, h);
    let r = scene_radius(scene);
    let dist = (scene.camera.look_at - scene.camera.eye).length().max(1e-3);
    let unbounded = scene
        .accel
        .instances()
        .iter()
        .any(|i| !i.bounds().is_finite());
    let mut far = if unbounded {
        1000.0 * (dist + r)
    } else {
        dist + 4.0 * r
    };
    let mut near = (dist * 1e-3).min(r * 1e-3).max(1e-4);
    if unbounded {
        // A plane at height `h` below the eye ends `h / far` radians short of its
        // horizon: far enough out that this is under a quarter of a pixel.
        let probe = ViewParams::from_camera(&scene.camera, w, h, near, far);
        let pixel = 2.0 / (probe.proj.y_axis.y.abs().max(1e-12) * h.max(1) as f32);
        for inst in scene.accel.instances() {
            if inst.shape.kind() != "plane" {
                continue;
            }
            if let Some((q, n)) = plane_of(inst.shape.as_ref()) {
                let q = inst.to_world().transform_point3(q);
                let n = (inst.to_object().matrix3.transpose() * n).normalize_or_zero();
                let height = (scene.camera.eye - q).dot(n).abs();
                far = far.max(height / (0.25 * pixel));
            }
        }
        // An f32 depth buffer tells depths apart near the far plane only while far /
        // near stays below about 1e6 (z = 1 - near / d in front of the clear value 1):
        // beyond that the far part of a plane rounds to z = 1 and fails the depth test.
        near = near.max(far * 1e-6);
    }
    p.view = ViewParams::from_camera(&scene.camera, w, h, near, far);
    p.materials = scene.materials.iter().map(raster_material).collect();
    for (m, sm) in p.materials.iter_mut().zip(&scene.materials) {
        if let Texture::Image { image, scale } = &sm.color {
            m.texture = Some(p.textures.len() as u32);
            p.textures
                .push(irradia_raster::Texture::new(image.clone(), *scale));
        }
    }
    p.lights = irradia_raster::Lights::from_scene(&scene.lights, scene.settings.ambient_light);
    if scene.lights.is_empty() {
        // Scenes lit only by emitting objects (for the path tracer): a headlight and a
        // dim ambient term, so that the rasterizer shows their shapes and colours.
        let forward = (scene.camera.look_at - scene.camera.eye).normalize_or_zero();
        p.lights = irradia_raster::Lights {
            ambient: Rgb::splat(0.15),
            lights: vec![irradia_raster::lighting::RasterLight::Directional {
                direction: forward,
                color: Rgb::splat(0.85),
            }],
        };
        for m in &mut p.materials {
            m.ambient = None;
        }
    }
    p.shading = irradia_raster::Shading::Phong;
    p.background = Some(scene.settings.background);
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

/// Where unbounded solids other than planes are tessellated: the box around the finite
/// objects, the eye and the camera's target, grown by half its size on every side.
pub fn finite_region(scene: &irradia_scene::Scene) -> Aabb {
    let mut b = Aabb::from_points([scene.camera.eye, scene.camera.look_at]);
    for inst in scene.accel.instances() {
        let ib = inst.bounds();
        if ib.is_finite() {
            b = b.union(ib);
        }
    }
    let margin = Vec3::splat((0.5 * b.extent().max_element()).max(1.0));
    Aabb::new(b.min - margin, b.max + margin)
}
