//! Scene workloads drawn by the rasterizer against the ray caster and the Whitted
//! tracer (the oracles): which object each pixel sees and its depth (a plane and a
//! sphere; a CSG difference and an implicit surface tessellated by marching cubes),
//! per-object highlights, and the parallel sorting schemes and submission with several
//! materials equal to the serial render bit for bit.

use glam::Vec3;
use irradia_core::{Image, Rgb};
use irradia_core::{Ray, Rng};
use irradia_parallel::comm::{run_local, LocalOptions};
use irradia_parallel::composite::{CompositeOptions, Strategy};
use irradia_parallel::submission::{self, Batch};
use irradia_parallel::tessellate::Tessellation;
use irradia_parallel::workload::{scene_pipeline, scene_triangles_with, SceneTriangles};
use irradia_parallel::{sort_common, sort_first, sort_last, sort_middle};
use irradia_raster::{
    ColorBuffer, ColorFormat, Framebuffer, Lights, Material, Mesh, MeshError, Pipeline,
    RasterLight, Shading, Triangle, ViewParams,
};
use irradia_render::{AovSample, Integrator, Stats, Whitted};
use irradia_scene::{Scene, SceneSyntax, Texture};
use std::path::Path;

fn scene(body: &str) -> Scene {
    let text = format!(
        "[image]\nwidth = 64\nheight = 48\n\n[camera]\neye = [0, 3, 3.5]\nlook_at = [0, 0.4, 0]\nfov = 50\n\n[render]\nambient_light = 0.3\n\n[[lights]]\ntype = \"point\"\nposition = [2, 5, 4]\nintensity = 40\n\n{body}"
    );
    irradia_scene::load_str(&text, SceneSyntax::Toml, Path::new("test.toml")).unwrap()
}

fn tessellate(s: &Scene, resolution: u32) -> SceneTriangles {
    scene_triangles_with(s, &Tessellation { resolution })
}

/// The object each pixel's triangle belongs to (`None` where nothing was drawn) and
/// the eye depth there.
fn raster_ids(s: &Scene, st: &SceneTriangles) -> (Vec<Option<usize>>, Vec<f32>, Pipeline) {
    let p = scene_pipeline(s);
    let mut fb = Framebuffer::new(p.width, p.height, ColorFormat::Id).unwrap();
    p.render_triangles(&st.triangles, &mut fb).unwrap();
    let ColorBuffer::Id(ids) = &fb.color else {
        unreachable!()
    };
    let object = ids
        .iter()
        .zip(&fb.depth)
        .map(|(&id, &z)| {
            (z < 1.0).then(|| {
                st.objects
                    .iter()
                    .position(|r| r.contains(&(id as usize)))
                    .unwrap()
            })
        })
        .collect();
    let depth = fb.depth.iter().map(|&z| p.view.eye_depth(z)).collect();
    (object, depth, p)
}

/// The ray caster through every pixel centre: (object, eye depth along the view axis,
/// unit normal, CSG leaf).
fn ray_cast(s: &Scene) -> Vec<Option<(usize, f32, Vec3, u32)>> {
    let (w, h) = (s.settings.width, s.settings.height);
    let rays = s.camera.rays(w, h);
    let fwd = rays.forward();
    (0..w * h)
        .map(|i| {
            let ray = rays.ray((i % w) as f32 + 0.5, (i / w) as f32 + 0.5);
            let hit = s.accel.intersect(&ray, f32::INFINITY)?;
            let depth = hit.hit.t * ray.dir.dot(fwd);
            Some((hit.instance as usize, depth, hit.hit.normal, hit.hit.leaf))
        })
        .collect()
}

/// Pixels whose neighbours up to `r` pixels away see the same object (and leaf) with a
/// normal within `cos` of theirs: away from silhouettes and creases.
fn interior(
    cast: &[Option<(usize, f32, Vec3, u32)>],
    (w, h): (u32, u32),
    r: i64,
    cos: f32,
) -> Vec<usize> {
    let mut out = Vec::new();
    for y in r..h as i64 - r {
        for x in r..w as i64 - r {
            let i = (y * w as i64 + x) as usize;
            let Some((o, _, n, leaf)) = cast[i] else {
                continue;
            };
            let same = (-r..=r).all(|dy| {
                (-r..=r).all(|dx| {
                    let j = ((y + dy) * w as i64 + x + dx) as usize;
                    matches!(cast[j], Some((o2, _, n2, l2)) if o2 == o && l2 == leaf && n2.dot(n) > cos)
                })
            });
            if same {
                out.push(i);
            }
        }
    }
    out
}

