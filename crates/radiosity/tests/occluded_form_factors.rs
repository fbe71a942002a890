//! Form factors with occlusion, for every numerical method, against a reference that
//! integrates visibility independently of the crate (`reference_quadrature`: composite
//! Gauss-Legendre over both patches with its own segment-against-rectangle visibility
//! test).
//!
//! Closure and reciprocity (`formfactor_methods.rs`) and the furnace hold by
//! construction for most methods (the hemicube's table is normalised to 1, the contour
//! formula covers the whole hemisphere, Monte Carlo fills both directions from one
//! integral), and an empty box never blocks a ray. These scenes are open and
//! non-uniform, with a blocker that hides part of the receiver, so only the right
//! value with the right shadow passes:
//!
//! - parallel: a sender `1 x 0.8` on `z = 0`, a receiver `1 x 1.1` at `z = 0.7`
//!   facing it, shifted, and a `0.4 x 0.35` blocker half way up and off centre;
//! - perpendicular: a `1 x 1` floor, a `1 x 1` wall standing `0.15` above the floor's
//!   plane at its edge, and a `0.55 x 0.35` blocker tilted at 45° between them.
//!
//! Each method's patch-to-patch factors `F(sender → receiver)`, `F(receiver →
//! sender)`, `F(sender quadrant → receiver)` for the four quadrants (their shadows
//! differ) and `F(sender → blocker)` are compared with the reference, at the tolerance
//! stated on each test; each test also computes the method without the blocker and
//! checks that the same tolerance rejects that value (so the tolerance is tight enough
//! to see the shadow) and accepts it against the unoccluded reference. The occluded
//! scene is computed twice, with the blocker's elements after and before the
//! receiver's, so that visibility decided by the order of the elements (a hemicube
//! without its depth test keeps whatever it drew last) fails in one of the two.

mod reference_quadrature;

use glam::DVec3;
use irradia_radiosity::formfactor::{self, FormFactors, Method, Params};
use irradia_radiosity::mesh::{spec, Mesh, MeshOptions, PatchSpec};
use reference_quadrature::{self as rq, Rect, Rule};
use std::sync::OnceLock;
use std::time::Instant;

const V: fn(f64, f64, f64) -> DVec3 = DVec3::new;

/// Sender, receiver and blocker.
struct Scene {
    name: &'static str,
    send: Rect,
    recv: Rect,
    blocker: Rect,
}

fn parallel_scene() -> Scene {
    Scene {
        name: "parallel",
        send: Rect::new(V(0., 0., 0.), V(1., 0., 0.), V(0., 0.8, 0.)),
        // Facing down: u × v = -z.
        recv: Rect::new(V(0.2, -0.1, 0.7), V(0., 1.0, 0.), V(1.1, 0., 0.)),
        blocker: Rect::new(V(0.35, 0.2, 0.35), V(0., 0.35, 0.), V(0.4, 0., 0.)),
    }
}

fn perpendicular_scene() -> Scene {
    Scene {
        name: "perpendicular",
        send: Rect::new(V(0., 0., 0.), V(1., 0., 0.), V(0., 1., 0.)),
        // The wall x = 0, facing +x, from z = 0.3 to 1.3.
        recv: Rect::new(V(0., 0., 0.3), V(0., 1., 0.), V(0., 0., 1.)),
        // A shelf tilted down towards the wall, from (0.1, y, 0.55) to (0.5, y, 0.45),
        // y in [0.2, 0.75], facing down (and a little towards the wall).
        blocker: Rect::new(V(0.1, 0.2, 0.55), V(0., 0.55, 0.), V(0.4, 0., -0.1)),
    }
}

/// Elements of at most 0.01 (10 x 8 on the parallel sender, 10 x 10 on the
/// perpendicular one: the quadrants are whole elements).
const ELEMENT_AREA: f64 = 0.01 * 1.000001;

