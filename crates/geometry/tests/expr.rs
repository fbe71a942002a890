//! The expression language: precedence, errors with columns, f64 values, interval
//! enclosures that contain sampled values (proptest), and gradients against finite
//! differences.

use irradia_geometry::expr::{Expr, Interval};
use proptest::prelude::*;

const XYZ: &[&str] = &["x", "y", "z"];

fn eval(src: &str, vars: &[f64]) -> f64 {
    Expr::parse(src, XYZ).unwrap().eval(vars)
}

fn tree(src: &str) -> String {
    Expr::parse(src, XYZ).unwrap().ast().to_parenthesised()
}

#[test]
fn precedence_and_associativity() {
    assert_eq!(tree("x + y * z"), "($0 + ($1 * $2))");
    assert_eq!(tree("x - y - z"), "(($0 - $1) - $2)");
    assert_eq!(tree("x / y / z"), "(($0 / $1) / $2)");
    assert_eq!(tree("-x^y"), "(-($0 ^ $1))");
    assert_eq!(tree("x^y^z"), "($0 ^ ($1 ^ $2))");
    assert_eq!(tree("x^-y"), "($0 ^ (-$1))");
    assert_eq!(tree("(x + y) * z"), "(($0 + $1) * $2)");
    assert_eq!(tree("x^2"), "($0^2)");
    assert_eq!(tree("2 * 3 + x"), "(6 + $0)");
    assert_eq!(eval("1 + 2 * 3", &[]), 7.0);
    assert_eq!(eval("2^3^2", &[]), 512.0);
    assert_eq!(eval("-2^2", &[]), -4.0);
    assert_eq!(eval("(-2)^2", &[]), 4.0);
    assert_eq!(eval("2^-1", &[]), 0.5);
    assert_eq!(eval("10 - 4 - 3", &[]), 3.0);
    assert_eq!(eval("1e-3 * 2E2", &[]), 0.2);
    assert_eq!(eval("--x", &[5.0]), 5.0);
    assert_eq!(eval("x*y - z", &[2.0, 3.0, 4.0]), 2.0);
}

#[test]
fn functions_and_constants() {
    let v = [0.3, -1.7, 2.5];
    let cases: &[(&str, f64)] = &[
        (
            "sin(x) + cos(y) * tan(z)",
            0.3f64.sin() + (-1.7f64).cos() * 2.5f64.tan(),
        ),
        (
            "asin(x) - acos(x) + atan(y)",
            0.3f64.asin() - 0.3f64.acos() + (-1.7f64).atan(),
        ),
        ("atan2(y, z)", (-1.7f64).atan2(2.5)),
        (
            "sqrt(z) * exp(x) / log(z)",
            2.5f64.sqrt() * 0.3f64.exp() / 2.5f64.ln(),
        ),
        ("abs(y) + min(x, y) + max(x, z)", 1.7 - 1.7 + 2.5),
        ("pow(z, x) + floor(y)", 2.5f64.powf(0.3) - 2.0),
        ("pi * e", std::f64::consts::PI * std::f64::consts::E),
    ];
    for (src, want) in cases {
        let got = eval(src, &v);
        assert!((got - want).abs() < 1e-12, "{src}: {got} vs {want}");
    }
}

