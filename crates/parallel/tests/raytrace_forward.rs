//! Object-parallel Whitted ray tracing with ray forwarding (`raytrace_forward`): each
//! rank owns a block of the objects, and the image equals the serial Whitted render bit
//! for bit (shadows, mirrors, glass with refraction and total internal reflection, area
//! light samples, CSG, the depth and weight limits). Controls: object-parallel ray
//! tracing without forwarding differs from it, the number of exchanges is bounded, and
//! a rank that never answers is named by the others.

use irradia_core::{Image, Ray, Rng};
use irradia_geometry::SceneHit;
use irradia_parallel::comm::{run_local, LocalOptions};
use irradia_parallel::composite::Strategy;
use irradia_parallel::raytrace_forward::{self, ForwardResult};
use irradia_parallel::sort_first::{Assign, Tiling};
use irradia_parallel::{raytrace_first, raytrace_last};
use irradia_render::raytree::NoRecorder;
use irradia_render::whitted::{ObjectSet, RayQuery, SceneGeometry};
use irradia_render::{driver, AovSample, Stats, Whitted};
use irradia_scene::Scene;
use std::cell::Cell;

fn scene(name: &str) -> Scene {
    let mut s = irradia_scene::builtin::load(name).unwrap();
    s.settings.width = 48;
    s.settings.height = 36;
    s
}

fn serial(s: &Scene) -> Image {
    driver::render_with(&Whitted::new(s), s, &Default::default())
        .unwrap()
        .image
}

/// Renders with forwarding on `ranks` threads: rank 0's image and every rank's result.
fn forward(s: &Scene, ranks: usize, tiling: Tiling) -> (Image, Vec<ForwardResult>) {
    let out = run_local(ranks, LocalOptions::default(), |c| {
        raytrace_forward::render(c, s, tiling, 0).unwrap()
    });
    let results: Vec<ForwardResult> = out.into_iter().map(|r| r.unwrap()).collect();
    let layer = results[0].image.as_ref().expect("rank 0 has the image");
    assert_eq!(raytrace_first::unwritten(layer), 0, "pixels missing");
    (raytrace_first::to_image(layer), results)
}

fn differing(a: &Image, b: &Image) -> usize {
    a.pixels()
        .iter()
        .zip(b.pixels())
        .filter(|(x, y)| x != y)
        .count()
}

#[test]
fn forwarded_whitted_equals_the_serial_render_for_one_to_four_ranks() {
    // whitted: shadows, a mirror, a glass sphere (refraction, total internal
    // reflection), 3 objects. default: an area light (9 samples), Fresnel glass, a CSG
    // difference with two materials, a teapot, metaballs, a weight cut-off, 7 objects.
    for name in ["whitted", "default"] {
        let s = scene(name);
        let want = serial(&s);
        for ranks in 1..=4 {
            let (got, results) = forward(&s, ranks, Tiling::STRIPS);
            assert_eq!(
                differing(&got, &want),
                0,
                "{name} at {ranks} ranks differs from the serial render"
            );
            // Every rank ran the same number of generations, and queries crossed ranks.
            let gens = results[0].generations.len();
            assert!(results.iter().all(|r| r.generations.len() == gens));
            if ranks > 1 {
                let bytes: u64 = results
                    .iter()
                    .flat_map(|r| &r.generations)
                    .map(|g| g.traffic.bytes_sent)
                    .sum();
                assert!(bytes > 0, "{name}: nothing was forwarded at {ranks} ranks");
            }
        }
    }
}

