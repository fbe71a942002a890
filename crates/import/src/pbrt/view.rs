//! `Camera`, `Film`, `Sampler`, `Integrator` and `PixelFilter`: Irradia's `[camera]`,
//! `[image]` and `[render]`.

use super::builder::{mirror_for, vec_node, Builder};
use super::params::Params;
use super::At;
use glam::{DMat4, DVec3};
use irradia_scene::file::tree::Node;

#[derive(Clone, Debug)]
pub struct View {
    /// pbrt's camera-from-world matrix and the camera's type and parameters.
    camera: Option<CameraDesc>,
    width: i64,
    height: i64,
    crop: Option<[f64; 4]>,
    spp: i64,
    max_depth: i64,
    filter: Option<Node>,
    pos: usize,
}

#[derive(Clone, Debug)]
struct CameraDesc {
    ctm: DMat4,
    orthographic: bool,
    fov: f64,
    lens_radius: f64,
    focal_distance: f64,
    screen: Option<[f64; 4]>,
    pos: usize,
}

impl Default for View {
    fn default() -> Self {
        View {
            camera: None,
            width: 1280,
            height: 720,
            crop: None,
            spp: 16,
            max_depth: 5,
            filter: None,
            pos: 0,
        }
    }
}

impl Builder {
    pub(super) fn camera(
        &mut self,
        ty: &str,
        p: &Params,
        ctm: DMat4,
        pos: usize,
    ) -> Result<(), At> {
        self.kind_now = Some(("camera", ty.to_string()));
        if !super::transform::is_invertible(&ctm) {
            return Err(At::new(
                pos,
                "Camera: the camera transformation is not invertible",
            ));
        }
        let mut orthographic = false;
        match ty {
            "perspective" => {}
            "orthographic" => orthographic = true,
            "realistic" | "spherical" => {
                self.warn(
                    pos,
                    &format!("camera:{ty}"),
                    format!("Camera \"{ty}\" is rendered as a perspective camera with pbrt's default field of view (90°)"),
                );
            }
            _ => {
                return Err(At::new(
                    pos,
                    format!("unknown camera \"{ty}\" (valid: perspective, orthographic, realistic, spherical)"),
                ))
            }
        }
        let fov = if ty == "perspective" {
            let f = p.float("fov", 90.0)?;
            if !(f > 0.0 && f < 180.0) {
                return Err(At::new(
                    p.pos("fov", pos),
                    format!("Camera: fov must be in (0, 180) degrees (got {f})"),
                ));
            }
            f
        } else {
            90.0
        };
        let (lens_radius, focal_distance) = if ty == "perspective" || orthographic {
            (p.float("lensradius", 0.0)?, p.float("focaldistance", 1e6)?)
        } else {
            (0.0, 1e6)
        };
        if lens_radius < 0.0 || focal_distance <= 0.0 {
            return Err(At::new(
                pos,
                "Camera: lensradius must not be negative and focaldistance must be positive",
            ));
        }
        if orthographic && lens_radius > 0.0 {
            self.warn(
                p.pos("lensradius", pos),
                "ortho-lens",
                "Camera \"orthographic\": depth of field (lensradius) is not rendered for orthographic cameras",
            );
        }
        let screen = match p.floats("screenwindow")? {
            Some(v) if v.len() == 4 => Some([v[0], v[1], v[2], v[3]]),
            Some(_) => {
                return Err(At::new(
                    p.pos("screenwindow", pos),
                    "Camera: screenwindow takes 4 numbers",
                ))
            }
            None => None,
        };
        if let Some(s) = screen {
            if (s[0] + s[1]).abs() > 1e-9 || (s[2] + s[3]).abs() > 1e-9 || !orthographic {
                self.warn(
                    p.pos("screenwindow", pos),
                    "screenwindow",
                    "Camera: an off-centre or perspective screenwindow is not rendered (the centred window of the image's aspect is used)",
                );
            }
        }
        if p.has("frameaspectratio") {
            let _ = p.float("frameaspectratio", 0.0)?;
            self.warn(
                p.pos("frameaspectratio", pos),
                "frameaspectratio",
                "Camera: frameaspectratio is not rendered (the image's own aspect ratio is used)",
            );
        }
        let _ = p.float("shutteropen", 0.0)?;
        let _ = p.float("shutterclose", 1.0)?;
        self.finish_params(
            p,
            &format!("Camera \"{ty}\""),
            &[
                "lensfile",
                "aperturediameter",
                "focusdistance",
                "aperture",
                "mapping",
            ],
        )?;
        self.mirror = Some(mirror_for(&ctm));
        self.view.camera = Some(CameraDesc {
            ctm,
            orthographic,
            fov,
            lens_radius,
            focal_distance,
            screen,
            pos: self.tp(pos),
        });
        Ok(())
    }