#[test]
fn a_plane_and_a_sphere_match_the_ray_caster_in_object_and_depth() {
    let s = scene(
        r#"
[materials.floor]
color = { type = "checker", colors = [0.8, 0.3], scale = 0.5 }
[materials.red]
color = [0.9, 0.2, 0.1]
[[objects]]
type = "plane"
normal = [0, 1, 0]
material = "floor"
[[objects]]
type = "sphere"
center = [0.2, 0.7, 0]
radius = 0.7
material = "red"
"#,
    );
    let st = tessellate(&s, 32);
    assert!(st.skipped.is_empty(), "{:?}", st.skipped);
    let (ids, depth, _) = raster_ids(&s, &st);
    let cast = ray_cast(&s);
    let (w, h) = (64, 48);
    let pixels = interior(&cast, (w, h), 1, 0.9);
    let mut seen = [0; 2];
    for &i in &pixels {
        let (o, truth, n, _) = cast[i].unwrap();
        assert_eq!(ids[i], Some(o), "pixel {i}: raster object vs ray caster");
        seen[o] += 1;
        let (x, y) = (i as u32 % w, i as u32 / w);
        let dir = s.camera.rays(w, h).ray(x as f32 + 0.5, y as f32 + 0.5).dir;
        let cos = n.dot(dir).abs().max(0.2);
        // The plane is cut exactly; the sphere's facets lie inside it by at most the
        // chord sagitta of 48 segments per turn.
        let sagitta = if o == 1 {
            0.7 * (1.0 - (2.0 * std::f32::consts::PI / 48.0).cos()) / cos
        } else {
            0.0
        };
        let tol = 2e-3 * truth + sagitta;
        assert!(
            (depth[i] - truth).abs() <= tol,
            "pixel {i} (object {o}): z-buffer {} vs ray {truth}, tolerance {tol}",
            depth[i]
        );
    }
    assert!(seen[0] > 500 && seen[1] > 200, "{seen:?}");
}

#[test]
fn a_csg_difference_and_an_implicit_surface_match_the_ray_caster_depth() {
    let s = scene(
        r#"
[materials.a]
color = [0.9, 0.6, 0.2]
[materials.b]
color = [0.2, 0.6, 0.9]
[[objects]]
name = "sphere minus box"
type = "difference"
material = "a"
children = [
  { type = "sphere", center = [0, 0, 0], radius = 0.9 },
  { type = "box", min = [0, 0, 0], max = [1, 1, 1] },
]
transform = [{ rotate = [0, 20, 0] }, { translate = [-0.8, 0.6, 0] }]
[[objects]]
name = "implicit"
type = "implicit"
expr = "x^2 + 2*y^2 + z^2 - 0.36"
bounds = { min = [-0.7, -0.5, -0.7], max = [0.7, 0.5, 0.7] }
material = "b"
transform = [{ translate = [0.9, 0.5, 0.2] }]
"#,
    );
    let resolution = 40;
    let st = tessellate(&s, resolution);
    assert!(st.skipped.is_empty(), "{:?}", st.skipped);
    let (ids, depth, _) = raster_ids(&s, &st);
    let cast = ray_cast(&s);
    // Two pixels from any crease: marching cubes bevels sharp edges across a cell.
    let pixels = interior(&cast, (64, 48), 2, 0.8);
    let mut seen = [0; 2];
    let mut worst: f32 = 0.0;
    for &i in &pixels {
        let (o, truth, _, _) = cast[i].unwrap();
        assert_eq!(ids[i], Some(o), "pixel {i}");
        seen[o] += 1;
        worst = worst.max((depth[i] - truth).abs());
    }
    // Vertices lie on the surface; between them the chords of cells 1.9/40 wide sag
    // by about h²/8r ~ 3e-4. Midpoint marching cubes would be off by up to h/2 = 0.024.
    assert!(worst < 6e-3, "largest depth error {worst}");
    assert!(seen[0] > 60 && seen[1] > 60, "{seen:?}");
}