/// Twelve objects (more than the tracer scans linearly, so the serial render and the
/// ranks with many objects go through the hierarchy): mirrors, Fresnel glass (one ball
/// inside a glass box: nested media), boxes, a CSG intersection, a floor; an area light
/// and a point light.
const TWELVE: &str = r#"
[image]
width = 48
height = 36
[camera]
eye = [0, 3, 9]
look_at = [0, 1, 0]
fov = 50
[render]
max_depth = 6
min_weight = 0.002
background = [0.2, 0.3, 0.5]
ambient_light = 0.1
[materials.floor]
color = { type = "checker", colors = [[0.9, 0.9, 0.9], [0.2, 0.2, 0.25]], scale = 1 }
diffuse = 0.8
ambient = 0.3
reflection = 0.1
[materials.mirror]
color = 1
diffuse = 0.05
specular = 0.8
shininess = 100
reflection = 0.85
[materials.glass]
color = 1
diffuse = 0
ambient = 0
specular = 0.9
shininess = 200
transmission = 1
filter = [0.9, 1, 0.95]
ior = 1.5
fresnel = true
reflection = 1
[materials.red]
color = [0.8, 0.2, 0.1]
specular = 0.3
shininess = 20
[materials.blue]
color = [0.2, 0.3, 0.9]
reflection = 0.2
[[lights]]
type = "rect"
corner = [-1.5, 6, 0]
edge_u = [1.5, 0, 0]
edge_v = [0, 0, 1.5]
radiance = 20
samples = 4
[[lights]]
type = "point"
position = [5, 5, 6]
intensity = 20
[[objects]]
type = "plane"
normal = [0, 1, 0]
offset = 0
material = "floor"
[[objects]]
type = "sphere"
center = [-2.2, 1, -1]
radius = 1
material = "mirror"
[[objects]]
type = "sphere"
center = [2.4, 0.7, -0.5]
radius = 0.7
material = "mirror"
[[objects]]
type = "sphere"
center = [0, 0.8, 1.5]
radius = 0.8
material = "glass"
[[objects]]
type = "box"
min = [0.9, 0, 1.6]
max = [2.1, 1.2, 2.8]
material = "glass"
[[objects]]
type = "sphere"
center = [1.5, 0.6, 2.2]
radius = 0.35
material = "glass"
[[objects]]
type = "box"
min = [-3.5, 0, -3.5]
max = [-2.5, 2.5, -2.5]
material = "red"
[[objects]]
type = "box"
min = [-0.5, 0, -3]
max = [0.5, 0.6, -2]
material = "blue"
[[objects]]
type = "intersection"
material = "red"
children = [
  { type = "box", min = [-0.6, -0.6, -0.6], max = [0.6, 0.6, 0.6] },
  { type = "sphere", radius = 0.8, material = "blue" },
]
transform = [{ rotate = [0, 30, 0] }, { translate = [-1, 0.6, 2.5] }]
[[objects]]
type = "sphere"
center = [3.5, 0.4, 1.5]
radius = 0.4
material = "blue"
[[objects]]
type = "sphere"
center = [-3.5, 0.5, 1.5]
radius = 0.5
material = "mirror"
[[objects]]
type = "box"
min = [2.8, 0, -3.5]
max = [3.8, 1.5, -2.5]
material = "blue"
"#;

#[test]
fn many_objects_through_the_hierarchy_equal_the_serial_render() {
    let s = irradia_scene::file::load_str(
        TWELVE,
        irradia_scene::file::Format::Toml,
        std::path::Path::new("twelve.toml"),
    )
    .unwrap();
    assert_eq!(s.objects.len(), 12);
    let want = serial(&s);
    for ranks in [1, 2, 3, 4] {
        let (got, _) = forward(&s, ranks, Tiling::STRIPS);
        assert_eq!(differing(&got, &want), 0, "{ranks} ranks differ");
    }
}

#[test]
fn forwarding_follows_supersampling_and_any_tiling() {
    // Several samples per pixel (area-light random numbers per sample) and adaptive
    // supersampling (whose decision reads the neighbours' centre samples), with tiles.
    let mut s = scene("default");
    s.settings.spp = 2;
    let tiles = Tiling {
        per_rank: 3,
        assign: Assign::Interleaved,
    };
    let (got, _) = forward(&s, 3, tiles);
    assert_eq!(differing(&got, &serial(&s)), 0, "2 spp differs");

    let mut s = scene("whitted");
    s.settings.adaptive_threshold = Some(0.05);
    let tiles = Tiling {
        per_rank: 2,
        assign: Assign::Cost,
    };
    let (got, _) = forward(&s, 2, tiles);
    assert_eq!(differing(&got, &serial(&s)), 0, "adaptive sampling differs");
}

#[test]
fn without_forwarding_object_parallel_ray_tracing_differs() {
    // The control: the same scene traced on each rank's own objects only loses the
    // shadows, reflections and refractions of the other ranks' objects.
    let s = scene("whitted");
    let want = serial(&s);
    for shading in [
        raytrace_last::Shading::Local,
        raytrace_last::Shading::WhittedOwnObjects,
    ] {
        let out = run_local(3, LocalOptions::default(), |c| {
            raytrace_last::render_shaded(c, &s, Strategy::BinarySwap, 0, shading).unwrap()
        });
        let layer = out.into_iter().next().unwrap().unwrap().unwrap();
        let img = raytrace_first::to_image(&layer);
        let n = differing(&img, &want);
        assert!(
            n > want.pixels().len() / 10,
            "{shading:?}: only {n} pixels differ from the serial Whitted image"
        );
    }
}

