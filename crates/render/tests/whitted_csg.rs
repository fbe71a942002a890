//! Whitted + CSG at the render level, against closed-form shading.
//!
//! Two scenes, loaded from scene-file text (so the loader's per-leaf materials are part
//! of what is tested), each seen by an orthographic camera and lit by one point light:
//!
//! - **Difference**: a box with a spherical dimple in its top face and an oblique
//!   cylindrical hole bored along a line through the light, over a ground plane. The
//!   dimple and the hole's wall are cavity surfaces: their normals point into the
//!   cavity (towards the viewer) and they show the subtracted leaves' materials. Light
//!   reaches the dimple's floor and the hole's wall through the removed region, and the
//!   ground through the hole: a lit spot inside the box's shadow.
//! - **Intersection**: a box intersected with a sphere (a rounded cube; flat faces show
//!   the box's material, rounded ones the sphere's), with a ball above it whose shadow
//!   falls onto the CSG object, over a ground plane that the CSG object shadows.
//!
//! For every pixel the test computes, in closed form and independently of the renderer
//! (ray-box slabs, ray-sphere and ray-cylinder quadratics, interval arithmetic on the
//! shadow segment), the first hit, the leaf it lies on (hence the material), the
//! outward normal of the combined solid, whether the light is visible, and the Phong
//! colour `k_a C + (I / r²) (k_d C cos θ + k_s (R·V)^n)`. Pixels whose centre lies
//! near an edge or a shadow boundary (where a sub-pixel shift changes the answer) are
//! skipped; the rest must match within 0.2%, and the normal AOV must equal the
//! closed-form normal. Each kind of pixel (every leaf, lit and shadowed, cavity faces,
//! light through the removed region) must occur often enough to matter.
//!
//! Set `IRRADIA_TEST_PNG=dir` to write the renders as PNG files there.

use glam::DVec3;
use irradia_core::Rgb;
use irradia_render::{render, Aov, RenderOptions};
use irradia_scene::{load_str, Scene, SceneSyntax};
use std::collections::BTreeMap;
use std::path::Path;

// ---------------------------------------------------------------------------------
// Closed-form ray queries (f64).

/// Parameter interval of the line `o + t d` inside the box, with the outward normals
/// of the faces where it enters and leaves.
fn box_interval(o: DVec3, d: DVec3, lo: DVec3, hi: DVec3) -> Option<(f64, f64, DVec3, DVec3)> {
    let (mut t0, mut t1) = (f64::NEG_INFINITY, f64::INFINITY);
    let (mut n0, mut n1) = (DVec3::ZERO, DVec3::ZERO);
    for i in 0..3 {
        if d[i] == 0.0 {
            if o[i] <= lo[i] || o[i] >= hi[i] {
                return None;
            }
            continue;
        }
        let (a, b) = ((lo[i] - o[i]) / d[i], (hi[i] - o[i]) / d[i]);
        let mut axis = DVec3::ZERO;
        axis[i] = 1.0;
        // Entering through the low face when moving up the axis, else the high face.
        let (near, far, n_near, n_far) = if a < b {
            (a, b, -axis, axis)
        } else {
            (b, a, axis, -axis)
        };
        if near > t0 {
            t0 = near;
            n0 = n_near;
        }
        if far < t1 {
            t1 = far;
            n1 = n_far;
        }
    }
    (t0 < t1).then_some((t0, t1, n0, n1))
}

/// Parameter interval of the line inside the sphere.
fn sphere_interval(o: DVec3, d: DVec3, c: DVec3, r: f64) -> Option<(f64, f64)> {
    let oc = o - c;
    let (a, b, cc) = (d.dot(d), oc.dot(d), oc.dot(oc) - r * r);
    let disc = b * b - a * cc;
    if disc <= 0.0 {
        return None;
    }
    let s = disc.sqrt();
    Some(((-b - s) / a, (-b + s) / a))
}

