//! An object element (`<bsdf>`, `<shape>`, ...) as Mitsuba's plugins see it: a
//! plugin name, an optional id, named properties (`<float name=...>`, named nested
//! objects and `<ref name=...>`), and unnamed nested objects. Each property records
//! whether the importer used it, so that one it does not know is an error.

use super::transform::{parse_transform, Xform};
use super::xml::Elem;
use glam::DVec3;
use irradia_scene::SceneError;
use std::cell::Cell;

/// Tags that make an object (a plugin instance).
pub const OBJECT_TAGS: &[&str] = &[
    "bsdf",
    "texture",
    "shape",
    "emitter",
    "sensor",
    "film",
    "rfilter",
    "sampler",
    "integrator",
    "medium",
    "phase",
    "volume",
];

/// Tags that set a property.
pub const PROPERTY_TAGS: &[&str] = &[
    "float",
    "integer",
    "boolean",
    "string",
    "rgb",
    "spectrum",
    "point",
    "vector",
    "transform",
    "ref",
];

/// A property's value.
#[derive(Debug, Clone)]
pub enum Val<'e> {
    Float(f64),
    Int(i64),
    Bool(bool),
    Str(String),
    Rgb([f64; 3]),
    /// `<spectrum value="0.5"/>`: a constant.
    SpectrumConst(f64),
    /// `<spectrum value="400:0.1, 500:0.2"/>`: the text and its wavelengths and values.
    SpectrumList(String, Vec<f64>, Vec<f64>),
    Point(DVec3),
    Vector(DVec3),
    Transform(Xform),
    /// A named nested object (`<texture name="reflectance" type=...>`).
    Object(&'e Elem),
    /// `<ref name="..." id="..."/>`.
    Ref(String),
}

impl Val<'_> {
    pub fn kind(&self) -> &'static str {
        match self {
            Val::Float(_) => "float",
            Val::Int(_) => "integer",
            Val::Bool(_) => "boolean",
            Val::Str(_) => "string",
            Val::Rgb(_) => "rgb",
            Val::SpectrumConst(_) | Val::SpectrumList(..) => "spectrum",
            Val::Point(_) => "point",
            Val::Vector(_) => "vector",
            Val::Transform(_) => "transform",
            Val::Object(_) => "object",
            Val::Ref(_) => "ref",
        }
    }
}

#[derive(Debug)]
pub struct Prop<'e> {
    pub name: String,
    pub val: Val<'e>,
    pub elem: &'e Elem,
    pub used: Cell<bool>,
}

impl Prop<'_> {
    pub fn err(&self, msg: impl Into<String>) -> SceneError {
        self.elem.err(&self.name, msg)
    }

    pub fn f64(&self) -> Result<f64, SceneError> {
        match &self.val {
            Val::Float(x) | Val::SpectrumConst(x) => Ok(*x),
            Val::Int(i) => Ok(*i as f64),
            v => Err(self.err(format!("`{}` must be a float, not {}", self.name, v.kind()))),
        }
    }

    pub fn int(&self) -> Result<i64, SceneError> {
        match &self.val {
            Val::Int(i) => Ok(*i),
            v => Err(self.err(format!(
                "`{}` must be an integer, not {}",
                self.name,
                v.kind()
            ))),
        }
    }

    pub fn bool(&self) -> Result<bool, SceneError> {
        match &self.val {
            Val::Bool(b) => Ok(*b),
            v => Err(self.err(format!(
                "`{}` must be a boolean, not {}",
                self.name,
                v.kind()
            ))),
        }
    }

    pub fn str(&self) -> Result<&str, SceneError> {
        match &self.val {
            Val::Str(s) => Ok(s),
            v => Err(self.err(format!(
                "`{}` must be a string, not {}",
                self.name,
                v.kind()
            ))),
        }
    }

    pub fn vec3(&self) -> Result<DVec3, SceneError> {
        match &self.val {
            Val::Point(p) | Val::Vector(p) => Ok(*p),
            Val::Rgb(c) => Ok(DVec3::from_array(*c)),
            v => Err(self.err(format!(
                "`{}` must be a point or vector, not {}",
                self.name,
                v.kind()
            ))),
        }
    }

    pub fn transform(&self) -> Result<&Xform, SceneError> {
        match &self.val {
            Val::Transform(t) => Ok(t),
            v => Err(self.err(format!(
                "`{}` must be a transform, not {}",
                self.name,
                v.kind()
            ))),
        }
    }
}

