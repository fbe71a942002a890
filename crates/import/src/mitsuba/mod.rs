//! Mitsuba 3 scene files (`.xml`, scene versions 2 and 3) into Irradia's schema.
//!
//! The file is read in two steps: [`xml`] parses it into elements (with `$name`
//! parameters, `<default>`, `<include>` and `<path>` resolved), and the builder here
//! turns each plugin into Irradia's tables: [`sensor`] (sensor, film, sampler,
//! integrator), [`bsdfs`] (BSDFs and textures: Irradia's materials have Mitsuba's
//! names and parameters), [`shapes`] and [`emitters`]. An unknown plugin, parameter
//! or directive is an error naming its file, line and column; a Mitsuba plugin that
//! Irradia does not render is a warning (and is left out or replaced, as it says).

pub mod bsdfs;
pub mod emitters;
pub mod props;
pub mod sensor;
pub mod shapes;
pub mod transform;
pub mod xml;

use crate::{Imported, Options};
use irradia_scene::file::tree::Node;
use irradia_scene::SceneError;
use std::collections::{HashMap, HashSet};
use std::path::{Path, PathBuf};
use std::rc::Rc;
use xml::{Elem, Loader, Source};

/// Imports a Mitsuba 3 XML file.
pub fn import(path: &Path, opts: &Options) -> Result<Imported, SceneError> {
    let text = crate::read_text(path)?;
    convert(text, path, opts, true)
}

/// Parses a Mitsuba scene held in memory (the fuzz target's entry point). Nothing is
/// read from disk: `<include>` is refused and file names are not looked up.
pub fn parse_str(text: &str, origin: &Path, opts: &Options) -> Result<Imported, SceneError> {
    convert(text.to_string(), origin, opts, false)
}

fn convert(
    text: String,
    origin: &Path,
    opts: &Options,
    read_files: bool,
) -> Result<Imported, SceneError> {
    let src = Rc::new(Source {
        path: origin.to_path_buf(),
        text,
    });
    let mut loader = Loader::new(&opts.defines, read_files);
    let root = loader.load(src.clone(), None)?;
    let main_dir = origin.parent().map(Path::to_path_buf).unwrap_or_default();
    let mut b = Builder::new(loader, main_dir);
    b.collect_ids(&root)?;
    b.scene(&root)?;
    let tree = b.finish();
    Ok(Imported {
        tree,
        text: src.text.clone(),
        origin: origin.to_path_buf(),
        warnings: b.warnings,
        notes: b.notes,
    })
}

/// Builds Irradia's tree from a scene's elements.
pub struct Builder<'e> {
    pub loader: Loader,
    /// The folder of the main file (Irradia's paths are relative to it).
    pub main_dir: PathBuf,
    /// Every object with an `id`.
    pub ids: HashMap<String, &'e Elem>,
    pub camera: Option<Node>,
    pub image: Node,
    pub render: Node,
    pub materials: Node,
    /// Material names given to BSDF elements (by address).
    pub material_names: HashMap<*const Elem, String>,
    pub used_names: HashSet<String>,
    /// BSDFs being converted (a reference cycle is an error).
    pub converting: Vec<*const Elem>,
    pub lights: Vec<Node>,
    pub objects: Vec<Node>,
    pub shape_groups: Vec<Node>,
    /// Shape groups left out (their instances are too).
    pub empty_groups: HashSet<String>,
    pub warnings: Vec<SceneError>,
    pub notes: Vec<String>,
}

