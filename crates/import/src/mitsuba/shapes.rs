//! `<shape>` into `[[objects]]`: Mitsuba's `sphere`, `rectangle`, `disk`, `cube` and
//! `cylinder` (Irradia's `tube`) are Irradia shapes with Mitsuba's definitions;
//! `obj`, `ply` and `serialized` files are meshes; a `shapegroup` is placed by each
//! `instance` of it (its shapes repeated with the instance's transform). A shape's
//! `area` emitter becomes its material's `emission`.

use super::bsdfs::{default_material, material_name, value};
use super::props::Obj;
use super::transform::Xform;
use super::xml::Elem;
use super::Builder;
use irradia_scene::file::tree::Node;
use irradia_scene::SceneError;

const SHAPES: &[&str] = &[
    "obj",
    "ply",
    "serialized",
    "sphere",
    "rectangle",
    "disk",
    "cube",
    "cylinder",
    "sdfgrid",
    "shapegroup",
    "instance",
];

/// Mitsuba's shapes that Irradia does not render.
const UNRENDERED: &[&str] = &[
    "bsplinecurve",
    "linearcurve",
    "ellipsoids",
    "ellipsoidsmesh",
    "merge",
];

/// Reads a top-level `<shape>` into `[[objects]]` (a `shapegroup` into
/// `[[shape_groups]]`).
pub fn shape<'e>(b: &mut Builder<'e>, e: &'e Elem) -> Result<(), SceneError> {
    if let Some(obj) = object(b, e, false)? {
        b.objects.push(obj);
    }
    Ok(())
}