/// The scene with every transparent material made opaque.
fn opaque(mut s: Scene) -> Scene {
    for m in &mut s.materials {
        m.transmission = 0.0;
    }
    s
}

#[test]
fn opaque_scenes_need_at_most_one_exchange_per_level_plus_one() {
    // One exchange per level of the ray tree (the camera rays, then each level's
    // reflected rays with the previous level's shadow rays), plus the deepest level's
    // shadow rays: max_depth + 1, with point lights and with an area light.
    for name in ["whitted", "default"] {
        let s = opaque(scene(name));
        let want = serial(&s);
        let (got, results) = forward(&s, 3, Tiling::STRIPS);
        assert_eq!(differing(&got, &want), 0, "{name} (opaque) differs");
        let exchanges = results[0].exchanges();
        assert!(
            exchanges <= s.settings.max_depth as usize + 1,
            "{name}: {exchanges} exchanges for max depth {}",
            s.settings.max_depth
        );
        assert!(exchanges >= 2, "{name}: shadow rays need a second exchange");
    }
}

/// Counts the geometry queries of the serial tracer.
struct Counting<'s> {
    inner: SceneGeometry<'s>,
    queries: Cell<usize>,
}

impl RayQuery for Counting<'_> {
    fn closest_hit(&self, set: ObjectSet, ray: &Ray, t_max: f32) -> Option<SceneHit> {
        self.queries.set(self.queries.get() + 1);
        self.inner.closest_hit(set, ray, t_max)
    }
    fn any_hit(&self, set: ObjectSet, ray: &Ray, t_max: f32) -> bool {
        self.queries.set(self.queries.get() + 1);
        self.inner.any_hit(set, ray, t_max)
    }
    fn is_solid(&self, object: u32) -> bool {
        self.inner.is_solid(object)
    }
}

#[test]
fn every_exchange_resolves_at_least_one_query_of_every_unfinished_pixel() {
    // The general guarantee: each generation answers at least the first query a
    // pixel's serial trace had not got an answer for, so no more exchanges are needed
    // than the most queries any pixel's serial trace asks (transparent objects and
    // area lights make chains of them).
    let s = scene("default");
    let tracer = Whitted::with_geometry(
        &s,
        Counting {
            inner: SceneGeometry::new(&s),
            queries: Cell::new(0),
        },
    );
    let cam = s.camera.rays(s.settings.width, s.settings.height);
    let mut most = 0;
    for y in 0..s.settings.height {
        for x in 0..s.settings.width {
            let (ray, mut rng): (_, Rng) = irradia_render::sampler::centre_sample(&cam, x, y);
            tracer.geometry().queries.set(0);
            tracer.sample_recorded(
                &ray,
                &mut rng,
                &mut Stats::default(),
                &mut AovSample::default(),
                &mut NoRecorder,
            );
            most = most.max(tracer.geometry().queries.get());
        }
    }
    let (_, results) = forward(&s, 2, Tiling::STRIPS);
    let exchanges = results[0].exchanges();
    assert!(
        exchanges >= 2 && exchanges <= most,
        "{exchanges} exchanges, {most} queries"
    );
    // Pixels finish over the generations, all of them in the last one traced.
    let gens = &results[0].generations;
    assert_eq!(gens.last().unwrap().traced, gens.last().unwrap().finished);
    assert_eq!(
        gens.iter().map(|g| g.finished).sum::<u64>(),
        gens[0].traced,
        "every pixel finishes exactly once"
    );
}

#[test]
fn a_rank_that_never_answers_is_named_on_the_others() {
    let s = scene("whitted");
    let opts = LocalOptions {
        timeout: std::time::Duration::from_millis(300),
        delay: None,
    };
    let t0 = std::time::Instant::now();
    let out = run_local(3, opts, |c| {
        if irradia_parallel::comm::Comm::rank(c) == 1 {
            std::thread::sleep(std::time::Duration::from_millis(900));
            return None;
        }
        Some(raytrace_forward::render(c, &s, Tiling::STRIPS, 0).map(|_| ()))
    });
    // A hang guard only (a loaded CI machine may be slow to notice); the errors'
    // content below is the check.
    assert!(
        t0.elapsed() < std::time::Duration::from_secs(60),
        "took {:?}",
        t0.elapsed()
    );
    for (r, res) in out.into_iter().enumerate() {
        if r == 1 {
            continue;
        }
        let e = res.unwrap().unwrap().expect_err("the job must fail");
        assert_eq!(e.culprit(), Some(1), "rank {r} blamed {e}");
    }
}
