//! Shape constructors by `type`: each reads its own fields from the object's table and
//! validates them (a radius must be positive, a polygon must not be degenerate). The
//! geometry crate's constructors check again and their refusals ([`ShapeError`]) are
//! reported at the field they concern.

use super::reader::{unknown_name_message, Result, Table, Val};
use glam::Vec3;
use irradia_geometry::shapes::{
    Cube, Cuboid, Disk, Plane, Polygon, Polyhedron, Quadric, Rectangle, SdfGrid, SdfNormals,
    ShapeError, Sphere, Torus, Tube,
};
use irradia_geometry::Shape;
use std::sync::Arc;

/// Every primitive shape `type` the scene format knows (CSG nodes, meshes and implicit
/// surfaces are handled by the object reader).
pub const PRIMITIVES: &[&str] = &[
    "sphere",
    "plane",
    "box",
    "polyhedron",
    "polygon",
    "disk",
    "quadric",
    "ellipsoid",
    "cylinder",
    "cone",
    "paraboloid",
    "hyperboloid",
    "torus",
    "rectangle",
    "cube",
    "tube",
    "sdfgrid",
];

/// The constructor's refusal, reported at `at`.
fn refused(at: &Val, e: ShapeError) -> super::reader::Error {
    at.err(e.to_string())
}

/// Builds the primitive named `kind` from table `t`; `None` when `kind` is not one.
pub fn build_primitive(kind: &str, t: &Table) -> Result<Option<Arc<dyn Shape>>> {
    let shape: Arc<dyn Shape> = match kind {
        "sphere" => {
            let r = t.req("radius")?;
            let center = t.vec3_or("center", Vec3::ZERO)?;
            let flip = t.bool_or("flip_normals", false)?;
            Arc::new(
                Sphere::try_new(center, r.positive()?)
                    .map_err(|e| refused(&r, e))?
                    .with_flipped_normals(flip),
            )
        }
        "rectangle" => Arc::new(Rectangle::flipped(t.bool_or("flip_normals", false)?)),
        "cube" => Arc::new(Cube::new(t.bool_or("flip_normals", false)?)),
        "tube" => {
            let radius = t.positive_or("radius", 1.0)?;
            let p0 = t.vec3_or("p0", Vec3::ZERO)?;
            let p1 = t.vec3_or("p1", Vec3::Z)?;
            if p0 == p1 {
                let at = t.get("p1").or_else(|| t.get("p0"));
                let msg = format!("p0 and p1 must differ (both are {p0})");
                return Err(at.map_or_else(|| t.err(msg.clone()), |v| v.err(msg.clone())));
            }
            let tube = Tube::new(p0, p1, radius).map_err(|e| t.err(e.to_string()))?;
            Arc::new(tube.with_flipped_normals(t.bool_or("flip_normals", false)?))
        }
        "sdfgrid" => Arc::new(sdfgrid(t)?),
        "plane" => {
            let n = t.req("normal")?;
            let normal = n.direction()?;
            let offset = t.f32_or("offset", 0.0)?;
            Arc::new(Plane::new(normal, offset).map_err(|e| refused(&n, e))?)
        }
        "box" => {
            let lo = t.req("min")?.vec3()?;
            let hi_v = t.req("max")?;
            let hi = hi_v.vec3()?;
            if lo.cmpge(hi).any() {
                return Err(hi_v.err(format!(
                    "every coordinate of max must exceed min (min {lo}, max {hi})"
                )));
            }
            Arc::new(Cuboid::new(lo, hi).map_err(|e| refused(&hi_v, e))?)
        }
        "polyhedron" => Arc::new(polyhedron(t)?),
        "polygon" => {
            let v = t.req("vertices")?;
            let points: Vec<Vec3> = v.array()?.iter().map(|p| p.vec3()).collect::<Result<_>>()?;
            Arc::new(Polygon::new(points).map_err(|e| refused(&v, e))?)
        }
        "disk" => {
            let r = t.req("radius")?;
            let radius = r.positive()?;
            let center = t.vec3_or("center", Vec3::ZERO)?;
            let normal = t.get("normal").map_or(Ok(Vec3::Y), |n| n.direction())?;
            let mut d = Disk::new(center, normal, radius).map_err(|e| refused(&r, e))?;
            if let Some(h) = t.get("hole") {
                d = d.with_hole(h.non_negative()?).map_err(|e| refused(&h, e))?;
            }
            Arc::new(d.with_flipped_normals(t.bool_or("flip_normals", false)?))
        }
        "torus" => {
            let major = t.req("major")?.positive()?;
            let minor_v = t.req("minor")?;
            let minor = minor_v.positive()?;
            Arc::new(Torus::try_new(major, minor).map_err(|e| minor_v.err(e))?)
        }
        "quadric" | "ellipsoid" | "cylinder" | "cone" | "paraboloid" | "hyperboloid" => {
            Arc::new(quadric(kind, t)?)
        }
        _ => return Ok(None),
    };
    Ok(Some(shape))
}