/// Parameter interval of the line inside the infinite cylinder of radius `r` around
/// the line through `p` along the unit vector `u`.
fn cylinder_interval(o: DVec3, d: DVec3, p: DVec3, u: DVec3, r: f64) -> Option<(f64, f64)> {
    let q = o - p;
    let (qp, dp) = (q - u * q.dot(u), d - u * d.dot(u));
    let (a, b, c) = (dp.dot(dp), qp.dot(dp), qp.dot(qp) - r * r);
    if a == 0.0 {
        return (c < 0.0).then_some((f64::NEG_INFINITY, f64::INFINITY));
    }
    let disc = b * b - a * c;
    if disc <= 0.0 {
        return None;
    }
    let s = disc.sqrt();
    Some(((-b - s) / a, (-b + s) / a))
}

/// Total length of `[lo, hi]` minus the union of `holes` (parameter units).
fn uncovered(lo: f64, hi: f64, holes: &[(f64, f64)]) -> f64 {
    if hi <= lo {
        return 0.0;
    }
    let mut holes: Vec<(f64, f64)> = holes
        .iter()
        .map(|&(a, b)| (a.max(lo), b.min(hi)))
        .filter(|(a, b)| a < b)
        .collect();
    holes.sort_by(|a, b| a.0.total_cmp(&b.0));
    let (mut covered, mut reach) = (0.0, lo);
    for (a, b) in holes {
        let a = a.max(reach);
        if b > a {
            covered += b - a;
            reach = b;
        }
    }
    (hi - lo) - covered
}

// ---------------------------------------------------------------------------------
// The camera (orthographic, as documented: the centre of pixel (i, j) is
// (i + 0.5, j + 0.5), y down) and the shading model.

struct Ortho {
    eye: DVec3,
    right: DVec3,
    up: DVec3,
    forward: DVec3,
    half: (f64, f64),
    size: (u32, u32),
}

impl Ortho {
    fn new(eye: DVec3, look_at: DVec3, height: f64, size: (u32, u32)) -> Self {
        let forward = (look_at - eye).normalize();
        let right = forward.cross(DVec3::Y).normalize();
        let up = right.cross(forward);
        let aspect = size.0 as f64 / size.1 as f64;
        Self {
            eye,
            right,
            up,
            forward,
            half: (0.5 * height * aspect, 0.5 * height),
            size,
        }
    }
    /// Ray origin for image position (x, y) in pixels; the direction is `forward`.
    fn origin(&self, x: f64, y: f64) -> DVec3 {
        let sx = (2.0 * x / self.size.0 as f64 - 1.0) * self.half.0;
        let sy = (1.0 - 2.0 * y / self.size.1 as f64) * self.half.1;
        self.eye + self.right * sx + self.up * sy
    }
}

#[derive(Clone, Copy, Debug)]
struct Mat {
    color: DVec3,
    ka: f64,
    kd: f64,
    ks: f64,
    n: i32,
}

/// What the closed form says about one camera ray.
#[derive(Clone, Copy, Debug)]
struct Shade {
    /// Object index in the scene and CSG leaf (0 for plain objects).
    object: u32,
    leaf: u32,
    point: DVec3,
    /// Outward normal of the solid (of the combined CSG solid: into a cavity on
    /// subtracted faces).
    normal: DVec3,
    lit: bool,
    /// The shadow ray crosses the bounds of the CSG object's first operand (the box)
    /// but only through removed material: light that reaches the point only because
    /// the CSG is evaluated.
    through_removed: bool,
    /// Shadowed by the CSG object (not by anything else, not self-facing).
    shadowed_by_csg: bool,
    /// Shadowed by the occluding ball.
    shadowed_by_ball: bool,
}

/// The Phong colour of `s` seen along `view` (unit, towards the viewer) for a point
/// light of intensity `intensity` at `light`, with ambient light 1.
fn phong(s: &Shade, m: &Mat, light: DVec3, intensity: f64, view: DVec3) -> DVec3 {
    let mut c = m.color * m.ka;
    let to_l = light - s.point;
    let r2 = to_l.length_squared();
    let l = to_l / r2.sqrt();
    let cos = s.normal.dot(l);
    if s.lit && cos > 0.0 {
        let e = intensity / r2;
        c += m.color * (e * m.kd * cos);
        let r = -l + s.normal * (2.0 * cos);
        let rv = r.dot(view);
        if m.ks > 0.0 && rv > 0.0 {
            c += DVec3::splat(e * m.ks * rv.powi(m.n));
        }
    }
    c
}

