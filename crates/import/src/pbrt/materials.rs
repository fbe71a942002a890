//! pbrt-v4's materials as Mitsuba-style BSDFs of Irradia's schema.
//!
//! pbrt's microfacet roughness is the Trowbridge–Reitz (GGX) distribution with
//! `alpha = sqrt(roughness)` when `remaproughness` is true (the default), `alpha =
//! roughness` otherwise; a zero alpha is the smooth BSDF. pbrt's dielectrics have
//! vacuum outside (`ext_ior = 1`).

use super::builder::{Builder, MatRef};
use super::params::{Params, Spec};
use super::spectra;
use super::textures::{constant, metal_rgb, rgb_node, Want};
use super::At;
use irradia_scene::file::tree::{Node, Value};

/// pbrt's roughness parameters, resolved.
enum Rough {
    Smooth,
    Iso(Node),
    Aniso(Node, Node),
}

impl Builder {
    /// Defines Irradia material `name` from pbrt material `ty`; `interface` gives a
    /// reference that shapes skip.
    pub(super) fn material(
        &mut self,
        name: &str,
        ty: &str,
        p: &Params,
        pos: usize,
    ) -> Result<MatRef, At> {
        self.kind_now = Some(("material", ty.to_string()));
        let tp = self.tp(pos);
        let mut m = Node::table(tp);
        let mut ignored: Vec<&str> = vec!["type"];
        match ty {
            "interface" => {
                self.finish_params(p, "Material \"interface\"", &["type"])?;
                return Ok(MatRef {
                    name: name.to_string(),
                    interface: true,
                });
            }
            "diffuse" => {
                m.put("type", "diffuse", tp);
                m.set("reflectance", self.color_param(p, "reflectance", 0.5)?);
            }
            "conductor" => self.conductor(&mut m, p, "", tp, pos)?,
            "dielectric" | "thindielectric" => {
                let eta = self.eta(p, "eta", pos)?;
                let rough = if ty == "dielectric" {
                    self.roughness(p, "", pos)?
                } else {
                    Rough::Smooth
                };
                let kind = match (&rough, ty) {
                    (_, "thindielectric") => "thindielectric",
                    (Rough::Smooth, _) => "dielectric",
                    _ => "roughdielectric",
                };
                m.put("type", kind, tp);
                m.put("int_ior", eta, tp).put("ext_ior", 1.0, tp);
                self.put_rough(&mut m, rough, tp, true);
            }
            "coateddiffuse" => {
                let rough = self.roughness(p, "", pos)?;
                let eta = self.eta(p, "eta", pos)?;
                let refl = self.color_param(p, "reflectance", 0.5)?;
                let smooth = matches!(rough, Rough::Smooth);
                m.put("type", if smooth { "plastic" } else { "roughplastic" }, tp);
                m.set("diffuse_reflectance", refl);
                m.put("int_ior", eta, tp)
                    .put("ext_ior", 1.0, tp)
                    .put("nonlinear", true, tp);
                if !smooth {
                    let a = self.number_only(rough, pos, 0.1);
                    m.put("distribution", "ggx", tp).put("alpha", a, tp);
                }
                self.warn(
                    pos,
                    "coateddiffuse",
                    "coateddiffuse is approximated by Mitsuba's (rough)plastic: the layer's random walk, thickness, albedo and g are not modelled",
                );
                ignored.extend(["thickness", "albedo", "g", "maxdepth", "nsamples", "seed"]);
            }
            "coatedconductor" => {
                self.coated_conductor(&mut m, p, tp, pos)?;
                ignored.extend(["thickness", "albedo", "g", "maxdepth", "nsamples", "seed"]);
            }
            "mix" => {
                let names = match p.get("materials") {
                    Some(par) if par.values.len() == 2 => par
                        .values
                        .iter()
                        .map(|v| match v {
                            super::parser::PVal::Str(s) => s.clone(),
                            _ => String::new(),
                        })
                        .collect::<Vec<_>>(),
                    Some(par) => {
                        return Err(At::new(
                            par.pos,
                            "mix: \"string materials\" takes two names",
                        ))
                    }
                    None => return Err(At::new(pos, "mix needs \"string materials\" [a b]")),
                };
                let mut bsdfs = Vec::new();
                for n in &names {
                    match self.named_materials.get(n) {
                        Some(r) if !r.interface => bsdfs.push(Node::new(r.name.as_str(), tp)),
                        Some(_) => {
                            self.warn(
                                pos,
                                "mix-interface",
                                "mix with an interface material: the interface is rendered as black diffuse",
                            );
                            let mut d = Node::table(tp);
                            d.put("type", "diffuse", tp).put("reflectance", 0.0, tp);
                            bsdfs.push(d);
                        }
                        None => {
                            return Err(At::new(
                                p.pos("materials", pos),
                                format!("mix: no material named \"{n}\""),
                            ))
                        }
                    }
                }
                m.put("type", "blendbsdf", tp);
                m.set("weight", self.tex_param(p, "amount", Want::Float, 0.5)?);
                m.set("bsdfs", Node::new(bsdfs, tp));
            }
            "diffusetransmission" | "subsurface" | "measured" | "hair" => {
                let refl = if p.has("reflectance") {
                    self.color_param(p, "reflectance", 0.5)?
                } else {
                    Node::new(0.5, tp)
                };
                self.warn(
                    pos,
                    &format!("material:{ty}"),
                    format!("material \"{ty}\" is not available: rendered as diffuse"),
                );
                m.put("type", "diffuse", tp);
                m.set("reflectance", refl);
                ignored.push("*");
            }
            _ => return Err(At::new(pos, format!("unknown material type \"{ty}\""))),
        }
        if p.has("displacement") {
            let _ = p.get("displacement");
            self.warn(
                p.pos("displacement", pos),
                "displacement",
                "displacement (bump mapping) of pbrt materials is not rendered",
            );
        }
        let normal_map = p.string("normalmap")?;
        self.finish_params(p, &format!("Material \"{ty}\""), &ignored)?;
        let reflective = matches!(
            m.get("type").map(|t| &t.value),
            Some(Value::Str(t)) if ["diffuse", "conductor", "roughconductor", "plastic", "roughplastic", "principled"].contains(&t.as_str())
        );
        let node = match normal_map {
            Some(file) => {
                let mut bm = Node::table(tp);
                bm.put("type", "bitmap", tp)
                    .put("filename", file.as_str(), tp)
                    .put("raw", true, tp);
                let mut s = Node::table(tp);
                s.put("scale", [1.0, -1.0], tp);
                let mut t = Node::table(tp);
                t.put("translate", [0.0, 1.0], tp);
                bm.set("to_uv", Node::new(vec![s, t], tp));
                let mut nm = Node::table(tp);
                nm.put("type", "normalmap", tp);
                nm.set("normalmap", bm);
                nm.set("bsdf", m);
                nm
            }
            None => m,
        };
        // pbrt's reflective BSDFs reflect on both sides of a surface, Mitsuba's on the
        // front only: `twosided` makes them agree.
        let node = if reflective {
            let mut t = Node::table(tp);
            t.put("type", "twosided", tp);
            t.set("bsdf", node);
            t
        } else {
            node
        };
        self.add_material(name, node);
        Ok(MatRef {
            name: name.to_string(),
            interface: false,
        })
    }

