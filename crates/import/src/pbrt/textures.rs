//! `Texture "name" "float"|"spectrum" "class"` as Irradia's texture tables, and
//! material parameters (a colour, a spectrum, a number or a named texture) as the
//! values Irradia's materials take.
//!
//! - `imagemap` → `bitmap`. pbrt looks an image up at `(s, 1 − t)` (its `t` runs up),
//!   Irradia and Mitsuba at `(u, v)` with `v` down, so `to_uv` is
//!   `scale [uscale, −vscale]` then `translate [udelta, 1 − vdelta]`.
//! - `checkerboard` (2D) → `checkerboard`: pbrt has one cell per unit of `(s, t)`,
//!   Mitsuba two (its `color0` where u and v are in the same halves of their cells),
//!   and pbrt's `tex1` is on the cells where `floor(s) + floor(t)` is even: so
//!   `color0 = tex1`, `color1 = tex2` (swapped for a float texture, which Mitsuba
//!   evaluates the other way round), and `to_uv` halves.
//! - `constant`, and `scale` and `mix` of constants, become the constant; `scale`
//!   or `mix` of a texture and a constant keep the texture, with a warning unless the
//!   constant changes nothing.

use super::builder::Builder;
use super::params::{Params, Spec};
use super::spectra;
use super::At;
use irradia_scene::file::tree::{Node, Value};

#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Want {
    Color,
    Float,
}

/// A constant's value: a number or `[r, g, b]`.
pub fn constant(n: &Node) -> Option<[f64; 3]> {
    match &n.value {
        Value::Float(x) => Some([*x; 3]),
        Value::Int(x) => Some([*x as f64; 3]),
        Value::Array(items) if items.len() == 3 => {
            let mut out = [0.0; 3];
            for (o, i) in out.iter_mut().zip(items) {
                *o = match i.value {
                    Value::Float(x) => x,
                    Value::Int(x) => x as f64,
                    _ => return None,
                };
            }
            Some(out)
        }
        _ => None,
    }
}

/// A node for a constant colour (grey as one number).
pub fn rgb_node(c: [f64; 3], pos: usize) -> Node {
    if c[0] == c[1] && c[1] == c[2] {
        Node::new(c[0], pos)
    } else {
        Node::new(c, pos)
    }
}

fn mean(c: [f64; 3]) -> f64 {
    (c[0] + c[1] + c[2]) / 3.0
}