#[test]
fn two_specular_materials_give_the_whitted_highlights() {
    let s = scene(
        r#"
[materials.dull]
color = [0.5, 0.5, 0.5]
specular = 0.2
shininess = 8
[materials.shiny]
color = [0.5, 0.5, 0.5]
specular = 0.9
shininess = 60
[[objects]]
type = "sphere"
center = [-0.8, 0.5, 0]
radius = 0.6
material = "dull"
[[objects]]
type = "sphere"
center = [0.8, 0.5, 0]
radius = 0.6
material = "shiny"
"#,
    );
    let st = tessellate(&s, 32);
    let p = scene_pipeline(&s);
    assert_eq!(p.shading, Shading::Phong);
    let mut fb = Framebuffer::new(64, 48, ColorFormat::Rgba32F).unwrap();
    p.render_triangles(&st.triangles, &mut fb).unwrap();
    let ColorBuffer::Rgba32F(px) = &fb.color else {
        unreachable!()
    };
    let tracer = Whitted::new(&s);
    let rays = s.camera.rays(64, 48);
    let cast = ray_cast(&s);
    let pixels = interior(&cast, (64, 48), 1, 0.9);
    // The brightest pixel of each sphere in the tracer's image: its highlight.
    let mut peak = [(0.0f32, 0usize, 0.0f32); 2];
    let mut worst: f32 = 0.0;
    for &i in &pixels {
        let (o, ..) = cast[i].unwrap();
        let ray: Ray = rays.ray((i % 64) as f32 + 0.5, (i / 64) as f32 + 0.5);
        let mut rng = Rng::new(i as u64, 0);
        let want = tracer
            .sample(
                &ray,
                &mut rng,
                &mut Stats::default(),
                &mut AovSample::default(),
            )
            .r;
        let got = px[i][0];
        worst = worst.max((got - want).abs() / want.max(0.05));
        if want > peak[o].0 {
            peak[o] = (want, i, got);
        }
    }
    for (want, i, got) in peak {
        assert!(
            (got - want).abs() <= 0.03 * want,
            "highlight at pixel {i}: raster {got}, Whitted {want}"
        );
    }
    // The shiny sphere's highlight is brighter by its larger k_s.
    assert!(peak[1].0 > peak[0].0 + 0.3, "{peak:?}");
    // Elsewhere the facets' interpolated normals tilt the flanks of the narrow
    // highlight a little.
    assert!(worst < 0.1, "largest relative difference {worst}");
}

/// The objects of [`many_materials`].
const MANY_MATERIALS: &str = r#"
[materials.floor]
color = { type = "checker", colors = [0.8, 0.3], scale = 0.5 }
[materials.red]
color = [0.9, 0.2, 0.1]
specular = 0.5
shininess = 30
[materials.blue]
color = [0.1, 0.3, 0.9]
specular = 0.9
shininess = 80
ambient = 0.4
[materials.glow]
color = [0.2, 0.2, 0.2]
emission = [0.5, 0.4, 0.1]
[[objects]]
type = "plane"
normal = [0, 1, 0]
material = "floor"
[[objects]]
type = "sphere"
center = [-0.9, 0.5, 0]
radius = 0.5
material = "red"
[[objects]]
type = "sphere"
center = [0.9, 0.5, 0]
radius = 0.5
material = "blue"
[[objects]]
name = "csg"
type = "difference"
material = "glow"
children = [
  { type = "box", min = [-0.4, 0, -0.4], max = [0.4, 0.8, 0.4] },
  { type = "sphere", center = [0, 0.8, 0], radius = 0.4 },
]
[[objects]]
name = "nothing"
type = "difference"
material = "red"
children = [
  { type = "sphere", center = [0, 2, -2], radius = 0.2 },
  { type = "sphere", center = [0, 2, -2], radius = 0.3 },
]
"#;

/// A scene with several materials (plane, spheres, CSG with per-leaf materials).
fn many_materials() -> Scene {
    scene(MANY_MATERIALS)
}