    /// An index of refraction: a number, a named glass or a spectrum (its value at
    /// 587.6 nm, dispersion not rendered).
    fn eta(&mut self, p: &Params, key: &str, pos: usize) -> Result<f64, At> {
        let eta = match p.spec(key)? {
            None => 1.5,
            Some((Spec::Float(x), _)) => x,
            Some((Spec::Named(n), at)) => match spectra::glass_ior(&n) {
                Some(x) => {
                    self.warn(
                        at,
                        "dispersion",
                        format!("{key} \"{n}\": dispersion is not rendered (its index at 587.6 nm, {x}, is used)"),
                    );
                    x
                }
                None => {
                    return Err(At::new(
                        at,
                        format!("{key}: unknown named spectrum \"{n}\""),
                    ))
                }
            },
            Some((Spec::Sampled(v), at)) => {
                self.warn(
                    at,
                    "dispersion",
                    format!("{key}: dispersion is not rendered (the value at 587.6 nm is used)"),
                );
                spectra::sample(&v, 587.6)
            }
            Some((Spec::Rgb(c), _)) => (c[0] + c[1] + c[2]) / 3.0,
            Some((Spec::Texture(_), at)) => {
                self.warn(
                    at,
                    "eta-tex",
                    format!("{key}: a textured index of refraction is rendered as 1.5"),
                );
                1.5
            }
            Some((Spec::Blackbody(_), at)) => {
                return Err(At::new(
                    at,
                    format!("{key}: a blackbody is not an index of refraction"),
                ))
            }
        };
        if !(eta > 0.0 && eta.is_finite()) {
            return Err(At::new(
                p.pos(key, pos),
                format!("{key} must be positive (got {eta})"),
            ));
        }
        Ok(eta)
    }