    pub(super) fn film(&mut self, ty: &str, p: &Params, pos: usize) -> Result<(), At> {
        self.kind_now = Some(("film", ty.to_string()));
        if !["rgb", "gbuffer", "spectral", "image"].contains(&ty) {
            return Err(At::new(
                pos,
                format!("unknown film \"{ty}\" (valid: rgb, gbuffer, spectral)"),
            ));
        }
        let w = p.int("xresolution", 1280)?;
        let h = p.int("yresolution", 720)?;
        if w < 1 || h < 1 || w > 1 << 20 || h > 1 << 20 {
            return Err(At::new(
                pos,
                format!("Film: the resolution must be between 1 and 2^20 (got {w}x{h})"),
            ));
        }
        self.view.width = w;
        self.view.height = h;
        self.view.pos = self.tp(pos);
        if let Some(f) = p.string("filename")? {
            self.note(format!(
                "Film filename \"{f}\" is ignored: irradia render writes where -o says"
            ));
        }
        if let Some(c) = p.floats("cropwindow")? {
            if c.len() != 4 || c[0] >= c[1] || c[2] >= c[3] {
                return Err(At::new(
                    p.pos("cropwindow", pos),
                    "Film: cropwindow takes x0 x1 y0 y1 with x0 < x1 and y0 < y1",
                ));
            }
            self.view.crop = Some([c[0], c[1], c[2], c[3]]);
        }
        let _ = p.float("diagonal", 35.0)?;
        let _ = p.bool("savefp16", true)?;
        self.finish_params(
            p,
            &format!("Film \"{ty}\""),
            &[
                "iso",
                "exposuretime",
                "whitebalance",
                "sensor",
                "maxcomponentvalue",
                "pixelbounds",
                "coordinatesystem",
                "writefp16",
                "nbuckets",
                "lambdamin",
                "lambdamax",
            ],
        )
    }

    pub(super) fn sampler(&mut self, ty: &str, p: &Params, pos: usize) -> Result<(), At> {
        self.kind_now = Some(("sampler", ty.to_string()));
        const KNOWN: &[&str] = &[
            "halton",
            "independent",
            "paddedsobol",
            "pmj02bn",
            "sobol",
            "zsobol",
            "stratified",
            "02sequence",
            "lowdiscrepancy",
            "maxmindist",
            "random",
        ];
        if !KNOWN.contains(&ty) {
            return Err(At::new(pos, format!("unknown sampler \"{ty}\"")));
        }
        let spp = if ty == "stratified" {
            p.int("xsamples", 4)? * p.int("ysamples", 4)?
        } else {
            p.int("pixelsamples", 16)?
        };
        if !(1..=1 << 24).contains(&spp) {
            return Err(At::new(pos, format!("Sampler: {spp} samples per pixel")));
        }
        self.view.spp = spp;
        let _ = p.bool("jitter", true)?;
        let _ = p.int("seed", 0)?;
        let _ = p.string("randomization")?;
        let _ = p.int("dimensions", 4)?;
        self.note(format!(
            "Sampler \"{ty}\": Irradia draws its own stratified samples ({spp} per pixel)"
        ));
        self.finish_params(p, &format!("Sampler \"{ty}\""), &[])
    }

    pub(super) fn integrator(&mut self, ty: &str, p: &Params, pos: usize) -> Result<(), At> {
        self.kind_now = Some(("integrator", ty.to_string()));
        match ty {
            "path" | "volpath" => {}
            "bdpt" | "mlt" | "sppm" | "lightpath" | "simplepath" | "simplevolpath"
            | "randomwalk" | "directlighting" | "whitted" => {
                self.note(format!(
                    "Integrator \"{ty}\" is rendered by Irradia's path tracer (the same image, other noise)"
                ));
            }
            "ambientocclusion" | "aov" => {
                self.warn(
                    pos,
                    &format!("integrator:{ty}"),
                    format!(
                        "Integrator \"{ty}\" is not available: the path tracer renders the scene"
                    ),
                );
            }
            _ => return Err(At::new(pos, format!("unknown integrator \"{ty}\""))),
        }
        let depth = p.int("maxdepth", 5)?;
        if !(0..=1 << 16).contains(&depth) {
            return Err(At::new(
                p.pos("maxdepth", pos),
                format!("Integrator: maxdepth must be between 0 and 65536 (got {depth})"),
            ));
        }
        self.view.max_depth = depth;
        self.finish_params(
            p,
            &format!("Integrator \"{ty}\""),
            &[
                "regularize",
                "lightsampler",
                "samplelights",
                "samplebsdf",
                "mutationsperpixel",
                "largestepprobability",
                "sigma",
                "bootstrapsamples",
                "chains",
                "iterations",
                "photonsperiteration",
                "radius",
                "seed",
                "maxdistance",
                "cossample",
                "visualizestrategies",
                "visualizeweights",
            ],
        )
    }

