//! Every closed form of the lecture's "Form Factor Examples 1-3" against an independent
//! numerical integration (adaptive Gauss-Kronrod 7-15, f64) of the form-factor integral
//!
//! `F_{1→2} = (1/A_1) ∫∫ cos θ_1 cos θ_2 / (π r²) dA_2 dA_1`
//!
//! (or its two-dimensional version `cos θ_1 cos θ_2 / (2 r)` for infinitely long
//! geometry) over the geometry each case's `geometry` text describes, at several
//! parameter points per case spanning small, medium and large aspect ratios and
//! distances: relative agreement 1e-6 (the quadrature's own error is below 1e-8).
//!
//! Beside the quadrature, independent of it:
//! - published table values (Howell's catalogue of configuration factors, the usual
//!   four-digit values);
//! - limits: `F → 0` at large distance with the `A cos θ1 cos θ2 / (π d²)` asymptote
//!   (the ratio's error shrinks as `(size/d)²`), `F → 1` (or the enclosure's share)
//!   for enclosing configurations, and cases that reduce to one another (an offset
//!   disk with a vanishing offset, a circular elliptical plate, long perpendicular
//!   rectangles and the crossed-strings enclosure);
//! - reciprocity `A_i F_ij = A_j F_ji` where the catalogue has both directions
//!   (perpendicular rectangles, coaxial disks, the enclosure) and closure
//!   `F_12 + F_13 = 1` for the enclosure;
//! - the contour formula of the matrix methods (`contour::point_to_polygon`) against
//!   the catalogue's element-to-rectangle closed forms.

use glam::DVec3;
use irradia_radiosity::formfactor::analytic::{self, CASES};
use irradia_radiosity::formfactor::contour;
use std::f64::consts::PI;

// The published 15-point Gauss-Kronrod nodes and weights, digit for digit.
#[allow(clippy::excessive_precision)]
const XK: [f64; 8] = [
    0.991455371120812639206854697526329,
    0.949107912342758524526189684047851,
    0.864864423359769072789712788640926,
    0.741531185599394439863864773280788,
    0.586087235467691130294144845693013,
    0.405845151377397166906606412076961,
    0.207784955007898467600689403773245,
    0.000000000000000000000000000000000,
];
#[allow(clippy::excessive_precision)]
const WK: [f64; 8] = [
    0.022935322010529224963732008058970,
    0.063092092629978553290700663189204,
    0.104790010322250183839876322541518,
    0.140653259715525918745189590510238,
    0.169004726639267902826583426598550,
    0.190350578064785409913256402421014,
    0.204432940075298892414161999234649,
    0.209482141084727828012999174891714,
];
#[allow(clippy::excessive_precision)]
const WG: [f64; 4] = [
    0.129484966168869693270611432679082,
    0.279705391489276667901467771423780,
    0.381830050505118944950369775488975,
    0.417959183673469387755102040816327,
];

fn gk15(f: &dyn Fn(f64) -> f64, a: f64, b: f64) -> (f64, f64) {
    let c = 0.5 * (a + b);
    let h = 0.5 * (b - a);
    let fc = f(c);
    let mut k = WK[7] * fc;
    let mut g = WG[3] * fc;
    for i in 0..7 {
        let x = h * XK[i];
        let s = f(c - x) + f(c + x);
        k += WK[i] * s;
        if i % 2 == 1 {
            g += WG[i / 2] * s;
        }
    }
    (k * h, ((k - g) * h).abs())
}

/// Adaptive Gauss-Kronrod quadrature of `f` on [a, b] to absolute tolerance `tol`.
fn integrate(f: &dyn Fn(f64) -> f64, a: f64, b: f64, tol: f64) -> f64 {
    fn rec(f: &dyn Fn(f64) -> f64, a: f64, b: f64, tol: f64, whole: (f64, f64), depth: u32) -> f64 {
        let (v, err) = whole;
        if err <= tol || depth > 40 {
            return v;
        }
        let m = 0.5 * (a + b);
        let l = gk15(f, a, m);
        let r = gk15(f, m, b);
        rec(f, a, m, tol * 0.5, l, depth + 1) + rec(f, m, b, tol * 0.5, r, depth + 1)
    }
    rec(f, a, b, tol, gk15(f, a, b), 0)
}