    /// `roughness`, `uroughness`, `vroughness`, `remaproughness` (with `prefix`:
    /// `interface.` or `conductor.` of coatedconductor).
    fn roughness(&mut self, p: &Params, prefix: &str, pos: usize) -> Result<Rough, At> {
        let remap =
            p.bool(&format!("{prefix}remaproughness"), true)? && p.bool("remaproughness", true)?;
        let base = p.spec(&format!("{prefix}roughness"))?;
        let u = p.spec(&format!("{prefix}uroughness"))?.or(base.clone());
        let v = p.spec(&format!("{prefix}vroughness"))?.or(base);
        let mut alpha = |s: Option<(Spec, usize)>| -> Result<Node, At> {
            Ok(match s {
                None => Node::new(0.0, 0),
                Some((Spec::Float(r), at)) => {
                    if r < 0.0 {
                        return Err(At::new(
                            at,
                            format!("roughness must not be negative (got {r})"),
                        ));
                    }
                    Node::new(if remap { r.sqrt() } else { r }, self.tp(at))
                }
                Some((spec, at)) => {
                    let n = self.spec_node(&spec, at, Want::Float, "roughness")?;
                    if let Some(c) = constant(&n) {
                        Node::new(if remap { c[0].sqrt() } else { c[0] }, self.tp(at))
                    } else {
                        if remap {
                            self.warn(
                                at,
                                "rough-tex",
                                "a roughness texture is used as alpha without pbrt's square-root remapping",
                            );
                        }
                        n
                    }
                }
            })
        };
        let (a, b) = (alpha(u)?, alpha(v)?);
        let _ = pos;
        let zero = |n: &Node| matches!(n.value, Value::Float(x) if x == 0.0);
        Ok(if zero(&a) && zero(&b) {
            Rough::Smooth
        } else if a == b || a.canonical() == b.canonical() {
            Rough::Iso(a)
        } else {
            Rough::Aniso(a, b)
        })
    }

    fn put_rough(&mut self, m: &mut Node, r: Rough, tp: usize, textures_ok: bool) {
        match r {
            Rough::Smooth => {}
            Rough::Iso(a) => {
                m.put("distribution", "ggx", tp);
                m.set("alpha", a);
            }
            Rough::Aniso(a, b) => {
                m.put("distribution", "ggx", tp);
                m.set("alpha_u", a);
                m.set("alpha_v", b);
            }
        }
        let _ = textures_ok;
    }

    /// A roughness where Irradia takes a number only.
    fn number_only(&mut self, r: Rough, pos: usize, fallback: f64) -> f64 {
        let num = |n: &Node| constant(n).map(|c| c[0]);
        match r {
            Rough::Smooth => 0.0,
            Rough::Iso(a) => num(&a).unwrap_or_else(|| {
                self.warn(pos, "rough-number", format!("a textured roughness is rendered as alpha {fallback} here (the BSDF takes a number)"));
                fallback
            }),
            Rough::Aniso(a, b) => {
                self.warn(pos, "aniso-plastic", "anisotropic roughness is rendered isotropic here (the geometric mean)");
                match (num(&a), num(&b)) {
                    (Some(x), Some(y)) => (x * y).sqrt(),
                    _ => fallback,
                }
            }
        }
    }