fn mesh(s: &Scene, with_blocker: bool) -> Mesh {
    let mut specs = vec![
        spec("sender", &s.send.corners(), [0.5; 3], [1.0; 3]),
        spec("receiver", &s.recv.corners(), [0.5; 3], [0.0; 3]),
    ];
    if with_blocker {
        specs.push(spec("blocker", &s.blocker.corners(), [0.5; 3], [0.0; 3]));
    }
    build(&specs)
}

/// The scene with the blocker listed first, so that its elements come before the
/// receiver's: a method whose visibility depends on the order of the elements (a
/// hemicube without a depth test keeps whichever it drew last; a ray caster that takes
/// the first hit it finds) fails in one of the two orders.
fn mesh_blocker_first(s: &Scene) -> Mesh {
    build(&[
        spec("blocker", &s.blocker.corners(), [0.5; 3], [0.0; 3]),
        spec("sender", &s.send.corners(), [0.5; 3], [1.0; 3]),
        spec("receiver", &s.recv.corners(), [0.5; 3], [0.0; 3]),
    ])
}

fn build(specs: &[PatchSpec]) -> Mesh {
    Mesh::build(
        specs,
        MeshOptions {
            max_element_area: Some(ELEMENT_AREA),
            ..Default::default()
        },
    )
    .unwrap()
}

/// The patch-level factors the tests compare.
#[derive(Clone, Copy, Debug, Default)]
struct Factors {
    send_recv: f64,
    recv_send: f64,
    quadrants: [f64; 4],
    send_blocker: f64,
}

impl Factors {
    /// (name, value) pairs in a fixed order.
    fn list(&self) -> Vec<(String, f64)> {
        let mut v = vec![
            ("S→R".to_string(), self.send_recv),
            ("R→S".to_string(), self.recv_send),
        ];
        for (q, f) in self.quadrants.iter().enumerate() {
            v.push((format!("S{q}→R"), *f));
        }
        v.push(("S→B".to_string(), self.send_blocker));
        v
    }
}

/// Quadrant of a sender point: bit 0 for the far half along `u`, bit 1 along `v`.
fn quadrant(s: &Rect, p: DVec3) -> usize {
    let (a, b) = s.params(p);
    usize::from(a > 0.5) | usize::from(b > 0.5) << 1
}

fn quadrant_rect(s: &Rect, q: usize) -> Rect {
    let half = |bit: bool| if bit { (0.5, 1.0) } else { (0.0, 0.5) };
    s.sub(half(q & 1 != 0), half(q & 2 != 0))
}

fn patch_name(mesh: &Mesh, i: usize) -> &str {
    mesh.patches[mesh.elements[i].patch as usize].name.as_str()
}

/// The sender's elements (indices into the mesh).
fn sender_elements(mesh: &Mesh) -> Vec<usize> {
    (0..mesh.len())
        .filter(|&i| patch_name(mesh, i) == "sender")
        .collect()
}

/// `Σ_{j ∈ patch} F_ij`: element `i` to a whole patch.
fn to_patch(mesh: &Mesh, ff: &FormFactors, i: usize, patch: &str) -> f64 {
    (0..mesh.len())
        .filter(|&j| patch_name(mesh, j) == patch)
        .map(|j| ff.get(i, j))
        .sum()
}

/// The patch-level factors of an element matrix: `Σ_{i∈P, j∈Q} A_i F_ij / A_P`.
fn patch_factors(s: &Scene, mesh: &Mesh, ff: &FormFactors) -> Factors {
    let mut out = Factors::default();
    let (mut a_s, mut a_r, mut a_q) = (0.0, 0.0, [0.0; 4]);
    for i in 0..mesh.len() {
        let ei = &mesh.elements[i];
        match patch_name(mesh, i) {
            "sender" => {
                let q = quadrant(&s.send, ei.centroid);
                let g = ei.area * to_patch(mesh, ff, i, "receiver");
                a_s += ei.area;
                a_q[q] += ei.area;
                out.send_recv += g;
                out.quadrants[q] += g;
                out.send_blocker += ei.area * to_patch(mesh, ff, i, "blocker");
            }
            "receiver" => {
                a_r += ei.area;
                out.recv_send += ei.area * to_patch(mesh, ff, i, "sender");
            }
            _ => {}
        }
    }
    out.send_recv /= a_s;
    out.recv_send /= a_r;
    out.send_blocker /= a_s;
    for (f, a) in out.quadrants.iter_mut().zip(a_q) {
        *f /= a;
    }
    out
}

