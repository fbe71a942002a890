//! Runs pbrt's directives against its graphics state and writes Irradia's tree.
//!
//! The state follows pbrt-v4: the CTM, `ReverseOrientation`, the current material and
//! area light and `Attribute` defaults are saved by `AttributeBegin` (and the old
//! `TransformBegin`, the CTM only) and restored by the matching end; named coordinate
//! systems, named materials and textures and object definitions are global.

use super::coverage::{Coverage, Status};
use super::params::Params;
use super::parser::{parse, Arg, Directive, Param};
use super::transform as tf;
use super::At;
use glam::{DMat4, DVec3};
use irradia_scene::file::tree::{line_col, Node, Value};
use irradia_scene::SceneError;
use std::collections::{HashMap, HashSet};
use std::path::{Path, PathBuf};

mod finish;

/// How much of the outside world a run may touch.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mode {
    /// Follow `Include`/`Import` and look at referenced images.
    Full,
    /// Touch no file (the fuzz target): includes are skipped with a note.
    InMemory,
    /// As `InMemory`, and an error skips its directive instead of ending the run.
    Survey,
}

struct FileCtx {
    path: PathBuf,
    text: String,
    /// Where the outermost `Include` leading here is in the main file.
    include_pos: Option<usize>,
}

/// A material as objects refer to it.
#[derive(Clone, Debug, PartialEq)]
pub struct MatRef {
    /// Irradia's name (a key of `[materials]`).
    pub name: String,
    /// pbrt's `interface`: marks a medium boundary, no surface.
    pub interface: bool,
}

#[derive(Clone, Debug)]
pub struct AreaLight {
    pub radiance: [f64; 3],
    pub two_sided: bool,
    /// pbrt-v4's `power`: the radiance is scaled per shape to emit this many watts.
    pub power: Option<f64>,
    pub pos: usize,
}

#[derive(Clone)]
pub struct GState {
    pub ctm: DMat4,
    pub reverse: bool,
    pub material: Option<MatRef>,
    pub area: Option<AreaLight>,
    pub defaults: HashMap<String, Vec<Param>>,
    /// `ActiveTransform EndTime`: transformations apply to the end time only, which
    /// Irradia (no motion blur) ignores.
    pub end_only: bool,
}