/// The differential form-factor kernel between points with unit normals (0 when
/// either faces away).
fn kernel(p1: DVec3, n1: DVec3, p2: DVec3, n2: DVec3) -> f64 {
    let d = p2 - p1;
    let r2 = d.length_squared();
    let r = r2.sqrt();
    let c1 = n1.dot(d) / r;
    let c2 = -n2.dot(d) / r;
    if c1 <= 0.0 || c2 <= 0.0 {
        return 0.0;
    }
    c1 * c2 / (PI * r2)
}

/// The two-dimensional kernel `cos θ1 cos θ2 / (2 r)` (per unit length of the receiver).
fn kernel2(p1: [f64; 2], n1: [f64; 2], p2: [f64; 2], n2: [f64; 2]) -> f64 {
    let d = [p2[0] - p1[0], p2[1] - p1[1]];
    let r = (d[0] * d[0] + d[1] * d[1]).sqrt();
    let c1 = (n1[0] * d[0] + n1[1] * d[1]) / r;
    let c2 = -(n2[0] * d[0] + n2[1] * d[1]) / r;
    if c1 <= 0.0 || c2 <= 0.0 {
        return 0.0;
    }
    c1 * c2 / (2.0 * r)
}

const TOL: f64 = 1e-10;

fn closed(name: &str, params: &[(&str, f64)]) -> f64 {
    let case = analytic::find(name).unwrap_or_else(|| panic!("case {name} missing"));
    let given: Vec<(String, f64)> = params.iter().map(|(n, v)| (n.to_string(), *v)).collect();
    case.eval_named(&given).unwrap()
}

/// Closed form against the numerical integral: relative difference below 1e-6.
fn check(name: &str, params: &[(&str, f64)], numeric: f64) {
    let c = closed(name, params);
    let rel = (c - numeric).abs() / numeric.abs().max(1e-300);
    println!("{name} {params:?}: closed form {c:.10}, numerical {numeric:.10}, relative difference {rel:.1e}");
    assert!(
        rel < 1e-6,
        "{name} {params:?}: closed form {c} but the integral is {numeric} (relative {rel:.2e})"
    );
    assert!(
        numeric > 1e-6,
        "{name}: pick parameters with a form factor that can be told apart from 0"
    );
}

/// `value` within `rel` (relative) of `expected`.
fn near(what: &str, value: f64, expected: f64, rel: f64) {
    let e = (value - expected).abs() / expected.abs();
    println!("{what}: {value:.8} vs {expected:.8} (relative {e:.1e}, allowed {rel:.0e})");
    assert!(
        e < rel,
        "{what}: {value} but expected {expected} (relative {e:.2e})"
    );
}

/// Large-distance asymptote: `F / F_far → 1` with an error that falls as `1/d²`, at
/// the distances `d` and `4d` (the error must shrink by 16 within a factor 1.5 and be
/// small at `4d`).
fn asymptote(what: &str, f: &dyn Fn(f64) -> (f64, f64), d: f64) {
    let (f1, far1) = f(d);
    let (f2, far2) = f(4.0 * d);
    let (e1, e2) = ((f1 / far1 - 1.0).abs(), (f2 / far2 - 1.0).abs());
    println!(
        "{what}: F/F_far - 1 = {e1:.3e} at d = {d}, {e2:.3e} at 4d (ratio {:.2})",
        e1 / e2
    );
    assert!(
        e1 < 0.1 && e2 < 0.01,
        "{what}: no 1/d² asymptote ({e1}, {e2})"
    );
    assert!(
        (e1 / e2) > 16.0 / 1.5 && (e1 / e2) < 16.0 * 1.5,
        "{what}: the asymptote's error falls by {} between d and 4d, not 16",
        e1 / e2
    );
}

fn strip_to_strip_numeric(b: f64, r: f64, phi: f64, dphi: f64) -> f64 {
    let n1 = DVec3::Y;
    let dir = DVec3::new(phi.sin(), phi.cos(), 0.0);
    let n2 = -dir;
    let width2 = r * dphi;
    integrate(
        &|z1| {
            integrate(
                &|z2| kernel(DVec3::new(0.0, 0.0, z1), n1, dir * r + DVec3::Z * z2, n2),
                0.0,
                b,
                TOL * 1e-2,
            )
        },
        0.0,
        b,
        TOL * 1e-2,
    ) * width2
        / b
}

