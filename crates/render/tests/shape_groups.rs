//! Shape groups (`[[shape_groups]]` placed by `type = "instance"` objects: Mitsuba's
//! `shapegroup`/`instance`, pbrt's `ObjectBegin`/`ObjectInstance`) render exactly as
//! the same objects written out one by one with the composed transforms: in the
//! Whitted tracer (materials per member, CSG leaves inside a member) and in the path
//! tracer (an anisotropic material, whose frame follows dp/du through two transforms).

use irradia_render::{render, RenderOptions};
use irradia_scene::{load_str, SceneSyntax};
use std::path::Path;

const HEAD: &str = r#"
[image]
width = 64
height = 48

[camera]
eye = [0, 3, 9]
look_at = [0, 0.5, 0]
fov = 50

[render]
max_depth = 4
background = [0.2, 0.3, 0.4]

[materials.red]
color = [0.9, 0.1, 0.1]
specular = 0.5
shininess = 40
[materials.blue]
color = [0.1, 0.2, 0.9]
reflection = 0.3
[materials.gold]
color = [1, 0.8, 0.2]

[[lights]]
type = "point"
position = [4, 6, 5]
intensity = 60
"#;

/// The group's members, as TOML object tables, each placed by `transform` (member to
/// group space); `{T}` is replaced by the placement of the whole group.
const MEMBERS: &[&str] = &[
    r#"type = "sphere"
center = [0, 0.5, 0]
radius = 0.5
material = "red"
transform = [{T}]"#,
    r#"type = "box"
min = [-0.4, 0, -0.4]
max = [0.4, 0.3, 0.4]
material = "blue"
transform = [{ rotate = [0, 30, 0] }, { translate = [1, 0, 0] }, {T}]"#,
    r#"type = "difference"
material = "gold"
transform = [{ translate = [-1, 0.4, 0] }, {T}]
children = [
  { type = "box", min = [-0.35, -0.35, -0.35], max = [0.35, 0.35, 0.35] },
  { type = "sphere", radius = 0.45, material = "red" },
]"#,
];

const PLACEMENTS: &[&str] = &[
    "{ translate = [-2, 0, 0] }",
    "{ rotate = [0, 45, 0] }, { translate = [1.5, 0, -1] }",
    "{ scale = [1, 1.5, 1] }, { translate = [0.5, 0, 2] }",
];

fn grouped() -> String {
    let mut s = String::from(HEAD);
    s.push_str("[[shape_groups]]\nname = \"trio\"\n");
    for m in MEMBERS {
        // Inside the group the member keeps only its own transform.
        let m = m.replace(", {T}]", "]").replace("[{T}]", "[]");
        s.push_str(&format!("[[shape_groups.objects]]\n{m}\n"));
    }
    for p in PLACEMENTS {
        s.push_str(&format!(
            "[[objects]]\ntype = \"instance\"\ngroup = \"trio\"\ntransform = [{p}]\n"
        ));
    }
    s
}

fn expanded() -> String {
    let mut s = String::from(HEAD);
    for p in PLACEMENTS {
        for m in MEMBERS {
            s.push_str(&format!("[[objects]]\n{}\n", m.replace("{T}", p)));
        }
    }
    s
}

fn image(text: &str) -> Vec<f32> {
    let scene = load_str(text, SceneSyntax::Toml, Path::new("groups.toml"))
        .unwrap_or_else(|e| panic!("{e}\n{text}"));
    let out = render(&scene, &RenderOptions::default()).unwrap();
    out.image
        .pixels()
        .iter()
        .flat_map(|p| [p.r, p.g, p.b])
        .collect()
}

#[test]
fn instances_of_a_group_render_as_the_objects_written_out() {
    let a = image(&grouped());
    let b = image(&expanded());
    let differing = a
        .iter()
        .zip(&b)
        .filter(|(x, y)| (*x - *y).abs() > 1e-3)
        .count();
    // Composing the transforms in another order rounds differently: a silhouette
    // pixel may flip, nothing more.
    assert!(
        differing <= a.len() / 200,
        "{differing} of {} channels differ",
        a.len()
    );
    // The picture is not empty: each material shows.
    let reddish = a
        .chunks(3)
        .filter(|p| p[0] > 2.0 * p[2] && p[0] > 0.2)
        .count();
    let bluish = a
        .chunks(3)
        .filter(|p| p[2] > 2.0 * p[0] && p[2] > 0.3)
        .count();
    assert!(
        reddish > 20 && bluish > 20,
        "{reddish} red, {bluish} blue pixels"
    );
}

#[test]
fn group_errors_name_the_field() {
    let bad = grouped().replace("group = \"trio\"", "group = \"quartet\"");
    let e = load_str(&bad, SceneSyntax::Toml, Path::new("g.toml")).unwrap_err();
    assert!(
        e.to_string()
            .contains("no shape group named 'quartet' (groups: trio)"),
        "{e}"
    );
    let bad = grouped().replacen(
        "type = \"instance\"",
        "type = \"instance\"\nmaterial = \"red\"",
        1,
    );
    let e = load_str(&bad, SceneSyntax::Toml, Path::new("g.toml")).unwrap_err();
    assert!(e.to_string().contains("takes its materials"), "{e}");
}

#[test]
fn the_path_tracer_sees_the_same_anisotropic_frames_through_a_group() {
    let path = |text: String| {
        text.replace(
            "[render]\nmax_depth = 4",
            "[render]\nintegrator = \"path\"\nspp = 4\nmax_depth = 4",
        )
        .replace(
            "[materials.red]\ncolor = [0.9, 0.1, 0.1]\nspecular = 0.5\nshininess = 40",
            "[materials.red]\ntype = \"roughconductor\"\nmaterial = \"Au\"\nalpha_u = 0.05\nalpha_v = 0.4",
        )
    };
    let a = image(&path(grouped()));
    let b = image(&path(expanded()));
    assert!(a.iter().all(|x| x.is_finite()));
    let (sa, sb): (f64, f64) = (
        a.iter().map(|&x| x as f64).sum(),
        b.iter().map(|&x| x as f64).sum(),
    );
    // Baked boxes and grouped ones round differently, so paths part ways after a
    // bounce now and then: compare 8x8-pixel blocks, whose means differ by noise only.
    // (The frames themselves are compared exactly in geometry's shape_group test.)
    let block = |img: &[f32], bx: usize, by: usize| -> f64 {
        let mut sum = 0.0;
        for y in by * 8..by * 8 + 8 {
            for x in bx * 8..bx * 8 + 8 {
                sum += img[(y * 64 + x) * 3..(y * 64 + x) * 3 + 3]
                    .iter()
                    .map(|&v| v as f64)
                    .sum::<f64>();
            }
        }
        sum / 192.0
    };
    for by in 0..6 {
        for bx in 0..8 {
            let (x, y) = (block(&a, bx, by), block(&b, bx, by));
            assert!(
                (x - y).abs() <= 0.05 * x.max(y) + 1e-3,
                "block ({bx}, {by}): {x} against {y} (image sums {sa} and {sb})"
            );
        }
    }
}