#[test]
fn sorting_schemes_with_several_materials_equal_the_serial_render() {
    let s = many_materials();
    let st = tessellate(&s, 24);
    assert_eq!(st.skipped, vec!["nothing".to_string()]);
    let mut used: Vec<u32> = st.triangles.iter().map(|t| t.material).collect();
    used.sort_unstable();
    used.dedup();
    assert_eq!(used, vec![0, 1, 2, 3]);
    let p = scene_pipeline(&s);
    let tris = &st.triangles;
    let serial = sort_common::serial(&p, tris);
    for ranks in [1, 3, 4] {
        for mode in ["sort-first", "sort-middle", "sort-last"] {
            let out = run_local(ranks, LocalOptions::default(), |c| match mode {
                "sort-first" => sort_first::render(c, &p, tris, 0).unwrap(),
                "sort-middle" => sort_middle::render(c, &p, tris, 0).unwrap(),
                _ => sort_last::render(
                    c,
                    &p,
                    tris,
                    Strategy::BinarySwap,
                    &CompositeOptions::default(),
                )
                .unwrap(),
            });
            let img = out.into_iter().next().unwrap().unwrap().unwrap();
            assert!(img == serial, "{mode} with {ranks} ranks differs");
        }
    }
    // The materials matter: with one material for all the image changes.
    let mut one = p.clone();
    one.materials.clear();
    assert!(sort_common::serial(&one, tris) != serial);
}

#[test]
fn submission_carries_material_changes_as_state() {
    let s = many_materials();
    let st = tessellate(&s, 16);
    let p = scene_pipeline(&s);
    // One colour for all, the material alternating every 32 triangles.
    let batches: Vec<Batch> = st
        .triangles
        .chunks(32)
        .enumerate()
        .map(|(i, c)| Batch {
            color: [0.7, 0.7, 0.7, 1.0],
            material: (i % 4) as u32,
            triangles: c.to_vec(),
        })
        .collect();
    let serial = sort_common::serial(&p, &submission::flatten(&batches));
    for ranks in [1, 3] {
        let out = run_local(ranks, LocalOptions::default(), |c| {
            submission::render(c, &p, &batches, 0).unwrap()
        });
        let (img, _) = out.into_iter().next().unwrap().unwrap();
        assert!(img.unwrap() == serial, "{ranks} ranks differ");
    }
    // A server that sees only a material change gets a state command.
    let (streams, stats) = submission::encode_streams(&p, &batches[..2], 1);
    let tris = submission::decode_stream(&streams[0]).unwrap();
    assert_eq!(stats.state_bytes, 2 * 21);
    assert_eq!(tris[0].material, 0);
    assert_eq!(tris.last().unwrap().material, 1);
}

/// The Whitted tracer's colour through the centre of every pixel.
fn whitted_image(s: &Scene) -> Vec<Rgb> {
    let (w, h) = (s.settings.width, s.settings.height);
    let tracer = Whitted::new(s);
    let rays = s.camera.rays(w, h);
    (0..w * h)
        .map(|i| {
            let ray: Ray = rays.ray((i % w) as f32 + 0.5, (i / w) as f32 + 0.5);
            let mut rng = Rng::new(i as u64, 0);
            tracer.sample(
                &ray,
                &mut rng,
                &mut Stats::default(),
                &mut AovSample::default(),
            )
        })
        .collect()
}

/// The scene drawn serially into a float framebuffer.
fn raster_rgb(s: &Scene, resolution: u32) -> Vec<[f32; 4]> {
    let st = tessellate(s, resolution);
    let p = scene_pipeline(s);
    let mut fb = Framebuffer::new(p.width, p.height, ColorFormat::Rgba32F).unwrap();
    p.render_triangles(&st.triangles, &mut fb).unwrap();
    let ColorBuffer::Rgba32F(px) = fb.color else {
        unreachable!()
    };
    px
}

fn max_diff(a: [f32; 4], b: Rgb) -> f32 {
    (a[0] - b.r)
        .abs()
        .max((a[1] - b.g).abs())
        .max((a[2] - b.b).abs())
}

/// An 8 x 8 texture of distinct colours, written as a PNG into `dir`.
fn texture_png(dir: &Path) -> std::path::PathBuf {
    let px = (0..64)
        .map(|i| {
            let (x, y) = (i % 8, i / 8);
            Rgb::new(
                0.1 + 0.8 * x as f32 / 7.0,
                0.1 + 0.8 * y as f32 / 7.0,
                if (x + y) % 2 == 0 { 0.9 } else { 0.2 },
            )
        })
        .collect();
    let path = dir.join("texture.png");
    irradia_core::io::save(&Image::from_pixels(8, 8, px), &path).unwrap();
    path
}