fn blockers(s: &Scene, with_blocker: bool) -> &[Rect] {
    if with_blocker {
        std::slice::from_ref(&s.blocker)
    } else {
        &[]
    }
}

/// Reference patch-level factors (the blocker in place or not).
fn reference(s: &Scene, with_blocker: bool) -> Factors {
    let rule = Rule {
        outer_panels: 4,
        ..Rule::default()
    };
    let mut out = Factors::default();
    for q in 0..4 {
        out.quadrants[q] = rq::rect_to_rect(
            &quadrant_rect(&s.send, q),
            &s.recv,
            blockers(s, with_blocker),
            rule,
        );
    }
    out.send_recv = out.quadrants.iter().sum::<f64>() / 4.0;
    out.recv_send = out.send_recv * s.send.area() / s.recv.area();
    // Nothing lies between the sender and the blocker.
    out.send_blocker = if with_blocker {
        rq::rect_to_rect(&s.send, &s.blocker, &[], Rule::default())
    } else {
        0.0
    };
    out
}

fn scene(which: usize) -> Scene {
    if which == 0 {
        parallel_scene()
    } else {
        perpendicular_scene()
    }
}

/// The references, computed once per scene and blocker (tests share them).
fn cached_reference(which: usize, with_blocker: bool) -> Factors {
    static CELLS: [OnceLock<Factors>; 4] = [const { OnceLock::new() }; 4];
    *CELLS[which * 2 + usize::from(with_blocker)].get_or_init(|| {
        let s = scene(which);
        let t = Instant::now();
        let r = reference(&s, with_blocker);
        println!(
            "reference {} (blocker {with_blocker}): {r:?} in {:.2?}",
            s.name,
            t.elapsed()
        );
        r
    })
}

/// Where a method evaluates a sender element, as points with weights summing to 1: the
/// value it approximates for row `i` is `Σ w F_{dA(x) → receiver}` with visibility.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Points {
    /// Hemicube, hemisphere, contour (rows without near pairs): the centroid.
    Centroid,
    /// Ray casting: the four corners, moved 1e-4 of the way to the centroid.
    Corners,
    /// The analytic method: its 3 x 3 Gauss rule over the element.
    Gauss3,
    /// Monte Carlo: the element's area integral (a 4 x 4 Gauss rule).
    Area,
}

fn points_of(m: Method) -> Points {
    match m {
        Method::Hemicube | Method::Hemisphere | Method::Contour => Points::Centroid,
        Method::RayCast => Points::Corners,
        Method::Analytic => Points::Gauss3,
        Method::MonteCarlo => Points::Area,
    }
}

/// The element as a `Rect` (the meshes here are grids of rectangles).
fn element_rect(mesh: &Mesh, i: usize) -> Rect {
    let v = mesh.elements[i].poly.v;
    assert_eq!(mesh.elements[i].poly.n, 4);
    Rect::new(v[0], v[1] - v[0], v[3] - v[0])
}

fn element_points(mesh: &Mesh, i: usize, pts: Points) -> Vec<(DVec3, f64)> {
    let e = &mesh.elements[i];
    let r = element_rect(mesh, i);
    let gauss = |k: usize| {
        let g = rq::gauss01(k);
        let mut out = Vec::new();
        for &(a, wa) in &g {
            for &(b, wb) in &g {
                out.push((r.at(a, b), wa * wb));
            }
        }
        out
    };
    match pts {
        Points::Centroid => vec![(e.centroid, 1.0)],
        Points::Corners => r
            .corners()
            .iter()
            .map(|&v| (v + (e.centroid - v) * 1e-4, 0.25))
            .collect(),
        Points::Gauss3 => gauss(3),
        Points::Area => gauss(4),
    }
}

