//! `LightSource` and `AreaLightSource` as Irradia's lights and emitting materials.
//!
//! pbrt-v4 divides a light's spectrum by its luminance before `scale`: an `rgb`
//! value keeps its RGB, a blackbody or named or sampled spectrum becomes its colour at
//! luminance 1 (`spectra`). `power` (point, spot and area lights) and `illuminance`
//! (distant lights, uniform infinite lights) rescale as pbrt-v4 does.

use super::builder::{vec_node, Builder};
use super::params::{Params, Spec};
use super::spectra;
use super::textures::rgb_node;
use super::At;
use glam::{DMat3, DMat4, DVec3};
use irradia_scene::file::tree::Node;

impl Builder {
    /// The colour of light parameter `key` (white when absent) times `scale`.
    fn light_rgb(&mut self, p: &Params, key: &str) -> Result<[f64; 3], At> {
        let c = match p.spec(key)? {
            None => [1.0; 3],
            Some((Spec::Rgb(c), _)) => c,
            Some((Spec::Float(x), _)) => [x; 3],
            Some((Spec::Blackbody(t), at)) => spectra::blackbody_rgb(t).ok_or_else(|| {
                At::new(
                    at,
                    format!("{key}: a blackbody needs a positive temperature"),
                )
            })?,
            Some((Spec::Named(n), at)) => spectra::illuminant_rgb(&n).ok_or_else(|| {
                At::new(
                    at,
                    format!("{key}: unknown named spectrum \"{n}\" for a light"),
                )
            })?,
            Some((Spec::Sampled(v), _)) => {
                spectra::emission_rgb(|w| spectra::sample(&v, w)).unwrap_or([0.0; 3])
            }
            Some((Spec::Texture(_), at)) => {
                return Err(At::new(
                    at,
                    format!("{key}: a light's colour cannot be a texture"),
                ))
            }
        };
        let s = match p.spec("scale")? {
            None => [1.0; 3],
            Some((Spec::Float(x), _)) => [x; 3],
            Some((Spec::Rgb(c), _)) => c,
            Some((_, at)) => return Err(At::new(at, "scale takes a number")),
        };
        let out = [c[0] * s[0], c[1] * s[1], c[2] * s[2]];
        if out.iter().any(|x| !x.is_finite() || *x < 0.0) {
            return Err(At::new(
                p.pos(key, 0),
                format!("{key}: a light's colour must be finite and not negative"),
            ));
        }
        Ok(out)
    }

    pub(super) fn light(&mut self, ty: &str, p: &Params, pos: usize) -> Result<(), At> {
        self.kind_now = Some(("light", ty.to_string()));
        let tp = self.tp(pos);
        let world = self.mirror() * self.gs.ctm;
        let mut l = Node::table(tp);
        match ty {
            "point" => {
                let mut i = self.light_rgb(p, "I")?;
                let from = DVec3::from(p.vec3("from", [0.0; 3])?);
                if let Some(power) = p.float_opt("power")?.filter(|x| *x > 0.0) {
                    i = i.map(|c| c * power / (4.0 * std::f64::consts::PI));
                }
                l.put("type", "point", tp);
                l.set("position", vec_node(world.transform_point3(from), tp));
                l.set("intensity", rgb_node(i, tp));
            }
            "spot" => {
                let mut i = self.light_rgb(p, "I")?;
                let from = DVec3::from(p.vec3("from", [0.0; 3])?);
                let to = DVec3::from(p.vec3("to", [0.0, 0.0, 1.0])?);
                if from == to {
                    return Err(At::new(pos, "spot light: from and to coincide"));
                }
                let cone = p.float("coneangle", 30.0)?;
                let delta = p.float("conedelta", 5.0)?;
                let outer = cone.clamp(1e-3, 90.0);
                let inner = (cone - delta).clamp(1e-3, outer);
                if cone > 90.0 || cone <= 0.0 {
                    self.warn(pos, "cone", format!("spot light: coneangle {cone} is clamped to (0, 90]"));
                }
                if let Some(power) = p.float_opt("power")?.filter(|x| *x > 0.0) {
                    let (co, ci) = (outer.to_radians().cos(), inner.to_radians().cos());
                    let k = 2.0 * std::f64::consts::PI * (1.0 - 0.5 * (ci + co));
                    i = i.map(|c| c * power / k);
                }
                l.put("type", "spot", tp);
                l.set("position", vec_node(world.transform_point3(from), tp));
                l.set("look_at", vec_node(world.transform_point3(to), tp));
                l.set("intensity", rgb_node(i, tp));
                l.put("outer_angle", outer, tp).put("inner_angle", inner, tp);
            }
            "distant" => {
                let mut e = self.light_rgb(p, "L")?;
                // pbrt-v4: `illuminance` E_v scales L (already of luminance 1) to it.
                if let Some(ev) = p.float_opt("illuminance")?.filter(|x| *x > 0.0) {
                    e = e.map(|c| c * ev);
                }
                let from = DVec3::from(p.vec3("from", [0.0; 3])?);
                let to = DVec3::from(p.vec3("to", [0.0, 0.0, 1.0])?);
                let dir = world.transform_vector3(to - from);
                if dir.length_squared() == 0.0 {
                    return Err(At::new(pos, "distant light: from and to coincide"));
                }
                l.put("type", "directional", tp);
                l.set("direction", vec_node(dir.normalize(), tp));
                l.set("irradiance", rgb_node(e, tp));
            }
            "infinite" => {
                let file = p.string("filename")?;
                if let Some(portal) = p.get("portal") {
                    let at = portal.pos;
                    self.warn(at, "portal", "infinite light: portals are not used (the map is sampled whole)");
                }
                match file {
                    None => {
                        let mut c = self.light_rgb(p, "L")?;
                        // pbrt-v4: `illuminance` is what the upper hemisphere gives a
                        // surface facing it, π L for a uniform L.
                        if let Some(ev) = p.float_opt("illuminance")?.filter(|x| *x > 0.0) {
                            c = c.map(|x| x * ev / std::f64::consts::PI);
                        }
                        l.put("type", "constant", tp);
                        l.set("radiance", rgb_node(c, tp));
                    }
                    Some(f) => {
                        let s = self.light_rgb(p, "__none")?;
                        self.envmap(&mut l, &f, s, world, pos, tp)?;
                    }
                }
            }
            "goniometric" | "projection" => {
                for param in &p.list {
                    let _ = p.get(&param.name);
                }
                self.warn(pos, &format!("light:{ty}"), format!("light \"{ty}\" is not available (left out)"));
                return Ok(());
            }
            _ => return Err(At::new(pos, format!("unknown light \"{ty}\" (valid: point, spot, distant, infinite, goniometric, projection)"))),
        }
        self.finish_params(p, &format!("LightSource \"{ty}\""), &["illuminance"])?;
        self.lights.push(l);
        Ok(())
    }

