//! A directive's parameter list with typed lookups. Each lookup marks the parameter
//! used; what is left at the end is either a known parameter Irradia does not render
//! (a warning) or one the directive does not define (an error naming it).

use super::parser::{PVal, Param};
use super::At;
use std::cell::Cell;

/// Every parameter type of pbrt-v4 (with v3's spellings `point`, `vector`, `normal`,
/// `color`).
pub const TYPES: &[&str] = &[
    "integer",
    "float",
    "point2",
    "vector2",
    "point3",
    "vector3",
    "normal3",
    "normal",
    "point",
    "vector",
    "rgb",
    "color",
    "spectrum",
    "blackbody",
    "string",
    "texture",
    "bool",
];

/// A colour-like value of a parameter.
#[derive(Clone, Debug, PartialEq)]
pub enum Spec {
    Rgb([f64; 3]),
    /// A blackbody of this temperature in kelvin (pbrt-v4 normalises its peak to 1).
    Blackbody(f64),
    /// A named spectrum (`"metal-Au-eta"`, `"glass-BK7"`, `"stdillum-D65"`) or a file.
    Named(String),
    /// (wavelength in nm, value) pairs.
    Sampled(Vec<(f64, f64)>),
    /// A named texture.
    Texture(String),
    /// One number (a grey value, or an index of refraction).
    Float(f64),
}

pub struct Params {
    pub list: Vec<Param>,
    used: Vec<Cell<bool>>,
}

fn norm_type(ty: &str) -> &str {
    match ty {
        "point" => "point3",
        "vector" => "vector3",
        "normal" => "normal3",
        "color" => "rgb",
        t => t,
    }
}

impl Params {
    /// Checks every parameter's type and values.
    pub fn new(list: Vec<Param>) -> Result<Params, At> {
        for p in &list {
            if !TYPES.contains(&p.ty.as_str()) {
                let msg = match crate::pbrt::closest(&p.ty, TYPES) {
                    Some(c) => format!(
                        "unknown parameter type `{}` in \"{} {}\"; did you mean `{c}`?",
                        p.ty, p.ty, p.name
                    ),
                    None => format!(
                        "unknown parameter type `{}` in \"{} {}\" (valid: {})",
                        p.ty,
                        p.ty,
                        p.name,
                        TYPES.join(", ")
                    ),
                };
                return Err(At::new(p.pos, msg));
            }
            check_values(p)?;
        }
        let used = list.iter().map(|_| Cell::new(false)).collect();
        Ok(Params { list, used })
    }

    /// Adds `defaults` (an `Attribute` directive's) for names not given here.
    pub fn with_defaults(mut self, defaults: &[Param]) -> Params {
        for d in defaults {
            if !self.list.iter().any(|p| p.name == d.name) {
                self.list.push(d.clone());
                self.used.push(Cell::new(false));
            }
        }
        self
    }

    /// The parameter called `name`, marked used.
    pub fn get(&self, name: &str) -> Option<&Param> {
        let i = self.list.iter().position(|p| p.name == name)?;
        self.used[i].set(true);
        Some(&self.list[i])
    }

    pub fn has(&self, name: &str) -> bool {
        self.list.iter().any(|p| p.name == name)
    }

    fn typed(&self, name: &str, types: &[&str]) -> Result<Option<&Param>, At> {
        match self.get(name) {
            None => Ok(None),
            Some(p) if types.contains(&norm_type(&p.ty)) => Ok(Some(p)),
            Some(p) => Err(At::new(
                p.pos,
                format!(
                    "parameter `{}` must be of type {}, not {}",
                    name,
                    types.join(" or "),
                    p.ty
                ),
            )),
        }
    }

    pub fn floats(&self, name: &str) -> Result<Option<Vec<f64>>, At> {
        Ok(self
            .typed(name, &["float", "integer"])?
            .map(|p| nums(&p.values)))
    }

    pub fn float(&self, name: &str, default: f64) -> Result<f64, At> {
        Ok(self.float_opt(name)?.unwrap_or(default))
    }