/// Reference `F(element → receiver)` and `F(element → blocker)` for each sender element
/// of the mesh with the blocker, at the method's own points.
fn element_reference(s: &Scene, with_blocker: bool, pts: Points) -> Vec<(f64, f64)> {
    let mesh = mesh(s, true);
    let n = s.send.normal();
    sender_elements(&mesh)
        .iter()
        .map(|&i| {
            let mut fr = 0.0;
            let mut fb = 0.0;
            for (x, w) in element_points(&mesh, i, pts) {
                fr += w * rq::point_to_rect(
                    x,
                    n,
                    &s.recv,
                    blockers(s, with_blocker),
                    Rule::default(),
                );
                if with_blocker {
                    fb += w * rq::point_to_rect(x, n, &s.blocker, &[], Rule::default());
                }
            }
            (fr, fb)
        })
        .collect()
}

fn cached_element_reference(which: usize, with_blocker: bool, pts: Points) -> Vec<(f64, f64)> {
    static CELLS: [OnceLock<Vec<(f64, f64)>>; 16] = [const { OnceLock::new() }; 16];
    let k = match pts {
        Points::Centroid => 0,
        Points::Corners => 1,
        Points::Gauss3 => 2,
        Points::Area => 3,
    };
    CELLS[(which * 2 + usize::from(with_blocker)) * 4 + k]
        .get_or_init(|| element_reference(&scene(which), with_blocker, pts))
        .clone()
}

fn params() -> Params {
    Params {
        hemicube_resolution: 256,
        hemisphere_resolution: 128,
        rays: 16,
        samples: 256,
        visibility_samples: 16,
        gauss_points: 3,
        seed: 5,
    }
}

/// Worst relative error over the patch-level factors.
fn worst_patch(got: &Factors, want: &Factors) -> f64 {
    got.list()
        .iter()
        .zip(want.list())
        .filter(|(_, (_, w))| *w > 0.0)
        .map(|((_, g), (_, w))| ((g - w) / w).abs())
        .fold(0.0, f64::max)
}

/// Worst absolute error over the sender's element rows (to the receiver and, with the
/// blocker, to the blocker).
fn worst_rows(mesh: &Mesh, ff: &FormFactors, want: &[(f64, f64)], with_blocker: bool) -> f64 {
    sender_elements(mesh)
        .iter()
        .zip(want)
        .map(|(&i, &(fr, fb))| {
            let er = (to_patch(mesh, ff, i, "receiver") - fr).abs();
            let eb = if with_blocker {
                (to_patch(mesh, ff, i, "blocker") - fb).abs()
            } else {
                0.0
            };
            er.max(eb)
        })
        .fold(0.0, f64::max)
}

fn report(what: &str, got: &Factors, want: &Factors) {
    for ((n, g), (_, w)) in got.list().iter().zip(want.list()) {
        println!(
            "  {what:<26} {n:<5} {g:.6} ref {w:.6} rel {:+.2e}",
            if w > 0.0 { (g - w) / w } else { g - w }
        );
    }
}

/// Tolerances of one method: `patch`, relative, on the patch-level factors (the element
/// discretisation included, so it bounds what a user of this mesh gets); `rows`,
/// absolute, on each sender element's row against the reference at the method's own
/// points (the method's own error: pixels, cells, visibility samples); `rows_open`, the
/// same without the blocker.
#[derive(Clone, Copy, Debug)]
struct Tolerance {
    patch: f64,
    rows: f64,
    rows_open: f64,
}

