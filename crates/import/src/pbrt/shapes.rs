//! pbrt-v4's shapes as Irradia objects: `sphere`, `disk`, `cylinder` (Mitsuba's
//! `tube`), `trianglemesh` (inline `triangles`), `bilinearmesh` (two triangles per
//! quad), `plymesh` (`mesh` with the file's path), `loopsubdiv` (its control mesh).
//!
//! Texture coordinates: spheres and cylinders get pbrt's (a sphere is turned over in its
//! own frame for it); a disk's are Mitsuba's (u and v of pbrt's swapped), and a
//! triangle mesh without `uv` gets Irradia's default `(b1, b2)` where pbrt's is
//! `(0,0), (1,0), (1,1)` per triangle.
//!
//! Orientation: pbrt's quadrics face out (in when `ReverseOrientation` differs from
//! whether the CTM swaps handedness, pbrt-v4's `flipNormal`), which Irradia's
//! `flip_normals` reproduces; a triangle without normals faces `(p1 − p0) × (p2 − p0)`
//! in both (its winding is reversed for `ReverseOrientation`); with normals, both turn
//! the face to the normals.

use super::builder::Builder;
use super::params::{Params, Spec};
use super::textures::{constant, Want};
use super::transform::swaps_handedness;
use super::At;
use glam::{DMat4, DVec3};
use irradia_scene::file::tree::Node;
use std::f64::consts::PI;

/// Each triangle's area after `ctm`.
fn triangle_areas(pts: &[[f64; 3]], tris: &[[u32; 3]], ctm: &DMat4) -> Vec<f64> {
    let p = |i: u32| ctm.transform_point3(DVec3::from(pts[i as usize]));
    tris.iter()
        .map(|t| 0.5 * (p(t[1]) - p(t[0])).cross(p(t[2]) - p(t[0])).length())
        .collect()
}