/// The message for an unknown `type`, with every valid one.
pub fn unknown_kind(kind_v: &Val, kind: &str, others: &[&str]) -> super::reader::Error {
    let mut valid = PRIMITIVES.to_vec();
    valid.extend_from_slice(others);
    kind_v.err(unknown_name_message("object type", kind, &valid))
}

/// `planes = [{ normal, offset }, ...]` (the solid `normal · p <= offset`) or
/// `platonic = "tetrahedron" | "cube" | "octahedron" | "dodecahedron" | "icosahedron"`
/// (inradius 1 at the origin).
fn polyhedron(t: &Table) -> Result<Polyhedron> {
    match (t.get("planes"), t.get("platonic")) {
        (Some(_), Some(p)) => Err(p.err("give either planes or platonic, not both")),
        (Some(planes_v), None) => {
            let mut planes = Vec::new();
            for p in planes_v.array()? {
                planes.push(half_space(&p)?);
            }
            Polyhedron::new(&planes).map_err(|e| refused(&planes_v, e))
        }
        (None, Some(p)) => {
            let faces = match p.choice(&[
                "tetrahedron",
                "cube",
                "octahedron",
                "dodecahedron",
                "icosahedron",
            ])? {
                "tetrahedron" => 4,
                "cube" => 6,
                "octahedron" => 8,
                "dodecahedron" => 12,
                _ => 20,
            };
            Polyhedron::platonic(faces).map_err(|e| refused(&p, e))
        }
        (None, None) => Err(t.err("a polyhedron needs planes or platonic")),
    }
}

/// `{ normal = [x, y, z], offset = d }`: the half-space `normal · p <= d`.
fn half_space(v: &Val) -> Result<(Vec3, f32)> {
    let t = v.table()?;
    let n = t.req("normal")?.direction()?;
    let d = t.f32_or("offset", 0.0)?;
    t.finish()?;
    Ok((n, d))
}

/// The quadric family. Unclipped named quadrics are infinite (except the ellipsoid);
/// `clip_box = { min, max }` and `clip_planes = [{ normal, offset }]` cut them (capped,
/// a solid) and `open = true` drops the caps (a surface, not usable in CSG).
fn quadric(kind: &str, t: &Table) -> Result<Quadric> {
    let mut q = match kind {
        "quadric" => {
            let c_v = t.req("coefficients")?;
            let c = c_v.numbers(10)?;
            let mut k = [0f64; 10];
            for (ki, ci) in k.iter_mut().zip(&c) {
                *ki = *ci as f64;
            }
            Quadric::new(k).map_err(|e| refused(&c_v, e))?
        }
        "ellipsoid" => {
            let r_v = t.req("radii")?;
            let radii = r_v.vec3()?;
            if radii.cmple(Vec3::ZERO).any() {
                return Err(r_v.err(format!("radii must be positive (got {radii})")));
            }
            let center = t.vec3_or("center", Vec3::ZERO)?;
            Quadric::ellipsoid(center, radii).map_err(|e| refused(&r_v, e))?
        }
        "cylinder" => {
            let r_v = t.req("radius")?;
            let r = r_v.positive()?;
            match (t.get("from"), t.get("to")) {
                (Some(a), Some(b)) => {
                    let (pa, pb) = (a.vec3()?, b.vec3()?);
                    if pa == pb {
                        return Err(b.err("from and to must differ"));
                    }
                    Quadric::capped_cylinder(pa, pb, r).map_err(|e| refused(&b, e))?
                }
                (None, None) => Quadric::cylinder(r).map_err(|e| refused(&r_v, e))?,
                (Some(a), None) | (None, Some(a)) => {
                    return Err(a.err("give both from and to (a capped cylinder) or neither"))
                }
            }
        }
        "cone" => match (t.get("from"), t.get("to")) {
            (Some(a), Some(b)) => {
                let (pa, pb) = (a.vec3()?, b.vec3()?);
                if pa == pb {
                    return Err(b.err("from and to must differ"));
                }
                let ra_v = t.req("radius_from")?;
                let ra = ra_v.non_negative()?;
                let rb_v = t.req("radius_to")?;
                let rb = rb_v.non_negative()?;
                if ra == 0.0 && rb == 0.0 {
                    return Err(rb_v.err("at least one of the radii must be positive"));
                }
                Quadric::capped_cone(pa, ra, pb, rb).map_err(|e| refused(&rb_v, e))?
            }
            (None, None) => {
                let s = t.req("slope")?;
                Quadric::cone(s.positive()?).map_err(|e| refused(&s, e))?
            }
            (Some(a), None) | (None, Some(a)) => {
                return Err(a.err("give both from and to (a capped cone) or neither"))
            }
        },
        "paraboloid" => {
            let k = t.req("curvature")?;
            let kv = k.f32()?;
            if kv == 0.0 {
                return Err(k.err("must not be zero"));
            }
            Quadric::paraboloid(kv).map_err(|e| refused(&k, e))?
        }
        _ => {
            let a = t.req("a")?.positive()?;
            let c_v = t.req("c")?;
            let c = c_v.positive()?;
            match t.get("sheets") {
                Some(s) if s.u32()? == 2 => {
                    Quadric::hyperboloid_two_sheets(a, c).map_err(|e| refused(&c_v, e))?
                }
                Some(s) if s.u32()? != 1 => return Err(s.err("must be 1 or 2")),
                _ => Quadric::hyperboloid_one_sheet(a, c).map_err(|e| refused(&c_v, e))?,
            }
        }
    };
    if let Some(b) = t.get("clip_box") {
        let bt = b.table()?;
        let lo = bt.req("min")?.vec3()?;
        let hi_v = bt.req("max")?;
        let hi = hi_v.vec3()?;
        bt.finish()?;
        if lo.cmpge(hi).any() {
            return Err(hi_v.err("every coordinate of max must exceed min"));
        }
        q = q.clipped_by_box(lo, hi).map_err(|e| refused(&b, e))?;
    }
    if let Some(planes) = t.get("clip_planes") {
        for p in planes.array()? {
            let (n, d) = half_space(&p)?;
            q = q.clipped_by_plane(n, d).map_err(|e| refused(&p, e))?;
        }
    }
    if t.bool_or("open", false)? {
        q = q.open();
    }
    Ok(q)
}