impl Builder {
    pub(super) fn texture(
        &mut self,
        name: &str,
        (ty, ty_pos): (&str, usize),
        class: &str,
        p: &Params,
        pos: usize,
    ) -> Result<(), At> {
        self.kind_now = Some(("texture", class.to_string()));
        let want = match ty {
            "float" => Want::Float,
            "spectrum" | "color" | "rgb" => Want::Color,
            _ => {
                return Err(At::new(
                    ty_pos,
                    format!(
                    "Texture \"{name}\": unknown texture type \"{ty}\" (valid: float, spectrum)"
                ),
                ))
            }
        };
        let tp = self.tp(pos);
        let node = match class {
            "imagemap" => self.imagemap(p, tp, pos)?,
            "checkerboard" => {
                let dim = p.int("dimension", 2)?;
                let t1 = self.tex_param(p, "tex1", want, 1.0)?;
                let t2 = self.tex_param(p, "tex2", want, 0.0)?;
                let (c1, c2) = match (constant(&t1), constant(&t2)) {
                    (Some(a), Some(b)) => (a, b),
                    _ => {
                        self.warn(
                            pos,
                            "checker-tex",
                            "checkerboard of textures: each texture is replaced by grey 0.5 (Irradia's checkerboard has constant colours)",
                        );
                        let a = constant(&t1).unwrap_or([0.5; 3]);
                        let b = constant(&t2).unwrap_or([0.5; 3]);
                        (a, b)
                    }
                };
                if dim == 3 {
                    self.warn(
                        pos,
                        "checker3d",
                        "3D checkerboard: rendered as the 2D checkerboard of the surface's uv",
                    );
                }
                let to_uv = self.uv_mapping(p, pos, tp, 0.5)?;
                let mut t = Node::table(tp);
                t.put("type", "checkerboard", tp);
                // Mitsuba evaluates a checkerboard as a number (a roughness, a mix
                // amount) the other way round from a colour.
                let (c0, c1) = match want {
                    Want::Color => (c1, c2),
                    Want::Float => (c2, c1),
                };
                t.set("color0", rgb_node(c0, tp));
                t.set("color1", rgb_node(c1, tp));
                if let Some(u) = to_uv {
                    t.set("to_uv", u);
                }
                t
            }
            "constant" => self.tex_param(p, "value", want, 1.0)?,
            "scale" => {
                let a = self.tex_param(p, "tex", want, 1.0)?;
                let b = self.tex_param(p, "scale", Want::Float, 1.0)?;
                match (constant(&a), constant(&b)) {
                    (Some(x), Some(y)) => rgb_node([x[0] * y[0], x[1] * y[1], x[2] * y[2]], tp),
                    (None, Some(y)) => {
                        if y != [1.0; 3] {
                            self.warn(
                                pos,
                                "scale-tex",
                                "scale texture: the factor on an image or checkerboard is not applied",
                            );
                        }
                        a
                    }
                    (Some(x), None) => {
                        if x != [1.0; 3] {
                            self.warn(
                                pos,
                                "scale-tex",
                                "scale texture: the factor on an image or checkerboard is not applied",
                            );
                        }
                        b
                    }
                    (None, None) => {
                        self.warn(
                            pos,
                            "scale-tex2",
                            "scale texture of two textures: only the first is used",
                        );
                        a
                    }
                }
            }
            "mix" | "directionmix" => {
                let a = self.tex_param(p, "tex1", want, 0.0)?;
                let b = self.tex_param(p, "tex2", want, 1.0)?;
                let amount = if class == "mix" {
                    self.tex_param(p, "amount", Want::Float, 0.5)?
                } else {
                    let _ = p.vec3("dir", [0.0, 1.0, 0.0])?;
                    self.warn(
                        pos,
                        "directionmix",
                        "directionmix texture: mixed half and half (the direction is not rendered)",
                    );
                    Node::new(0.5, tp)
                };
                match (constant(&a), constant(&b), constant(&amount)) {
                    (Some(x), Some(y), Some(t)) => {
                        let t = t[0];
                        rgb_node(
                            [
                                x[0] * (1.0 - t) + y[0] * t,
                                x[1] * (1.0 - t) + y[1] * t,
                                x[2] * (1.0 - t) + y[2] * t,
                            ],
                            tp,
                        )
                    }
                    (_, _, t) => {
                        self.warn(
                            pos,
                            "mix-tex",
                            "mix texture of textures: the heavier input is used alone",
                        );
                        if t.map_or(0.5, |t| t[0]) > 0.5 {
                            b
                        } else {
                            a
                        }
                    }
                }
            }
            "bilerp" | "dots" | "fbm" | "wrinkled" | "windy" | "marble" | "ptex" => {
                self.warn(
                    pos,
                    &format!("texture:{class}"),
                    format!("texture \"{class}\" is not available: replaced by grey 0.5"),
                );
                for param in &p.list {
                    let _ = p.get(&param.name);
                }
                Node::new(0.5, tp)
            }
            _ => {
                return Err(At::new(
                    pos,
                    format!("Texture \"{name}\": unknown texture class \"{class}\""),
                ))
            }
        };
        self.finish_params(
            p,
            &format!("Texture \"{class}\""),
            &["mapping", "v1", "v2", "maxanisotropy"],
        )?;
        match want {
            Want::Float => self.float_tex.insert(name.to_string(), node),
            Want::Color => self.spec_tex.insert(name.to_string(), node),
        };
        Ok(())
    }