#[test]
fn strip_to_strip() {
    for (b, r, phi) in [
        (2.0, 1.5, 0.4),
        (0.2, 2.0, 0.0),
        (10.0, 0.5, 1.2),
        (1.0, 1.0, -0.9),
    ] {
        let dphi = 1e-3;
        let f = strip_to_strip_numeric(b, r, phi, dphi);
        check(
            "strip-to-strip",
            &[("b", b), ("r", r), ("phi", phi), ("dphi", dphi)],
            f,
        );
    }
    // Long strips: atan(b/r) → π/2, dF → cos φ dφ / 2 (the two-dimensional strip).
    near(
        "strip-to-strip, b/r = 1e6",
        closed(
            "strip-to-strip",
            &[("b", 1e6), ("r", 1.0), ("phi", 0.3), ("dphi", 1e-3)],
        ),
        0.3f64.cos() * 1e-3 / 2.0,
        1e-5,
    );
}

fn element_parallel_rectangle_numeric(a: f64, b: f64, c: f64) -> f64 {
    integrate(
        &|x| {
            integrate(
                &|y| kernel(DVec3::ZERO, DVec3::Z, DVec3::new(x, y, c), -DVec3::Z),
                0.0,
                b,
                TOL,
            )
        },
        0.0,
        a,
        TOL,
    )
}

#[test]
fn element_parallel_rectangle() {
    for (a, b, c) in [
        (1.2, 0.7, 0.9),
        (0.1, 0.15, 1.0),
        (1.0, 1.0, 1.0),
        (10.0, 5.0, 0.1),
    ] {
        check(
            "element-parallel-rectangle",
            &[("a", a), ("b", b), ("c", c)],
            element_parallel_rectangle_numeric(a, b, c),
        );
    }
    let f = |a: f64, b: f64, c: f64| {
        closed(
            "element-parallel-rectangle",
            &[("a", a), ("b", b), ("c", c)],
        )
    };
    // Howell's table: X = Y = 1 gives 0.1385.
    near(
        "element-parallel-rectangle X = Y = 1",
        f(1.0, 1.0, 1.0),
        0.1385,
        5e-4,
    );
    // An infinite quadrant above the element: a quarter of the hemisphere.
    near(
        "element-parallel-rectangle, infinite quadrant",
        f(1e7, 1e7, 1.0),
        0.25,
        1e-6,
    );
    // Far away: ab / (π c²) (the rectangle's corner on the axis: cos θ = 1 to first order,
    // so the far value is the corner-centred one; the error falls as 1/c²).
    asymptote(
        "element-parallel-rectangle far",
        &|d| (f(0.3, 0.2, d), 0.3 * 0.2 / (PI * d * d)),
        5.0,
    );
}

fn strip_parallel_rectangle_numeric(a: f64, b: f64, c: f64) -> f64 {
    integrate(
        &|y0| {
            integrate(
                &|x| {
                    integrate(
                        &|y| {
                            kernel(
                                DVec3::new(0.0, y0, 0.0),
                                DVec3::Z,
                                DVec3::new(x, y, c),
                                -DVec3::Z,
                            )
                        },
                        0.0,
                        b,
                        1e-10,
                    )
                },
                0.0,
                a,
                1e-10,
            )
        },
        0.0,
        b,
        1e-10,
    ) / b
}

#[test]
fn strip_parallel_rectangle() {
    for (a, b, c) in [(1.1, 0.8, 0.6), (0.2, 0.3, 1.0), (5.0, 4.0, 0.3)] {
        check(
            "strip-parallel-rectangle",
            &[("a", a), ("b", b), ("c", c)],
            strip_parallel_rectangle_numeric(a, b, c),
        );
    }
    let f = |a: f64, b: f64, c: f64| {
        closed("strip-parallel-rectangle", &[("a", a), ("b", b), ("c", c)])
    };
    // A long strip under the edge of a half plane: half of what it sees.
    near(
        "strip-parallel-rectangle, half plane",
        f(1e7, 1e7, 1.0),
        0.5,
        1e-6,
    );
    // Far away the strip (length b) and rectangle (a x b) are two parallel areas facing
    // each other along the z axis but offset by up to (a, b): the mean of
    // cos² / (π r²) over both tends to a b / (π c²).
    asymptote(
        "strip-parallel-rectangle far",
        &|d| (f(0.3, 0.2, d), 0.3 * 0.2 / (PI * d * d)),
        5.0,
    );
}