/// A `<shape>` as an object table (`None` when left out); `in_group` for the members
/// of a shape group.
fn object<'e>(
    b: &mut Builder<'e>,
    e: &'e Elem,
    in_group: bool,
) -> Result<Option<Node>, SceneError> {
    let o = Obj::read(e)?;
    let pos = e.main_pos;
    let kind = o.plugin.as_str();
    if !SHAPES.contains(&kind) {
        if UNRENDERED.contains(&kind) {
            b.warn(
                e,
                "type",
                format!("the `{kind}` shape is not rendered: left out"),
            );
            return Ok(None);
        }
        let valid: Vec<&str> = SHAPES.iter().chain(UNRENDERED).copied().collect();
        return Err(e.err_at(
            "type",
            "type",
            format!("unknown shape `{kind}` (valid: {})", valid.join(", ")),
        ));
    }
    if kind == "shapegroup" {
        if in_group {
            return Err(e.err("type", "a shapegroup cannot hold another shapegroup"));
        }
        let id = e
            .get("id")
            .ok_or_else(|| e.err("id", "a shapegroup needs an id (its instances refer to it)"))?;
        let mut members = Vec::new();
        for c in &o.nested {
            if c.tag != "shape" {
                return Err(c.err(
                    &c.tag,
                    format!("a shapegroup holds shapes, not <{}>", c.tag),
                ));
            }
            if let Some(m) = object(b, c, true)? {
                members.push(m);
            }
        }
        o.finish(&[])?;
        if members.is_empty() {
            b.warn(
                e,
                "shapegroup",
                "the shapegroup holds nothing Irradia renders: left out",
            );
            b.empty_groups.insert(id.to_string());
            return Ok(None);
        }
        let mut g = Node::table(pos);
        g.put("name", id, pos);
        g.set("objects", Node::new(members, pos));
        b.shape_groups.push(g);
        return Ok(None);
    }
    let xf = match o.get("to_world") {
        Some(p) => p.transform()?.clone(),
        None => Xform::identity(),
    };
    if kind == "instance" {
        if in_group {
            return Err(e.err("type", "an instance cannot be part of a shapegroup"));
        }
        let group = match o.nested.as_slice() {
            [r] if r.tag == "ref" => b.lookup(r, r.req("id")?)?,
            _ => {
                return Err(e.err(
                    "ref",
                    "an instance holds one <ref id=\"...\"/> to a shapegroup",
                ))
            }
        };
        if group.tag != "shape" || group.get("type") != Some("shapegroup") {
            return Err(o.nested[0].err_at("id", "id", "an instance refers to a shapegroup"));
        }
        o.finish(&["to_world"])?;
        let id = group.get("id").unwrap_or_default();
        if b.empty_groups.contains(id) {
            return Ok(None);
        }
        let mut inst = Node::table(pos);
        inst.put("type", "instance", pos).put("group", id, pos);
        if !xf.steps.is_empty() {
            inst.set("transform", Node::new(xf.steps.clone(), pos));
        }
        return Ok(Some(inst));
    }

    let mut obj = Node::table(pos);
    if let Some(id) = e.get("id") {
        obj.put("name", id, pos);
    }
    let mut params: Vec<&str> = vec!["to_world", "flip_normals"];
    match kind {
        "obj" | "ply" | "serialized" => {
            obj.put("type", "mesh", pos);
            let f = o
                .get("filename")
                .ok_or_else(|| e.err("filename", format!("`{kind}` needs `filename`")))?;
            let path = b.file(e, f.elem, f.str()?)?;
            obj.put("path", path, f.elem.main_pos);
            // Mitsuba's OBJ reader turns v upside down unless told not to.
            let flip_uv = match o.get("flip_tex_coords") {
                Some(p) => p.bool()?,
                None => kind == "obj",
            };
            if flip_uv {
                obj.put("flip_tex_coords", true, pos);
            }
            if let Some(p) = o.get("face_normals") {
                if p.bool()? {
                    obj.put("face_normals", true, p.elem.main_pos);
                }
            }
            if kind == "serialized" {
                if let Some(p) = o.get("shape_index") {
                    obj.put("shape_index", p.int()?, p.elem.main_pos);
                }
            }
            params.extend([
                "filename",
                "flip_tex_coords",
                "face_normals",
                "shape_index",
                "max_smooth_angle",
            ]);
            if let Some(p) = o.get("max_smooth_angle") {
                b.warn(
                    p.elem,
                    "max_smooth_angle",
                    "max_smooth_angle is not rendered",
                );
            }
            if let Some(p) = o.get("flip_normals") {
                if p.bool()? {
                    b.warn(
                        p.elem,
                        "flip_normals",
                        "flip_normals of a mesh is not rendered",
                    );
                }
            }
        }
        "sphere" => {
            obj.put("type", "sphere", pos);
            let c = o
                .get("center")
                .map_or(Ok(glam::DVec3::ZERO), |p| p.vec3())?;
            let r = o.get("radius").map_or(Ok(1.0), |p| p.f64())?;
            obj.put("center", [c.x, c.y, c.z], pos)
                .put("radius", r, pos);
            params.extend(["center", "radius"]);
        }
        "rectangle" | "cube" => {
            obj.put("type", kind, pos);
        }
        "disk" => {
            obj.put("type", "disk", pos)
                .put("normal", [0.0, 0.0, 1.0], pos)
                .put("radius", 1.0, pos);
        }
        "cylinder" => {
            obj.put("type", "tube", pos);
            for n in ["p0", "p1", "radius"] {
                if let Some(p) = o.get(n) {
                    let v = value(b, p, false)?;
                    obj.set(n, v);
                }
            }
            params.extend(["p0", "p1", "radius"]);
        }
        "sdfgrid" => {
            // Mitsuba's grid over [0, 1]³ from its binary `.vol` file (or inline `data`).
            obj.put("type", "sdfgrid", pos);
            let f = o.get("filename").ok_or_else(|| {
                e.err(
                    "filename",
                    "an sdfgrid needs `filename` (a .vol grid; Irradia does not read `data`)",
                )
            })?;
            let path = b.file(e, f.elem, f.str()?)?;
            obj.put("path", path, f.elem.main_pos);
            if let Some(n) = o.get("normals") {
                let v = n.str()?;
                if !matches!(v, "smooth" | "analytic") {
                    return Err(n.elem.err_at(
                        "value",
                        "normals",
                        format!("normals `{v}`: expected smooth or analytic"),
                    ));
                }
                obj.put("normals", v, n.elem.main_pos);
            }
            params.extend(["filename", "normals"]);
        }
        _ => unreachable!("checked against SHAPES"),
    }
    if kind != "obj" && kind != "ply" && kind != "serialized" {
        if let Some(p) = o.get("flip_normals") {
            obj.put("flip_normals", p.bool()?, p.elem.main_pos);
        }
    }
    if !xf.steps.is_empty() {
        obj.set("transform", Node::new(xf.steps.clone(), pos));
    }

    // The material, and an area emitter.
    let mut bsdf: Option<&'e Elem> = None;
    let mut area: Option<&'e Elem> = None;
    for c in o.nested.iter().copied() {
        let target = if c.tag == "ref" {
            b.lookup(c, c.req("id")?)?
        } else {
            c
        };
        match target.tag.as_str() {
            "bsdf" if bsdf.is_none() => bsdf = Some(c),
            "emitter" if area.is_none() => area = Some(target),
            "bsdf" | "emitter" => {
                return Err(c.err(&target.tag, format!("a shape has one <{}>", target.tag)));
            }
            "medium" => {
                b.warn(
                    c,
                    "medium",
                    "participating media are not rendered: the shape's medium is left out",
                );
            }
            t => return Err(c.err(t, format!("<{t}> does not belong in a <shape>"))),
        }
    }
    if let Some(p) = o
        .props
        .iter()
        .find(|p| matches!(p.name.as_str(), "interior" | "exterior"))
    {
        p.used.set(true);
        b.warn(
            p.elem,
            &p.name,
            "participating media are not rendered: the shape's medium is left out",
        );
    }
    let mut material = match bsdf {
        Some(m) => material_name(b, m)?,
        None => default_material(b, area.is_some()),
    };
    if let Some(a) = area.filter(|a| {
        if in_group {
            b.warn(
                a,
                "emitter",
                "an emitter in a shapegroup is not rendered (as in Mitsuba): left out",
            );
        }
        !in_group
    }) {
        if let Some(emission) = super::emitters::area_radiance(b, a)? {
            let base = b
                .materials
                .get(&material)
                .cloned()
                .unwrap_or_else(|| Node::table(pos));
            let mut m = base;
            m.set("emission", emission);
            let name = b.unique(&format!("{material}_emitter"));
            b.materials.set(&name, m);
            material = name;
        }
    }
    obj.put("material", material, pos);
    o.finish(&params)?;
    Ok(Some(obj))
}