/// Runs `m` on the scene with and without the blocker and checks the claims of the
/// module comment.
fn check(m: Method, p: Params, which: usize, tol: Tolerance) {
    let s = scene(which);
    let t = Instant::now();
    let method = formfactor::method(m, p);
    let blocked = mesh(&s, true);
    let open = mesh(&s, false);
    let reordered = mesh_blocker_first(&s);
    let ff = method.compute(&blocked, None).unwrap();
    let ff_reordered = method.compute(&reordered, None).unwrap();
    let ff_open = method.compute(&open, None).unwrap();
    let got = patch_factors(&s, &blocked, &ff);
    let got_reordered = patch_factors(&s, &reordered, &ff_reordered);
    let got_open = patch_factors(&s, &open, &ff_open);
    let elapsed = t.elapsed();
    let (want, want_open) = (
        cached_reference(which, true),
        cached_reference(which, false),
    );
    let pts = points_of(m);
    let rows = cached_element_reference(which, true, pts);
    let rows_open = cached_element_reference(which, false, pts);
    println!(
        "{} {} ({} elements, method {elapsed:.2?}, all {:.2?}):",
        m.name(),
        s.name,
        blocked.len(),
        t.elapsed()
    );
    report("with blocker", &got, &want);
    report("with blocker listed first", &got_reordered, &want);
    report("no blocker vs unoccluded", &got_open, &want_open);
    let e = worst_patch(&got, &want);
    let e_open = worst_patch(&got_open, &want_open);
    let r = worst_rows(&blocked, &ff, &rows, true);
    let e_reordered = worst_patch(&got_reordered, &want);
    let r_reordered = worst_rows(&reordered, &ff_reordered, &rows, true);
    let r_open = worst_rows(&open, &ff_open, &rows_open, false);
    // The method run without the blocker, against the occluded references.
    let e_blind = ((got_open.send_recv - want.send_recv) / want.send_recv).abs();
    let r_blind = worst_rows(&open, &ff_open, &rows, false);
    println!(
        "  patch: worst relative error {e:.2e} (unoccluded {e_open:.2e}, blocker ignored {e_blind:.2e}; tolerance {:.1e})\n  \
         rows at {pts:?} points: worst absolute error {r:.2e} (unoccluded {r_open:.2e}, blocker ignored {r_blind:.2e}; tolerances {:.1e}, unoccluded {:.1e})",
        tol.patch, tol.rows, tol.rows_open
    );
    let what = format!("{} {}", m.name(), s.name);
    assert!(
        e < tol.patch,
        "{what}: patch factors off the occluded reference by {e:.3e} (tolerance {})",
        tol.patch
    );
    assert!(
        e_reordered < tol.patch && r_reordered < tol.rows,
        "{what}, blocker listed first: patch factors off by {e_reordered:.3e} (tolerance {}), element rows by {r_reordered:.3e} (tolerance {})",
        tol.patch,
        tol.rows
    );
    assert!(
        e_open < tol.patch,
        "{what}: patch factors off the unoccluded reference by {e_open:.3e} (tolerance {})",
        tol.patch
    );
    assert!(
        r < tol.rows,
        "{what}: element rows off the occluded reference by {r:.3e} (tolerance {})",
        tol.rows
    );
    assert!(
        r_open < tol.rows_open,
        "{what}: element rows off the unoccluded reference by {r_open:.3e} (tolerance {})",
        tol.rows_open
    );
    // Power: the same tolerances reject the blocker's absence by a wide margin.
    assert!(e_blind > 5.0 * tol.patch, "{what}: without the blocker F(S→R) moves by only {e_blind:.3e}: the patch tolerance {} cannot see the shadow", tol.patch);
    assert!(r_blind > 5.0 * tol.rows, "{what}: without the blocker the rows move by only {r_blind:.3e}: the row tolerance {} cannot see the shadow", tol.rows);
}

// ---- Every numerical method, both scenes ----
//
// Measured (seed 5, this mesh) in brackets: worst patch-level relative error, worst
// element-row absolute error, with the blocker; parallel scene / perpendicular scene.

