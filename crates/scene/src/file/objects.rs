//! The `[[objects]]` array: a shape (`type` and its fields), an optional `name`,
//! `material` and `transform`. CSG nodes (`union`, `intersection`, `difference`,
//! `merge`) hold `children`, each an object without a name; a child's `material`
//! overrides its parent's for the leaves under it.

use super::materials::material_index;
use super::reader::{Result, Table, Val};
use super::shapes::{build_primitive, unknown_kind};
use super::surfaces::build_surface;
use super::transform::read_transform;
use crate::material::Material;
use crate::scene::Object;
use irradia_geometry::{Csg, CsgOp, CsgOperand, Instance, Shape, TriangleMesh};
use std::sync::Arc;

/// CSG operations (their shapes come from the geometry crate's CSG module).
pub const CSG_KINDS: &[&str] = &["union", "intersection", "difference", "merge"];

/// Object types besides the primitives and CSG.
pub const OTHER_KINDS: &[&str] = &[
    "mesh",
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

pub fn read_objects(
    v: Option<Val>,
    mats: &mut MaterialTable,
) -> Result<(Vec<Object>, Vec<Instance>)> {
    let mut objects = Vec::new();
    let mut instances = Vec::new();
    let Some(v) = v else {
        return Ok((objects, instances));
    };
    for (i, o) in v.array()?.iter().enumerate() {
        let t = o.table()?;
        let name = match t.get("name") {
            Some(n) => n.str()?.to_string(),
            None => format!("objects[{i}]"),
        };
        let material = mats.lookup(t.get("material"))?;
        let transform = read_transform(t.get("transform"))?;
        let kind_v = t.req("type")?;
        let kind = kind_v.str()?;
        let mut leaf_materials = Vec::new();
        let shape = if CSG_KINDS.contains(&kind) {
            let csg = read_csg(kind, &t, material, mats, &mut leaf_materials)?;
            if leaf_materials.iter().all(|m| *m == material) {
                leaf_materials.clear();
            }
            Arc::new(csg)
        } else {
            match build_shape(kind, &t)? {
                Some(s) => s,
                None => return Err(unknown_kind(&kind_v, kind, OTHER_KINDS)),
            }
        };
        t.finish()?;
        objects.push(Object {
            name,
            material,
            leaf_materials,
        });
        instances.push(Instance::new(shape, transform));
    }
    Ok((objects, instances))
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

/// `type = "mesh"`, `path = "bunny.ply"` (OBJ, PLY, glTF or GLB, relative to the scene
/// file); `group = "name"` picks an OBJ file's faces that use one material, `mesh = N`
/// and `primitive = N` a glTF file's primitive.
fn read_mesh(t: &Table) -> Result<TriangleMesh> {
    let path_v = t.req("path")?;
    let path = path_v.doc.resolve(path_v.str()?);
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
    };
    irradia_geometry::io::load_mesh_part(&path, &part).map_err(|e| {
        // A selector that does not fit the file is the selector's error.
        let at = match e.field.as_deref() {
            Some("group") => group.as_ref(),
            Some("mesh") => mesh.as_ref(),
            Some("primitive") => primitive.as_ref(),
            _ => None,
        };
        at.unwrap_or(&path_v)
            .err(format!("cannot load the mesh: {e}"))
    })
}