    pub fn float_opt(&self, name: &str) -> Result<Option<f64>, At> {
        match self.typed(name, &["float", "integer"])? {
            None => Ok(None),
            Some(p) => one(p).map(|v| match v {
                PVal::Num(x) => Some(*x),
                _ => None,
            }),
        }
    }

    pub fn ints(&self, name: &str) -> Result<Option<Vec<i64>>, At> {
        Ok(self
            .typed(name, &["integer"])?
            .map(|p| nums(&p.values).into_iter().map(|x| x as i64).collect()))
    }

    pub fn int(&self, name: &str, default: i64) -> Result<i64, At> {
        match self.typed(name, &["integer"])? {
            None => Ok(default),
            Some(p) => match one(p)? {
                PVal::Num(x) => Ok(*x as i64),
                _ => Ok(default),
            },
        }
    }

    pub fn string(&self, name: &str) -> Result<Option<String>, At> {
        match self.typed(name, &["string"])? {
            None => Ok(None),
            Some(p) => match one(p)? {
                PVal::Str(s) => Ok(Some(s.clone())),
                _ => Ok(None),
            },
        }
    }

    pub fn bool(&self, name: &str, default: bool) -> Result<bool, At> {
        match self.typed(name, &["bool"])? {
            None => Ok(default),
            Some(p) => match one(p)? {
                PVal::Bool(b) => Ok(*b),
                PVal::Str(s) => Ok(s == "true"),
                _ => Ok(default),
            },
        }
    }

    /// `point3`, `vector3` or `normal` values, three numbers each.
    pub fn vec3s(&self, name: &str) -> Result<Option<Vec<[f64; 3]>>, At> {
        Ok(self
            .typed(name, &["point3", "vector3", "normal3"])?
            .map(|p| {
                nums(&p.values)
                    .chunks(3)
                    .map(|c| [c[0], c[1], c[2]])
                    .collect()
            }))
    }

    pub fn vec3(&self, name: &str, default: [f64; 3]) -> Result<[f64; 3], At> {
        match self.vec3s(name)? {
            None => Ok(default),
            Some(v) if v.len() == 1 => Ok(v[0]),
            Some(_) => Err(self.one_value_error(name)),
        }
    }

    pub fn vec2s(&self, name: &str) -> Result<Option<Vec<[f64; 2]>>, At> {
        Ok(self
            .typed(name, &["point2", "vector2", "float"])?
            .map(|p| nums(&p.values).chunks(2).map(|c| [c[0], c[1]]).collect()))
    }

    fn one_value_error(&self, name: &str) -> At {
        let p = self.list.iter().find(|p| p.name == name).expect("present");
        At::new(p.pos, format!("parameter `{name}` takes one value"))
    }

    /// A colour, spectrum, number or texture reference.
    pub fn spec(&self, name: &str) -> Result<Option<(Spec, usize)>, At> {
        let Some(p) = self.get(name) else {
            return Ok(None);
        };
        let s = match norm_type(&p.ty) {
            "rgb" => {
                let v = nums(&p.values);
                Spec::Rgb([v[0], v[1], v[2]])
            }
            "blackbody" => Spec::Blackbody(nums(&p.values)[0]),
            "spectrum" => match &p.values[..] {
                [PVal::Str(s)] => Spec::Named(s.clone()),
                v => {
                    let v = nums(v);
                    Spec::Sampled(v.chunks(2).map(|c| (c[0], c[1])).collect())
                }
            },
            "texture" => match one(p)? {
                PVal::Str(s) => Spec::Texture(s.clone()),
                _ => return Ok(None),
            },
            "float" | "integer" => match one(p)? {
                PVal::Num(x) => Spec::Float(*x),
                _ => return Ok(None),
            },
            _ => {
                return Err(At::new(
                    p.pos,
                    format!(
                        "parameter `{name}` must be a colour, spectrum, number or texture, not {}",
                        p.ty
                    ),
                ))
            }
        };
        Ok(Some((s, p.pos)))
    }