    /// `conductor` (or the `conductor.` part of `coatedconductor` with `prefix`).
    fn conductor(
        &mut self,
        m: &mut Node,
        p: &Params,
        prefix: &str,
        tp: usize,
        pos: usize,
    ) -> Result<(), At> {
        let rough = self.roughness(p, prefix, pos)?;
        let smooth = matches!(rough, Rough::Smooth);
        m.put(
            "type",
            if smooth {
                "conductor"
            } else {
                "roughconductor"
            },
            tp,
        );
        let (eta, k) = self.conductor_ior(p, prefix, pos)?;
        match (eta, k) {
            (Ior::Named(a), Ior::Named(b)) if a == b && a != "CuZn" => {
                m.put("material", a.as_str(), tp);
            }
            (e, k) => {
                m.set("eta", rgb_node(e.rgb("eta"), tp));
                m.set("k", rgb_node(k.rgb("k"), tp));
            }
        }
        self.put_rough(m, rough, tp, true);
        Ok(())
    }

    fn conductor_ior(&mut self, p: &Params, prefix: &str, pos: usize) -> Result<(Ior, Ior), At> {
        if let Some((s, at)) = p.spec("reflectance")? {
            // pbrt-v4: eta = 1, k = 2 sqrt(r) / sqrt(1 - r).
            let n = self.spec_node(&s, at, Want::Color, "reflectance")?;
            let r = constant(&n).unwrap_or_else(|| {
                self.warn(
                    at,
                    "conductor-refl-tex",
                    "a textured conductor reflectance is rendered as 0.8",
                );
                [0.8; 3]
            });
            let k = r.map(|r| {
                let r = r.clamp(0.0, 0.9999);
                2.0 * r.sqrt() / (1.0 - r).sqrt()
            });
            return Ok((Ior::Rgb([1.0; 3]), Ior::Rgb(k)));
        }
        let mut get = |key: &str, default: &str| -> Result<Ior, At> {
            let full = format!("{prefix}{key}");
            Ok(match p.spec(&full)? {
                None => Ior::Named(default.to_string()),
                Some((Spec::Named(n), at)) => match spectra::metal(&n) {
                    Some((metal, _)) => Ior::Named(metal.to_string()),
                    None if n.to_ascii_lowercase().ends_with(".spd") => {
                        match self.spectrum_file(&n) {
                            Some(v) => Ior::Rgb(spectra::reflectance_rgb(&v)),
                            None => {
                                self.warn(at, &format!("spd:{n}"), format!("{full}: the spectrum file \"{n}\" was not read; copper's is used"));
                                Ior::Named("Cu".into())
                            }
                        }
                    }
                    None => {
                        return Err(At::new(
                            at,
                            format!("{full}: unknown named spectrum \"{n}\""),
                        ))
                    }
                },
                Some((Spec::Rgb(c), _)) => Ior::Rgb(c),
                Some((Spec::Float(x), _)) => Ior::Rgb([x; 3]),
                Some((Spec::Sampled(v), _)) => Ior::Rgb(spectra::reflectance_rgb(&v)),
                Some((Spec::Texture(_), at)) => {
                    self.warn(
                        at,
                        "ior-tex",
                        format!("{full}: a textured {key} is rendered as copper's"),
                    );
                    Ior::Named("Cu".into())
                }
                Some((Spec::Blackbody(_), at)) => {
                    return Err(At::new(
                        at,
                        format!("{full}: a blackbody is not an index of refraction"),
                    ))
                }
            })
        };
        let e = get("eta", "Cu")?;
        let k = get("k", "Cu")?;
        let _ = pos;
        Ok((e, k))
    }