    /// An image-based infinite light: pbrt-v4's equal-area octahedral square map
    /// becomes an `envmap` with `mapping = "equal_area"` (resampled by the scene
    /// reader), a 2:1 map (pbrt-v3's latitude-longitude, +z up) a plain `envmap`; each
    /// turned into place by `to_world` (the mirror, the CTM's rotation and the map's
    /// frame). Without the file system the map is taken to be pbrt-v4's square.
    fn envmap(
        &mut self,
        l: &mut Node,
        file: &str,
        scale: [f64; 3],
        world: DMat4,
        pos: usize,
        tp: usize,
    ) -> Result<(), At> {
        let path = self.resolve(file);
        let dims = if self.loads_files() {
            match image::image_dimensions(&path) {
                Ok(d) => Some(d),
                Err(e) => {
                    return Err(At::new(
                        pos,
                        format!("infinite light: cannot read \"{file}\": {e}"),
                    ))
                }
            }
        } else {
            None
        };
        let latlong = matches!(dims, Some((w, h)) if w == 2 * h);
        if let Some((w, h)) = dims {
            if !latlong && w != h {
                return Err(At::new(
                    pos,
                    format!("infinite light \"{file}\": the image must be square (pbrt-v4's equal-area map) or 2:1 (latitude-longitude), not {w}x{h}"),
                ));
            }
        }
        // The pbrt light frame from the envmap's frame (y up in both of Irradia's).
        let frame = if latlong {
            // pbrt-v3: u = phi / 2pi from +x towards +y, v = theta / pi from +z.
            DMat3::from_cols(DVec3::Y, DVec3::Z, -DVec3::X)
        } else {
            // The scene reader reads the square at (x, -z, y).
            DMat3::from_cols(DVec3::X, DVec3::Z, -DVec3::Y)
        };
        let lin = DMat3::from_mat4(world);
        let r = lin * frame;
        let rot = DMat3::from_cols(
            r.x_axis.normalize_or_zero(),
            r.y_axis.normalize_or_zero(),
            r.z_axis.normalize_or_zero(),
        );
        let orthonormal = (rot.transpose() * rot - DMat3::IDENTITY)
            .to_cols_array()
            .iter()
            .all(|x| x.abs() < 1e-6);
        if !orthonormal {
            return Err(At::new(
                pos,
                "infinite light: the transformation is not a rotation (with a uniform scale)",
            ));
        }
        l.put("type", "envmap", tp).put("filename", file, tp);
        if !latlong {
            l.put("mapping", "equal_area", tp);
        }
        let s = (scale[0] + scale[1] + scale[2]) / 3.0;
        if scale.iter().any(|c| (c - s).abs() > 1e-12) {
            self.warn(
                pos,
                "envmap-tint",
                "infinite light: a coloured scale on an image is applied as its mean",
            );
        }
        if s != 1.0 {
            l.put("scale", s, tp);
        }
        let rows: Vec<Node> = (0..3)
            .map(|i| {
                let row = rot.row(i);
                let z = |x: f64| if x.abs() < 1e-14 { 0.0 } else { x };
                Node::new([z(row.x), z(row.y), z(row.z), 0.0], tp)
            })
            .collect();
        let mut step = Node::table(tp);
        step.set("matrix", Node::new(rows, tp));
        l.set("to_world", Node::new(vec![step], tp));
        Ok(())
    }

    pub(super) fn area_light(&mut self, ty: &str, p: &Params, pos: usize) -> Result<(), At> {
        self.kind_now = Some(("arealight", ty.to_string()));
        if ty != "diffuse" {
            return Err(At::new(
                pos,
                format!("unknown area light \"{ty}\" (valid: diffuse)"),
            ));
        }
        let radiance = self.light_rgb(p, "L")?;
        let two_sided = p.bool("twosided", false)?;
        if p.has("filename") {
            let _ = p.string("filename")?;
            self.warn(
                pos,
                "area-image",
                "area light: an image of emission is not rendered (L is used)",
            );
        }
        let power = p.float_opt("power")?.filter(|x| *x > 0.0);
        self.finish_params(p, "AreaLightSource \"diffuse\"", &[])?;
        self.gs.area = Some(super::builder::AreaLight {
            radiance,
            two_sided,
            power,
            pos,
        });
        Ok(())
    }
}