    /// Parameters not looked up.
    pub fn unused(&self) -> impl Iterator<Item = &Param> {
        self.list
            .iter()
            .zip(&self.used)
            .filter(|(_, u)| !u.get())
            .map(|(p, _)| p)
    }

    /// The position of `name`'s declaration (or `fallback`).
    pub fn pos(&self, name: &str, fallback: usize) -> usize {
        self.list
            .iter()
            .find(|p| p.name == name)
            .map_or(fallback, |p| p.pos)
    }
}

fn nums(v: &[PVal]) -> Vec<f64> {
    v.iter()
        .map(|x| match x {
            PVal::Num(n) => *n,
            _ => 0.0,
        })
        .collect()
}

fn one(p: &Param) -> Result<&PVal, At> {
    match &p.values[..] {
        [v] => Ok(v),
        _ => Err(At::new(
            p.pos,
            format!(
                "parameter \"{} {}\" takes one value, found {}",
                p.ty,
                p.name,
                p.values.len()
            ),
        )),
    }
}

/// Values of the right kind and count for the type.
fn check_values(p: &Param) -> Result<(), At> {
    let ty = norm_type(&p.ty);
    let at = |i: usize, msg: String| At::new(p.value_pos.get(i).copied().unwrap_or(p.pos), msg);
    let decl = format!("\"{} {}\"", p.ty, p.name);
    if p.values.is_empty() {
        return Err(At::new(p.pos, format!("parameter {decl} has no values")));
    }
    let numeric = |group: usize| -> Result<(), At> {
        for (i, v) in p.values.iter().enumerate() {
            if !matches!(v, PVal::Num(_)) {
                return Err(at(i, format!("parameter {decl} takes numbers")));
            }
        }
        if !p.values.len().is_multiple_of(group) {
            return Err(At::new(
                p.pos,
                format!(
                    "parameter {decl} takes a multiple of {group} numbers, found {}",
                    p.values.len()
                ),
            ));
        }
        Ok(())
    };
    match ty {
        "integer" => {
            numeric(1)?;
            for (i, v) in p.values.iter().enumerate() {
                if let PVal::Num(x) = v {
                    if x.fract() != 0.0 {
                        return Err(at(i, format!("parameter {decl} takes integers (got {x})")));
                    }
                }
            }
        }
        "float" => numeric(1)?,
        "point2" | "vector2" => numeric(2)?,
        "point3" | "vector3" | "normal3" => numeric(3)?,
        "rgb" => {
            numeric(3)?;
            if p.values.len() != 3 {
                return Err(At::new(p.pos, format!("parameter {decl} takes 3 numbers")));
            }
        }
        "blackbody" => {
            numeric(1)?;
            if p.values.len() > 2 {
                return Err(At::new(
                    p.pos,
                    format!("parameter {decl} takes one temperature"),
                ));
            }
        }
        "spectrum" if !matches!(&p.values[..], [PVal::Str(_)]) => {
            numeric(2)?;
            let w: Vec<f64> = nums(&p.values).iter().step_by(2).copied().collect();
            if w.windows(2).any(|w| w[1] <= w[0]) {
                return Err(At::new(
                    p.pos,
                    format!("parameter {decl}: the wavelengths must increase"),
                ));
            }
        }
        "string" | "texture" => {
            for (i, v) in p.values.iter().enumerate() {
                if !matches!(v, PVal::Str(_)) {
                    return Err(at(i, format!("parameter {decl} takes quoted strings")));
                }
            }
        }
        "bool" => {
            for (i, v) in p.values.iter().enumerate() {
                let ok = match v {
                    PVal::Bool(_) => true,
                    PVal::Str(s) => s == "true" || s == "false",
                    PVal::Num(_) => false,
                };
                if !ok {
                    return Err(at(i, format!("parameter {decl} takes true or false")));
                }
            }
        }
        _ => {}
    }
    Ok(())
}