/// `type = "sdfgrid"`: Mitsuba's signed distance grid over `[0, 1]³`, from `grid`
/// (nested arrays `grid[z][y][x]`) or from the volume file `path` (NRRD or raw, as the
/// `volume` generator reads it; its spacing is ignored: the grid spans `[0, 1]³`);
/// `normals = "smooth" | "analytic"` (Mitsuba's default `smooth`).
fn sdfgrid(t: &Table) -> Result<SdfGrid> {
    let normals = match t.get("normals") {
        Some(n) => match n.choice(&["smooth", "analytic"])? {
            "analytic" => SdfNormals::Analytic,
            _ => SdfNormals::Smooth,
        },
        None => SdfNormals::Smooth,
    };
    let (dims, values, at) = match (t.get("grid"), t.get("path")) {
        (Some(_), Some(p)) => return Err(p.err("give either grid or path, not both")),
        (None, None) => return Err(t.err("an sdfgrid needs grid (nested z, y, x arrays) or path")),
        (Some(g), None) => {
            let (dims, values) = nested_grid(&g)?;
            (dims, values, g)
        }
        (None, Some(p)) => {
            let grid = super::generators::read_volume(t)?;
            let d = grid.dims;
            ([d.x as usize, d.y as usize, d.z as usize], grid.values, p)
        }
    };
    SdfGrid::new(dims, values, normals).map_err(|e| refused(&at, e))
}

/// `grid = [[[v, ...], ...], ...]`: `grid[z][y][x]`, every row of one length, at
/// least 2 along each axis, at most 256 (values past the limit are not read).
fn nested_grid(g: &Val) -> Result<([usize; 3], Vec<f32>)> {
    const MAX: usize = 256;
    let planes = g.array()?;
    let mut dims = [0usize, 0, planes.len()];
    let mut values = Vec::new();
    if !(2..=MAX).contains(&planes.len()) {
        return Err(g.err(format!(
            "expected 2 to {MAX} planes along z (got {})",
            planes.len()
        )));
    }
    for (z, plane) in planes.iter().enumerate() {
        let rows = plane.array()?;
        if z == 0 {
            if !(2..=MAX).contains(&rows.len()) {
                return Err(plane.err(format!(
                    "expected 2 to {MAX} rows along y (got {})",
                    rows.len()
                )));
            }
            dims[1] = rows.len();
        } else if rows.len() != dims[1] {
            return Err(plane.err(format!(
                "the grid is not box-shaped: this plane has {} rows, the first has {}",
                rows.len(),
                dims[1]
            )));
        }
        for (y, row) in rows.iter().enumerate() {
            let xs = row.array()?;
            if z == 0 && y == 0 {
                if !(2..=MAX).contains(&xs.len()) {
                    return Err(row.err(format!(
                        "expected 2 to {MAX} values along x (got {})",
                        xs.len()
                    )));
                }
                dims[0] = xs.len();
            } else if xs.len() != dims[0] {
                return Err(row.err(format!(
                    "the grid is not box-shaped: this row has {} values, the first has {}",
                    xs.len(),
                    dims[0]
                )));
            }
            for x in xs {
                values.push(x.f32()?);
            }
        }
    }
    Ok((dims, values))
}