fn rgb(c: Rgb) -> DVec3 {
    DVec3::new(c.r as f64, c.g as f64, c.b as f64)
}

/// A scene of the test: its file text, the closed form and the materials by
/// (object, leaf).
struct Case {
    name: &'static str,
    toml: &'static str,
    camera: Ortho,
    light: DVec3,
    intensity: f64,
    materials: BTreeMap<(u32, u32), Mat>,
    /// Closed form for the ray from `o` along `d`; `None` when nothing is hit.
    shade: fn(DVec3, DVec3) -> Option<Shade>,
}

#[derive(Debug, Default)]
struct Tally {
    compared: u32,
    skipped: u32,
    /// Compared pixels per (object, leaf, lit).
    kinds: BTreeMap<(u32, u32, bool), u32>,
    cavity: u32,
    /// Lit through removed material, per object.
    through_removed: [u32; 2],
    shadowed_by_csg: u32,
    shadowed_by_ball: u32,
    failures: Vec<String>,
}

fn same_kind(a: &Option<Shade>, b: &Option<Shade>) -> bool {
    match (a, b) {
        (None, None) => true,
        (Some(a), Some(b)) => {
            a.object == b.object
                && a.leaf == b.leaf
                && a.lit == b.lit
                && a.through_removed == b.through_removed
                && a.shadowed_by_csg == b.shadowed_by_csg
                && a.shadowed_by_ball == b.shadowed_by_ball
                && a.normal.dot(b.normal) > 0.9
        }
        _ => false,
    }
}

fn check_case(case: &Case) -> Tally {
    let scene: Scene = load_str(case.toml, SceneSyntax::Toml, Path::new("whitted_csg.toml"))
        .unwrap_or_else(|e| panic!("{}: {e}", case.name));
    let out = render(
        &scene,
        &RenderOptions {
            aovs: vec![Aov::Normal, Aov::ObjectId],
            ..RenderOptions::default()
        },
    )
    .unwrap();
    if let Some(dir) = std::env::var_os("IRRADIA_TEST_PNG") {
        // Six times larger (nearest neighbour) so that it can be looked at.
        let (w, h) = (out.image.width(), out.image.height());
        let mut big = irradia_core::Image::new(w * 6, h * 6).unwrap();
        for y in 0..h * 6 {
            for x in 0..w * 6 {
                big.set(x, y, out.image.get(x / 6, y / 6));
            }
        }
        let bytes = irradia_core::io::encode(&big, irradia_core::io::Format::Png).unwrap();
        std::fs::write(Path::new(&dir).join(format!("{}.png", case.name)), bytes).unwrap();
    }
    let normals = &out.aovs[0].1;
    let ids = &out.aovs[1].1;
    let cam = &case.camera;
    let view = -cam.forward;
    let background = rgb(scene.settings.background);
    let mut tally = Tally::default();
    for j in 0..cam.size.1 {
        for i in 0..cam.size.0 {
            let (x, y) = (i as f64 + 0.5, j as f64 + 0.5);
            let centre = (case.shade)(cam.origin(x, y), cam.forward);
            // Skip pixels where a shift of a third of a pixel changes what is seen.
            let stable = [(-0.34, -0.34), (0.34, -0.34), (-0.34, 0.34), (0.34, 0.34)]
                .iter()
                .all(|&(dx, dy)| {
                    same_kind(
                        &centre,
                        &(case.shade)(cam.origin(x + dx, y + dy), cam.forward),
                    )
                });
            if !stable {
                tally.skipped += 1;
                continue;
            }
            tally.compared += 1;
            let got = rgb(out.image.get(i, j));
            let (expected, what) = match &centre {
                None => (background, "background".to_string()),
                Some(s) => {
                    let m = &case.materials[&(s.object, s.leaf)];
                    *tally.kinds.entry((s.object, s.leaf, s.lit)).or_default() += 1;
                    tally.cavity += (s.normal.dot(view) > 0.0 && s.object == 1 && {
                        // A cavity face: a subtracted leaf of the difference.
                        case.name == "difference" && s.leaf > 0
                    }) as u32;
                    if s.lit && s.through_removed {
                        tally.through_removed[s.object as usize] += 1;
                    }
                    tally.shadowed_by_csg += s.shadowed_by_csg as u32;
                    tally.shadowed_by_ball += s.shadowed_by_ball as u32;
                    let n_got = rgb(normals.get(i, j));
                    if (n_got - s.normal).length() > 1e-3 {
                        tally.failures.push(format!(
                            "{} pixel ({i}, {j}): normal AOV {n_got:?}, expected {:?} ({s:?})",
                            case.name, s.normal
                        ));
                    }
                    let id = ids.get(i, j).r;
                    if id != s.object as f32 {
                        tally.failures.push(format!(
                            "{} pixel ({i}, {j}): object {id}, expected {} ({s:?})",
                            case.name, s.object
                        ));
                    }
                    (
                        phong(s, m, case.light, case.intensity, view),
                        format!("{s:?}"),
                    )
                }
            };
            let err = (got - expected).abs().max_element();
            if err > 2e-3 * expected.max_element().max(0.05) {
                tally.failures.push(format!(
                    "{} pixel ({i}, {j}): rendered {got:?}, expected {expected:?} for {what}",
                    case.name
                ));
            }
        }
    }
    tally
}