    /// pbrt's uv mapping (`uscale`, `vscale`, `udelta`, `vdelta`) as `to_uv`, each
    /// factor times `k` (Mitsuba's checkerboard cells are half as large); `None` for
    /// the identity.
    fn uv_mapping(
        &mut self,
        p: &Params,
        pos: usize,
        tp: usize,
        k: f64,
    ) -> Result<Option<Node>, At> {
        if let Some(m) = p.string("mapping")? {
            if m != "uv" {
                self.warn(
                    p.pos("mapping", pos),
                    &format!("mapping:{m}"),
                    format!("texture mapping \"{m}\" is rendered as the surface's uv"),
                );
            }
        }
        let su = p.float("uscale", 1.0)?;
        let sv = p.float("vscale", 1.0)?;
        let du = p.float("udelta", 0.0)?;
        let dv = p.float("vdelta", 0.0)?;
        if su == 1.0 && sv == 1.0 && du == 0.0 && dv == 0.0 && k == 1.0 {
            return Ok(None);
        }
        let mut steps = Vec::new();
        let mut s = Node::table(tp);
        s.put("scale", [su * k, sv * k], tp);
        steps.push(s);
        if du != 0.0 || dv != 0.0 {
            let mut t = Node::table(tp);
            t.put("translate", [du * k, dv * k], tp);
            steps.push(t);
        }
        Ok(Some(Node::new(steps, tp)))
    }

    fn imagemap(&mut self, p: &Params, tp: usize, pos: usize) -> Result<Node, At> {
        let file = p
            .string("filename")?
            .ok_or_else(|| At::new(pos, "imagemap texture needs \"string filename\""))?;
        let mut t = Node::table(tp);
        t.put("type", "bitmap", tp)
            .put("filename", file.as_str(), tp);
        match p.string("filter")?.as_deref() {
            None | Some("bilinear") | Some("trilinear") | Some("ewa") | Some("EWA") => {}
            Some("point") => {
                t.put("filter_type", "nearest", tp);
            }
            Some(f) => {
                return Err(At::new(
                    p.pos("filter", pos),
                    format!(
                        "imagemap: unknown filter \"{f}\" (valid: point, bilinear, trilinear, ewa)"
                    ),
                ))
            }
        }
        match p.string("wrap")?.as_deref() {
            None | Some("repeat") => {}
            Some("clamp") => {
                t.put("wrap_mode", "clamp", tp);
            }
            Some(w @ ("black" | "octahedralsphere")) => {
                self.warn(
                    p.pos("wrap", pos),
                    &format!("wrap:{w}"),
                    format!("imagemap: wrap mode \"{w}\" is rendered as clamp"),
                );
                t.put("wrap_mode", "clamp", tp);
            }
            Some(w) => {
                return Err(At::new(
                    p.pos("wrap", pos),
                    format!("imagemap: unknown wrap mode \"{w}\""),
                ))
            }
        }
        match p.string("encoding")?.as_deref() {
            None | Some("sRGB") => {}
            Some("linear") => {
                t.put("raw", true, tp);
            }
            Some(e) if e.starts_with("gamma") => {
                self.warn(
                    p.pos("encoding", pos),
                    "gamma",
                    format!("imagemap: encoding \"{e}\" is decoded as sRGB"),
                );
            }
            Some(e) => {
                return Err(At::new(
                    p.pos("encoding", pos),
                    format!("imagemap: unknown encoding \"{e}\""),
                ))
            }
        }
        if p.bool("invert", false)? {
            self.warn(
                p.pos("invert", pos),
                "invert",
                "imagemap: invert is not applied",
            );
        }
        let scale = p.float("scale", 1.0)?;
        if scale != 1.0 {
            if !(scale.is_finite() && scale >= 0.0) {
                return Err(At::new(
                    p.pos("scale", pos),
                    format!("imagemap: scale must be finite and not negative (got {scale})"),
                ));
            }
            // pbrt-v4 multiplies the looked-up value: the bitmap's own `scale`.
            t.put("scale", scale, tp);
        }
        // pbrt looks up (s, 1 - t).
        let mapping = self.uv_mapping(p, pos, tp, 1.0)?;
        let (su, sv, du, dv) = match mapping {
            None => (1.0, 1.0, 0.0, 0.0),
            Some(_) => (
                p.float("uscale", 1.0)?,
                p.float("vscale", 1.0)?,
                p.float("udelta", 0.0)?,
                p.float("vdelta", 0.0)?,
            ),
        };
        let mut s = Node::table(tp);
        s.put("scale", [su, -sv], tp);
        let mut tr = Node::table(tp);
        tr.put("translate", [du, 1.0 - dv], tp);
        t.set("to_uv", Node::new(vec![s, tr], tp));
        Ok(t)
    }

