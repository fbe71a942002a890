//! The `[[objects]]` array: a shape (`type` and its fields), an optional `name`,
//! `material` and `transform`. CSG nodes (`union`, `intersection`, `difference`,
//! `merge`) hold `children`, each an object without a name; a child's `material`
//! overrides its parent's for the leaves under it.

use super::attributes::check_attributes;
use super::materials::material_index;
use super::reader::{Result, Table, Val};
use super::shapes::{build_primitive, unknown_kind};
use super::surfaces::build_surface;
use super::transform::read_transform;
use crate::material::Material;
use crate::scene::Object;
use irradia_geometry::{Csg, CsgOp, CsgOperand, Instance, Shape, ShapeGroup, TriangleMesh};
use std::sync::Arc;

/// CSG operations (their shapes come from the geometry crate's CSG module).
pub const CSG_KINDS: &[&str] = &["union", "intersection", "difference", "merge"];

/// Object types besides the primitives and CSG.
pub const OTHER_KINDS: &[&str] = &[
    "mesh",
    "triangles",
    "gyroid_mesh",
    "generator",
    "implicit",
    "parametric",
    "bezier",
    "teapot",
    "union",
    "intersection",
    "difference",
    "merge",
    "instance",
];

/// Materials, with a default one added on first use by an object that names none.
pub struct MaterialTable {
    pub materials: Vec<Material>,
    default: Option<u32>,
}

impl MaterialTable {
    pub fn new(materials: Vec<Material>) -> Self {
        let default = materials
            .iter()
            .position(|m| m.name == "default")
            .map(|i| i as u32);
        Self { materials, default }
    }

    fn default_index(&mut self) -> u32 {
        *self.default.get_or_insert_with(|| {
            self.materials.push(Material::default());
            (self.materials.len() - 1) as u32
        })
    }

    fn lookup(&mut self, v: Option<Val>) -> Result<u32> {
        match v {
            Some(v) => material_index(&self.materials, &v),
            None => Ok(self.default_index()),
        }
    }
}

/// The shape groups of `[[shape_groups]]` by name: the shared group and the material
/// of each of its leaves.
pub type Groups = std::collections::HashMap<String, (Arc<ShapeGroup>, Vec<u32>)>;

/// `[[shape_groups]]`: each a `name` and `objects` (object tables as in `[[objects]]`,
/// placed in the group's own space), rendered only where an object of `type =
/// "instance"` places the group.
pub fn read_shape_groups(v: Option<Val>, mats: &mut MaterialTable) -> Result<Groups> {
    let mut groups = Groups::new();
    let Some(v) = v else {
        return Ok(groups);
    };
    for g in v.array()?.iter() {
        let t = g.table()?;
        let name_v = t.req("name")?;
        let name = name_v.str()?.to_string();
        if groups.contains_key(&name) {
            return Err(name_v.err(format!("a second shape group named '{name}'")));
        }
        let objects_v = t.req("objects")?;
        let list = objects_v.array()?;
        if list.is_empty() {
            return Err(objects_v.err("a shape group needs at least one object"));
        }
        let mut members = Vec::new();
        let mut leaf_materials = Vec::new();
        for (i, o) in list.iter().enumerate() {
            let (object, instance, leaves) = read_object(o, i, mats, &groups)?;
            for leaf in 0..leaves {
                let m = object.material_for_leaf(leaf);
                if mats.materials[m as usize].emission.max_component() > 0.0 {
                    return Err(o.err(
                        "an object in a shape group cannot emit light (as in Mitsuba, \
                         emitters are not instanced): place it as an object of its own",
                    ));
                }
                leaf_materials.push(m);
            }
            members.push((instance, leaves));
        }
        t.finish()?;
        groups.insert(name, (Arc::new(ShapeGroup::new(members)), leaf_materials));
    }
    Ok(groups)
}