// ---------------------------------------------------------------------------------
// The difference scene.

const LIGHT_A: DVec3 = DVec3::new(0.0, 6.0, -4.0);
const BOX_A: (DVec3, DVec3) = (DVec3::new(-1.0, 0.0, -1.0), DVec3::new(1.0, 1.5, 1.0));
const DIMPLE: (DVec3, f64) = (DVec3::new(-0.5, 1.5, -0.5), 0.42);
/// The hole's axis runs from the light through this point on the front face.
const HOLE_EXIT: DVec3 = DVec3::new(0.0, 0.65, 1.0);
const HOLE_R: f64 = 0.25;

fn hole_axis() -> DVec3 {
    (HOLE_EXIT - LIGHT_A).normalize()
}

const DIFFERENCE: &str = r#"
[camera]
type = "orthographic"
eye = [1.5, 8.0, 4.0]
look_at = [0.0, 0.7, 0.5]
height = 4.0

[image]
width = 96
height = 72

[render]
background = [0.02, 0.03, 0.05]
ambient_light = 1

[materials.ground]
color = [0.85, 0.85, 0.8]
ambient = 0.1
diffuse = 0.8

[materials.red]
color = [0.8, 0.25, 0.2]
ambient = 0.1
diffuse = 0.9

[materials.gold]
color = [0.9, 0.7, 0.15]
ambient = 0.1
diffuse = 0.7
specular = 0.4
shininess = 10

[materials.blue]
color = [0.2, 0.35, 0.9]
ambient = 0.1
diffuse = 0.9

[[lights]]
type = "point"
position = [0.0, 6.0, -4.0]
intensity = 40

[[objects]]
name = "ground"
type = "plane"
normal = [0, 1, 0]
offset = 0
material = "ground"

[[objects]]
name = "bored box"
type = "difference"
material = "red"
children = [
  { type = "box", min = [-1, 0, -1], max = [1, 1.5, 1] },
  { type = "sphere", center = [-0.5, 1.5, -0.5], radius = 0.42, material = "gold" },
  # Along the line from the light through (0, 0.65, 1), capped far outside the box.
  { type = "cylinder", radius = 0.25, from = [0.0, 3.325, -1.5], to = [0.0, -0.955, 2.5], material = "blue" },
]
"#;