#[test]
fn errors_report_the_column() {
    let cases: &[(&str, usize, &str)] = &[
        ("x + ", 5, "unexpected end"),
        ("x + * y", 5, "expected a number"),
        ("x + w", 5, "unknown name 'w'"),
        ("2 * foo(x)", 5, "unknown function 'foo'"),
        ("sin(x, y)", 1, "takes 1 argument"),
        ("atan2(x)", 1, "takes 2 arguments"),
        ("(x + y", 7, "missing ')'"),
        ("x + y)", 6, "unmatched ')'"),
        ("x $ y", 3, "unexpected character '$'"),
        ("x y", 3, "expected an operator"),
        ("", 1, "empty"),
        ("1.2.3 + x", 1, "malformed number"),
        ("1e999", 1, "not finite"),
        ("sqrt + 1", 1, "needs arguments"),
        ("x + u", 5, "unknown name 'u'"),
    ];
    for (src, col, msg) in cases {
        let err = Expr::parse(src, XYZ).expect_err(src);
        assert_eq!(err.column, *col, "{src}: {err}");
        assert!(err.message.contains(msg), "{src}: {err}");
        assert!(err.to_string().starts_with(&format!("column {col}:")));
    }
    assert!(Expr::parse("u * v", &["u", "v"]).is_ok());
    let deep = "(".repeat(500) + "x" + &")".repeat(500);
    assert!(Expr::parse(&deep, XYZ)
        .unwrap_err()
        .message
        .contains("nested too deeply"));
}

#[test]
fn interval_special_cases() {
    let x = |lo, hi| Interval::new(lo, hi);
    let e = |src: &str, iv: Interval| Expr::parse(src, &["x"]).unwrap().eval_interval(&[iv]);
    // Even powers are non-negative.
    let r = e("x^2", x(-1.0, 2.0));
    assert!(r.lo == 0.0 && r.hi >= 4.0 && r.hi < 4.0 + 1e-12);
    // Division by an interval containing 0 is everything.
    assert_eq!(e("1 / x", x(-1.0, 1.0)), Interval::ENTIRE);
    // Wide intervals of sin and cos reach ±1; narrow ones are tight.
    assert_eq!(e("sin(x)", x(0.0, 7.0)), x(-1.0, 1.0));
    let r = e("sin(x)", x(1.0, 2.0));
    assert!(r.hi == 1.0 && (r.lo - 1f64.sin()).abs() < 1e-12);
    let r = e("cos(x)", x(3.0, 3.5));
    assert!(r.lo == -1.0 && (r.hi - 3.5f64.cos()).abs() < 1e-12);
    // tan across a pole.
    assert_eq!(e("tan(x)", x(1.0, 2.0)), Interval::ENTIRE);
    // Outside the domain: empty; partly outside: clipped.
    assert!(e("sqrt(x)", x(-2.0, -1.0)).is_empty());
    assert!(e("sqrt(x)", x(-2.0, 4.0)).contains(0.0));
    assert!(e("log(x)", x(-1.0, 1.0)).lo == f64::NEG_INFINITY);
    // atan2 across the branch cut.
    let a = Expr::parse("atan2(y, x)", &["x", "y"]).unwrap();
    let r = a.eval_interval(&[x(-2.0, -1.0), x(-0.5, 0.5)]);
    assert!(r.lo <= -std::f64::consts::PI && r.hi >= std::f64::consts::PI);
}

