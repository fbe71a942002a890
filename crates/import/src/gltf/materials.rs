//! glTF's metallic-roughness materials as Mitsuba's `principled` BSDF:
//!
//! | glTF | Irradia |
//! |---|---|
//! | `baseColorFactor` (rgb) or `baseColorTexture` | `base_color` (a colour, or a `bitmap`; with `COLOR_0` and no texture, the `mesh_attribute` `vertex_color`) |
//! | `metallicFactor` or `metallicRoughnessTexture` | `metallic` (the texture's B channel: `bitmap` with `channel = "b"`, `raw = true`) |
//! | `roughnessFactor` or `metallicRoughnessTexture` | `roughness` (its G channel) |
//! | `normalTexture` | `normalmap` around the BSDF (`raw = true`) |
//! | `emissiveFactor`, `emissiveTexture`, `KHR_materials_emissive_strength` | `emission` (a colour, or a `bitmap` scaled by factor × strength) |
//! | `KHR_materials_transmission` `transmissionFactor`, `KHR_materials_ior` `ior` | `spec_trans`, `eta` |
//! | `KHR_texture_transform` | the bitmap's `to_uv` (`offset · rotation · scale`) |
//! | `alphaMode = "MASK"` or `"BLEND"` | `mask`, `opacity` = the base colour's alpha (the texture's A channel, or the factor's) |
//! | `doubleSided = true` | `twosided` around the BSDF |
//!
//! A factor beside its texture multiplies it (the bitmap's `scale`, glTF's product).
//! `occlusionTexture` (the path tracer computes occlusion), `transmissionTexture`,
//! texture coordinate sets other than 0 and MASK's `alphaCutoff` (the opacity is
//! fractional) are warnings. Samplers' wrap modes and nearest filtering are kept. A
//! primitive without a material gets glTF's default (white, metallic 1, roughness 1).

use crate::model::{color, num, rel_name};
use irradia_geometry::io::gltf::GltfFile;
use irradia_scene::file::tree::Node;
use irradia_scene::SceneError;
use std::collections::HashMap;
use std::path::{Path, PathBuf};

/// The materials a scene uses, made on first use.
pub struct Materials<'a> {
    file: &'a GltfFile,
    /// The glTF file's name as the tree writes it.
    name: String,
    dir: PathBuf,
    /// (glTF material index or `None` for the default, with vertex colours) → key.
    keys: HashMap<(Option<usize>, bool), String>,
    table: Node,
    /// Whether any material emits.
    pub emissive: bool,
}

impl<'a> Materials<'a> {
    pub fn new(file: &'a GltfFile, name: &str, dir: &Path) -> Self {
        Materials {
            file,
            name: name.to_string(),
            dir: dir.to_path_buf(),
            keys: HashMap::new(),
            table: Node::table(0),
            emissive: false,
        }
    }

    /// The key of `m`'s material (with vertex colours when `colored`), made when new.
    pub fn material(
        &mut self,
        m: &gltf::Material,
        colored: bool,
        warnings: &mut Vec<SceneError>,
        origin: &Path,
    ) -> String {
        let id = (m.index(), colored);
        if let Some(k) = self.keys.get(&id) {
            return k.clone();
        }
        let base = match (m.index(), m.name()) {
            (None, _) => "gltf_default".to_string(),
            (Some(_), Some(n)) if !n.is_empty() => n.to_string(),
            (Some(i), _) => format!("material_{i}"),
        };
        let base = if colored {
            format!("{base}_vertex_color")
        } else {
            base
        };
        let mut key = base.clone();
        let mut k = 2;
        while self.keys.values().any(|v| v == &key) {
            key = format!("{base}_{k}");
            k += 1;
        }
        let node = self.build(m, colored, warnings, origin);
        self.table.set(&key, node);
        self.keys.insert(id, key.clone());
        key
    }

    /// Adds `[materials]` to `tree` when any was made.
    pub fn write(self, tree: &mut Node) {
        if !self.keys.is_empty() {
            tree.set("materials", self.table);
        }
    }