/// Closed form of the difference scene: object 0 the ground (y ≤ 0), object 1 the box
/// minus the dimple sphere (leaf 1) minus the hole cylinder (leaf 2).
fn shade_difference(o: DVec3, d: DVec3) -> Option<Shade> {
    let (lo, hi) = BOX_A;
    let (sc, sr) = DIMPLE;
    let axis = hole_axis();
    let cyl = |o, d| cylinder_interval(o, d, LIGHT_A, axis, HOLE_R);
    let inside_removed = |t: f64, s: Option<(f64, f64)>, c: Option<(f64, f64)>| {
        s.is_some_and(|(a, b)| a < t && t < b) || c.is_some_and(|(a, b)| a < t && t < b)
    };
    // First hit on the CSG object: the first t > 0 inside the box not inside a hole:
    // the box's entry, or where the ray leaves the sphere or the cylinder.
    let mut best: Option<(f64, u32, DVec3)> = None;
    if let Some((b0, b1, n0, _)) = box_interval(o, d, lo, hi) {
        let (s, c) = (sphere_interval(o, d, sc, sr), cyl(o, d));
        let mut candidates = vec![(b0, 0u32, n0)];
        if let Some((_, s1)) = s {
            let p = o + d * s1;
            candidates.push((s1, 1, -(p - sc) / sr));
        }
        if let Some((_, c1)) = c {
            let q = o + d * c1 - LIGHT_A;
            candidates.push((c1, 2, -(q - axis * q.dot(axis)) / HOLE_R));
        }
        for (t, leaf, n) in candidates {
            if t > 0.0
                && t >= b0
                && t < b1
                && !inside_removed(t, s, c)
                && best.is_none_or(|(bt, _, _)| t < bt)
            {
                best = Some((t, leaf, n));
            }
        }
    }
    let ground = (d.y < 0.0).then(|| -o.y / d.y).filter(|&t| t > 0.0);
    let (object, leaf, t, normal) = match (best, ground) {
        (Some((t, leaf, n)), g) if g.is_none_or(|g| t < g) => (1, leaf, t, n),
        (_, Some(g)) => (0, 0, g, DVec3::Y),
        _ => return None,
    };
    let point = o + d * t;
    // The shadow segment from the point to the light, parameter in (0, 1).
    let seg = LIGHT_A - point;
    let (eps, end) = (1e-6, 1.0);
    let (mut blocked, mut through) = (false, false);
    if let Some((b0, b1, _, _)) = box_interval(point, seg, lo, hi) {
        let (b0, b1) = (b0.max(eps), b1.min(end));
        if b1 > b0 {
            let holes: Vec<(f64, f64)> = [sphere_interval(point, seg, sc, sr), cyl(point, seg)]
                .into_iter()
                .flatten()
                .collect();
            let solid = uncovered(b0, b1, &holes) * seg.length();
            blocked = solid > 1e-9;
            through = !blocked && (b1 - b0) * seg.length() > 1e-3;
        }
    }
    let faces = normal.dot(seg) > 0.0;
    Some(Shade {
        object,
        leaf,
        point,
        normal,
        lit: faces && !blocked,
        through_removed: faces && through,
        shadowed_by_csg: faces && blocked,
        shadowed_by_ball: false,
    })
}

// ---------------------------------------------------------------------------------
// The intersection scene.

const LIGHT_B: DVec3 = DVec3::new(1.5, 7.0, 2.0);
const BOX_B: (DVec3, DVec3) = (DVec3::new(-1.0, 0.3, -1.0), DVec3::new(1.0, 2.3, 1.0));
const ROUND: (DVec3, f64) = (DVec3::new(0.0, 1.3, 0.0), 1.3);
const BALL: (DVec3, f64) = (DVec3::new(0.2, 3.3, 0.1), 0.35);

const INTERSECTION: &str = r#"
[camera]
type = "orthographic"
eye = [3.0, 4.0, 5.0]
look_at = [0.3, 1.5, 0.6]
height = 4.6

[image]
width = 96
height = 72

[render]
background = [0.02, 0.03, 0.05]
ambient_light = 1

[materials.ground]
color = [0.85, 0.85, 0.8]
ambient = 0.1
diffuse = 0.8

[materials.teal]
color = [0.15, 0.7, 0.6]
ambient = 0.1
diffuse = 0.85

