//! Built-in radiosity scenes: the measured Cornell box (reference/cornell-box.md §2),
//! with and without its two blocks, and closed boxes for furnace tests.
//!
//! Units of the Cornell box are millimetres. Its reflectances are the RGB versions of
//! the measured spectra used by Mitsuba 3's `cornell_box()` (cornell-box.md §1): white
//! (0.885809, 0.698859, 0.666422), red (0.570068, 0.0430135, 0.0443706), green
//! (0.105421, 0.37798, 0.076425); the light's own surface reflects 0.78. The light emits
//! the radiosity `π L` for Mitsuba's radiance `L = (18.387, 13.9873, 6.75357)`.
//! The front of the box is open, as in the real one: its form-factor rows sum to less
//! than 1.

use crate::mesh::{spec, PatchSpec};
use glam::DVec3;
use std::f64::consts::PI;

pub const WHITE: [f64; 3] = [0.885809, 0.698859, 0.666422];
pub const RED: [f64; 3] = [0.570068, 0.0430135, 0.0443706];
pub const GREEN: [f64; 3] = [0.105421, 0.37798, 0.076425];
pub const LIGHT_REFLECTANCE: [f64; 3] = [0.78, 0.78, 0.78];
pub const LIGHT_RADIANCE: [f64; 3] = [18.387, 13.9873, 6.75357];

/// The names `--builtin` accepts.
pub const BUILTINS: &[(&str, &str)] = &[
    (
        "cornell",
        "the measured Cornell box with its two blocks (the default)",
    ),
    (
        "cornell-empty",
        "the measured Cornell box without the blocks",
    ),
    (
        "furnace",
        "a closed 1 m cube, every wall emitting 1 and reflecting 0.5 (b = 2 everywhere)",
    ),
];

pub fn builtin(name: &str) -> Option<Vec<PatchSpec>> {
    match name {
        "cornell" => Some(cornell_measured()),
        "cornell-empty" => Some(cornell_empty()),
        "furnace" => Some(closed_box(1.0, [0.5; 3], [1.0; 3])),
        _ => None,
    }
}

fn v(x: f64, y: f64, z: f64) -> DVec3 {
    DVec3::new(x, y, z)
}

/// Orders the corners so the normal points towards `inside` (walls) or away from it.
fn orient(mut c: Vec<DVec3>, towards: DVec3, inward: bool) -> Vec<DVec3> {
    let mut n = DVec3::ZERO;
    for i in 0..c.len() {
        n += c[i].cross(c[(i + 1) % c.len()]);
    }
    let centre = c.iter().copied().sum::<DVec3>() / c.len() as f64;
    let facing = n.dot(towards - centre) > 0.0;
    if facing != inward {
        c.reverse();
    }
    c
}

pub fn light_emission() -> [f64; 3] {
    [
        LIGHT_RADIANCE[0] * PI,
        LIGHT_RADIANCE[1] * PI,
        LIGHT_RADIANCE[2] * PI,
    ]
}

/// The light: 130 x 105 mm at the ceiling's height, facing down.
pub fn cornell_light() -> Vec<DVec3> {
    let y = 548.8;
    orient(
        vec![
            v(343.0, y, 227.0),
            v(343.0, y, 332.0),
            v(213.0, y, 332.0),
            v(213.0, y, 227.0),
        ],
        v(278.0, 0.0, 280.0),
        true,
    )
}

/// The open front of the box (z = 0), for closure checks.
pub fn cornell_front_opening() -> Vec<DVec3> {
    orient(
        vec![
            v(552.8, 0.0, 0.0),
            v(0.0, 0.0, 0.0),
            v(0.0, 548.8, 0.0),
            v(556.0, 548.8, 0.0),
        ],
        v(278.0, 274.0, 280.0),
        true,
    )
}