fn arb_expr() -> impl Strategy<Value = String> {
    let leaf = prop_oneof![
        Just("x".to_string()),
        Just("y".to_string()),
        (-3.0f64..3.0).prop_map(|c| format!("({c:.3})")),
    ];
    leaf.prop_recursive(4, 24, 2, |inner| {
        prop_oneof![
            (inner.clone(), inner.clone(), 0..6usize).prop_map(|(a, b, k)| {
                let op = ["+", "-", "*", "/", "^", "^"][k];
                if op == "^" {
                    // integer and fractional powers
                    format!("({a})^{}", if b.len() % 2 == 0 { "2" } else { "3" })
                } else {
                    format!("({a}) {op} ({b})")
                }
            }),
            (inner.clone(), 0..12usize).prop_map(|(a, k)| {
                let f = [
                    "sin", "cos", "tan", "asin", "acos", "atan", "sqrt", "exp", "log", "abs",
                    "floor", "-",
                ][k];
                format!("{f}({a})")
            }),
            (inner.clone(), inner, 0..4usize).prop_map(|(a, b, k)| {
                let f = ["atan2", "min", "max", "pow"][k];
                format!("{f}({a}, {b})")
            }),
        ]
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(1000))]
    /// Every f64 value at a point of the box lies in the interval enclosure over the box.
    #[test]
    fn interval_enclosures_contain_sampled_values(
        src in arb_expr(),
        x0 in -4.0f64..4.0, wx in 0.0f64..3.0,
        y0 in -4.0f64..4.0, wy in 0.0f64..3.0,
        samples in proptest::collection::vec((0.0f64..=1.0, 0.0f64..=1.0), 12),
    ) {
        let e = Expr::parse(&src, &["x", "y"]).unwrap();
        let bx = Interval::new(x0, x0 + wx);
        let by = Interval::new(y0, y0 + wy);
        let enclosure = e.eval_interval(&[bx, by]);
        for (s, t) in samples.iter().copied().chain([(0.0, 0.0), (1.0, 1.0), (0.0, 1.0), (1.0, 0.0)]) {
            let (x, y) = (x0 + s * wx, y0 + t * wy);
            let v = e.eval(&[x.min(bx.hi), y.min(by.hi)]);
            if v.is_nan() {
                continue; // outside the domain: nothing to enclose
            }
            prop_assert!(
                enclosure.contains(v) || (v.is_infinite() && (enclosure.lo == v || enclosure.hi == v)),
                "{} at ({}, {}) = {} not in [{}, {}]", src, x, y, v, enclosure.lo, enclosure.hi
            );
        }
    }

    /// The directional-derivative enclosure contains the exact directional derivative
    /// (forward-mode duals) at points of the box.
    #[test]
    fn derivative_enclosures_contain_sampled_derivatives(
        src in arb_expr(),
        x0 in -4.0f64..4.0, wx in 0.0f64..2.0,
        y0 in -4.0f64..4.0, wy in 0.0f64..2.0,
        dx in -2.0f64..2.0, dy in -2.0f64..2.0,
        samples in proptest::collection::vec((0.0f64..=1.0, 0.0f64..=1.0), 8),
    ) {
        let e = Expr::parse(&src, &["x", "y"]).unwrap();
        let bx = Interval::new(x0, x0 + wx);
        let by = Interval::new(y0, y0 + wy);
        let (value, slope) = e.eval_interval_directional(&[bx, by], &[dx, dy]);
        for (s, t) in samples {
            let (x, y) = ((x0 + s * wx).min(bx.hi), (y0 + t * wy).min(by.hi));
            let (v, g) = e.eval_gradient(&[x, y]);
            if !v.is_finite() {
                continue;
            }
            prop_assert!(value.contains(v), "{} value {} not in {:?}", src, v, value);
            // The oracle g·dir is itself rounded: allow it a few ulps.
            let dd = g[0] * dx + g[1] * dy;
            let slack = 8.0 * f64::EPSILON * (g[0].abs() * dx.abs() + g[1].abs() * dy.abs());
            if dd.is_finite() {
                prop_assert!(slope.lo <= dd + slack && dd - slack <= slope.hi, "{} at ({}, {}): slope {} not in {:?}", src, x, y, dd, slope);
            }
        }
    }

    /// Forward-mode gradients agree with central differences.
    #[test]
    fn gradients_match_finite_differences(x in -1.5f64..1.5, y in -1.5f64..1.5, z in 0.2f64..2.0) {
        let e = Expr::parse("sin(x*y) + z^3 / (1 + x^2) - sqrt(z) * atan2(y, z) + exp(-x) * pow(z, 0.7)", XYZ).unwrap();
        let (v, g) = e.eval_gradient(&[x, y, z]);
        prop_assert!((v - e.eval(&[x, y, z])).abs() < 1e-12);
        let h = 1e-6;
        for i in 0..3 {
            let mut a = [x, y, z];
            let mut b = [x, y, z];
            a[i] += h;
            b[i] -= h;
            let fd = (e.eval(&a) - e.eval(&b)) / (2.0 * h);
            prop_assert!((fd - g[i]).abs() < 1e-6 * (1.0 + fd.abs()), "d/d{}: {} vs {}", i, g[i], fd);
        }
    }
}