[materials.orange]
color = [0.95, 0.5, 0.1]
ambient = 0.1
diffuse = 0.6
specular = 0.5
shininess = 12

[materials.white]
color = [0.9, 0.9, 0.9]
ambient = 0.1
diffuse = 0.9

[[lights]]
type = "point"
position = [1.5, 7.0, 2.0]
intensity = 35

[[objects]]
name = "ground"
type = "plane"
normal = [0, 1, 0]
offset = 0
material = "ground"

[[objects]]
name = "rounded cube"
type = "intersection"
material = "teal"
children = [
  { type = "box", min = [-1, 0.3, -1], max = [1, 2.3, 1] },
  { type = "sphere", center = [0, 1.3, 0], radius = 1.3, material = "orange" },
]

[[objects]]
name = "ball"
type = "sphere"
center = [0.2, 3.3, 0.1]
radius = 0.35
material = "white"
"#;

/// Closed form of the intersection scene: object 0 the ground, object 1 the box
/// (leaf 0) intersected with the sphere (leaf 1), object 2 the ball.
fn shade_intersection(o: DVec3, d: DVec3) -> Option<Shade> {
    let (lo, hi) = BOX_B;
    let (sc, sr) = ROUND;
    let (bc, br) = BALL;
    // The CSG object: inside both; the later entry is the surface.
    let csg = |o: DVec3, d: DVec3| -> Option<(f64, f64, u32, DVec3)> {
        let (b0, b1, bn, _) = box_interval(o, d, lo, hi)?;
        let (s0, s1) = sphere_interval(o, d, sc, sr)?;
        let (t0, t1) = (b0.max(s0), b1.min(s1));
        if t0 >= t1 {
            return None;
        }
        if b0 > s0 {
            Some((t0, t1, 0, bn))
        } else {
            Some((t0, t1, 1, (o + d * s0 - sc) / sr))
        }
    };
    let mut hits: Vec<(f64, u32, u32, DVec3)> = Vec::new();
    if let Some((t0, _, leaf, n)) = csg(o, d) {
        hits.push((t0, 1, leaf, n));
    }
    if let Some((t0, _)) = sphere_interval(o, d, bc, br) {
        hits.push((t0, 2, 0, (o + d * t0 - bc) / br));
    }
    if d.y < 0.0 {
        hits.push((-o.y / d.y, 0, 0, DVec3::Y));
    }
    let &(t, object, leaf, normal) = hits
        .iter()
        .filter(|h| h.0 > 0.0)
        .min_by(|a, b| a.0.total_cmp(&b.0))?;
    let point = o + d * t;
    let seg = LIGHT_B - point;
    let eps = 1e-6;
    let by_csg =
        csg(point, seg).is_some_and(|(t0, t1, _, _)| t0.max(eps) < t1.min(1.0) && t1 > eps);
    let by_ball = sphere_interval(point, seg, bc, br)
        .is_some_and(|(t0, t1)| t0.max(eps) < t1.min(1.0) && t1 > eps);
    let faces = normal.dot(seg) > 0.0;
    Some(Shade {
        object,
        leaf,
        point,
        normal,
        lit: faces && !by_csg && !by_ball,
        through_removed: false,
        shadowed_by_csg: faces && by_csg,
        shadowed_by_ball: faces && by_ball,
    })
}

fn mat(color: [f64; 3], ka: f64, kd: f64, ks: f64, n: i32) -> Mat {
    Mat {
        color: DVec3::from(color),
        ka,
        kd,
        ks,
        n,
    }
}

fn report(case: &Case, t: &Tally) {
    eprintln!(
        "{}: compared {} pixels, skipped {}; kinds (object, leaf, lit) {:?}; cavity {}, \
         lit through removed material (ground, CSG) {:?}, shadowed by the CSG {}, by the ball {}",
        case.name,
        t.compared,
        t.skipped,
        t.kinds,
        t.cavity,
        t.through_removed,
        t.shadowed_by_csg,
        t.shadowed_by_ball
    );
    assert!(
        t.failures.is_empty(),
        "{} of {} pixels differ from the closed form:\n{}",
        t.failures.len(),
        t.compared,
        t.failures[..t.failures.len().min(30)].join("\n")
    );
}