/// The walls of the measured box: floor, ceiling (with the light's hole), back, green
/// (x = 0) and red (x near 556) walls, and the light.
pub fn cornell_empty() -> Vec<PatchSpec> {
    let inside = v(278.0, 274.4, 279.6);
    let w = |name: &str, c: Vec<DVec3>, rho: [f64; 3]| {
        spec(name, &orient(c, inside, true), rho, [0.0; 3])
    };
    let y = 548.8;
    let mut s = vec![
        w(
            "floor",
            vec![
                v(552.8, 0.0, 0.0),
                v(0.0, 0.0, 0.0),
                v(0.0, 0.0, 559.2),
                v(549.6, 0.0, 559.2),
            ],
            WHITE,
        ),
        w(
            "ceiling front",
            vec![
                v(556.0, y, 0.0),
                v(556.0, y, 227.0),
                v(0.0, y, 227.0),
                v(0.0, y, 0.0),
            ],
            WHITE,
        ),
        w(
            "ceiling back",
            vec![
                v(556.0, y, 332.0),
                v(556.0, y, 559.2),
                v(0.0, y, 559.2),
                v(0.0, y, 332.0),
            ],
            WHITE,
        ),
        w(
            "ceiling left of light",
            vec![
                v(213.0, y, 227.0),
                v(213.0, y, 332.0),
                v(0.0, y, 332.0),
                v(0.0, y, 227.0),
            ],
            WHITE,
        ),
        w(
            "ceiling right of light",
            vec![
                v(556.0, y, 227.0),
                v(556.0, y, 332.0),
                v(343.0, y, 332.0),
                v(343.0, y, 227.0),
            ],
            WHITE,
        ),
        w(
            "back wall",
            vec![
                v(549.6, 0.0, 559.2),
                v(0.0, 0.0, 559.2),
                v(0.0, y, 559.2),
                v(556.0, y, 559.2),
            ],
            WHITE,
        ),
        w(
            "green wall",
            vec![
                v(0.0, 0.0, 559.2),
                v(0.0, 0.0, 0.0),
                v(0.0, y, 0.0),
                v(0.0, y, 559.2),
            ],
            GREEN,
        ),
        w(
            "red wall",
            vec![
                v(552.8, 0.0, 0.0),
                v(549.6, 0.0, 559.2),
                v(556.0, y, 559.2),
                v(556.0, y, 0.0),
            ],
            RED,
        ),
    ];
    s.push(spec(
        "light",
        &cornell_light(),
        LIGHT_REFLECTANCE,
        light_emission(),
    ));
    s
}

/// A block from its four top corners and height: the top and four sides (the bottom
/// stands on the floor and is never seen).
fn block(name: &str, top: [DVec3; 4]) -> Vec<PatchSpec> {
    let centre = top.iter().copied().sum::<DVec3>() / 4.0 - DVec3::Y * (top[0].y / 2.0);
    let mut out = vec![spec(
        &format!("{name} top"),
        &orient(top.to_vec(), centre, false),
        WHITE,
        [0.0; 3],
    )];
    for k in 0..4 {
        let (a, b) = (top[k], top[(k + 1) % 4]);
        let c = vec![v(a.x, 0.0, a.z), v(b.x, 0.0, b.z), b, a];
        out.push(spec(
            &format!("{name} side {}", k + 1),
            &orient(c, centre, false),
            WHITE,
            [0.0; 3],
        ));
    }
    out
}

/// The measured Cornell box with its short and tall blocks.
pub fn cornell_measured() -> Vec<PatchSpec> {
    let mut s = cornell_empty();
    s.extend(block(
        "short block",
        [
            v(130.0, 165.0, 65.0),
            v(82.0, 165.0, 225.0),
            v(240.0, 165.0, 272.0),
            v(290.0, 165.0, 114.0),
        ],
    ));
    s.extend(block(
        "tall block",
        [
            v(423.0, 330.0, 247.0),
            v(265.0, 330.0, 296.0),
            v(314.0, 330.0, 456.0),
            v(472.0, 330.0, 406.0),
        ],
    ));
    s
}

/// A closed cube of side `size` (walls facing in), every wall reflecting `rho` and
/// emitting `emission`: the furnace, where `b = e / (1 − ρ)` everywhere.
pub fn closed_box(size: f64, rho: [f64; 3], emission: [f64; 3]) -> Vec<PatchSpec> {
    let s = size;
    let inside = DVec3::splat(s / 2.0);
    let faces = [
        (
            "floor",
            [v(0., 0., 0.), v(s, 0., 0.), v(s, 0., s), v(0., 0., s)],
        ),
        (
            "ceiling",
            [v(0., s, 0.), v(s, s, 0.), v(s, s, s), v(0., s, s)],
        ),
        (
            "left",
            [v(0., 0., 0.), v(0., s, 0.), v(0., s, s), v(0., 0., s)],
        ),
        (
            "right",
            [v(s, 0., 0.), v(s, s, 0.), v(s, s, s), v(s, 0., s)],
        ),
        ("back", [v(0., 0., s), v(s, 0., s), v(s, s, s), v(0., s, s)]),
        (
            "front",
            [v(0., 0., 0.), v(s, 0., 0.), v(s, s, 0.), v(0., s, 0.)],
        ),
    ];
    faces
        .iter()
        .map(|(n, c)| spec(n, &orient(c.to_vec(), inside, true), rho, emission))
        .collect()
}

/// A closed cube with one emitting face (the ceiling) and a smaller box standing on the
/// floor (an occluder): for tests of occlusion and solver agreement.
pub fn closed_box_with_block(rho: [f64; 3]) -> Vec<PatchSpec> {
    let mut s = closed_box(1.0, rho, [0.0; 3]);
    s[1].emission = [1.0; 3];
    let top = [
        v(0.3, 0.4, 0.3),
        v(0.7, 0.4, 0.3),
        v(0.7, 0.4, 0.7),
        v(0.3, 0.4, 0.7),
    ];
    for mut b in block("block", top) {
        b.reflectance = rho;
        s.push(b);
    }
    s
}