impl Builder {
    pub(super) fn shape(&mut self, ty: &str, p: &Params, pos: usize) -> Result<(), At> {
        self.kind_now = Some(("shape", ty.to_string()));
        let tp = self.tp(pos);
        let ctm = self.gs.ctm;
        if !super::transform::is_affine(&ctm) || !super::transform::is_invertible(&ctm) {
            return Err(At::new(
                pos,
                "Shape: the current transformation is not an invertible affine map",
            ));
        }
        let flip = self.gs.reverse ^ swaps_handedness(&ctm);
        let mut o = Node::table(tp);
        // The areas pbrt-v4 gives an area light's `power` to: a quadric's (in its own
        // frame, full: partial quadrics render whole), each triangle's (transformed).
        let mut areas: Vec<f64> = Vec::new();
        match ty {
            "sphere" => {
                let r = p.float("radius", 1.0)?;
                if r <= 0.0 {
                    return Err(At::new(p.pos("radius", pos), format!("sphere: radius must be positive (got {r})")));
                }
                self.partial(p, pos, ty, r)?;
                areas.push(4.0 * PI * r * r);
                o.put("type", "sphere", tp).put("radius", r, tp);
                if flip {
                    o.put("flip_normals", true, tp);
                }
            }
            "disk" => {
                let h = p.float("height", 0.0)?;
                let r = p.float("radius", 1.0)?;
                let ri = p.float("innerradius", 0.0)?;
                if r <= 0.0 || ri < 0.0 || ri >= r {
                    return Err(At::new(pos, format!("disk: need 0 <= innerradius < radius (got {ri}, {r})")));
                }
                if p.float("phimax", 360.0)? < 360.0 {
                    self.warn(p.pos("phimax", pos), "phimax", "partial quadrics (phimax < 360) are rendered whole");
                }
                areas.push(PI * (r * r - ri * ri));
                o.put("type", "disk", tp)
                    .put("center", [0.0, 0.0, h], tp)
                    .put("normal", [0.0, 0.0, 1.0], tp)
                    .put("radius", r, tp);
                if ri > 0.0 {
                    o.put("hole", ri, tp);
                }
                if flip {
                    o.put("flip_normals", true, tp);
                }
            }
            "cylinder" => {
                let r = p.float("radius", 1.0)?;
                let z0 = p.float("zmin", -1.0)?;
                let z1 = p.float("zmax", 1.0)?;
                if r <= 0.0 || z0 == z1 {
                    return Err(At::new(pos, "cylinder: need radius > 0 and zmin != zmax"));
                }
                if p.float("phimax", 360.0)? < 360.0 {
                    self.warn(p.pos("phimax", pos), "phimax", "partial quadrics (phimax < 360) are rendered whole");
                }
                areas.push(2.0 * PI * r * (z1 - z0).abs());
                o.put("type", "tube", tp)
                    .put("p0", [0.0, 0.0, z0.min(z1)], tp)
                    .put("p1", [0.0, 0.0, z0.max(z1)], tp)
                    .put("radius", r, tp);
                if flip {
                    o.put("flip_normals", true, tp);
                }
            }
            "trianglemesh" | "loopsubdiv" => {
                let pts = p
                    .vec3s("P")?
                    .ok_or_else(|| At::new(pos, format!("{ty} needs \"point3 P\"")))?;
                let idx = match p.ints("indices")? {
                    Some(i) => i,
                    None if pts.len() == 3 => vec![0, 1, 2],
                    None => return Err(At::new(pos, format!("{ty} needs \"integer indices\""))),
                };
                if ty == "loopsubdiv" {
                    let _ = p.int("levels", 3)?;
                    self.warn(pos, "loopsubdiv", "loopsubdiv: the control mesh is rendered without subdivision");
                }
                let ipos = p.pos("indices", pos);
                if idx.len() % 3 != 0 || idx.is_empty() {
                    return Err(At::new(ipos, format!("{ty}: the number of indices ({}) is not a positive multiple of 3", idx.len())));
                }
                let tris: Vec<[u32; 3]> = check_indices(&idx, pts.len(), 3, ipos)?
                    .iter()
                    .map(|t| [t[0], t[1], t[2]])
                    .collect();
                let normals = self.per_vertex3(p, "N", pts.len(), pos)?;
                let uv = self.per_vertex2(p, "uv", pts.len(), pos)?;
                let rev = self.gs.reverse && normals.is_none();
                areas = triangle_areas(&pts, &tris, &ctm);
                self.triangles(&mut o, &pts, tris, rev, normals, uv, tp);
                if p.has("S") {
                    let _ = p.get("S");
                    self.warn(p.pos("S", pos), "S", "trianglemesh: tangents (S) are not used");
                }
                let _ = p.ints("faceIndices")?;
            }
            "bilinearmesh" => {
                let pts = p
                    .vec3s("P")?
                    .ok_or_else(|| At::new(pos, "bilinearmesh needs \"point3 P\""))?;
                let idx = match p.ints("indices")? {
                    Some(i) => i,
                    None if pts.len() == 4 => vec![0, 1, 2, 3],
                    None => return Err(At::new(pos, "bilinearmesh needs \"integer indices\"")),
                };
                let ipos = p.pos("indices", pos);
                if idx.len() % 4 != 0 || idx.is_empty() {
                    return Err(At::new(ipos, format!("bilinearmesh: the number of indices ({}) is not a positive multiple of 4", idx.len())));
                }
                let quads = check_indices(&idx, pts.len(), 4, ipos)?;
                let normals = self.per_vertex3(p, "N", pts.len(), pos)?;
                let mut uv = self.per_vertex2(p, "uv", pts.len(), pos)?;
                // pbrt's patch (p00, p10, p01, p11): triangles (p00, p10, p11), (p00, p11, p01).
                let mut tris = Vec::new();
                let mut points = pts.clone();
                let mut norms = normals.clone();
                if uv.is_none() {
                    // pbrt's default uv is the patch's own (u, v): vertices are
                    // duplicated per patch to carry it.
                    points.clear();
                    let mut uvs = Vec::new();
                    let mut ns = Vec::new();
                    for q in &quads {
                        let base = points.len() as u32;
                        for (k, &i) in q.iter().enumerate() {
                            points.push(pts[i as usize]);
                            uvs.push([(k % 2) as f64, (k / 2) as f64]);
                            if let Some(n) = &normals {
                                ns.push(n[i as usize]);
                            }
                        }
                        tris.push([base, base + 1, base + 3]);
                        tris.push([base, base + 3, base + 2]);
                    }
                    uv = Some(uvs);
                    norms = normals.as_ref().map(|_| ns);
                } else {
                    for q in &quads {
                        tris.push([q[0], q[1], q[3]]);
                        tris.push([q[0], q[3], q[2]]);
                    }
                }
                let rev = self.gs.reverse && norms.is_none();
                areas = triangle_areas(&points, &tris, &ctm);
                self.triangles(&mut o, &points, tris, rev, norms, uv, tp);
            }
            "plymesh" => {
                let file = p
                    .string("filename")?
                    .ok_or_else(|| At::new(pos, "plymesh needs \"string filename\""))?;
                o.put("type", "mesh", tp).put("path", file.as_str(), tp);
                if p.has("displacement") {
                    let _ = p.get("displacement");
                    self.warn(p.pos("displacement", pos), "ply-displacement", "plymesh: displacement is not rendered");
                }
                let _ = p.float("edgelength", 1.0)?;
                if self.gs.reverse && self.gs.area.is_some() {
                    self.warn(pos, "ply-reverse", "ReverseOrientation on a plymesh area light is not applied (the file's winding is kept)");
                }
            }
            "curve" | "heightfield" | "nurbs" => {
                for param in &p.list {
                    let _ = p.get(&param.name);
                }
                self.warn(pos, &format!("shape:{ty}"), format!("shape \"{ty}\" is not available (left out)"));
                return Ok(());
            }
            _ => return Err(At::new(pos, format!("unknown shape \"{ty}\" (valid: sphere, disk, cylinder, trianglemesh, bilinearmesh, plymesh, loopsubdiv, curve)"))),
        }
        // The material, the area light and the alpha mask.
        let mat = match self.gs.material.clone() {
            Some(m) if m.interface => {
                self.finish_params(p, &format!("Shape \"{ty}\""), &["emissionfilename"])?;
                self.note("shapes with the interface material (medium boundaries) are left out");
                return Ok(());
            }
            Some(m) => m.name,
            None => self.default_material_name(),
        };
        let mut mat = mat;
        if let Some(alpha) = self.alpha(p, pos)? {
            match constant(&alpha) {
                Some(c) if c[0] <= 0.0 => {
                    self.finish_params(p, &format!("Shape \"{ty}\""), &["emissionfilename"])?;
                    return Ok(());
                }
                Some(c) if c[0] >= 1.0 => {}
                _ => mat = self.masked(&mat, alpha, tp),
            }
        }
        if let Some(a) = self.gs.area.clone() {
            if self.in_object_definition() {
                self.warn(a.pos, "instanced-area", "area lights in object instances are not supported by pbrt-v4 either: not emitting");
            } else {
                let radiance = self.area_power(&a, &areas, ty);
                mat = self.emitting(&mat, radiance, a.two_sided, tp);
            }
        }
        self.finish_params(p, &format!("Shape \"{ty}\""), &["emissionfilename"])?;
        o.put("material", mat.as_str(), tp);
        // pbrt's sphere has v = 1 − θ/π where Irradia's (Mitsuba's) has θ/π: turning
        // the sphere over in its own frame (z → −z, the same sphere) makes them agree.
        let first = (ty == "sphere").then(|| {
            let mut step = Node::table(tp);
            step.put("scale", [1.0, 1.0, -1.0], tp);
            step
        });
        self.push_object(o, ctm, pos, first);
        Ok(())
    }