pub fn read_objects(
    v: Option<Val>,
    mats: &mut MaterialTable,
    groups: &Groups,
) -> Result<(Vec<Object>, Vec<Instance>)> {
    let mut objects = Vec::new();
    let mut instances = Vec::new();
    let Some(v) = v else {
        return Ok((objects, instances));
    };
    for (i, o) in v.array()?.iter().enumerate() {
        let (object, instance, _) = read_object(o, i, mats, groups)?;
        objects.push(object);
        instances.push(instance);
    }
    Ok((objects, instances))
}

/// One object table: the object, its placement, and how many leaves its hits report.
fn read_object(
    o: &Val,
    i: usize,
    mats: &mut MaterialTable,
    groups: &Groups,
) -> Result<(Object, Instance, u32)> {
    let t = o.table()?;
    let name = match t.get("name") {
        Some(n) => n.str()?.to_string(),
        None => format!("objects[{i}]"),
    };
    let transform = read_transform(t.get("transform"))?;
    let kind_v = t.req("type")?;
    let kind = kind_v.str()?;
    if kind == "instance" {
        if let Some(m) = t.get("material") {
            return Err(m.err("an instance takes its materials from its shape group's objects"));
        }
        let group_v = t.req("group")?;
        let group_name = group_v.str()?;
        let Some((group, leaf_materials)) = groups.get(group_name) else {
            let mut known: Vec<&str> = groups.keys().map(String::as_str).collect();
            known.sort();
            return Err(group_v.err(format!(
                "no shape group named '{group_name}' (groups: {})",
                if known.is_empty() {
                    "none".to_string()
                } else {
                    known.join(", ")
                }
            )));
        };
        t.finish()?;
        let object = Object {
            name,
            material: leaf_materials[0],
            leaf_materials: leaf_materials.clone(),
        };
        let shape: Arc<dyn Shape> = group.clone();
        return Ok((object, Instance::new(shape, transform), group.leaf_count()));
    }
    let material = mats.lookup(t.get("material"))?;
    let mut leaf_materials = Vec::new();
    let mut leaves = 1;
    let shape: Arc<dyn Shape> = if CSG_KINDS.contains(&kind) {
        let csg = read_csg(kind, &t, material, mats, &mut leaf_materials)?;
        if leaf_materials.iter().all(|m| *m == material) {
            leaf_materials.clear();
        }
        leaves = csg.leaf_count();
        Arc::new(csg)
    } else {
        let shape = match build_shape(kind, &t)? {
            Some(s) => s,
            None => return Err(unknown_kind(&kind_v, kind, OTHER_KINDS)),
        };
        let at = t.get("material").unwrap_or(kind_v.clone());
        check_attributes(&mats.materials[material as usize], shape.attributes(), kind)
            .map_err(|e| at.err(e))?;
        shape
    };
    t.finish()?;
    let object = Object {
        name,
        material,
        leaf_materials,
    };
    Ok((object, Instance::new(shape, transform), leaves))
}

/// Reads a CSG node: `children` is an array of objects (primitives or CSG nodes), each
/// with an optional `transform` (child to parent) and `material` (default: the
/// parent's). Leaf materials are pushed in depth-first order, matching `Hit::leaf`.
fn read_csg(
    kind: &str,
    t: &Table,
    material: u32,
    mats: &mut MaterialTable,
    leaf_materials: &mut Vec<u32>,
) -> Result<Csg> {
    let op = match kind {
        "union" => CsgOp::Union,
        "intersection" => CsgOp::Intersection,
        "difference" => CsgOp::Difference,
        _ => CsgOp::Merge,
    };
    let children_v = t.req("children")?;
    let children = children_v.array()?;
    if children.is_empty() {
        return Err(children_v.err(format!("a CSG {kind} needs at least one child")));
    }
    let mut operands = Vec::new();
    for c in &children {
        let ct = c.table()?;
        let child_material = match ct.get("material") {
            Some(m) => material_index(&mats.materials, &m)?,
            None => material,
        };
        let to_parent = read_transform(ct.get("transform"))?;
        let kind_v = ct.req("type")?;
        let child_kind = kind_v.str()?;
        let operand = if CSG_KINDS.contains(&child_kind) {
            let node = read_csg(child_kind, &ct, child_material, mats, leaf_materials)?;
            CsgOperand::node(node, to_parent)
        } else {
            let shape = match build_shape(child_kind, &ct)? {
                Some(s) => s,
                None => return Err(unknown_kind(&kind_v, child_kind, OTHER_KINDS)),
            };
            if !shape.is_solid() {
                return Err(kind_v.err(format!(
                    "a CSG operand must be a closed solid, but a {child_kind} here is an open surface"
                )));
            }
            let at = ct.get("material").unwrap_or(kind_v.clone());
            check_attributes(
                &mats.materials[child_material as usize],
                shape.attributes(),
                child_kind,
            )
            .map_err(|e| at.err(e))?;
            leaf_materials.push(child_material);
            CsgOperand::shape(shape, to_parent)
        };
        ct.finish()?;
        operands.push(operand);
    }
    Csg::new(op, operands).map_err(|e| children_v.err(e.to_string()))
}