fn element_perpendicular_rectangle_numeric(a: f64, b: f64, c: f64) -> f64 {
    integrate(
        &|x| {
            integrate(
                &|z| kernel(DVec3::ZERO, DVec3::Z, DVec3::new(x, c, z), -DVec3::Y),
                0.0,
                a,
                TOL,
            )
        },
        0.0,
        b,
        TOL,
    )
}

#[test]
fn element_perpendicular_rectangle() {
    for (a, b, c) in [
        (0.7, 1.3, 0.9),
        (0.2, 0.3, 1.0),
        (8.0, 6.0, 0.2),
        (1.0, 0.1, 3.0),
    ] {
        check(
            "element-perpendicular-rectangle",
            &[("a", a), ("b", b), ("c", c)],
            element_perpendicular_rectangle_numeric(a, b, c),
        );
    }
    let f = |a: f64, b: f64, c: f64| {
        closed(
            "element-perpendicular-rectangle",
            &[("a", a), ("b", b), ("c", c)],
        )
    };
    // A perpendicular quarter plane: a quarter of the hemisphere.
    near(
        "element-perpendicular-rectangle, infinite quarter plane",
        f(1e7, 1e7, 1.0),
        0.25,
        1e-6,
    );
    // Unbounded height: atan(b/c) / (2π) (the wedge of directions that reach the strip
    // x in [0, b] of the wall).
    near(
        "element-perpendicular-rectangle, unbounded height",
        f(1e8, 0.7, 0.4),
        (0.7f64 / 0.4).atan() / (2.0 * PI),
        1e-6,
    );
    // Far away (distance d along y, the rectangle's corner at the foot): cos θ_1 = z/d,
    // cos θ_2 = 1, so F → ∫∫ z dz dx / (π d³) = a² b / (2 π d³).
    asymptote(
        "element-perpendicular-rectangle far",
        &|d| (f(0.3, 0.2, d), 0.3 * 0.3 * 0.2 / (2.0 * PI * d * d * d)),
        5.0,
    );
}

fn perpendicular_rectangles_numeric(h: f64, l: f64, w: f64) -> f64 {
    // ∫_0^l ∫_0^l g(y2 − y1) dy1 dy2 = 2 ∫_0^l (l − u) g(u) du (g is even), and the
    // (x1, z2) quarter plane in polar coordinates (x1 = ρ cos α, z2 = ρ sin α), which
    // takes the 1/ρ singularity at the common edge into the Jacobian. The polar domain
    // of the rectangle [0,w] x [0,h] splits at the diagonal angle.
    let g = |x1: f64, z2: f64| {
        2.0 * integrate(
            &|u| {
                (l - u)
                    * kernel(
                        DVec3::new(x1, 0.0, 0.0),
                        DVec3::Z,
                        DVec3::new(0.0, u, z2),
                        DVec3::X,
                    )
            },
            0.0,
            l,
            1e-10,
        )
    };
    let diag = h.atan2(w);
    let part = |a0: f64, a1: f64, rmax: &dyn Fn(f64) -> f64| {
        integrate(
            &|a| {
                integrate(
                    &|rho| rho * g(rho * a.cos(), rho * a.sin()),
                    0.0,
                    rmax(a),
                    1e-9,
                )
            },
            a0,
            a1,
            1e-9,
        )
    };
    (part(0.0, diag, &|a: f64| w / a.cos()) + part(diag, PI / 2.0, &|a: f64| h / a.sin())) / (w * l)
}