    fn build(
        &mut self,
        m: &gltf::Material,
        colored: bool,
        warnings: &mut Vec<SceneError>,
        origin: &Path,
    ) -> Node {
        let label = match m.index() {
            Some(i) => format!("material {i}"),
            None => "default material".into(),
        };
        let mut warn = |msg: String| {
            warnings.push(SceneError::input(label.as_str(), msg).with_file(origin));
        };
        let pbr = m.pbr_metallic_roughness();
        let factor = pbr.base_color_factor();
        let mut bsdf = Node::table(0);
        bsdf.put("type", "principled", 0);
        let base_tex = pbr.base_color_texture();
        match &base_tex {
            Some(t) => {
                let mut tex = self.bitmap(t, false, None, &mut warn);
                scale(&mut tex, [factor[0], factor[1], factor[2]]);
                bsdf.set("base_color", tex);
            }
            None if colored => {
                let mut attr = Node::table(0);
                attr.put("type", "mesh_attribute", 0)
                    .put("name", "vertex_color", 0);
                if factor[..3] != [1.0, 1.0, 1.0] {
                    warn("baseColorFactor times COLOR_0: the vertex colours alone are used".into());
                }
                bsdf.set("base_color", attr);
            }
            None => {
                bsdf.set("base_color", color([factor[0], factor[1], factor[2]]));
            }
        }
        match pbr.metallic_roughness_texture() {
            Some(t) => {
                let mut metallic = self.bitmap(&t, true, Some("b"), &mut warn);
                scale(&mut metallic, [pbr.metallic_factor(); 3]);
                bsdf.set("metallic", metallic);
                let mut roughness = self.bitmap(&t, true, Some("g"), &mut warn);
                scale(&mut roughness, [pbr.roughness_factor(); 3]);
                bsdf.set("roughness", roughness);
            }
            None => {
                bsdf.put("metallic", num(pbr.metallic_factor()), 0).put(
                    "roughness",
                    num(pbr.roughness_factor()),
                    0,
                );
            }
        }
        if let Some(n) = m.normal_texture() {
            if n.scale() != 1.0 {
                warn("normalTexture scale is not read (1 is used)".into());
            }
            let tex = self.image(&n.texture(), n.tex_coord(), true, None, &mut warn);
            let mut nm = Node::table(0);
            nm.put("type", "normalmap", 0)
                .set("normalmap", tex)
                .set("bsdf", bsdf);
            bsdf = nm;
        }
        if m.occlusion_texture().is_some() {
            warn("occlusionTexture is not rendered (the path tracer computes occlusion)".into());
        }
        use gltf::material::AlphaMode;
        match m.alpha_mode() {
            AlphaMode::Opaque => {}
            mode => {
                if mode == AlphaMode::Mask {
                    warn(format!(
                        "alphaMode MASK: alphaCutoff {} is not applied; the alpha is a fractional opacity",
                        m.alpha_cutoff().unwrap_or(0.5)
                    ));
                } else {
                    warn("alphaMode BLEND is rendered as a mask of the alpha (no sorting)".into());
                }
                let opacity = match &base_tex {
                    Some(t) => {
                        let mut a = self.bitmap(t, true, Some("a"), &mut warn);
                        scale(&mut a, [factor[3]; 3]);
                        a
                    }
                    None => Node::new(num(factor[3]), 0),
                };
                let mut mask = Node::table(0);
                mask.put("type", "mask", 0)
                    .set("opacity", opacity)
                    .set("bsdf", bsdf);
                bsdf = mask;
            }
        }
        if let Some(tr) = m.transmission() {
            if tr.transmission_texture().is_some() {
                warn("transmissionTexture is not read: transmissionFactor is used".into());
            }
            if tr.transmission_factor() > 0.0 {
                put_inner(
                    &mut bsdf,
                    "spec_trans",
                    Node::new(num(tr.transmission_factor()), 0),
                );
            }
        }
        if let Some(ior) = m.ior() {
            if ior != 1.5 {
                put_inner(&mut bsdf, "eta", Node::new(num(ior), 0));
            }
        }
        if m.double_sided() {
            let mut two = Node::table(0);
            two.put("type", "twosided", 0).set("bsdf", bsdf);
            bsdf = two;
        }
        let strength = m.emissive_strength().unwrap_or(1.0);
        let e = m.emissive_factor().map(|c| c * strength);
        if e.iter().any(|&x| x > 0.0) {
            match m.emissive_texture() {
                Some(t) => {
                    let mut tex = self.bitmap(&t, false, None, &mut warn);
                    scale(&mut tex, e);
                    bsdf.set("emission", tex);
                }
                None => {
                    bsdf.set("emission", color(e));
                }
            }
            self.emissive = true;
        }
        bsdf
    }