    /// A texture's parameter `name` (a constant or another texture), `default` when
    /// absent.
    pub(super) fn tex_param(
        &mut self,
        p: &Params,
        name: &str,
        want: Want,
        default: f64,
    ) -> Result<Node, At> {
        match p.spec(name)? {
            None => Ok(Node::new(default, 0)),
            Some((s, pos)) => self.spec_node(&s, pos, want, name),
        }
    }

    /// A colour parameter of a material (absent: `default`).
    pub(super) fn color_param(&mut self, p: &Params, name: &str, default: f64) -> Result<Node, At> {
        self.tex_param(p, name, Want::Color, default)
    }

    /// Irradia's value for a parameter's spectrum, number or texture.
    pub(super) fn spec_node(
        &mut self,
        s: &Spec,
        pos: usize,
        want: Want,
        what: &str,
    ) -> Result<Node, At> {
        let tp = self.tp(pos);
        Ok(match s {
            Spec::Float(x) => Node::new(*x, tp),
            Spec::Rgb(c) => match want {
                Want::Color => rgb_node(*c, tp),
                Want::Float => Node::new(mean(*c), tp),
            },
            Spec::Blackbody(t) => {
                let c = spectra::blackbody_rgb(*t).ok_or_else(|| {
                    At::new(
                        pos,
                        format!("`{what}`: a blackbody needs a positive temperature"),
                    )
                })?;
                rgb_node(c, tp)
            }
            Spec::Sampled(v) => {
                let text: Vec<String> = v.iter().map(|(w, x)| format!("{w}:{x}")).collect();
                if v.len() < 2 {
                    rgb_node([v.first().map_or(0.0, |x| x.1); 3], tp)
                } else {
                    match want {
                        Want::Color => Node::new(text.join(", "), tp),
                        Want::Float => Node::new(mean(spectra::reflectance_rgb(v)), tp),
                    }
                }
            }
            Spec::Named(n) => {
                if let Some(c) = spectra::illuminant_rgb(n) {
                    rgb_node(c, tp)
                } else if let Some(ior) = spectra::glass_ior(n) {
                    Node::new(ior, tp)
                } else if let Some((metal, which)) = spectra::metal(n) {
                    rgb_node(metal_rgb(metal, which), tp)
                } else {
                    return Err(At::new(
                        pos,
                        format!("`{what}`: unknown named spectrum \"{n}\""),
                    ));
                }
            }
            Spec::Texture(name) => {
                let found = match want {
                    Want::Color => self.spec_tex.get(name).or_else(|| self.float_tex.get(name)),
                    Want::Float => self.float_tex.get(name).or_else(|| self.spec_tex.get(name)),
                };
                match found {
                    Some(n) => n.clone(),
                    None => {
                        return Err(At::new(
                            pos,
                            format!("`{what}`: no texture named \"{name}\""),
                        ))
                    }
                }
            }
        })
    }
}

/// A pbrt metal's eta or k in RGB (Mitsuba's tables; brass from pbrt's).
pub fn metal_rgb(metal: &str, which: &str) -> [f64; 3] {
    let (eta, k) = if metal == "CuZn" {
        spectra::CUZN
    } else {
        match irradia_scatter::ior::conductor_ior(metal) {
            Some((e, k)) => (
                [e.r as f64, e.g as f64, e.b as f64],
                [k.r as f64, k.g as f64, k.b as f64],
            ),
            None => ([0.2, 0.92, 1.1], [3.9, 2.45, 2.14]),
        }
    };
    if which == "eta" {
        eta
    } else {
        k
    }
}