#[test]
fn image_textures_are_looked_up_per_fragment_as_the_ray_tracer_does() {
    let dir = tempfile::tempdir().unwrap();
    let png = texture_png(dir.path());
    // A floor quad seen at a slant (perspective-correct uv matters), a sphere and a
    // disk.
    let body = format!(
        r#"
[materials.picture]
color = {{ type = "image", path = "{}", scale = [1, 1] }}
[[objects]]
type = "polygon"
vertices = [[-1.6, 0, -1.2], [1.6, 0, -1.2], [1.6, 0, 1.6], [-1.6, 0, 1.6]]
material = "picture"
[[objects]]
type = "sphere"
center = [0.9, 0.9, -0.6]
radius = 0.55
material = "picture"
[[objects]]
type = "disk"
center = [-0.9, 0.9, -0.6]
normal = [0, 0.5, 1]
radius = 0.55
material = "picture"
"#,
        png.display()
    );
    let s = scene(&body);
    assert!(matches!(s.materials[0].color, Texture::Image { .. }));
    let got = raster_rgb(&s, 32);
    let want = whitted_image(&s);
    let cast = ray_cast(&s);
    let pixels = interior(&cast, (64, 48), 1, 0.9);
    for object in [0, 1, 2] {
        let mine: Vec<usize> = pixels
            .iter()
            .copied()
            .filter(|&i| cast[i].unwrap().0 == object)
            .collect();
        assert!(mine.len() > 50, "object {object}: {} pixels", mine.len());
        let close = mine
            .iter()
            .filter(|&&i| max_diff(got[i], want[i]) < 0.02)
            .count();
        // Exact on the quad (uv is affine on it) but where a pixel centre falls
        // within rounding of a texel edge; on the sphere and the disk (polar uv, its
        // face cut into wedges around the centre) the facets' affine uv is a fit, so
        // texel edges can move by a fraction of a pixel.
        let need = if object == 0 { 0.95 } else { 0.9 };
        assert!(
            close as f32 >= need * mine.len() as f32,
            "object {object}: {close} of {} pixels match the Whitted tracer",
            mine.len()
        );
    }
    // The old behaviour, the texture's colour at uv = 0 everywhere, misses most of
    // them: the test sees the texture.
    let mut flat = scene(&body);
    let uv0 = flat.materials[0].color.eval(Vec3::ZERO, glam::Vec2::ZERO);
    flat.materials[0].color = Texture::Solid(uv0);
    let old = raster_rgb(&flat, 32);
    let quad: Vec<usize> = pixels
        .iter()
        .copied()
        .filter(|&i| cast[i].unwrap().0 == 0)
        .collect();
    let wrong = quad
        .iter()
        .filter(|&&i| max_diff(old[i], want[i]) > 0.05)
        .count();
    assert!(wrong * 2 > quad.len(), "{wrong} of {}", quad.len());
}

/// A pipeline looking down -z at the unit square, unlit (colours as given) or lit by
/// one light along the view axis.
fn square_view(shading: Shading) -> Pipeline {
    let mut p = Pipeline::new(64, 48);
    p.view = ViewParams::look_at_perspective(
        Vec3::new(0.0, 0.0, 3.0),
        Vec3::ZERO,
        Vec3::Y,
        45.0,
        64.0 / 48.0,
        0.1,
        10.0,
    );
    p.shading = shading;
    p.lights = Lights {
        ambient: Rgb::BLACK,
        lights: vec![RasterLight::Directional {
            direction: -Vec3::Z,
            color: Rgb::WHITE,
        }],
    };
    p
}

fn rgba32(p: &Pipeline, f: impl FnOnce(&Pipeline, &mut Framebuffer)) -> Vec<[f32; 4]> {
    let mut fb = Framebuffer::new(p.width, p.height, ColorFormat::Rgba32F).unwrap();
    f(p, &mut fb);
    let ColorBuffer::Rgba32F(px) = fb.color else {
        unreachable!()
    };
    px
}