    /// An area light's radiance on a shape of these `areas`: with pbrt-v4's `power`,
    /// scaled so that each shape emits it, `L · power / (π · sides · area)` (pbrt-v4's
    /// `DiffuseAreaLight::Create`; a triangle mesh is one shape per triangle there).
    /// Irradia's emission is one radiance per object, so a mesh of unequal triangles
    /// gets the mean area (the same total power, spread evenly) and a warning.
    fn area_power(&mut self, a: &super::builder::AreaLight, areas: &[f64], ty: &str) -> [f64; 3] {
        let Some(power) = a.power else {
            return a.radiance;
        };
        if areas.is_empty() {
            self.warn(a.pos, "power-ply", format!("area light: `power` on a {ty} is not applied (its file is not read here): L is used"));
            return a.radiance;
        }
        let mean = areas.iter().sum::<f64>() / areas.len() as f64;
        if areas.iter().any(|x| (x - mean).abs() > 1e-6 * mean) {
            self.warn(a.pos, "power-mesh", format!("area light: `power` on a {ty} of unequal triangles: every triangle emits as one of the mean area (the same total power)"));
        }
        if mean <= 0.0 {
            return a.radiance;
        }
        let sides = if a.two_sided { 2.0 } else { 1.0 };
        a.radiance.map(|c| c * power / (PI * sides * mean))
    }

