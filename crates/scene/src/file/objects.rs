//! The `[[objects]]` array: a shape (`type` and its fields), an optional `name`,
//! `material` and `transform`. CSG nodes (`union`, `intersection`, `difference`,
//! `merge`) hold `children`, each an object without a name; a child's `material`
//! overrides its parent's for the leaves under it.

use super::materials::material_index;
use super::reader::{Result, Table, Val};
use super::shapes::{build_primitive, unknown_kind};
use super::transform::read_transform;
use crate::material::Material;
use crate::scene::Object;
use irradia_geometry::Instance;

/// CSG operations (their shapes come from the geometry crate's CSG module).
pub const CSG_KINDS: &[&str] = &[];

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
            read_csg(kind, &t, material, mats, &mut leaf_materials)?
        } else {
            match build_primitive(kind, &t)? {
                Some(s) => s,
                None => return Err(unknown_kind(&kind_v, kind, CSG_KINDS)),
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

fn read_csg(
    kind: &str,
    t: &Table,
    _material: u32,
    _mats: &mut MaterialTable,
    _leaf_materials: &mut Vec<u32>,
) -> Result<std::sync::Arc<dyn irradia_geometry::Shape>> {
    Err(t.err(format!("CSG `{kind}` is not available yet")))
}