pub struct Builder {
    pub(super) mode: Mode,
    origin: PathBuf,
    dir: PathBuf,
    files: Vec<FileCtx>,
    pub(super) gs: GState,
    stack: Vec<(GState, &'static str, usize)>,
    named_cs: HashMap<String, DMat4>,
    pub(super) named_materials: HashMap<String, MatRef>,
    /// Irradia's materials, in order of definition.
    pub(super) mats: Vec<(String, Node)>,
    pub(super) float_tex: HashMap<String, Node>,
    pub(super) spec_tex: HashMap<String, Node>,
    pub(super) lights: Vec<Node>,
    pub(super) objects: Vec<Node>,
    groups: Vec<(String, Vec<Node>, usize)>,
    group_index: HashMap<String, usize>,
    current_group: Option<usize>,
    /// Irradia's world from pbrt's world: `z → −z` or the identity (module doc).
    pub(super) mirror: Option<DMat4>,
    pub(super) view: super::view::View,
    in_world: bool,
    warnings: Vec<SceneError>,
    warned: HashSet<String>,
    notes: Vec<String>,
    noted: HashSet<String>,
    cov: Coverage,
    /// Set by [`Builder::warn`] during the directive being run.
    warned_now: bool,
    /// The type the directive being run names (`("shape", "sphere")`), for coverage.
    pub(super) kind_now: Option<(&'static str, String)>,
    pub(super) counter: usize,
}

const MAX_INCLUDE_DEPTH: usize = 32;

impl Builder {
    pub fn new(origin: &Path, text: &str, mode: Mode) -> Builder {
        let dir = origin.parent().map(Path::to_path_buf).unwrap_or_default();
        Builder {
            mode,
            origin: origin.to_path_buf(),
            dir,
            files: vec![FileCtx {
                path: origin.to_path_buf(),
                text: text.to_string(),
                include_pos: None,
            }],
            gs: GState {
                ctm: DMat4::IDENTITY,
                reverse: false,
                material: None,
                area: None,
                defaults: HashMap::new(),
                end_only: false,
            },
            stack: Vec::new(),
            named_cs: HashMap::new(),
            named_materials: HashMap::new(),
            mats: Vec::new(),
            float_tex: HashMap::new(),
            spec_tex: HashMap::new(),
            lights: Vec::new(),
            objects: Vec::new(),
            groups: Vec::new(),
            group_index: HashMap::new(),
            current_group: None,
            mirror: None,
            view: super::view::View::default(),
            in_world: false,
            warnings: Vec::new(),
            warned: HashSet::new(),
            notes: Vec::new(),
            noted: HashSet::new(),
            cov: Coverage::default(),
            warned_now: false,
            kind_now: None,
            counter: 0,
        }
    }

    /// Runs the main file.
    pub fn run(&mut self) -> Result<(), SceneError> {
        let text = self.files[0].text.clone();
        let directives = parse(&text).map_err(|e| self.error(At::new(e.pos, e.message)))?;
        self.run_all(directives)
    }

    fn run_all(&mut self, directives: Vec<Directive>) -> Result<(), SceneError> {
        for d in directives {
            let name = d.name.clone();
            let pos = d.pos;
            self.warned_now = false;
            self.kind_now = None;
            let r = self.exec(d);
            let status = match &r {
                Err(_) => Status::Refused,
                Ok(()) if self.warned_now => Status::Warned,
                Ok(()) => Status::Supported,
            };
            if name != "Include" && name != "Import" {
                self.cov.add("directive", &name, status);
            }
            if let Some((cat, kind)) = self.kind_now.take() {
                self.cov.add(cat, &kind, status);
            }
            if let Err(e) = r {
                if self.mode == Mode::Survey {
                    self.cov.errors.push(e.to_string());
                    continue;
                }
                return Err(e);
            }
            let _ = pos;
        }
        Ok(())
    }

    /// The error `at` in the file being read.
    pub(super) fn error(&self, at: At) -> SceneError {
        let f = self.files.last().expect("a file");
        let (l, c) = line_col(&f.text, at.pos);
        SceneError::input("", at.message)
            .at(l, c)
            .with_file(&f.path)
    }

    /// The position in the main file's text a tree node made now carries.
    pub(super) fn tp(&self, pos: usize) -> usize {
        match self.files.get(1) {
            Some(f) => f.include_pos.unwrap_or(0),
            None => pos,
        }
    }

    /// A warning (a feature Irradia does not render), once per `key`.
    pub(super) fn warn(&mut self, pos: usize, key: &str, message: impl Into<String>) {
        self.warned_now = true;
        if self.warned.insert(key.to_string()) {
            let e = self.error(At::new(pos, message));
            self.warnings.push(e);
        }
    }

    /// A note (something the importer decided that the file did not say), once each.
    pub(super) fn note(&mut self, message: impl Into<String>) {
        let m = message.into();
        if self.noted.insert(m.clone()) {
            self.notes.push(m);
        }
    }

    /// A fresh number for generated names.
    pub(super) fn next_id(&mut self) -> usize {
        self.counter += 1;
        self.counter
    }

    /// The mirror between pbrt's world and Irradia's, fixed by the camera (the
    /// default camera when none came).
    pub(super) fn mirror(&mut self) -> DMat4 {
        *self
            .mirror
            .get_or_insert_with(|| mirror_for(&DMat4::IDENTITY))
    }

    /// Whether referenced files may be opened.
    pub(super) fn loads_files(&self) -> bool {
        self.mode == Mode::Full
    }

    /// A path of the file as written, resolved against the main file's folder (pbrt
    /// resolves every relative name there).
    pub(super) fn resolve(&self, p: &str) -> PathBuf {
        let path = Path::new(p);
        if path.is_absolute() {
            path.to_path_buf()
        } else {
            self.dir.join(path)
        }
    }

    /// Reports the parameters no handler used: a warning for those `ignored` names
    /// (known to pbrt, not rendered by Irradia), an error for any other.
    pub(super) fn finish_params(
        &mut self,
        p: &Params,
        what: &str,
        ignored: &[&str],
    ) -> Result<(), At> {
        let unused: Vec<Param> = p.unused().cloned().collect();
        for u in unused {
            if ignored.contains(&u.name.as_str()) || ignored.contains(&"*") {
                self.warn(
                    u.pos,
                    &format!("{what}:{}", u.name),
                    format!(
                        "{what}: parameter `{}` is not rendered by Irradia (ignored)",
                        u.name
                    ),
                );
            } else {
                return Err(At::new(
                    u.pos,
                    format!("{what}: unknown parameter \"{} {}\"", u.ty, u.name),
                ));
            }
        }
        Ok(())
    }

    fn params(&self, d: &Directive, target: &str) -> Result<Params, At> {
        let p = Params::new(d.params.clone())?;
        Ok(match self.gs.defaults.get(target) {
            Some(defs) => p.with_defaults(defs),
            None => p,
        })
    }

    fn exec(&mut self, d: Directive) -> Result<(), SceneError> {
        if d.name == "Include" || d.name == "Import" {
            return self.include(&d);
        }
        self.exec_local(&d).map_err(|e| self.error(e))
    }

    fn include(&mut self, d: &Directive) -> Result<(), SceneError> {
        let (Arg::Str(name), _) = &d.args[0] else {
            unreachable!("the parser gives a string")
        };
        self.cov.add("directive", &d.name, Status::Supported);
        if self.mode != Mode::Full {
            self.note(format!(
                "{} \"{name}\" not followed (reading without the file system)",
                d.name
            ));
            return Ok(());
        }
        if self.files.len() > MAX_INCLUDE_DEPTH {
            return Err(self.error(At::new(
                d.pos,
                format!(
                    "{} nested more than {MAX_INCLUDE_DEPTH} deep (a cycle?)",
                    d.name
                ),
            )));
        }
        let path = self.resolve(name);
        let text = read_maybe_gz(&path).map_err(|e| {
            let f = self.files.last().expect("a file");
            let (l, c) = line_col(&f.text, d.pos);
            SceneError {
                file: Some(f.path.clone()),
                line: Some(l),
                column: Some(c),
                message: format!("{} \"{name}\": {e}", d.name),
                ..e
            }
        })?;
        let include_pos = Some(self.tp(d.pos));
        self.files.push(FileCtx {
            path,
            text: text.clone(),
            include_pos,
        });
        let r = match parse(&text) {
            Ok(list) => self.run_all(list),
            Err(e) => Err(self.error(At::new(e.pos, e.message))),
        };
        self.files.pop();
        r
    }

    fn nums(d: &Directive) -> Vec<f64> {
        d.args
            .iter()
            .map(|(a, _)| match a {
                Arg::Num(x) => *x,
                Arg::Str(_) => 0.0,
            })
            .collect()
    }

    fn str_arg(d: &Directive, i: usize) -> String {
        match &d.args[i].0 {
            Arg::Str(s) => s.clone(),
            Arg::Num(x) => x.to_string(),
        }
    }

    /// Applies `m` to the CTM (post-multiplied, as pbrt).
    fn concat(&mut self, pos: usize, m: DMat4) -> Result<(), At> {
        if !m.is_finite() {
            return Err(At::new(pos, "the transformation is not finite"));
        }
        if self.gs.end_only {
            self.warn(
                pos,
                "motion",
                "transformations for `ActiveTransform EndTime` (motion blur) are not rendered (ignored)",
            );
            return Ok(());
        }
        self.gs.ctm *= m;
        Ok(())
    }

    fn exec_local(&mut self, d: &Directive) -> Result<(), At> {
        let pos = d.pos;
        match d.name.as_str() {
            "Identity" => self.set_ctm(pos, DMat4::IDENTITY),
            "Translate" => {
                let v = Self::nums(d);
                self.concat(pos, tf::translate([v[0], v[1], v[2]]))
            }
            "Scale" => {
                let v = Self::nums(d);
                self.concat(pos, tf::scale([v[0], v[1], v[2]]))
            }
            "Rotate" => {
                let v = Self::nums(d);
                let m = tf::rotate(v[0], [v[1], v[2], v[3]])
                    .ok_or_else(|| At::new(d.args[1].1, "Rotate: the axis is zero"))?;
                self.concat(pos, m)
            }
            "LookAt" => {
                let v = Self::nums(d);
                let m = tf::look_at([v[0], v[1], v[2]], [v[3], v[4], v[5]], [v[6], v[7], v[8]])
                    .ok_or_else(|| {
                        At::new(
                            pos,
                            "LookAt: the eye and the target coincide, or the up vector is zero or along the view",
                        )
                    })?;
                self.concat(pos, m)
            }
            "Transform" => {
                let m = tf::from_pbrt(&Self::nums(d));
                self.set_ctm(pos, m)
            }
            "ConcatTransform" => {
                let m = tf::from_pbrt(&Self::nums(d));
                self.concat(pos, m)
            }
            "CoordinateSystem" => {
                self.named_cs.insert(Self::str_arg(d, 0), self.gs.ctm);
                Ok(())
            }
            "CoordSysTransform" => {
                let name = Self::str_arg(d, 0);
                match self.named_cs.get(&name) {
                    Some(m) => {
                        let m = *m;
                        self.set_ctm(pos, m)
                    }
                    None => {
                        self.warn(
                            d.args[0].1,
                            &format!("cs:{name}"),
                            format!("CoordSysTransform: no coordinate system \"{name}\" (ignored, as pbrt does)"),
                        );
                        Ok(())
                    }
                }
            }
            "ActiveTransform" => {
                let w = Self::str_arg(d, 0);
                match w.as_str() {
                    "StartTime" | "All" => self.gs.end_only = false,
                    "EndTime" => self.gs.end_only = true,
                    _ => {
                        return Err(At::new(
                            d.args[0].1,
                            format!("ActiveTransform takes StartTime, EndTime or All, not `{w}`"),
                        ))
                    }
                }
                Ok(())
            }
            "TransformTimes" => Ok(()),
            "ReverseOrientation" => {
                self.gs.reverse = !self.gs.reverse;
                Ok(())
            }
            "AttributeBegin" | "TransformBegin" => {
                let kind = if d.name == "AttributeBegin" {
                    "AttributeBegin"
                } else {
                    "TransformBegin"
                };
                self.stack.push((self.gs.clone(), kind, pos));
                Ok(())
            }
            "AttributeEnd" | "TransformEnd" => self.pop(d),
            "Attribute" => {
                let target = Self::str_arg(d, 0);
                const TARGETS: &[&str] = &["shape", "light", "material", "medium", "texture"];
                if !TARGETS.contains(&target.as_str()) {
                    return Err(At::new(
                        d.args[0].1,
                        format!(
                            "Attribute: unknown target \"{target}\" (valid: {})",
                            TARGETS.join(", ")
                        ),
                    ));
                }
                let p = Params::new(d.params.clone())?;
                let defs = self.gs.defaults.entry(target).or_default();
                for param in p.list {
                    defs.retain(|q| q.name != param.name);
                    defs.push(param);
                }
                Ok(())
            }
            "WorldBegin" => {
                if self.in_world {
                    return Err(At::new(pos, "a second WorldBegin"));
                }
                self.in_world = true;
                self.mirror();
                self.named_cs.insert("world".into(), DMat4::IDENTITY);
                self.gs.ctm = DMat4::IDENTITY;
                Ok(())
            }
            "WorldEnd" => Ok(()),
            "Option" => {
                let p = Params::new(d.params.clone())?;
                for param in &p.list {
                    self.warn(
                        param.pos,
                        &format!("option:{}", param.name),
                        format!(
                            "Option \"{}\" is a pbrt run-time option (ignored)",
                            param.name
                        ),
                    );
                }
                Ok(())
            }
            "ColorSpace" => {
                let cs = Self::str_arg(d, 0);
                if cs != "srgb" {
                    self.warn(
                        d.args[0].1,
                        &format!("colorspace:{cs}"),
                        format!("ColorSpace \"{cs}\": Irradia's colours are linear sRGB; RGB values are used as they are"),
                    );
                }
                Ok(())
            }
            "Camera" => {
                let ty = Self::str_arg(d, 0);
                let p = self.params(d, "camera")?;
                let ctm = self.gs.ctm;
                self.named_cs.insert("camera".into(), ctm.inverse());
                self.camera(&ty, &p, ctm, pos)
            }
            "Film" => {
                let ty = Self::str_arg(d, 0);
                let p = self.params(d, "film")?;
                self.film(&ty, &p, pos)
            }
            "Sampler" => {
                let ty = Self::str_arg(d, 0);
                let p = self.params(d, "sampler")?;
                self.sampler(&ty, &p, pos)
            }
            "Integrator" => {
                let ty = Self::str_arg(d, 0);
                let p = self.params(d, "integrator")?;
                self.integrator(&ty, &p, pos)
            }
            "PixelFilter" => {
                let ty = Self::str_arg(d, 0);
                let p = self.params(d, "filter")?;
                self.pixel_filter(&ty, &p, pos)
            }
            "Accelerator" => {
                self.kind_now = Some(("accelerator", Self::str_arg(d, 0)));
                Ok(())
            }
            "MakeNamedMedium" | "MediumInterface" => {
                self.warn(
                    pos,
                    "media",
                    format!("{}: participating media are not rendered (ignored)", d.name),
                );
                Ok(())
            }
            "Texture" => {
                let name = Self::str_arg(d, 0);
                let ty = Self::str_arg(d, 1);
                let class = Self::str_arg(d, 2);
                let p = self.params(d, "texture")?;
                self.texture(&name, (&ty, d.args[1].1), &class, &p, pos)
            }
            "Material" => {
                let ty = Self::str_arg(d, 0);
                let p = self.params(d, "material")?;
                let id = self.next_id();
                let name = format!("material#{id}");
                let m = self.material(&name, &ty, &p, pos)?;
                self.gs.material = Some(m);
                Ok(())
            }
            "MakeNamedMaterial" => {
                let name = Self::str_arg(d, 0);
                let p = self.params(d, "material")?;
                let ty_pos = p.pos("type", pos);
                let ty = p.string("type")?.ok_or_else(|| {
                    At::new(
                        pos,
                        format!("MakeNamedMaterial \"{name}\" needs \"string type\""),
                    )
                })?;
                if self.named_materials.contains_key(&name) {
                    self.warn(
                        pos,
                        &format!("redefined:{name}"),
                        format!("named material \"{name}\" redefined (the new definition is used from here)"),
                    );
                }
                let m = self.material(&name, &ty, &p, ty_pos)?;
                self.named_materials.insert(name, m);
                Ok(())
            }
            "NamedMaterial" => {
                let name = Self::str_arg(d, 0);
                match self.named_materials.get(&name) {
                    Some(m) => {
                        self.gs.material = Some(m.clone());
                        Ok(())
                    }
                    None => Err(At::new(
                        d.args[0].1,
                        format!("NamedMaterial: no material named \"{name}\""),
                    )),
                }
            }
            "LightSource" => {
                let ty = Self::str_arg(d, 0);
                let p = self.params(d, "light")?;
                self.light(&ty, &p, pos)
            }
            "AreaLightSource" => {
                let ty = Self::str_arg(d, 0);
                let p = self.params(d, "light")?;
                self.area_light(&ty, &p, pos)
            }
            "Shape" => {
                let ty = Self::str_arg(d, 0);
                let p = self.params(d, "shape")?;
                self.shape(&ty, &p, pos)
            }
            "ObjectBegin" => {
                let name = Self::str_arg(d, 0);
                if self.current_group.is_some() {
                    return Err(At::new(pos, "ObjectBegin inside another object definition"));
                }
                self.stack.push((self.gs.clone(), "ObjectBegin", pos));
                if self.group_index.contains_key(&name) {
                    return Err(At::new(
                        d.args[0].1,
                        format!("object \"{name}\" is defined twice"),
                    ));
                }
                self.group_index.insert(name.clone(), self.groups.len());
                self.current_group = Some(self.groups.len());
                let tp = self.tp(pos);
                self.groups.push((name, Vec::new(), tp));
                Ok(())
            }
            "ObjectEnd" => {
                if self.current_group.is_none() {
                    return Err(At::new(pos, "ObjectEnd without ObjectBegin"));
                }
                self.current_group = None;
                self.pop(d)
            }
            "ObjectInstance" => {
                let name = Self::str_arg(d, 0);
                if self.current_group.is_some() {
                    return Err(At::new(pos, "ObjectInstance inside an object definition"));
                }
                let Some(&g) = self.group_index.get(&name) else {
                    return Err(At::new(
                        d.args[0].1,
                        format!("ObjectInstance: no object named \"{name}\""),
                    ));
                };
                if self.groups[g].1.is_empty() {
                    self.note(format!(
                        "object \"{name}\" has no shape Irradia renders: its instances are left out"
                    ));
                    return Ok(());
                }
                let m = self.mirror() * self.gs.ctm;
                let tp = self.tp(pos);
                let mut o = Node::table(tp);
                o.put("type", "instance", tp)
                    .put("group", name.as_str(), tp);
                if let Some(t) = transform_node(&m, tp) {
                    o.set("transform", t);
                }
                self.objects.push(o);
                Ok(())
            }
            other => Err(At::new(pos, format!("unknown directive `{other}`"))),
        }
    }

    fn set_ctm(&mut self, pos: usize, m: DMat4) -> Result<(), At> {
        if !m.is_finite() {
            return Err(At::new(pos, "the transformation is not finite"));
        }
        if self.gs.end_only {
            return self.concat(pos, DMat4::IDENTITY);
        }
        self.gs.ctm = m;
        Ok(())
    }

    fn pop(&mut self, d: &Directive) -> Result<(), At> {
        let want = match d.name.as_str() {
            "AttributeEnd" => "AttributeBegin",
            "TransformEnd" => "TransformBegin",
            _ => "ObjectBegin",
        };
        let Some((saved, kind, _)) = self.stack.pop() else {
            return Err(At::new(d.pos, format!("{} without {want}", d.name)));
        };
        if kind != want {
            self.warn(
                d.pos,
                &format!("mismatch:{}", d.pos),
                format!("{} closes a {kind}", d.name),
            );
        }
        if kind == "TransformBegin" {
            self.gs.ctm = saved.ctm;
            self.gs.end_only = saved.end_only;
        } else {
            self.gs = saved;
        }
        Ok(())
    }

    /// Adds an object (already in pbrt's world or object-definition space) with the
    /// current CTM: to the object being defined, or to the scene mirrored.
    /// `first` is a transform step applied before the CTM (a sphere's uv turn).
    pub(super) fn push_object(&mut self, mut o: Node, ctm: DMat4, pos: usize, first: Option<Node>) {
        let tp = self.tp(pos);
        let m = match self.current_group {
            Some(_) => ctm,
            None => self.mirror() * ctm,
        };
        let mut steps = Vec::new();
        steps.extend(first);
        if let Some(Node {
            value: Value::Array(t),
            ..
        }) = transform_node(&m, tp)
        {
            steps.extend(t);
        }
        if !steps.is_empty() {
            o.set("transform", Node::new(steps, tp));
        }
        match self.current_group {
            Some(g) => self.groups[g].1.push(o),
            None => self.objects.push(o),
        }
    }

    pub(super) fn in_object_definition(&self) -> bool {
        self.current_group.is_some()
    }

    /// Adds (or replaces) Irradia material `name`.
    pub(super) fn add_material(&mut self, name: &str, node: Node) {
        match self.mats.iter().position(|(n, _)| n == name) {
            Some(i) => self.mats[i].1 = node,
            None => self.mats.push((name.to_string(), node)),
        }
    }

    pub(super) fn material_node(&self, name: &str) -> Option<&Node> {
        self.mats.iter().find(|(n, _)| n == name).map(|(_, n)| n)
    }
}

/// The mirror for a camera whose camera-from-world matrix is `camera_from_world`.
pub(super) fn mirror_for(camera_from_world: &DMat4) -> DMat4 {
    if tf::swaps_handedness(&camera_from_world.inverse()) {
        DMat4::IDENTITY
    } else {
        DMat4::from_scale(DVec3::new(1.0, 1.0, -1.0))
    }
}

/// `[{ matrix = rows }]`, or `None` for the identity.
pub(super) fn transform_node(m: &DMat4, pos: usize) -> Option<Node> {
    if (*m - DMat4::IDENTITY).abs_diff_eq(DMat4::ZERO, 0.0) {
        return None;
    }
    let rows: Vec<Node> = tf::rows(m)
        .iter()
        .map(|r| Node::new(r.map(|x| if x.abs() < 1e-14 { 0.0 } else { x }), pos))
        .collect();
    let mut step = Node::table(pos);
    step.set("matrix", Node::new(rows, pos));
    Some(Node::new(vec![step], pos))
}

/// `[x, y, z]` as a node.
pub(super) fn vec_node(v: DVec3, pos: usize) -> Node {
    Node::new(v.to_array(), pos)
}

/// A text file, gunzipped when its name ends in `.gz` (pbrt-v4 reads such includes).
fn read_maybe_gz(path: &Path) -> Result<String, SceneError> {
    if !path.to_string_lossy().to_ascii_lowercase().ends_with(".gz") {
        return crate::read_text(path);
    }
    let bytes = crate::read_bytes(path)?;
    let mut text = String::new();
    std::io::Read::read_to_string(&mut flate2::read::GzDecoder::new(&bytes[..]), &mut text)
        .map_err(|e| {
            SceneError::input("", format!("cannot decompress (gzip): {e}")).with_file(path)
        })?;
    Ok(text)
}