#[test]
fn perpendicular_rectangles() {
    for (h, l, w) in [(0.8, 1.0, 0.6), (0.1, 1.0, 2.0), (3.0, 0.5, 4.0)] {
        check(
            "perpendicular-rectangles",
            &[("h", h), ("l", l), ("w", w)],
            perpendicular_rectangles_numeric(h, l, w),
        );
    }
    let f = |h: f64, l: f64, w: f64| {
        closed("perpendicular-rectangles", &[("h", h), ("l", l), ("w", w)])
    };
    // Howell's table: two unit squares at 90° share 0.2000.
    near(
        "perpendicular-rectangles, unit squares",
        f(1.0, 1.0, 1.0),
        0.20004,
        1e-4,
    );
    // Reciprocity: A_1 F_12 = A_2 F_21 (w l F(h, l, w) = h l F(w, l, h)).
    for (h, l, w) in [
        (0.8, 1.0, 0.6),
        (0.1, 1.0, 2.0),
        (3.0, 0.5, 4.0),
        (0.05, 7.0, 0.3),
    ] {
        near(
            &format!("perpendicular-rectangles reciprocity ({h}, {l}, {w})"),
            w * l * f(h, l, w),
            h * l * f(w, l, h),
            1e-12,
        );
    }
    // Infinitely long: the two-dimensional L, whose factor the crossed-strings rule
    // gives: the enclosure with sides w, h and the diagonal.
    for (h, w) in [(0.8, 0.6), (0.1, 2.0), (3.0, 4.0)] {
        let enclosure = closed(
            "three-plane-enclosure",
            &[("a1", w), ("a2", h), ("a3", (w * w + h * h).sqrt())],
        );
        near(
            &format!("perpendicular-rectangles ({h}, l → ∞, {w}) vs crossed strings"),
            f(h, 1e6, w),
            enclosure,
            1e-5,
        );
    }
    // An infinitely tall wall over a square: half the hemisphere minus what the open ends
    // let out; a wall of unbounded height and length sees exactly half.
    near(
        "perpendicular-rectangles, unbounded wall",
        f(1e6, 1e6, 1.0),
        0.5,
        1e-5,
    );
}

fn three_plane_enclosure_numeric(a1: f64, a2: f64, a3: f64) -> f64 {
    // Triangle A B C with |AB| = a1, |BC| = a2, |CA| = a3.
    let cx = (a1 * a1 + a3 * a3 - a2 * a2) / (2.0 * a1);
    let cy = (a3 * a3 - cx * cx).sqrt();
    let (pa, pb, pc) = ([0.0, 0.0], [a1, 0.0], [cx, cy]);
    let n1 = [0.0, 1.0];
    let e2 = [(pc[0] - pb[0]) / a2, (pc[1] - pb[1]) / a2];
    let n2 = [-e2[1], e2[0]]; // left of B->C: inward for a counter-clockwise triangle
    let inward = (n2[0] * (pa[0] - pb[0]) + n2[1] * (pa[1] - pb[1])) > 0.0;
    let n2 = if inward { n2 } else { [-n2[0], -n2[1]] };
    integrate(
        &|s1| {
            integrate(
                &|s2| kernel2([s1, 0.0], n1, [pb[0] + e2[0] * s2, pb[1] + e2[1] * s2], n2),
                0.0,
                a2,
                TOL,
            )
        },
        0.0,
        a1,
        TOL,
    ) / a1
}

#[test]
fn three_plane_enclosure() {
    for (a1, a2, a3) in [
        (1.0, 1.2, 0.9),
        (1.0, 1.0, 1.0),
        (0.2, 1.0, 0.95),
        (3.0, 2.0, 1.5),
    ] {
        check(
            "three-plane-enclosure",
            &[("a1", a1), ("a2", a2), ("a3", a3)],
            three_plane_enclosure_numeric(a1, a2, a3),
        );
    }
    let f = |a1: f64, a2: f64, a3: f64| {
        closed(
            "three-plane-enclosure",
            &[("a1", a1), ("a2", a2), ("a3", a3)],
        )
    };
    near(
        "three-plane-enclosure, equilateral",
        f(1.0, 1.0, 1.0),
        0.5,
        1e-12,
    );
    for (a1, a2, a3) in [(1.0, 1.2, 0.9), (0.2, 1.0, 0.95), (3.0, 2.0, 1.5)] {
        // Reciprocity and closure (a flat side sees nothing of itself).
        near(
            &format!("three-plane-enclosure reciprocity ({a1}, {a2}, {a3})"),
            a1 * f(a1, a2, a3),
            a2 * f(a2, a1, a3),
            1e-12,
        );
        near(
            &format!("three-plane-enclosure closure ({a1}, {a2}, {a3})"),
            f(a1, a2, a3) + f(a1, a3, a2),
            1.0,
            1e-12,
        );
    }
    // A sliver: a side sees almost nothing of a tiny one.
    assert!(f(1.0, 1e-6, 1.0 - 1e-7) < 1e-5);
}

fn disk_integral(
    centre: DVec3,
    u: DVec3,
    v: DVec3,
    normal: DVec3,
    r: f64,
    from: DVec3,
    from_n: DVec3,
) -> f64 {
    integrate(
        &|rho| {
            integrate(
                &|t| {
                    rho * kernel(
                        from,
                        from_n,
                        centre + u * (rho * t.cos()) + v * (rho * t.sin()),
                        normal,
                    )
                },
                0.0,
                2.0 * PI,
                TOL,
            )
        },
        0.0,
        r,
        TOL,
    )
}