/// Hemicube at 256 pixels: rows within 4e-3 (aliasing of the receiver's outline, about
/// 0.5/resolution: 6.1e-3, 2.9e-3, 1.9e-3, 9.2e-4 at 64 to 512 pixels unoccluded)
/// [2.1e-3 / 1.3e-3]; patch factors within 1.5%, mostly the centroid rule over 0.1-wide
/// elements [3.6e-3 / 8.7e-3].
const HEMICUBE: Tolerance = Tolerance {
    patch: 0.015,
    rows: 4e-3,
    rows_open: 4e-3,
};
/// Hemisphere at 128² cells: rows within 3e-3 [1.5e-3 / 1.2e-3, unoccluded 1.6e-3];
/// patch factors within 2% [5.2e-3 / 1.2e-2].
const HEMISPHERE: Tolerance = Tolerance {
    patch: 0.02,
    rows: 3e-3,
    rows_open: 3e-3,
};
/// Ray casting, 16 rays: rows within 1e-3 of the corner values (one visibility ray per
/// cell of the receiver) [3.8e-5 / 2.9e-4], exact (1e-9) without a blocker, where it
/// sums exact point-to-cell terms; patch factors within 3%, the corner rule over the
/// elements next to the wall [7.1e-3 / 2.0e-2].
const RAYCAST: Tolerance = Tolerance {
    patch: 0.03,
    rows: 1e-3,
    rows_open: 1e-9,
};
/// Monte Carlo, 256 pairs per element pair: rows within 3e-3 [1.2e-3 / 4.6e-4];
/// patch factors within 0.3% [5.5e-4 / 2.7e-4] (no discretisation error: it integrates
/// the area). Statistical: seeds 11 and 12 measured 7.7e-4 and 5.0e-4 (patch), 9.4e-4
/// and 9.7e-4 (rows) on the parallel scene.
const MONTE_CARLO: Tolerance = Tolerance {
    patch: 3e-3,
    rows: 3e-3,
    rows_open: 3e-3,
};
/// Contour with 16 visibility rays: rows within 5e-3 (the unoccluded factor times the
/// fraction of 4 x 4 points of each receiving element seen) [2.4e-3 / 2.1e-3], exact
/// (1e-9) without a blocker; patch factors within 3% [3.5e-3 / 1.4e-2].
const CONTOUR: Tolerance = Tolerance {
    patch: 0.03,
    rows: 5e-3,
    rows_open: 1e-9,
};
/// Analytic (3 x 3 Gauss, 16 visibility rays per point): rows within 2e-3 [1.0e-3 /
/// 8.8e-4], exact (1e-9) without a blocker; patch factors within 0.5% [3.2e-4 / 2.8e-3].
const ANALYTIC: Tolerance = Tolerance {
    patch: 5e-3,
    rows: 2e-3,
    rows_open: 1e-9,
};

#[test]
fn hemicube_parallel() {
    check(Method::Hemicube, params(), 0, HEMICUBE);
}
#[test]
fn hemicube_perpendicular() {
    check(Method::Hemicube, params(), 1, HEMICUBE);
}
#[test]
fn hemisphere_parallel() {
    check(Method::Hemisphere, params(), 0, HEMISPHERE);
}
#[test]
fn hemisphere_perpendicular() {
    check(Method::Hemisphere, params(), 1, HEMISPHERE);
}
#[test]
fn raycast_parallel() {
    check(Method::RayCast, params(), 0, RAYCAST);
}
#[test]
fn raycast_perpendicular() {
    check(Method::RayCast, params(), 1, RAYCAST);
}
#[test]
fn montecarlo_parallel() {
    check(Method::MonteCarlo, params(), 0, MONTE_CARLO);
}
#[test]
fn montecarlo_perpendicular() {
    check(Method::MonteCarlo, params(), 1, MONTE_CARLO);
}
#[test]
fn contour_parallel() {
    check(Method::Contour, params(), 0, CONTOUR);
}
#[test]
fn contour_perpendicular() {
    check(Method::Contour, params(), 1, CONTOUR);
}
#[test]
fn analytic_parallel() {
    check(Method::Analytic, params(), 0, ANALYTIC);
}
#[test]
fn analytic_perpendicular() {
    check(Method::Analytic, params(), 1, ANALYTIC);
}