/// A primitive, mesh or implicit surface; `None` when `kind` names none of them.
fn build_shape(kind: &str, t: &Table) -> Result<Option<Arc<dyn Shape>>> {
    if kind == "mesh" {
        return Ok(Some(Arc::new(read_mesh(t)?)));
    }
    if kind == "triangles" {
        return Ok(Some(Arc::new(read_triangles(t)?)));
    }
    if kind == "gyroid_mesh" {
        return Ok(Some(Arc::new(gyroid_mesh(t)?)));
    }
    if kind == "generator" {
        return Ok(Some(Arc::new(super::generators::read_generator(t)?)));
    }
    if let Some(s) = build_primitive(kind, t)? {
        return Ok(Some(s));
    }
    build_surface(kind, t)
}

/// `type = "gyroid_mesh"`, `grid = n`: the gyroid of PEERS.md's triangles workload,
/// meshed by marching cubes on an n³ grid over [-1, 1]³ (n = 342 gives 2,254,089
/// triangles). The grid is limited to 512 so that it cannot exhaust memory.
fn gyroid_mesh(t: &Table) -> Result<TriangleMesh> {
    let n = match t.get("grid") {
        None => 64,
        Some(g) => {
            let n = g.u32()?;
            if !(2..=512).contains(&n) {
                return Err(g.err(format!("must be between 2 and 512 (got {n})")));
            }
            n
        }
    };
    let data = irradia_geometry::generators::gyroid::gyroid_mesh(n);
    TriangleMesh::new(data.positions, data.indices, None, None)
        .map_err(|e| t.err(format!("gyroid mesh: {e}")))
}