#[test]
fn element_coaxial_disk() {
    for (h, r) in [(0.8, 0.5), (1.0, 0.1), (0.1, 5.0)] {
        let f = disk_integral(
            DVec3::new(0.0, 0.0, h),
            DVec3::X,
            DVec3::Y,
            -DVec3::Z,
            r,
            DVec3::ZERO,
            DVec3::Z,
        );
        check("element-coaxial-disk", &[("h", h), ("r", r)], f);
    }
    let f = |h: f64, r: f64| closed("element-coaxial-disk", &[("h", h), ("r", r)]);
    near("element-coaxial-disk, touching", f(1e-6, 1.0), 1.0, 1e-11);
    asymptote(
        "element-coaxial-disk far",
        &|d| (f(d, 0.2), 0.04 / (d * d)),
        5.0,
    );
}

#[test]
fn element_offset_disk() {
    // Beside the disk, under its rim, under it, and far.
    for (h, r, a) in [
        (0.7, 0.4, 0.9),
        (0.5, 1.0, 0.3),
        (0.3, 0.5, 0.5),
        (3.0, 0.2, 2.0),
    ] {
        let f = disk_integral(
            DVec3::new(a, 0.0, h),
            DVec3::X,
            DVec3::Y,
            -DVec3::Z,
            r,
            DVec3::ZERO,
            DVec3::Z,
        );
        check("element-offset-disk", &[("h", h), ("r", r), ("a", a)], f);
    }
    let f = |h: f64, r: f64, a: f64| closed("element-offset-disk", &[("h", h), ("r", r), ("a", a)]);
    // No offset: the coaxial disk.
    near(
        "element-offset-disk, a → 0",
        f(0.8, 0.5, 1e-7),
        closed("element-coaxial-disk", &[("h", 0.8), ("r", 0.5)]),
        1e-9,
    );
    // Far along the diagonal: π r² cos² θ / (π d²) with cos θ = h/d.
    asymptote(
        "element-offset-disk far",
        &|d| {
            let (h, a) = (0.6 * d, 0.8 * d);
            (f(h, 0.2, a), 0.04 * (h / d).powi(2) / (d * d))
        },
        5.0,
    );
}

#[test]
fn element_perpendicular_disk() {
    for (h, r, l) in [
        (0.8, 0.5, 1.1),
        (0.2, 0.1, 2.0),
        (0.3, 1.0, 1.0),
        (4.0, 0.5, 0.6),
    ] {
        let f = disk_integral(
            DVec3::new(h, 0.0, l),
            DVec3::Y,
            DVec3::Z,
            -DVec3::X,
            r,
            DVec3::ZERO,
            DVec3::Z,
        );
        check(
            "element-perpendicular-disk",
            &[("h", h), ("r", r), ("l", l)],
            f,
        );
    }
    let f = |h: f64, r: f64, l: f64| {
        closed(
            "element-perpendicular-disk",
            &[("h", h), ("r", r), ("l", l)],
        )
    };
    // Far along the diagonal: π r² cos θ_1 cos θ_2 / (π d²), cos θ_1 = l/d, cos θ_2 = h/d.
    asymptote(
        "element-perpendicular-disk far",
        &|d| {
            let (h, l) = (0.6 * d, 0.8 * d);
            (f(h, 0.2, l), 0.04 * (h / d) * (l / d) / (d * d))
        },
        5.0,
    );
}

#[test]
fn element_elliptical_plate() {
    for (a, b, h) in [(0.6, 0.3, 0.5), (0.05, 0.1, 1.0), (4.0, 0.5, 0.2)] {
        let f = integrate(
            &|rho| {
                integrate(
                    &|t| {
                        a * b
                            * rho
                            * kernel(
                                DVec3::ZERO,
                                DVec3::Z,
                                DVec3::new(a * rho * t.cos(), b * rho * t.sin(), h),
                                -DVec3::Z,
                            )
                    },
                    0.0,
                    2.0 * PI,
                    TOL,
                )
            },
            0.0,
            1.0,
            TOL,
        );
        check(
            "element-elliptical-plate",
            &[("a", a), ("b", b), ("h", h)],
            f,
        );
    }
    let f = |a: f64, b: f64, h: f64| {
        closed("element-elliptical-plate", &[("a", a), ("b", b), ("h", h)])
    };
    // A circle is the coaxial disk.
    near(
        "element-elliptical-plate, a = b",
        f(0.7, 0.7, 0.4),
        closed("element-coaxial-disk", &[("h", 0.4), ("r", 0.7)]),
        1e-12,
    );
    near(
        "element-elliptical-plate, touching",
        f(1.0, 2.0, 1e-6),
        1.0,
        1e-11,
    );
    asymptote(
        "element-elliptical-plate far",
        &|d| (f(0.3, 0.1, d), 0.03 / (d * d)),
        5.0,
    );
}