#[test]
fn difference_cavities_leaf_materials_and_shadows_through_the_hole_match_closed_form() {
    let case = Case {
        name: "difference",
        toml: DIFFERENCE,
        camera: Ortho::new(
            DVec3::new(1.5, 8.0, 4.0),
            DVec3::new(0.0, 0.7, 0.5),
            4.0,
            (96, 72),
        ),
        light: LIGHT_A,
        intensity: 40.0,
        materials: BTreeMap::from([
            ((0, 0), mat([0.85, 0.85, 0.8], 0.1, 0.8, 0.0, 1)),
            ((1, 0), mat([0.8, 0.25, 0.2], 0.1, 0.9, 0.0, 1)),
            ((1, 1), mat([0.9, 0.7, 0.15], 0.1, 0.7, 0.4, 10)),
            ((1, 2), mat([0.2, 0.35, 0.9], 0.1, 0.9, 0.0, 1)),
        ]),
        shade: shade_difference,
    };
    // The scene file's hole cylinder must lie on the closed form's axis.
    let (from, to) = (DVec3::new(0.0, 3.325, -1.5), DVec3::new(0.0, -0.955, 2.5));
    for p in [from, to] {
        let q = p - LIGHT_A;
        assert!((q - hole_axis() * q.dot(hole_axis())).length() < 1e-9);
    }
    let t = check_case(&case);
    report(&case, &t);
    let k = |o, l, lit| t.kinds.get(&(o, l, lit)).copied().unwrap_or(0);
    // Every leaf seen lit; the box and ground also in shadow; cavity faces of both
    // subtracted leaves; light through the removed material onto the cavity faces and
    // through the hole onto the ground.
    for (o, l) in [(0, 0), (1, 0), (1, 1), (1, 2)] {
        assert!(k(o, l, true) >= 15, "({o}, {l}) lit: {t:?}");
    }
    assert!(k(0, 0, false) >= 100 && k(1, 0, false) >= 100, "{t:?}");
    assert!(t.cavity >= 60, "{t:?}");
    assert!(
        t.through_removed[0] >= 20 && t.through_removed[1] >= 20,
        "{t:?}"
    );
    assert!(t.shadowed_by_csg >= 100, "{t:?}");
    assert!(t.compared >= 96 * 72 * 3 / 4, "{t:?}");
}

#[test]
fn intersection_leaf_materials_and_shadows_onto_and_from_it_match_closed_form() {
    let case = Case {
        name: "intersection",
        toml: INTERSECTION,
        camera: Ortho::new(
            DVec3::new(3.0, 4.0, 5.0),
            DVec3::new(0.3, 1.5, 0.6),
            4.6,
            (96, 72),
        ),
        light: LIGHT_B,
        intensity: 35.0,
        materials: BTreeMap::from([
            ((0, 0), mat([0.85, 0.85, 0.8], 0.1, 0.8, 0.0, 1)),
            ((1, 0), mat([0.15, 0.7, 0.6], 0.1, 0.85, 0.0, 1)),
            ((1, 1), mat([0.95, 0.5, 0.1], 0.1, 0.6, 0.5, 12)),
            ((2, 0), mat([0.9, 0.9, 0.9], 0.1, 0.9, 0.0, 1)),
        ]),
        shade: shade_intersection,
    };
    let t = check_case(&case);
    report(&case, &t);
    let k = |o, l, lit| t.kinds.get(&(o, l, lit)).copied().unwrap_or(0);
    for (o, l) in [(0, 0), (1, 0), (1, 1), (2, 0)] {
        assert!(k(o, l, true) >= 15, "({o}, {l}) lit: {t:?}");
    }
    assert!(k(0, 0, false) >= 100, "{t:?}");
    // The ball's shadow on the CSG object, and the CSG object's on the ground.
    assert!(t.shadowed_by_ball >= 10, "{t:?}");
    assert!(t.shadowed_by_csg >= 100, "{t:?}");
    assert!(t.compared >= 96 * 72 * 3 / 4, "{t:?}");
}