/// `type = "mesh"`, `path = "bunny.ply"` (OBJ, PLY, Mitsuba `.serialized`, glTF or GLB,
/// relative to the scene file); `shape_index` (0) picks a `.serialized` file's shape,
/// `group = "name"` an OBJ file's faces that use one material, `mesh = N` and
/// `primitive = N` a glTF file's primitive; `flip_tex_coords` (false) turns v into
/// 1 − v, `face_normals` (false) shades flat.
fn read_mesh(t: &Table) -> Result<TriangleMesh> {
    let path_v = t.req("path")?;
    let path = path_v.doc.resolve(path_v.str()?);
    let index = t.u32_or("shape_index", 0)? as usize;
    let flip = t.bool_or("flip_tex_coords", false)?;
    let flat = t.bool_or("face_normals", false)?;
    let group = t.get("group");
    let mesh = t.get("mesh");
    let primitive = t.get("primitive");
    let part = irradia_geometry::io::MeshPart {
        group: group
            .as_ref()
            .map(|g| g.str().map(str::to_string))
            .transpose()?,
        mesh: mesh
            .as_ref()
            .map(|m| m.u32().map(|x| x as usize))
            .transpose()?,
        primitive: primitive
            .as_ref()
            .map(|p| p.u32().map(|x| x as usize))
            .transpose()?,
        shape_index: index,
    };
    let mut data = irradia_geometry::io::read_mesh_part(&path, &part).map_err(|e| {
        // A selector that does not fit the file is the selector's error.
        let at = match e.field.as_deref() {
            Some("group") => group.as_ref(),
            Some("mesh") => mesh.as_ref(),
            Some("primitive") => primitive.as_ref(),
            _ => None,
        };
        at.unwrap_or(&path_v)
            .err(format!("cannot load the mesh: {e}"))
    })?;
    if flip {
        for uv in data.uvs.iter_mut().flatten() {
            uv.y = 1.0 - uv.y;
        }
    }
    if flat
        && data
            .indices
            .iter()
            .flatten()
            .all(|&i| (i as usize) < data.positions.len())
    {
        // Every triangle its own corners, each with the face's normal; vertex
        // attributes follow the corners, face attributes stay with the triangles.
        let mut out = irradia_geometry::io::MeshFile::default();
        let corners: Vec<u32> = data.indices.iter().flatten().copied().collect();
        out.attributes = data.attributes.gather_vertices(&corners);
        for tri in &data.indices {
            let p = tri.map(|i| data.positions.get(i as usize).copied().unwrap_or_default());
            let n = (p[1] - p[0]).cross(p[2] - p[0]).normalize_or(glam::Vec3::Z);
            let base = out.positions.len() as u32;
            out.positions.extend(p);
            out.normals.get_or_insert_with(Vec::new).extend([n; 3]);
            if let Some(uv) = &data.uvs {
                let t = tri.map(|i| uv.get(i as usize).copied().unwrap_or_default());
                out.uvs.get_or_insert_with(Vec::new).extend(t);
            }
            out.indices.push([base, base + 1, base + 2]);
        }
        data = out;
    }
    data.into_mesh(&path)
        .map_err(|e| path_v.err(format!("cannot load the mesh: {e}")))
}

/// `type = "triangles"`: a triangle mesh written in the scene file itself (the pbrt
/// importer's `trianglemesh`): `positions = [[x, y, z], ...]`, `indices = [[a, b, c],
/// ...]` (0-based), optional `normals` (one per position) and `uv` (`[u, v]` each).
fn read_triangles(t: &Table) -> Result<TriangleMesh> {
    let positions_v = t.req("positions")?;
    let positions: Vec<glam::Vec3> = positions_v
        .array()?
        .iter()
        .map(|p| p.vec3())
        .collect::<Result<_>>()?;
    let indices_v = t.req("indices")?;
    let mut indices = Vec::new();
    for tri in indices_v.array()? {
        let items = tri.array()?;
        if items.len() != 3 {
            return Err(tri.err(format!("expected 3 vertex indices, found {}", items.len())));
        }
        let mut ids = [0u32; 3];
        for (slot, item) in ids.iter_mut().zip(&items) {
            *slot = item.u32()?;
        }
        indices.push(ids);
    }
    let per_vertex = |key: &'static str| -> Result<Option<(Val, Vec<Val>)>> {
        let Some(v) = t.get(key) else {
            return Ok(None);
        };
        let items = v.array()?;
        if items.len() != positions.len() {
            return Err(v.err(format!(
                "expected one entry per position ({}), found {}",
                positions.len(),
                items.len()
            )));
        }
        Ok(Some((v, items)))
    };
    let normals = match per_vertex("normals")? {
        Some((_, items)) => Some(items.iter().map(|n| n.vec3()).collect::<Result<_>>()?),
        None => None,
    };
    let uvs = match per_vertex("uv")? {
        Some((_, items)) => Some(
            items
                .iter()
                .map(|uv| uv.numbers(2).map(|c| glam::Vec2::new(c[0], c[1])))
                .collect::<Result<_>>()?,
        ),
        None => None,
    };
    TriangleMesh::new(positions, indices, normals, uvs)
        .map_err(|e| indices_v.err(format!("the triangles: {e}")))
}
