//! Scene workloads drawn by the rasterizer against the ray caster and the Whitted
//! tracer (the oracles): which object each pixel sees and its depth (a plane and a
//! sphere; a CSG difference and an implicit surface tessellated by marching cubes),
//! per-object highlights, and the parallel sorting schemes and submission with several
//! materials equal to the serial render bit for bit.

use glam::Vec3;
use irradia_core::{Ray, Rng};
use irradia_parallel::comm::{run_local, LocalOptions};
use irradia_parallel::composite::{CompositeOptions, Strategy};
use irradia_parallel::submission::{self, Batch};
use irradia_parallel::tessellate::Tessellation;
use irradia_parallel::workload::{scene_pipeline, scene_triangles_with, SceneTriangles};
use irradia_parallel::{frame, sort_first, sort_last, sort_middle};
use irradia_raster::{ColorBuffer, ColorFormat, Framebuffer, Pipeline, Shading};
use irradia_render::{AovSample, Integrator, Stats, Whitted};
use irradia_scene::{Format, Scene};
use std::path::Path;

fn scene(body: &str) -> Scene {
    let text = format!(
        "[image]\nwidth = 64\nheight = 48\n\n[camera]\neye = [0, 3, 3.5]\nlook_at = [0, 0.4, 0]\nfov = 50\n\n[render]\nambient_light = 0.3\n\n[[lights]]\ntype = \"point\"\nposition = [2, 5, 4]\nintensity = 40\n\n{body}"
    );
    irradia_scene::load_str(&text, Format::Toml, Path::new("test.toml")).unwrap()
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

/// A scene with several materials (plane, spheres, CSG with per-leaf materials).
fn many_materials() -> Scene {
    scene(
        r#"
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
"#,
    )
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
    let serial = frame::serial(&p, tris);
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
    assert!(frame::serial(&one, tris) != serial);
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
    let serial = frame::serial(&p, &submission::flatten(&batches));
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