impl<'e> Builder<'e> {
    fn new(loader: Loader, main_dir: PathBuf) -> Builder<'e> {
        Builder {
            loader,
            main_dir,
            ids: HashMap::new(),
            camera: None,
            image: Node::table(0),
            render: Node::table(0),
            materials: Node::table(0),
            material_names: HashMap::new(),
            used_names: HashSet::new(),
            converting: Vec::new(),
            lights: Vec::new(),
            objects: Vec::new(),
            shape_groups: Vec::new(),
            empty_groups: HashSet::new(),
            warnings: Vec::new(),
            notes: Vec::new(),
        }
    }

    /// A feature Irradia does not render.
    pub fn warn(&mut self, e: &Elem, field: &str, msg: impl Into<String>) {
        let w = e.err(field, msg);
        // A declared texture or BSDF is read again where it is used: one warning.
        if !self.warnings.iter().any(|x| x.to_string() == w.to_string()) {
            self.warnings.push(w);
        }
    }

    fn collect_ids(&mut self, e: &'e Elem) -> Result<(), SceneError> {
        for c in &e.children {
            if c.tag == "alias" {
                c.check_attrs(&["id", "as"])?;
                let id = c.req("id")?;
                let target = *self.ids.get(id).ok_or_else(|| {
                    c.err_at("id", "id", format!("<alias> of an unknown id `{id}`"))
                })?;
                self.ids.insert(c.req("as")?.to_string(), target);
                continue;
            }
            if let Some(id) = c.get("id") {
                if c.tag != "ref" && self.ids.insert(id.to_string(), c).is_some() {
                    return Err(c.err_at("id", "id", format!("the id `{id}` is used twice")));
                }
            }
            self.collect_ids(c)?;
        }
        Ok(())
    }

    /// The object an id names.
    pub fn lookup(&self, at: &Elem, id: &str) -> Result<&'e Elem, SceneError> {
        self.ids
            .get(id)
            .copied()
            .ok_or_else(|| at.err_at("id", "id", format!("reference to an unknown id `{id}`")))
    }

    /// A unique name built from `base`.
    pub fn unique(&mut self, base: &str) -> String {
        let mut name = base.to_string();
        let mut k = 1;
        while self.used_names.contains(&name) {
            k += 1;
            name = format!("{base}_{k}");
        }
        self.used_names.insert(name.clone());
        name
    }

    /// A file the scene names, found as Mitsuba finds it, as a path relative to the
    /// main file's folder (where Irradia looks for it).
    pub fn file(&self, e: &Elem, attr_elem: &Elem, name: &str) -> Result<String, SceneError> {
        let found = self.loader.resolve(&e.dir(), name).ok_or_else(|| {
            attr_elem.err_at(
                "value",
                "filename",
                format!("cannot find the file `{name}`"),
            )
        })?;
        Ok(crate::toml_out::rebase(
            &found.to_string_lossy(),
            Path::new("."),
            &self.main_dir,
        ))
    }

    fn scene(&mut self, root: &'e Elem) -> Result<(), SceneError> {
        root.check_attrs(&["version"])?;
        // Mitsuba samples every emitter equally often (`sampling_weight` 1): the same
        // image, and the same noise, which its test criterion measures against.
        self.render.put("light_selection", "uniform", root.main_pos);
        let mut sensor_seen = false;
        for c in &root.children {
            match c.tag.as_str() {
                "sensor" => {
                    if sensor_seen {
                        self.warn(c, "sensor", "only the first <sensor> is rendered");
                        continue;
                    }
                    sensor_seen = true;
                    sensor::sensor(self, c)?;
                }
                "integrator" => sensor::integrator(self, c)?,
                "shape" => shapes::shape(self, c)?,
                "emitter" => emitters::emitter(self, c)?,
                // Declared for reference (a BSDF becomes a named material).
                "bsdf" => {
                    bsdfs::material_name(self, c)?;
                }
                "texture" => {
                    bsdfs::texture(self, c)?;
                }
                "medium" | "phase" | "volume" => {
                    self.warn(
                        c,
                        &c.tag,
                        format!(
                            "participating media are not rendered: <{}> left out",
                            c.tag
                        ),
                    );
                }
                "alias" => {}
                "film" | "sampler" | "rfilter" => {
                    return Err(c.err(&c.tag, format!("<{}> belongs inside a <sensor>", c.tag)))
                }
                t if props::PROPERTY_TAGS.contains(&t) => {
                    let name = c.get("name").unwrap_or("");
                    return Err(c.err(name, format!("unknown parameter `{name}` of the scene")));
                }
                t => {
                    return Err(c.err(
                        t,
                        format!("unknown directive <{t}> (valid: sensor, integrator, shape, emitter, bsdf, texture, medium, include, default, path, alias)"),
                    ))
                }
            }
        }
        if self.camera.is_none() {
            sensor::default_sensor(self);
        }
        Ok(())
    }

    fn finish(&mut self) -> Node {
        let mut tree = Node::table(0);
        if let Some(c) = self.camera.take() {
            tree.set("camera", c);
        }
        tree.set("image", std::mem::replace(&mut self.image, Node::table(0)));
        tree.set(
            "render",
            std::mem::replace(&mut self.render, Node::table(0)),
        );
        let materials = std::mem::replace(&mut self.materials, Node::table(0));
        if !matches!(&materials.value, irradia_scene::file::tree::Value::Table(t) if t.is_empty()) {
            tree.set("materials", materials);
        }
        for l in self.lights.drain(..) {
            tree.push("lights", l);
        }
        for g in self.shape_groups.drain(..) {
            tree.push("shape_groups", g);
        }
        for o in self.objects.drain(..) {
            tree.push("objects", o);
        }
        tree
    }
}