fn strip_cylinder_numeric(x: f64, y: f64, r: f64) -> f64 {
    let c = [x, y];
    // Points of the circle c + r (cos ψ, sin ψ), outward normal (cos ψ, sin ψ); the
    // visible arc lies between the tangent points seen from the strip.
    let d = (x * x + y * y).sqrt();
    let toward = (-y).atan2(-x);
    let half = (r / d).acos();
    // kernel2 wants the receiver's normal pointing back at the sender: the outward one.
    let g = |psi: f64| {
        let n = [psi.cos(), psi.sin()];
        r * kernel2(
            [0.0, 0.0],
            [0.0, 1.0],
            [c[0] + r * n[0], c[1] + r * n[1]],
            n,
        )
    };
    integrate(&g, toward - half, toward + half, TOL * 1e-2)
}

#[test]
fn strip_cylinder() {
    for (x, y, r) in [
        (0.7, 1.5, 0.5),
        (0.0, 1.2, 1.0),
        (5.0, 3.0, 0.2),
        (-2.0, 1.0, 0.8),
    ] {
        check(
            "strip-cylinder",
            &[("x", x), ("y", y), ("r", r)],
            strip_cylinder_numeric(x, y, r),
        );
    }
    let f = |x: f64, y: f64, r: f64| closed("strip-cylinder", &[("x", x), ("y", y), ("r", r)]);
    // Resting on the strip: the cylinder fills the strip's whole view.
    near("strip-cylinder, touching", f(0.0, 1.0, 1.0), 1.0, 1e-12);
    // Independently of the closed form: a strip sees a convex two-dimensional body as
    // the angle between its tangents, F = (sin θ_+ − sin θ_−) / 2 (θ from the strip's
    // normal); the cylinder's tangents lie at θ ± asin(r/d). Near, far and to the side.
    for (x, y, r) in [
        (0.0f64, 1.0f64, 0.999),
        (0.7, 1.5, 0.5),
        (30.0, 40.0, 0.3),
        (-8.0, 0.5, 0.4),
    ] {
        let (d, theta) = ((x * x + y * y).sqrt(), x.atan2(y));
        let delta = (r / d).asin();
        near(
            &format!("strip-cylinder ({x}, {y}, {r}) vs tangent angles"),
            f(x, y, r),
            ((theta + delta).sin() - (theta - delta).sin()) / 2.0,
            1e-12,
        );
    }
}

#[test]
fn coaxial_disks() {
    for (r1, r2, h) in [
        (0.6, 0.4, 0.5),
        (0.1, 0.15, 2.0),
        (1.0, 3.0, 0.1),
        (2.0, 0.5, 0.3),
    ] {
        let f = integrate(
            &|rho1| {
                2.0 * PI
                    * rho1
                    * disk_integral(
                        DVec3::new(0.0, 0.0, h),
                        DVec3::X,
                        DVec3::Y,
                        -DVec3::Z,
                        r2,
                        DVec3::new(rho1, 0.0, 0.0),
                        DVec3::Z,
                    )
            },
            0.0,
            r1,
            1e-10,
        ) / (PI * r1 * r1);
        check("coaxial-disks", &[("r1", r1), ("r2", r2), ("h", h)], f);
    }
    let f = |r1: f64, r2: f64, h: f64| closed("coaxial-disks", &[("r1", r1), ("r2", r2), ("h", h)]);
    // Howell's table: equal disks one radius apart, 0.382.
    near(
        "coaxial-disks, r1 = r2 = h",
        f(1.0, 1.0, 1.0),
        0.38197,
        1e-4,
    );
    // Reciprocity: π r1² F_12 = π r2² F_21.
    for (r1, r2, h) in [(0.6, 0.4, 0.5), (0.1, 0.15, 2.0), (1.0, 3.0, 0.1)] {
        near(
            &format!("coaxial-disks reciprocity ({r1}, {r2}, {h})"),
            r1 * r1 * f(r1, r2, h),
            r2 * r2 * f(r2, r1, h),
            1e-10,
        );
    }
    // A small disk close under a large one is enclosed: F → 1.
    near("coaxial-disks, enclosed", f(0.1, 100.0, 1e-3), 1.0, 1e-6);
    asymptote(
        "coaxial-disks far",
        &|d| (f(0.2, 0.3, d), 0.09 / (d * d)),
        5.0,
    );
}