    /// coatedconductor → `principled`: metallic, the conductor's normal-incidence
    /// reflectance as base colour, its roughness, and a clear coat for the interface.
    fn coated_conductor(
        &mut self,
        m: &mut Node,
        p: &Params,
        tp: usize,
        pos: usize,
    ) -> Result<(), At> {
        let (eta, k) = self.conductor_ior(p, "conductor.", pos)?;
        let (e, k) = (eta.rgb("eta"), k.rgb("k"));
        let f0: [f64; 3] = std::array::from_fn(|i| {
            ((e[i] - 1.0).powi(2) + k[i] * k[i]) / ((e[i] + 1.0).powi(2) + k[i] * k[i])
        });
        let cr = self.roughness(p, "conductor.", pos)?;
        let ca = self.number_only(cr, pos, 0.1);
        let ir = self.roughness(p, "interface.", pos)?;
        let ia = self.number_only(ir, pos, 0.0);
        let _ = self.eta(p, "interface.eta", pos)?;
        m.put("type", "principled", tp);
        m.set("base_color", rgb_node(f0, tp));
        m.put("metallic", 1.0, tp)
            .put("roughness", ca.sqrt().min(1.0), tp)
            .put("clearcoat", 1.0, tp)
            .put("clearcoat_gloss", ((0.1 - ia) / 0.099).clamp(0.0, 1.0), tp);
        self.warn(
            pos,
            "coatedconductor",
            "coatedconductor is approximated by a metallic principled BSDF with a clear coat (base colour: the conductor's reflectance at normal incidence; the layer's thickness, albedo and the interface's index are not modelled)",
        );
        Ok(())
    }

    /// The emitting twin of material `base` (an area light on a shape).
    pub(super) fn emitting(
        &mut self,
        base: &str,
        radiance: [f64; 3],
        two_sided: bool,
        tp: usize,
    ) -> String {
        let key = format!(
            "{base}+emit({},{},{}{})",
            fmt(radiance[0]),
            fmt(radiance[1]),
            fmt(radiance[2]),
            if two_sided { ",twosided" } else { "" }
        );
        if self.material_node(&key).is_none() {
            let mut node = self
                .material_node(base)
                .cloned()
                .unwrap_or_else(|| default_material(tp));
            node.set("emission", rgb_node(radiance, tp));
            if two_sided {
                node.put("emission_two_sided", true, tp);
            }
            self.add_material(&key, node);
        }
        key
    }

    /// The masked twin of `base` (a shape's `alpha`).
    pub(super) fn masked(&mut self, base: &str, opacity: Node, tp: usize) -> String {
        let id = self.next_id();
        let name = format!("{base}+alpha#{id}");
        let mut node = Node::table(tp);
        node.put("type", "mask", tp);
        node.set("opacity", opacity);
        node.put("bsdf", base, tp);
        self.add_material(&name, node);
        name
    }

    /// pbrt's default material (diffuse, reflectance 0.5), defined on first use.
    pub(super) fn default_material_name(&mut self) -> String {
        let name = "pbrt-default";
        if self.material_node(name).is_none() {
            self.add_material(name, default_material(0));
        }
        name.to_string()
    }
}

fn default_material(tp: usize) -> Node {
    let mut m = Node::table(tp);
    m.put("type", "diffuse", tp).put("reflectance", 0.5, tp);
    m
}

fn fmt(x: f64) -> String {
    format!("{x}")
}

enum Ior {
    Named(String),
    Rgb([f64; 3]),
}

impl Ior {
    fn rgb(&self, which: &str) -> [f64; 3] {
        match self {
            Ior::Named(n) => metal_rgb(n, which),
            Ior::Rgb(c) => *c,
        }
    }
}

impl Builder {
    /// A spectrum file (`.spd`: wavelength and value pairs), when files may be read.
    pub(super) fn spectrum_file(&self, name: &str) -> Option<Vec<(f64, f64)>> {
        if !self.loads_files() {
            return None;
        }
        let text = std::fs::read_to_string(self.resolve(name)).ok()?;
        irradia_scatter::ior::parse_spd(&text)
            .ok()
            .filter(|v| v.len() >= 2)
    }
}