    /// A `bitmap` of the texture `info` refers to, its `KHR_texture_transform` as
    /// `to_uv`: glTF's `uv' = T(offset) · R(rotation) · S(scale) · uv` with
    /// `R = [[cos, −sin], [sin, cos]]` (the extension's GLSL, whose `mat3` is given
    /// column by column), written as one `{ matrix = [[a, b, tu], [c, d, tv]] }` step.
    fn bitmap(
        &self,
        info: &gltf::texture::Info,
        raw: bool,
        channel: Option<&str>,
        warn: &mut dyn FnMut(String),
    ) -> Node {
        let tr = info.texture_transform();
        let tex_coord = tr
            .as_ref()
            .and_then(|t| t.tex_coord())
            .unwrap_or(info.tex_coord());
        let mut b = self.image(&info.texture(), tex_coord, raw, channel, warn);
        if let Some(t) = tr {
            let ([ox, oy], r, [sx, sy]) = (t.offset(), t.rotation(), t.scale());
            if [ox, oy, r, sx - 1.0, sy - 1.0] != [0.0; 5] {
                let (c, s) = (f64::from(r).cos(), f64::from(r).sin());
                let (sx, sy) = (f64::from(sx), f64::from(sy));
                let row = |a: f64, b: f64, t: f32| Node::new([a, b, num(t)], 0);
                let mut step = Node::table(0);
                step.set(
                    "matrix",
                    Node::new(vec![row(c * sx, -s * sy, ox), row(s * sx, c * sy, oy)], 0),
                );
                b.set("to_uv", Node::new(vec![step], 0));
            }
        }
        b
    }

    /// A `bitmap` texture of glTF texture `t` (an external image by its own name, an
    /// embedded one as `filename` = the glTF file with `image = N`).
    fn image(
        &self,
        t: &gltf::Texture,
        tex_coord: u32,
        raw: bool,
        channel: Option<&str>,
        warn: &mut dyn FnMut(String),
    ) -> Node {
        if tex_coord != 0 {
            warn(format!(
                "texture {} uses TEXCOORD_{tex_coord}: TEXCOORD_0 is used",
                t.index()
            ));
        }
        let image = t.source().index();
        let mut b = Node::table(0);
        b.put("type", "bitmap", 0);
        match self.file.image_uri(image) {
            Some(uri) => {
                b.put("filename", rel_name(&self.dir.join(uri), &self.dir), 0);
            }
            None => {
                b.put("filename", self.name.as_str(), 0)
                    .put("image", image as i64, 0);
            }
        }
        if let Some(c) = channel {
            b.put("channel", c, 0);
        }
        if raw {
            b.put("raw", true, 0);
        }
        let s = t.sampler();
        use gltf::texture::{MagFilter, WrappingMode};
        if s.mag_filter() == Some(MagFilter::Nearest) {
            b.put("filter_type", "nearest", 0);
        }
        let wrap = |w: WrappingMode| match w {
            WrappingMode::ClampToEdge => "clamp",
            WrappingMode::MirroredRepeat => "mirror",
            WrappingMode::Repeat => "repeat",
        };
        let (ws, wt) = (wrap(s.wrap_s()), wrap(s.wrap_t()));
        if ws != wt {
            warn(format!(
                "texture {}: wrap modes differ in s and t ({ws}, {wt}): {ws} is used for both",
                t.index()
            ));
        }
        if ws != "repeat" {
            b.put("wrap_mode", ws, 0);
        }
        b
    }
}

/// Multiplies a bitmap by glTF's factor `k` (its `scale`; nothing when 1).
fn scale(bitmap: &mut Node, k: [f32; 3]) {
    if k != [1.0; 3] {
        bitmap.set("scale", color(k));
    }
}

/// Sets `key` on the `principled` BSDF inside the wrappers (`normalmap`, `mask`).
fn put_inner(bsdf: &mut Node, key: &str, value: Node) {
    let is_principled = matches!(
        bsdf.get("type").map(|t| &t.value),
        Some(irradia_scene::file::tree::Value::Str(s)) if s == "principled"
    );
    if is_principled {
        bsdf.set(key, value);
    } else if let Some(inner) = bsdf.get_mut("bsdf") {
        put_inner(inner, key, value);
    }
}