/// An object element read into its properties.
#[derive(Debug)]
pub struct Obj<'e> {
    pub elem: &'e Elem,
    /// `bsdf`, `shape`, ...
    pub tag: &'e str,
    /// The plugin (`type` attribute).
    pub plugin: String,
    pub id: Option<String>,
    pub props: Vec<Prop<'e>>,
    /// Unnamed nested objects and unnamed `<ref>`s, in order.
    pub nested: Vec<&'e Elem>,
}

impl<'e> Obj<'e> {
    pub fn read(elem: &'e Elem) -> Result<Obj<'e>, SceneError> {
        elem.check_attrs(&["type", "id", "name"])?;
        let plugin = elem.req("type")?.to_string();
        let mut props: Vec<Prop<'e>> = Vec::new();
        let mut nested = Vec::new();
        for c in &elem.children {
            let tag = c.tag.as_str();
            let is_object = OBJECT_TAGS.contains(&tag)
                || (matches!(tag, "spectrum" | "rgb") && c.get("type").is_some());
            let name = c.get("name");
            if is_object || tag == "ref" {
                match name {
                    None => {
                        nested.push(c);
                        continue;
                    }
                    Some(n) => {
                        let val = if tag == "ref" {
                            c.check_attrs(&["name", "id"])?;
                            Val::Ref(c.req("id")?.to_string())
                        } else {
                            Val::Object(c)
                        };
                        push(&mut props, c, n, val)?;
                        continue;
                    }
                }
            }
            if !PROPERTY_TAGS.contains(&tag) {
                return Err(c.err(
                    &c.tag,
                    format!("unknown directive <{tag}> inside <{}>", elem.tag),
                ));
            }
            let n = c.req("name")?;
            let val = property(c)?;
            push(&mut props, c, n, val)?;
        }
        Ok(Obj {
            elem,
            tag: &elem.tag,
            plugin,
            id: elem.get("id").map(str::to_string),
            props,
            nested,
        })
    }

    /// The property `name`, marked as used.
    pub fn get(&self, name: &str) -> Option<&Prop<'e>> {
        let p = self.props.iter().find(|p| p.name == name)?;
        p.used.set(true);
        Some(p)
    }

    /// Marks properties that Irradia reads nothing from (output encodings and the
    /// like) as used.
    pub fn accept(&self, names: &[&str]) {
        for n in names {
            let _ = self.get(n);
        }
    }

    /// The first property nothing asked for.
    pub fn unused(&self) -> Option<&Prop<'e>> {
        self.props.iter().find(|p| !p.used.get())
    }

    /// Error for the first property nothing asked for.
    pub fn finish(&self, valid: &[&str]) -> Result<(), SceneError> {
        match self.unused() {
            Some(p) => Err(p.err(format!(
                "unknown parameter `{}` of {} `{}`{}",
                p.name,
                self.tag,
                self.plugin,
                if valid.is_empty() {
                    String::new()
                } else {
                    format!(" (valid: {})", valid.join(", "))
                }
            ))),
            None => Ok(()),
        }
    }

    pub fn err(&self, field: &str, msg: impl Into<String>) -> SceneError {
        self.elem.err(field, msg)
    }
}

fn push<'e>(
    props: &mut Vec<Prop<'e>>,
    c: &'e Elem,
    name: &str,
    val: Val<'e>,
) -> Result<(), SceneError> {
    if props.iter().any(|p| p.name == name) {
        return Err(c.err(name, format!("the parameter `{name}` is given twice")));
    }
    props.push(Prop {
        name: name.to_string(),
        val,
        elem: c,
        used: Cell::new(false),
    });
    Ok(())
}