#[test]
fn cylinder_element_plane() {
    for phi in [0.0, 0.6, PI / 2.0, 2.5] {
        let n = DVec3::Z;
        let m = DVec3::new(phi.sin(), 0.0, phi.cos()); // towards the plane
        let u = DVec3::new(phi.cos(), 0.0, -phi.sin());
        let v = m.cross(u);
        // Directions towards the plane: angle α from m in [0, π/2); weight cos θ / π.
        let f = integrate(
            &|alpha| {
                integrate(
                    &|beta| {
                        let d = u * (alpha.sin() * beta.cos())
                            + v * (alpha.sin() * beta.sin())
                            + m * alpha.cos();
                        d.dot(n).max(0.0) * alpha.sin() / PI
                    },
                    0.0,
                    2.0 * PI,
                    1e-12,
                )
            },
            0.0,
            PI / 2.0,
            1e-12,
        );
        check("cylinder-element-plane", &[("phi", phi)], f);
    }
    let f = |phi: f64| closed("cylinder-element-plane", &[("phi", phi)]);
    near("cylinder-element-plane, facing", f(0.0), 1.0, 1e-15);
    assert!(f(PI).abs() < 1e-15, "facing away: {}", f(PI));
}

/// The contour formula of the contour and analytic matrix methods (point to polygon)
/// against the catalogue's element-to-rectangle closed forms, across aspect ratios and
/// distances.
#[test]
fn contour_formula_matches_the_catalogue() {
    for (a, b, c) in [
        (1.2, 0.7, 0.9),
        (0.01, 0.02, 1.0),
        (30.0, 20.0, 0.05),
        (1.0, 1.0, 1.0),
    ] {
        let rect = [
            DVec3::new(0.0, 0.0, c),
            DVec3::new(a, 0.0, c),
            DVec3::new(a, b, c),
            DVec3::new(0.0, b, c),
        ];
        near(
            &format!("contour vs element-parallel-rectangle ({a}, {b}, {c})"),
            contour::point_to_polygon(DVec3::ZERO, DVec3::Z, &rect),
            closed(
                "element-parallel-rectangle",
                &[("a", a), ("b", b), ("c", c)],
            ),
            1e-9,
        );
        // The same rectangle stood up in the plane y = c: x in [0, b], z in [0, a].
        let wall = [
            DVec3::new(0.0, c, 0.0),
            DVec3::new(b, c, 0.0),
            DVec3::new(b, c, a),
            DVec3::new(0.0, c, a),
        ];
        near(
            &format!("contour vs element-perpendicular-rectangle ({a}, {b}, {c})"),
            contour::point_to_polygon(DVec3::ZERO, DVec3::Z, &wall),
            closed(
                "element-perpendicular-rectangle",
                &[("a", a), ("b", b), ("c", c)],
            ),
            1e-9,
        );
    }
}

#[test]
fn catalogue_covers_the_lecture() {
    assert_eq!(CASES.len(), 13);
    for c in CASES {
        assert!(!c.params.is_empty() && !c.geometry.is_empty(), "{}", c.name);
    }
}

#[test]
fn bad_parameters_are_reported() {
    let c = analytic::find("coaxial-disks").unwrap();
    let e = c
        .eval_named(&[("r1".into(), 1.0), ("h".into(), 1.0)])
        .unwrap_err();
    assert!(e.contains("--r2"), "{e}");
    let e = c
        .eval_named(&[("r1".into(), -1.0), ("r2".into(), 1.0), ("h".into(), 1.0)])
        .unwrap_err();
    assert!(e.contains("positive"), "{e}");
    let e = analytic::find("three-plane-enclosure")
        .unwrap()
        .eval_named(&[("a1".into(), 1.0), ("a2".into(), 1.0), ("a3".into(), 3.0)])
        .unwrap_err();
    assert!(e.contains("triangle"), "{e}");
}