    fn partial(&mut self, p: &Params, pos: usize, ty: &str, r: f64) -> Result<(), At> {
        let z0 = p.float("zmin", -r)?;
        let z1 = p.float("zmax", r)?;
        let phi = p.float("phimax", 360.0)?;
        if z0 > -r || z1 < r || phi < 360.0 {
            self.warn(
                pos,
                "partial",
                format!("{ty}: partial quadrics (zmin, zmax, phimax) are rendered whole"),
            );
        }
        Ok(())
    }

    fn alpha(&mut self, p: &Params, _pos: usize) -> Result<Option<Node>, At> {
        match p.spec("alpha")? {
            None => Ok(None),
            Some((s @ (Spec::Float(_) | Spec::Texture(_)), at)) => {
                Ok(Some(self.spec_node(&s, at, Want::Float, "alpha")?))
            }
            Some((_, at)) => Err(At::new(at, "alpha takes a float or a float texture")),
        }
    }

    fn per_vertex3(
        &mut self,
        p: &Params,
        key: &str,
        n: usize,
        pos: usize,
    ) -> Result<Option<Vec<[f64; 3]>>, At> {
        match p.vec3s(key)? {
            None => Ok(None),
            Some(v) if v.len() == n => Ok(Some(v)),
            Some(v) => Err(At::new(
                p.pos(key, pos),
                format!("{key}: {} values for {n} vertices", v.len()),
            )),
        }
    }

    fn per_vertex2(
        &mut self,
        p: &Params,
        key: &str,
        n: usize,
        pos: usize,
    ) -> Result<Option<Vec<[f64; 2]>>, At> {
        let key = if p.has(key) {
            key
        } else if p.has("st") {
            "st"
        } else {
            key
        };
        match p.vec2s(key)? {
            None => Ok(None),
            Some(v) if v.len() == n => Ok(Some(v)),
            Some(v) => Err(At::new(
                p.pos(key, pos),
                format!("{key}: {} values for {n} vertices", v.len()),
            )),
        }
    }

    #[allow(clippy::too_many_arguments)]
    fn triangles(
        &mut self,
        o: &mut Node,
        pts: &[[f64; 3]],
        mut tris: Vec<[u32; 3]>,
        reverse: bool,
        normals: Option<Vec<[f64; 3]>>,
        uv: Option<Vec<[f64; 2]>>,
        tp: usize,
    ) {
        if reverse {
            for t in &mut tris {
                t.swap(1, 2);
            }
        }
        o.put("type", "triangles", tp);
        o.set(
            "positions",
            Node::new(
                pts.iter().map(|p| Node::new(*p, tp)).collect::<Vec<_>>(),
                tp,
            ),
        );
        o.set(
            "indices",
            Node::new(
                tris.iter()
                    .map(|t| {
                        Node::new(
                            t.iter()
                                .map(|i| Node::new(*i as i64, tp))
                                .collect::<Vec<_>>(),
                            tp,
                        )
                    })
                    .collect::<Vec<_>>(),
                tp,
            ),
        );
        if let Some(n) = normals {
            o.set(
                "normals",
                Node::new(n.iter().map(|v| Node::new(*v, tp)).collect::<Vec<_>>(), tp),
            );
        }
        if let Some(uv) = uv {
            o.set(
                "uv",
                Node::new(uv.iter().map(|v| Node::new(*v, tp)).collect::<Vec<_>>(), tp),
            );
        }
    }
}

/// Groups of `k` indices, each below `n`.
fn check_indices(idx: &[i64], n: usize, k: usize, pos: usize) -> Result<Vec<Vec<u32>>, At> {
    let mut out = Vec::new();
    for (j, c) in idx.chunks(k).enumerate() {
        for &i in c {
            if i < 0 || i as usize >= n {
                return Err(At::new(
                    pos,
                    format!("index {i} (in face {j}) is out of range: there are {n} vertices"),
                ));
            }
        }
        out.push(c.iter().map(|&i| i as u32).collect());
    }
    Ok(out)
}