    pub(super) fn pixel_filter(&mut self, ty: &str, p: &Params, pos: usize) -> Result<(), At> {
        self.kind_now = Some(("filter", ty.to_string()));
        let tp = self.tp(pos);
        let radius = |d: f64| -> Result<f64, At> {
            let x = p.float("xradius", d)?;
            let y = p.float("yradius", d)?;
            Ok(x.max(y))
        };
        let mut f = Node::table(tp);
        match ty {
            "gaussian" => {
                let r = radius(1.5)?;
                let sigma = p.float("sigma", 0.5)?;
                if !(sigma > 0.0 && sigma <= 4.0) || r <= 0.0 {
                    return Err(At::new(pos, "PixelFilter: sigma must be in (0, 4]"));
                }
                f.put("type", "gaussian", tp).put("stddev", sigma, tp);
            }
            "box" => {
                let r = radius(0.5)?;
                if !(r > 0.0 && r <= 16.0) {
                    return Err(At::new(pos, "PixelFilter: the radius must be in (0, 16]"));
                }
                f.put("type", "box", tp).put("radius", r, tp);
            }
            "triangle" => {
                let r = radius(2.0)?;
                if !(r > 0.0 && r <= 16.0) {
                    return Err(At::new(pos, "PixelFilter: the radius must be in (0, 16]"));
                }
                f.put("type", "tent", tp).put("radius", r, tp);
            }
            "mitchell" | "sinc" | "lanczos" => {
                let _ = radius(2.0)?;
                self.warn(
                    pos,
                    &format!("filter:{ty}"),
                    format!("PixelFilter \"{ty}\" is rendered with a Gaussian of σ = 0.5"),
                );
                f.put("type", "gaussian", tp).put("stddev", 0.5, tp);
            }
            _ => return Err(At::new(pos, format!("unknown pixel filter \"{ty}\""))),
        }
        self.finish_params(p, &format!("PixelFilter \"{ty}\""), &["B", "C", "tau"])?;
        self.view.filter = Some(f);
        Ok(())
    }

    /// `[camera]`, `[image]`, `[render]`.
    pub(super) fn view_nodes(&mut self) -> (Node, Node, Node) {
        let mirror = self.mirror();
        let v = self.view.clone();
        let cam = v.camera.clone().unwrap_or(CameraDesc {
            ctm: DMat4::IDENTITY,
            orthographic: false,
            fov: 90.0,
            lens_radius: 0.0,
            focal_distance: 1e6,
            screen: None,
            pos: 0,
        });
        let tp = self.tp_main(cam.pos);
        let world_from_camera = cam.ctm.inverse();
        let eye = world_from_camera.transform_point3(DVec3::ZERO);
        let fwd = world_from_camera
            .transform_vector3(DVec3::Z)
            .normalize_or_zero();
        let up = world_from_camera.transform_vector3(DVec3::Y);
        let mut c = Node::table(tp);
        let eye_i = mirror.transform_point3(eye);
        let look_i = mirror.transform_point3(eye + fwd);
        let up_i = mirror.transform_vector3(up);
        let aspect = v.width as f64 / v.height as f64;
        if cam.orthographic {
            c.put("type", "orthographic", tp);
        } else if cam.lens_radius > 0.0 {
            c.put("type", "thinlens", tp);
        } else {
            c.put("type", "perspective", tp);
        }
        c.set("eye", vec_node(eye_i, tp));
        c.set("look_at", vec_node(look_i, tp));
        c.set("up", vec_node(up_i, tp));
        if cam.orthographic {
            // pbrt's default screen window spans 2 units across the shorter side.
            let height = match cam.screen {
                Some(s) => (s[3] - s[2]).abs(),
                None if aspect >= 1.0 => 2.0,
                None => 2.0 / aspect,
            };
            let scale = up.length();
            c.put("height", height * if scale > 0.0 { scale } else { 1.0 }, tp);
        } else {
            c.put("fov", cam.fov, tp).put("fov_axis", "smaller", tp);
            if cam.lens_radius > 0.0 {
                c.put("aperture_radius", cam.lens_radius, tp).put(
                    "focus_distance",
                    cam.focal_distance,
                    tp,
                );
            }
        }
        let ip = self.tp_main(v.pos);
        let mut image = Node::table(ip);
        image.put("width", v.width, ip).put("height", v.height, ip);
        let filter = v.filter.clone().unwrap_or_else(|| {
            let mut f = Node::table(ip);
            f.put("type", "gaussian", ip).put("stddev", 0.5, ip);
            f
        });
        image.set("filter", filter);
        if let Some(cw) = v.crop {
            // pbrt-v4: pixel bounds (ceil(res · x0), ceil(res · x1)) and likewise in y.
            let (w, h) = (v.width as f64, v.height as f64);
            let x0 = (w * cw[0].clamp(0.0, 1.0)).ceil() as i64;
            let x1 = (w * cw[1].clamp(0.0, 1.0)).ceil() as i64;
            let y0 = (h * cw[2].clamp(0.0, 1.0)).ceil() as i64;
            let y1 = (h * cw[3].clamp(0.0, 1.0)).ceil() as i64;
            if x1 > x0 && y1 > y0 {
                image
                    .put("crop_offset_x", x0, ip)
                    .put("crop_offset_y", y0, ip)
                    .put("crop_width", x1 - x0, ip)
                    .put("crop_height", y1 - y0, ip);
            }
        }
        let mut render = Node::table(0);
        render
            .put("integrator", "path", 0)
            .put("spp", v.spp, 0)
            .put("max_depth", v.max_depth + 1, 0);
        (c, image, render)
    }

    /// Positions stored from directives are already main-file positions.
    fn tp_main(&self, pos: usize) -> usize {
        pos
    }
}