#[test]
fn each_face_of_an_indexed_mesh_takes_its_own_material() {
    // A square of two triangles, split along its diagonal from (-1,-1) to (1,1):
    // the lower right triangle red, the upper left green.
    let mut mesh = Mesh::new(
        vec![
            Vec3::new(-1.0, -1.0, 0.0),
            Vec3::new(1.0, -1.0, 0.0),
            Vec3::new(1.0, 1.0, 0.0),
            Vec3::new(-1.0, 1.0, 0.0),
        ],
        vec![[0, 1, 2], [0, 2, 3]],
    );
    mesh.materials = vec![1, 2];
    let colour = |c: Rgb| Material {
        diffuse: c,
        ambient: Some(Rgb::BLACK),
        ..Material::default()
    };
    let red = Rgb::new(0.9, 0.1, 0.1);
    let green = Rgb::new(0.1, 0.8, 0.2);
    let lower_right = (44u32, 34u32);
    let upper_left = (20u32, 14u32);
    for shading in [Shading::Gouraud, Shading::Phong] {
        for normals in [false, true] {
            let mut m = mesh.clone();
            if normals {
                m.compute_vertex_normals();
            }
            let mut p = square_view(shading);
            p.materials = vec![Material::default(), colour(red), colour(green)];
            let px = rgba32(&p, |p, fb| p.render_mesh(&m, fb).unwrap());
            let at = |(x, y): (u32, u32)| px[(y * 64 + x) as usize];
            for ((x, y), c) in [(lower_right, red), (upper_left, green)] {
                assert!(
                    max_diff(at((x, y)), c) < 1e-5,
                    "{shading:?} normals {normals}: pixel ({x}, {y}) {:?}, want {c:?}",
                    at((x, y))
                );
            }
            // The same through independent triangles.
            let tris = px.clone();
            let again = rgba32(&p, |p, fb| {
                p.render_triangles(&m.to_triangles(), fb).unwrap()
            });
            assert_eq!(tris, again);
        }
    }
    let mut bad = mesh.clone();
    bad.materials = vec![1];
    assert!(matches!(
        square_view(Shading::Phong).render_mesh(
            &bad,
            &mut Framebuffer::new(64, 48, ColorFormat::Rgba8).unwrap()
        ),
        Err(irradia_raster::RasterError::Mesh(
            MeshError::MaterialCount {
                count: 1,
                triangles: 2
            }
        ))
    ));
}

/// A flat unlit square of colour `c` at depth `z`, corners `lo`..`hi` in x and y.
fn square(lo: f32, hi: f32, z: f32, c: [f32; 4], id: u32, material: u32) -> [Triangle; 2] {
    let p = |x: f32, y: f32| Vec3::new(x, y, z);
    let mut a = Triangle::flat([p(lo, lo), p(hi, lo), p(hi, hi)], c, id);
    let mut b = Triangle::flat([p(lo, lo), p(hi, hi), p(lo, hi)], c, id + 1);
    a.material = material;
    b.material = material;
    [a, b]
}

#[test]
fn a_transparent_square_is_blended_over_the_opaque_one_behind_it() {
    let mut p = square_view(Shading::Unlit);
    let clear = |t: f32| Material {
        transmission: t,
        filter: Some(Rgb::WHITE),
        ..Material::default()
    };
    p.materials = vec![Material::default(), clear(0.6), clear(0.3)];
    let back = [0.2, 0.4, 0.8, 1.0];
    let front = [0.3, 0.1, 0.05, 1.0];
    let behind = square(-1.4, 1.4, -0.5, back, 0, 0);
    let glass = square(-0.6, 0.6, 0.2, front, 2, 1);
    // Submitted first, the transparent square is still drawn after the opaque one.
    let tris: Vec<Triangle> = glass.iter().chain(&behind).copied().collect();
    let px = rgba32(&p, |p, fb| p.render_triangles(&tris, fb).unwrap());
    let centre = px[24 * 64 + 32];
    // Premultiplied "over": front + transmission * back.
    for k in 0..3 {
        let want = front[k] + 0.6 * back[k];
        assert!(
            (centre[k] - want).abs() < 1e-6,
            "channel {k}: {} vs {want}",
            centre[k]
        );
    }
    assert!((centre[3] - 1.0).abs() < 1e-6);
    // Outside the glass, the opaque square alone; the glass writes no depth.
    let outside = px[24 * 64 + 12];
    assert!(
        (0..4).all(|k| (outside[k] - back[k]).abs() < 1e-6),
        "{outside:?}"
    );
    // Two transparent squares overlapping (0.6 behind, 0.3 in front): whichever
    // order they come in, the far one is blended first.
    let near = square(-0.3, 0.8, 0.5, [0.05, 0.3, 0.1, 1.0], 4, 2);
    let orders: Vec<Vec<Triangle>> = vec![
        behind.iter().chain(&glass).chain(&near).copied().collect(),
        near.iter().chain(&behind).chain(&glass).copied().collect(),
    ];
    let images: Vec<Vec<[f32; 4]>> = orders
        .iter()
        .map(|t| rgba32(&p, |p, fb| p.render_triangles(t, fb).unwrap()))
        .collect();
    assert_eq!(images[0], images[1]);
    let both = images[0][22 * 64 + 34];
    for k in 0..3 {
        let near_colour = [0.05, 0.3, 0.1][k];
        let far_first = near_colour + 0.3 * (front[k] + 0.6 * back[k]);
        assert!(
            (both[k] - far_first).abs() < 1e-6,
            "channel {k}: {} vs {far_first}",
            both[k]
        );
        // Drawn near first (no sorting), the result would differ.
        let near_first = front[k] + 0.6 * (near_colour + 0.3 * back[k]);
        assert!((near_first - far_first).abs() > 0.01 || k == 2);
    }
    // Over the empty background: the colour, and alpha = 1 - transmission.
    let only_glass = rgba32(&p, |p, fb| p.render_triangles(&glass, fb).unwrap());
    let c = only_glass[24 * 64 + 32];
    assert!(
        (c[0] - front[0]).abs() < 1e-6 && (c[3] - 0.4).abs() < 1e-6,
        "{c:?}"
    );
}