/// The value of a property element.
fn property(c: &Elem) -> Result<Val<'static>, SceneError> {
    let tag = c.tag.as_str();
    Ok(match tag {
        "float" => {
            c.check_attrs(&["name", "value"])?;
            Val::Float(number(c, "value")?)
        }
        "integer" => {
            c.check_attrs(&["name", "value"])?;
            let v = c.req("value")?;
            Val::Int(
                v.trim()
                    .parse()
                    .map_err(|_| c.err_at("value", "value", format!("`{v}` is not an integer")))?,
            )
        }
        "boolean" => {
            c.check_attrs(&["name", "value"])?;
            match c.req("value")?.trim().to_ascii_lowercase().as_str() {
                "true" => Val::Bool(true),
                "false" => Val::Bool(false),
                v => {
                    return Err(c.err_at(
                        "value",
                        "value",
                        format!("`{v}` is not a boolean (true or false)"),
                    ))
                }
            }
        }
        "string" => {
            c.check_attrs(&["name", "value"])?;
            Val::Str(c.req("value")?.to_string())
        }
        "rgb" => {
            c.check_attrs(&["name", "value"])?;
            let v = numbers(c, "value")?;
            match v.len() {
                1 => Val::Rgb([v[0]; 3]),
                3 => Val::Rgb([v[0], v[1], v[2]]),
                n => {
                    return Err(c.err_at(
                        "value",
                        "value",
                        format!("an rgb value has 1 or 3 numbers, not {n}"),
                    ))
                }
            }
        }
        "spectrum" => {
            c.check_attrs(&["name", "value", "filename"])?;
            if c.get("filename").is_some() {
                return Err(c.err_at(
                    "filename",
                    "filename",
                    "spectra read from files are not supported; write the wavelength:value list",
                ));
            }
            let v = c.req("value")?;
            if v.contains(':') {
                let (w, x) = irradia_scene::texture::spectrum::parse_spectrum(v)
                    .map_err(|e| c.err_at("value", "value", e.to_string()))?;
                Val::SpectrumList(v.to_string(), w, x)
            } else {
                Val::SpectrumConst(number(c, "value")?)
            }
        }
        "point" | "vector" => {
            c.check_attrs(&["name", "value", "x", "y", "z"])?;
            let p = if c.get("value").is_some() {
                let v = numbers(c, "value")?;
                match v.len() {
                    1 => DVec3::splat(v[0]),
                    3 => DVec3::new(v[0], v[1], v[2]),
                    n => {
                        return Err(c.err_at(
                            "value",
                            "value",
                            format!("a {tag} has 3 numbers, not {n}"),
                        ))
                    }
                }
            } else {
                DVec3::new(
                    opt_number(c, "x", 0.0)?,
                    opt_number(c, "y", 0.0)?,
                    opt_number(c, "z", 0.0)?,
                )
            };
            if tag == "point" {
                Val::Point(p)
            } else {
                Val::Vector(p)
            }
        }
        "transform" => {
            c.check_attrs(&["name"])?;
            Val::Transform(parse_transform(c)?)
        }
        _ => return Err(c.err(tag, format!("unknown directive <{tag}>"))),
    })
}

/// One finite number.
pub fn number(c: &Elem, attr: &str) -> Result<f64, SceneError> {
    let v = c.req(attr)?;
    parse_f64(v).ok_or_else(|| c.err_at(attr, attr, format!("`{v}` is not a finite number")))
}

pub fn opt_number(c: &Elem, attr: &str, default: f64) -> Result<f64, SceneError> {
    match c.get(attr) {
        None => Ok(default),
        Some(_) => number(c, attr),
    }
}

/// Numbers separated by commas and/or spaces.
pub fn numbers(c: &Elem, attr: &str) -> Result<Vec<f64>, SceneError> {
    let v = c.req(attr)?;
    let out: Option<Vec<f64>> = v
        .split(|ch: char| ch == ',' || ch.is_whitespace())
        .filter(|s| !s.is_empty())
        .map(parse_f64)
        .collect();
    match out {
        Some(o) if !o.is_empty() => Ok(o),
        _ => Err(c.err_at(attr, attr, format!("`{v}` is not a list of finite numbers"))),
    }
}

fn parse_f64(s: &str) -> Option<f64> {
    s.trim().parse::<f64>().ok().filter(|x| x.is_finite())
}