/// The contour rows are compared at the centroid: that holds while no sender element has
/// a near pair (then the method integrates the row with Gauss points instead). Checks
/// the crate's rule (`contour::is_near`) for these meshes.
#[test]
fn contour_rows_use_centroids_here() {
    use irradia_radiosity::formfactor::contour::is_near;
    for which in 0..2 {
        let m = mesh(&scene(which), true);
        for i in sender_elements(&m) {
            let ei = &m.elements[i];
            for (j, ej) in m.elements.iter().enumerate() {
                if patch_name(&m, j) != "sender" {
                    assert!(
                        !is_near(
                            ei.centroid,
                            ei.poly.diameter(),
                            ej.centroid,
                            ej.poly.diameter()
                        ),
                        "{}: sender element {i} has a near pair {j}",
                        scene(which).name
                    );
                }
            }
        }
    }
}

// ---- The reference rule against closed forms ----

fn rel(a: f64, b: f64) -> f64 {
    ((a - b) / b).abs()
}

/// Unoccluded: the closed forms written in `reference_quadrature` against the crate's
/// catalogue (the oracle for this step), and the quadrature against them: directly
/// opposed rectangles, the perpendicular scene's wall with a gap (form-factor algebra
/// on the common-edge case), and the parallel scene's shifted receiver (semi-analytic:
/// the exact point-to-rectangle factor under a Gauss rule).
#[test]
fn reference_matches_closed_forms_unoccluded() {
    use irradia_radiosity::formfactor::analytic::{self, rectangles};
    for (a, b, c) in [(1.0, 1.0, 1.0), (0.3, 2.0, 0.7), (5.0, 0.2, 1.5)] {
        let cat = (analytic::find("element-parallel-rectangle").unwrap().eval)(&[a, b, c]).unwrap();
        assert!(rel(rq::corner_parallel(a, b, c), cat) < 1e-12);
    }
    for (w, h, l) in [(1.0, 1.0, 1.0), (0.5, 2.0, 1.0), (3.0, 0.4, 0.8)] {
        let cat = rectangles::perpendicular_rectangles(h / l, w / l);
        assert!(rel(rq::perpendicular_common_edge(w, h, l), cat) < 1e-12);
    }
    // Unit squares one apart: 0.19982 (Siegel and Howell's table: 0.1998).
    assert!((rq::opposed_rectangles(1.0, 1.0, 1.0) - 0.19982).abs() < 1e-5);
    let rule = Rule::default();
    for (a, b, c) in [(1.0, 1.0, 1.0), (0.5, 1.0, 1.0), (2.0, 1.0, 0.5)] {
        let send = Rect::new(V(0., 0., 0.), V(a, 0., 0.), V(0., b, 0.));
        let recv = Rect::new(V(0., 0., c), V(0., b, 0.), V(a, 0., 0.));
        let q = rq::rect_to_rect(&send, &recv, &[], rule);
        let exact = rq::opposed_rectangles(a, b, c);
        println!("opposed {a} x {b} at {c}: quadrature {q:.8}, closed form {exact:.8}");
        assert!(rel(q, exact) < 1e-6, "{q} vs {exact}");
    }
    let s = perpendicular_scene();
    let q = rq::rect_to_rect(&s.send, &s.recv, &[], rule);
    let exact = rq::perpendicular_with_gap(1.0, (0.3, 1.3), 1.0);
    println!("perpendicular with a gap: quadrature {q:.8}, closed form {exact:.8}");
    assert!(rel(q, exact) < 1e-6, "{q} vs {exact}");
    assert!(rel(cached_reference(1, false).send_recv, exact) < 1e-6);
    let semi = rq::parallel_semi_analytic(
        ((0.0, 1.0), (0.0, 0.8)),
        &rq::ParallelBox {
            x: (0.2, 1.3),
            y: (-0.1, 0.9),
            z: 0.7,
        },
        None,
        16,
        6,
    );
    let r = cached_reference(0, false).send_recv;
    println!("parallel scene unoccluded: quadrature {r:.8}, semi-analytic {semi:.8}");
    assert!(rel(r, semi) < 1e-6, "{r} vs {semi}");
}