/// [`many_materials`] with a glass box and a tinted glass sphere in front.
fn with_glass() -> Scene {
    scene(&format!(
        "{MANY_MATERIALS}{}",
        r#"
[materials.glass]
color = [0.9, 0.95, 1.0]
transmission = 0.7
[materials.tint]
color = [0.2, 0.8, 0.3]
transmission = 0.5
model = "povray"
specular = 0.6
shininess = 40
[[objects]]
type = "box"
min = [-1.4, 0.1, 0.6]
max = [0.2, 0.9, 1.0]
material = "glass"
[[objects]]
type = "sphere"
center = [0.7, 0.8, 0.9]
radius = 0.45
material = "tint"
"#
    ))
}

#[test]
fn with_transparency_sort_first_and_sort_middle_equal_the_serial_render() {
    let s = with_glass();
    let st = tessellate(&s, 16);
    let p = scene_pipeline(&s);
    assert!(st.has_transparency(&p));
    let tris = &st.triangles;
    let serial = sort_common::serial(&p, tris);
    // WireGL-style submission: runs of one material, one colour per batch.
    let batches: Vec<Batch> = tris
        .chunk_by(|a, b| a.material == b.material)
        .flat_map(|run| run.chunks(40))
        .map(|c| Batch {
            color: [0.8, 0.8, 0.8, 1.0],
            material: c[0].material,
            triangles: c.to_vec(),
        })
        .collect();
    let submitted = sort_common::serial(&p, &submission::flatten(&batches));
    for ranks in [1, 3, 4] {
        for mode in ["sort-first", "sort-middle", "submission"] {
            let out = run_local(ranks, LocalOptions::default(), |c| match mode {
                "sort-first" => sort_first::render(c, &p, tris, 0).unwrap(),
                "sort-middle" => sort_middle::render(c, &p, tris, 0).unwrap(),
                _ => submission::render(c, &p, &batches, 0).unwrap().0,
            });
            let img = out.into_iter().next().unwrap().unwrap().unwrap();
            let want = if mode == "submission" {
                &submitted
            } else {
                &serial
            };
            assert!(img == *want, "{mode} with {ranks} ranks differs");
        }
    }
    // The glass shows what lies behind it: drawn opaque, the image changes.
    let mut opaque = p.clone();
    for m in &mut opaque.materials {
        m.transmission = 0.0;
    }
    assert!(sort_common::serial(&opaque, tris) != serial);
}

