//! Surfaces written as expressions or control points: implicit `f(x, y, z) = 0`,
//! parametric `p(u, v)`, bicubic Bézier patches and the Utah teapot. Errors inside an
//! expression point at the offending character of the scene file.

use super::reader::{Error, Result, Table, Val};
use super::tree::Value;
use glam::Vec3;
use irradia_core::Aabb;
use irradia_geometry::expr::{Expr, ExprError};
use irradia_geometry::shapes::{
    BezierPatch, BezierSurface, ImplicitError, ImplicitSurface, ParametricError, ParametricSurface,
};
use irradia_geometry::Shape;
use std::sync::Arc;

pub const KINDS: &[&str] = &["implicit", "parametric", "bezier", "teapot"];

/// Largest parametric grid (cells): two triangles each, so about 8M triangles at most.
const MAX_PARAMETRIC_CELLS: u64 = 1 << 22;

pub fn build_surface(kind: &str, t: &Table) -> Result<Option<Arc<dyn Shape>>> {
    Ok(Some(match kind {
        "implicit" => Arc::new(implicit(t)?),
        "parametric" => Arc::new(parametric(t)?),
        "bezier" => {
            let p_v = t.req("patches")?;
            let mut patches = Vec::new();
            for p in p_v.array()? {
                let pts = p.array()?;
                if pts.len() != 16 {
                    return Err(p.err(format!(
                        "a bicubic patch needs 16 control points (4 rows of 4), found {}",
                        pts.len()
                    )));
                }
                let mut points = [Vec3::ZERO; 16];
                for (k, q) in pts.iter().enumerate() {
                    points[k] = q.vec3()?;
                }
                patches.push(BezierPatch::new(points));
            }
            let level = level(t)?;
            Arc::new(BezierSurface::new(patches, level).map_err(|e| p_v.err(e.to_string()))?)
        }
        "teapot" => {
            let level = level(t)?;
            Arc::new(BezierSurface::teapot(level).map_err(|e| t.err(e.to_string()))?)
        }
        _ => return Ok(None),
    }))
}

/// Tessellation level of Bézier patches (cells per patch side), 1..=256, default 8.
fn level(t: &Table) -> Result<u32> {
    match t.get("level") {
        None => Ok(8),
        Some(l) => {
            let v = l.u32()?;
            if !(1..=256).contains(&v) {
                return Err(l.err(format!("must be between 1 and 256 (got {v})")));
            }
            Ok(v)
        }
    }
}

/// An expression error placed at its character in the file when the string is written
/// plainly (no escapes, one line); otherwise at the string.
fn expr_error(v: &Val, e: &ExprError, prefix: &str) -> Error {
    let msg = format!(
        "{prefix}{} (at character {} of the expression)",
        e.message, e.column
    );
    let mut err = v.err(msg);
    if let Value::Str(s) = &v.node.value {
        let text = v.doc.text;
        let start = v.node.pos + 1;
        let plain = text.get(start..start + s.len()) == Some(s.as_str());
        if plain && !s.contains('\n') {
            if let Some(c) = err.column.as_mut() {
                *c += e.column;
            }
        }
    }
    err
}

fn bounds_box(v: &Val) -> Result<Aabb> {
    let t = v.table()?;
    let lo = t.req("min")?.vec3()?;
    let hi_v = t.req("max")?;
    let hi = hi_v.vec3()?;
    t.finish()?;
    if lo.cmpge(hi).any() {
        return Err(hi_v.err(format!(
            "every coordinate of max must exceed min (min {lo}, max {hi})"
        )));
    }
    Ok(Aabb::new(lo, hi))
}

/// `expr = "x^2 + y^2 + z^2 - 1"`, `bounds = { min, max }`, optional `lipschitz` (use
/// sphere tracing with that bound instead of interval isolation) and `tolerance`.
fn implicit(t: &Table) -> Result<ImplicitSurface> {
    let e_v = t.req("expr")?;
    let src = e_v.str()?;
    let b_v = t.req("bounds")?;
    let bounds = bounds_box(&b_v)?;
    let mut s = match ImplicitSurface::parse(src, bounds) {
        Ok(s) => s,
        Err(ImplicitError::Expr(e)) => return Err(expr_error(&e_v, &e, "")),
        Err(e @ ImplicitError::BadBounds { .. }) => return Err(b_v.err(e.to_string())),
        Err(e) => return Err(e_v.err(e.to_string())),
    };
    if let Some(l) = t.get("lipschitz") {
        s = s
            .with_lipschitz(l.positive()? as f64)
            .map_err(|e| l.err(e.to_string()))?;
    }
    if let Some(tol) = t.get("tolerance") {
        s = s
            .with_tolerance(tol.positive()? as f64)
            .map_err(|e| tol.err(e.to_string()))?;
    }
    Ok(s)
}

/// A number, or a string holding a constant expression (`"2*pi"`).
fn constant(v: &Val) -> Result<f64> {
    if v.is_str() {
        let e = Expr::parse(v.str()?, &[]).map_err(|e| expr_error(v, &e, ""))?;
        let x = e.eval(&[]);
        if !x.is_finite() {
            return Err(v.err(format!("must be a finite number (got {x})")));
        }
        Ok(x)
    } else {
        v.f64()
    }
}

fn range(v: &Val) -> Result<(f64, f64)> {
    let items = v.array()?;
    if items.len() != 2 {
        return Err(v.err(format!(
            "expected [min, max], found {} elements",
            items.len()
        )));
    }
    let (a, b) = (constant(&items[0])?, constant(&items[1])?);
    if a >= b {
        return Err(items[1].err(format!("max must exceed min (got [{a}, {b}])")));
    }
    Ok((a, b))
}

/// `x`, `y`, `z` expressions over `u, v`; `u` and `v` ranges; `resolution = [nu, nv]`.
fn parametric(t: &Table) -> Result<ParametricSurface> {
    let xv = t.req("x")?;
    let yv = t.req("y")?;
    let zv = t.req("z")?;
    let mut exprs = Vec::new();
    for v in [&xv, &yv, &zv] {
        exprs.push(Expr::parse(v.str()?, &["u", "v"]).map_err(|e| expr_error(v, &e, ""))?);
    }
    let u = range(&t.req("u")?)?;
    let v = range(&t.req("v")?)?;
    let res = match t.get("resolution") {
        None => (64, 32),
        Some(r) => {
            let items = r.array()?;
            if items.len() != 2 {
                return Err(r.err("expected [cells along u, cells along v]"));
            }
            let (a, b) = (items[0].count()?, items[1].count()?);
            if a > 4096 || b > 4096 || a as u64 * b as u64 > MAX_PARAMETRIC_CELLS {
                return Err(r.err(format!(
                    "at most 4096 cells each way and {MAX_PARAMETRIC_CELLS} in all (got [{a}, {b}])"
                )));
            }
            (a, b)
        }
    };
    let [x, y, z]: [Expr; 3] = exprs.try_into().expect("three expressions");
    ParametricSurface::new([x, y, z], u, v, res).map_err(|e| match &e {
        ParametricError::Expr { coordinate, error } => {
            let at = match *coordinate {
                "x" => &xv,
                "y" => &yv,
                _ => &zv,
            };
            expr_error(at, error, "")
        }
        _ => t.err(e.to_string()),
    })
}