/// Occluded: the parallel scene's blocker casts a rectangular shadow from every point,
/// so `F(receiver) − F(shadow ∩ receiver)` is the exact inner integral, point by point
/// and under a Gauss rule over the sender; a divider wall between opposed squares
/// splits them into two opposed pairs (closed form, with visibility that depends on both
/// end points); the perpendicular scene's reference is converged (a finer rule agrees).
#[test]
fn reference_matches_closed_forms_occluded() {
    let s = parallel_scene();
    let recv = rq::ParallelBox {
        x: (0.2, 1.3),
        y: (-0.1, 0.9),
        z: 0.7,
    };
    let bl = rq::ParallelBox {
        x: (0.35, 0.75),
        y: (0.2, 0.55),
        z: 0.35,
    };
    let rule = Rule::default();
    for (px, py) in [(0.5, 0.4), (0.1, 0.7), (0.93, 0.05), (0.55, 0.37)] {
        let q = rq::point_to_rect(V(px, py, 0.), V(0., 0., 1.), &s.recv, &[s.blocker], rule);
        let open = rq::point_parallel(px, py, recv.x, recv.y, recv.z);
        let exact = rq::point_parallel_shadowed(px, py, &recv, Some(&bl));
        println!("point ({px}, {py}): quadrature {q:.8}, exact {exact:.8} (unoccluded {open:.6})");
        assert!(
            exact < 0.95 * open,
            "the blocker must hide part of the receiver"
        );
        assert!((q - exact).abs() < 2e-6, "{q} vs {exact}");
    }
    // The inner integral is exact here; the outer one has kinks (where a shadow edge
    // crosses a receiver edge), so the semi-analytic value uses many panels.
    let semi = rq::parallel_semi_analytic(((0.0, 1.0), (0.0, 0.8)), &recv, Some(&bl), 64, 4);
    let r = cached_reference(0, true).send_recv;
    println!(
        "parallel scene occluded: quadrature {r:.8}, semi-analytic {semi:.8}, relative {:.1e}",
        rel(r, semi)
    );
    assert!(rel(r, semi) < 2e-5, "{r} vs {semi}");

    // Divider: opposed unit squares one apart, a wall x = 0.47 from plane to plane. Each
    // half of the bottom sees exactly the opposite half of the top; the bottom is
    // integrated half by half (the outer integrand jumps at the wall), while the top's
    // visible part ends inside the inner rule's panels and leaves.
    let top = Rect::new(V(0., 0., 1.), V(0., 1., 0.), V(1., 0., 0.));
    let wall = Rect::new(V(0.47, -1.0, 0.0), V(0., 3.0, 0.), V(0., 0., 1.0));
    for (x0, w) in [(0.0, 0.47), (0.47, 0.53)] {
        let half = Rect::new(V(x0, 0., 0.), V(w, 0., 0.), V(0., 1., 0.));
        let q = rq::rect_to_rect(&half, &top, &[wall], rule);
        let exact = rq::opposed_rectangles(w, 1.0, 1.0);
        let open = rq::rect_to_rect(&half, &top, &[], rule);
        println!("divider, bottom x in [{x0}, {}]: quadrature {q:.8}, closed form {exact:.8} (unoccluded {open:.6})", x0 + w);
        // 5e-5: the wall touches both planes, the hardest case for the leaf rule.
        assert!(rel(q, exact) < 5e-5, "{q} vs {exact}");
        assert!(exact < 0.8 * open);
    }

    // Perpendicular scene, one quadrant: a finer rule agrees.
    let p = perpendicular_scene();
    let quad = quadrant_rect(&p.send, 1);
    let base = rq::rect_to_rect(
        &quad,
        &p.recv,
        &[p.blocker],
        Rule {
            outer_panels: 4,
            ..rule
        },
    );
    let fine = rq::rect_to_rect(
        &quad,
        &p.recv,
        &[p.blocker],
        Rule {
            outer_panels: 6,
            outer_points: 4,
            inner_panels: 48,
            leaf: 8,
            depth: 4,
        },
    );
    println!("perpendicular quadrant 1: {base:.8}, finer rule {fine:.8}");
    assert!(rel(base, fine) < 1e-5, "{base} vs {fine}");
    assert!(rel(base, cached_reference(1, true).quadrants[1]) < 1e-12);
}