#[test]
fn a_floor_far_below_a_large_scene_reaches_the_horizon() {
    // The eye 3.6 above the floor, the scene 100 wide: far / near of the old choice
    // (1000 x the scene's size, 1e-3 x the eye's distance) was 5e7, beyond what an f32
    // inverse projection and depth buffer resolve, and the floor vanished.
    let s = irradia_scene::load_str(
        r#"
[image]
width = 64
height = 48
[camera]
eye = [0, 0.6, 2]
look_at = [0, 0.5, 0]
fov = 60
[[lights]]
type = "directional"
direction = [-0.3, -1, -0.5]
irradiance = 1
[[objects]]
type = "plane"
normal = [0, 1, 0]
offset = -3
[[objects]]
type = "sphere"
center = [0, 0.5, 0]
radius = 0.3
[[objects]]
type = "sphere"
center = [60, 0.5, -80]
radius = 1
"#,
        SceneSyntax::Toml,
        Path::new("horizon.toml"),
    )
    .unwrap();
    let st = tessellate(&s, 32);
    assert!(!st.objects[0].is_empty());
    let (ids, _, p) = raster_ids(&s, &st);
    // far / near of a 0..1 depth projection: z_axis.z = f / (n - f).
    let zz = p.view.proj.z_axis.z as f64;
    let ratio = zz / (zz + 1.0);
    assert!(ratio > 1e3 && ratio < 1.2e6, "far / near = {ratio}");
    let cast = ray_cast(&s);
    let floor = cast.iter().filter(|c| matches!(c, Some((0, ..)))).count();
    assert!(floor > 64 * 20, "{floor}");
    // Pixel by pixel the same floor as the ray caster: the floor ends within a
    // quarter pixel of the horizon, so at most one row of pixel centres differs.
    let differ = (0..64 * 48)
        .filter(|&i| (cast[i].map(|c| c.0) == Some(0)) != (ids[i] == Some(0)))
        .count();
    assert!(differ <= 64, "{differ} pixels differ");
}

#[test]
fn transparent_polygons_over_an_emitter_and_the_background_match_the_whitted_tracer() {
    // Two clear polygons (the lecture's Phong model and POV-Ray's finish) in front of
    // an emitting square whose colour needs no light, so that the tracer's shadow
    // rays change nothing; the polygons are not solids, so their rays go straight on.
    // Where a polygon hangs over the background, the background shows through.
    let s = irradia_scene::load_str(
        r#"
[image]
width = 64
height = 48
[camera]
eye = [0, 0, 4]
look_at = [0, 0, 0]
fov = 50
[render]
ambient_light = 0.3
background = [0.3, 0.6, 0.2]
[[lights]]
type = "point"
position = [1, 2, 5]
intensity = 20
[materials.glow]
color = 0
ambient = 0
diffuse = 0
emission = [0.2, 0.5, 0.9]
[materials.clear]
color = [0.8, 0.3, 0.2]
transmission = 0.6
filter = [1, 0.9, 0.5]
[materials.tint]
color = [0.2, 0.7, 0.9]
transmission = 0.4
model = "povray"
[[objects]]
type = "polygon"
vertices = [[-1.5, -1, -1], [1.5, -1, -1], [1.5, 0.6, -1], [-1.5, 0.6, -1]]
material = "glow"
[[objects]]
type = "polygon"
vertices = [[-1.3, -0.7, 0], [-0.1, -0.7, 0], [-0.1, 1.2, 0], [-1.3, 1.2, 0]]
material = "clear"
[[objects]]
type = "polygon"
vertices = [[0.1, -0.7, 0], [1.3, -0.7, 0], [1.3, 1.2, 0], [0.1, 1.2, 0]]
material = "tint"
"#,
        SceneSyntax::Toml,
        Path::new("clear.toml"),
    )
    .unwrap();
    let st = tessellate(&s, 16);
    let p = scene_pipeline(&s);
    assert!(st.has_transparency(&p));
    let got = raster_rgb(&s, 16);
    let want = whitted_image(&s);
    let cast = ray_cast(&s);
    let rays = s.camera.rays(64, 48);
    let (mut over_emitter, mut over_background) = ([0; 3], [0; 3]);
    for i in interior(&cast, (64, 48), 1, 0.9) {
        let (o, ..) = cast[i].unwrap();
        if o == 0 {
            continue;
        }
        // Behind the polygon: the emitter, or nothing (the pipeline blends over the
        // scene's background there, channel by channel).
        let ray = rays.ray((i % 64) as f32 + 0.5, (i / 64) as f32 + 0.5);
        match s.accel.instances()[0].intersect(&ray, f32::INFINITY) {
            Some(_) => over_emitter[o] += 1,
            None => over_background[o] += 1,
        }
        let px = got[i];
        assert!((px[3] - 1.0).abs() < 1e-6, "pixel {i}: alpha {}", px[3]);
        assert!(
            max_diff(px, want[i]) < 2e-3,
            "pixel {i} (object {o}): raster {px:?}, Whitted {:?}",
            want[i]
        );
    }
    for o in [1, 2] {
        assert!(
            over_emitter[o] > 40 && over_background[o] > 10,
            "object {o}: {} over the emitter, {} over the background",
            over_emitter[o],
            over_background[o]
        );
    }
}
