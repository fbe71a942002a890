//! Every closed form of the lecture's "Form Factor Examples 1-3" against an independent
//! numerical integration (adaptive Gauss-Kronrod 7-15, f64) of the form-factor integral
//!
//! `F_{1→2} = (1/A_1) ∫∫ cos θ_1 cos θ_2 / (π r²) dA_2 dA_1`
//!
//! (or its two-dimensional version `cos θ_1 cos θ_2 / (2 r)` for infinitely long
//! geometry) over the geometry each case's `geometry` text describes. Agreement to 1e-5.

use glam::DVec3;
use irradia_radiosity::formfactor::analytic::{self, CASES};
use std::f64::consts::PI;

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

fn check(name: &str, params: &[(&str, f64)], numeric: f64) {
    let c = closed(name, params);
    println!(
        "{name}: closed form {c:.10}, numerical {numeric:.10}, difference {:.2e}",
        (c - numeric).abs()
    );
    assert!(
        (c - numeric).abs() < 1e-5,
        "{name}: closed form {c} but the integral is {numeric}"
    );
    assert!(
        numeric > 1e-4,
        "{name}: pick parameters with a form factor that can be told apart from 0"
    );
}

#[test]
fn strip_to_strip() {
    let (b, r, phi, dphi): (f64, f64, f64, f64) = (2.0, 1.5, 0.4, 1e-3);
    let n1 = DVec3::Y;
    let dir = DVec3::new(phi.sin(), phi.cos(), 0.0);
    let n2 = -dir;
    let width2 = r * dphi;
    let f = integrate(
        &|z1| {
            integrate(
                &|z2| kernel(DVec3::new(0.0, 0.0, z1), n1, dir * r + DVec3::Z * z2, n2),
                0.0,
                b,
                TOL,
            )
        },
        0.0,
        b,
        TOL,
    ) * width2
        / b;
    check(
        "strip-to-strip",
        &[("b", b), ("r", r), ("phi", phi), ("dphi", dphi)],
        f,
    );
}

#[test]
fn element_parallel_rectangle() {
    let (a, b, c) = (1.2, 0.7, 0.9);
    let f = integrate(
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
    );
    check(
        "element-parallel-rectangle",
        &[("a", a), ("b", b), ("c", c)],
        f,
    );
}

#[test]
fn strip_parallel_rectangle() {
    let (a, b, c) = (1.1, 0.8, 0.6);
    let f = integrate(
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
                        1e-9,
                    )
                },
                0.0,
                a,
                1e-9,
            )
        },
        0.0,
        b,
        1e-9,
    ) / b;
    check(
        "strip-parallel-rectangle",
        &[("a", a), ("b", b), ("c", c)],
        f,
    );
}

#[test]
fn element_perpendicular_rectangle() {
    let (a, b, c) = (0.7, 1.3, 0.9);
    let f = integrate(
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
    );
    check(
        "element-perpendicular-rectangle",
        &[("a", a), ("b", b), ("c", c)],
        f,
    );
}

#[test]
fn perpendicular_rectangles() {
    let (h, l, w): (f64, f64, f64) = (0.8, 1.0, 0.6);
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
            1e-8,
        )
    };
    let f = (part(0.0, diag, &|a: f64| w / a.cos()) + part(diag, PI / 2.0, &|a: f64| h / a.sin()))
        / (w * l);
    check(
        "perpendicular-rectangles",
        &[("h", h), ("l", l), ("w", w)],
        f,
    );
}

#[test]
fn three_plane_enclosure() {
    let (a1, a2, a3): (f64, f64, f64) = (1.0, 1.2, 0.9);
    // Triangle A B C with |AB| = a1, |BC| = a2, |CA| = a3.
    let cx = (a1 * a1 + a3 * a3 - a2 * a2) / (2.0 * a1);
    let cy = (a3 * a3 - cx * cx).sqrt();
    let (pa, pb, pc) = ([0.0, 0.0], [a1, 0.0], [cx, cy]);
    let n1 = [0.0, 1.0];
    let e2 = [(pc[0] - pb[0]) / a2, (pc[1] - pb[1]) / a2];
    let n2 = [-e2[1], e2[0]]; // left of B->C: inward for a counter-clockwise triangle
    let inward = (n2[0] * (pa[0] - pb[0]) + n2[1] * (pa[1] - pb[1])) > 0.0;
    let n2 = if inward { n2 } else { [-n2[0], -n2[1]] };
    let f = integrate(
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
    ) / a1;
    check(
        "three-plane-enclosure",
        &[("a1", a1), ("a2", a2), ("a3", a3)],
        f,
    );
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
    let (h, r) = (0.8, 0.5);
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

#[test]
fn element_offset_disk() {
    let (h, r, a) = (0.7, 0.4, 0.9);
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

#[test]
fn element_perpendicular_disk() {
    let (h, r, l) = (0.8, 0.5, 1.1);
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

#[test]
fn element_elliptical_plate() {
    let (a, b, h) = (0.6, 0.3, 0.5);
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

#[test]
fn strip_cylinder() {
    let (x, y, r): (f64, f64, f64) = (0.7, 1.5, 0.5);
    let c = [x, y];
    // Points of the circle c + r (cos ψ, sin ψ), outward normal (cos ψ, sin ψ); split
    // the integral where the surface turns away from the strip (tangent points).
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
    // The visible arc faces the strip: its outward normal points towards the origin.
    let f = integrate(&g, toward - half, toward + half, TOL);
    check("strip-cylinder", &[("x", x), ("y", y), ("r", r)], f);
}

#[test]
fn coaxial_disks() {
    let (r1, r2, h) = (0.6, 0.4, 0.5);
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
        1e-9,
    ) / (PI * r1 * r1);
    check("coaxial-disks", &[("r1", r1), ("r2", r2), ("h", h)], f);
}

#[test]
fn cylinder_element_plane() {
    let phi: f64 = 0.6;
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
