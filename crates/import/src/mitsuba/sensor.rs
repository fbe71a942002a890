//! `<sensor>` (with its `<film>`, `<rfilter>` and `<sampler>`) into `[camera]` and
//! `[image]`, and `<integrator>` into `[render]`.

use super::props::Obj;
use super::xml::Elem;
use super::Builder;
use glam::DVec3;
use irradia_scene::file::tree::Node;
use irradia_scene::SceneError;

fn v3(v: DVec3, pos: usize) -> Node {
    Node::new([v.x, v.y, v.z], pos)
}

/// Mitsuba's `parse_fov`: `fov` with `fov_axis`, or the diagonal field of view of a
/// 35 mm film behind a lens of `focal_length` (default `50mm`).
fn fov(b: &mut Builder, o: &Obj, cam: &mut Node) -> Result<(), SceneError> {
    let pos = o.elem.main_pos;
    match (o.get("fov"), o.get("focal_length")) {
        (Some(f), Some(_)) => {
            return Err(f.err("give either fov or focal_length, not both"));
        }
        (Some(f), None) => {
            cam.put("fov", f.f64()?, f.elem.main_pos);
            if let Some(a) = o.get("fov_axis") {
                let axis = a.str()?.to_ascii_lowercase();
                if !["x", "y", "diagonal", "smaller", "larger"].contains(&axis.as_str()) {
                    return Err(a.err(format!(
                        "unknown fov_axis `{axis}` (valid: x, y, diagonal, smaller, larger)"
                    )));
                }
                cam.put("fov_axis", axis, a.elem.main_pos);
            } else {
                cam.put("fov_axis", "x", pos);
            }
        }
        (None, f) => {
            let text = match f {
                Some(p) => p.str()?.to_string(),
                None => "50mm".to_string(),
            };
            let mm: f64 = text
                .trim()
                .trim_end_matches("mm")
                .parse()
                .ok()
                .filter(|x: &f64| *x > 0.0 && x.is_finite())
                .ok_or_else(|| {
                    o.err(
                        "focal_length",
                        format!("focal_length `{text}` is not of the form <x>mm"),
                    )
                })?;
            let diag = (36.0f64 * 36.0 + 24.0 * 24.0).sqrt();
            let deg = 2.0 * (diag / (2.0 * mm)).atan().to_degrees();
            cam.put("fov", deg, pos);
            cam.put("fov_axis", "diagonal", pos);
            let _ = b;
        }
    }
    Ok(())
}

pub fn sensor<'e>(b: &mut Builder<'e>, e: &'e Elem) -> Result<(), SceneError> {
    let o = Obj::read(e)?;
    let pos = e.main_pos;
    let kind = o.plugin.as_str();
    if !["perspective", "thinlens", "orthographic"].contains(&kind) {
        if ["radiancemeter", "irradiancemeter", "distant", "batch"].contains(&kind) {
            b.warn(
                e,
                "type",
                format!(
                    "the `{kind}` sensor is not rendered: a default perspective camera is used"
                ),
            );
            default_sensor(b);
            return Ok(());
        }
        return Err(e.err_at(
            "type",
            "type",
            format!("unknown sensor `{kind}` (valid: perspective, thinlens, orthographic, radiancemeter, irradiancemeter, distant, batch)"),
        ));
    }
    // The film first: the orthographic view's height depends on the aspect ratio.
    let (mut width, mut height) = (768i64, 576i64);
    let mut film_seen = false;
    let mut sampler_seen = false;
    for c in &o.nested {
        match c.tag.as_str() {
            "film" if !film_seen => {
                film_seen = true;
                (width, height) = film(b, c)?;
            }
            "sampler" if !sampler_seen => {
                sampler_seen = true;
                sampler(b, c)?;
            }
            "film" | "sampler" => {
                return Err(c.err(&c.tag, format!("a sensor has one <{}>", c.tag)));
            }
            t => return Err(c.err(t, format!("<{t}> does not belong in a <sensor>"))),
        }
    }
    if !film_seen {
        b.image.put("width", width, pos).put("height", height, pos);
        b.image.set("filter", gaussian(pos));
    }
    let xf = match o.get("to_world") {
        Some(p) => p.transform()?.clone(),
        None => super::transform::Xform::identity(),
    };
    let eye = xf.point(DVec3::ZERO);
    let dir = xf.vector(DVec3::Z);
    let up = xf.vector(DVec3::Y);
    let side = xf.vector(DVec3::X);
    if xf.m.determinant() < 0.0 {
        b.warn(
            e,
            "to_world",
            "the sensor's to_world mirrors the image; Irradia renders it unmirrored",
        );
    }
    let mut cam = Node::table(pos);
    cam.put("type", kind, pos);
    cam.set("eye", v3(eye, pos));
    cam.set("look_at", v3(eye + dir.normalize(), pos));
    cam.set("up", v3(up.normalize(), pos));
    let near = match o.get("near_clip") {
        Some(p) => p.f64()?,
        None => 0.01,
    };
    if kind == "orthographic" {
        // Mitsuba's view spans [-1, 1] along the camera's x, [-1/aspect, 1/aspect]
        // along y, both scaled by to_world.
        let aspect = width as f64 / height as f64;
        let (sx, sy) = (side.length(), up.length());
        if (sx - sy).abs() > 1e-6 * sx.max(sy) {
            b.warn(e, "to_world", format!("the orthographic view is scaled unequally ({sx} across, {sy} up): Irradia keeps the vertical extent and the image's aspect ratio"));
        }
        cam.put("height", 2.0 * sy / aspect, pos);
        // Orthographic rays start on the near plane (Mitsuba's `near_clip`).
        cam.put("near_clip", near * dir.length(), pos);
    } else {
        fov(b, &o, &mut cam)?;
        cam.put("near_clip", near, pos);
        if kind == "thinlens" {
            let a = o.get("aperture_radius").map_or(Ok(1.0), |p| p.f64())?;
            let f = o.get("focus_distance").map_or(Ok(0.0), |p| p.f64())?;
            cam.put("aperture_radius", a, pos);
            cam.put("focus_distance", f, pos);
        }
    }
    if let Some(f) = o.get("far_clip") {
        b.notes.push(format!(
            "far_clip = {} ignored: Irradia's cameras see to infinity",
            f.f64()?
        ));
    }
    o.accept(&[
        "shutter_open",
        "shutter_close",
        "srf",
        "principal_point_offset_x",
        "principal_point_offset_y",
    ]);
    for n in ["principal_point_offset_x", "principal_point_offset_y"] {
        if let Some(p) = o.props.iter().find(|p| p.name == n) {
            if p.f64()? != 0.0 {
                b.warn(p.elem, n, format!("{n} is not rendered"));
            }
        }
    }
    o.finish(&[
        "to_world",
        "fov",
        "fov_axis",
        "focal_length",
        "near_clip",
        "far_clip",
        "aperture_radius",
        "focus_distance",
    ])?;
    b.camera = Some(cam);
    Ok(())
}

fn gaussian(pos: usize) -> Node {
    let mut f = Node::table(pos);
    f.put("type", "gaussian", pos).put("stddev", 0.5, pos);
    f
}

/// `<film type="hdrfilm">`: size, crop window, reconstruction filter.
fn film<'e>(b: &mut Builder<'e>, e: &'e Elem) -> Result<(i64, i64), SceneError> {
    let o = Obj::read(e)?;
    let pos = e.main_pos;
    if o.plugin != "hdrfilm" {
        if o.plugin == "specfilm" {
            b.warn(e, "type", "specfilm is rendered as an RGB film");
        } else {
            return Err(e.err_at(
                "type",
                "type",
                format!("unknown film `{}` (valid: hdrfilm, specfilm)", o.plugin),
            ));
        }
    }
    let width = o.get("width").map_or(Ok(768), |p| p.int())?;
    let height = o.get("height").map_or(Ok(576), |p| p.int())?;
    for (n, v) in [("width", width), ("height", height)] {
        if v < 1 {
            return Err(o
                .get(n)
                .unwrap()
                .err(format!("{n} must be at least 1 (got {v})")));
        }
    }
    b.image.put("width", width, pos).put("height", height, pos);
    for n in [
        "crop_offset_x",
        "crop_offset_y",
        "crop_width",
        "crop_height",
    ] {
        if let Some(p) = o.get(n) {
            b.image.put(n, p.int()?, p.elem.main_pos);
        }
    }
    // Output encodings: Irradia writes what `-o` asks for.
    o.accept(&[
        "pixel_format",
        "component_format",
        "file_format",
        "banner",
        "compensate",
        "sample_border",
    ]);
    if let Some(p) = o.props.iter().find(|p| p.name == "sample_border") {
        if p.bool()? {
            b.warn(p.elem, "sample_border", "sample_border is not rendered");
        }
    }
    if let Some(p) = o.props.iter().find(|p| p.name == "rfilter") {
        return Err(p.err("the reconstruction filter is an unnamed <rfilter> inside the film"));
    }
    let mut filter = gaussian(pos);
    for c in &o.nested {
        if c.tag != "rfilter" {
            return Err(c.err(&c.tag, format!("<{}> does not belong in a <film>", c.tag)));
        }
        filter = rfilter(b, c)?;
    }
    b.image.set("filter", filter);
    o.finish(&[
        "width",
        "height",
        "crop_offset_x",
        "crop_offset_y",
        "crop_width",
        "crop_height",
        "pixel_format",
        "component_format",
        "file_format",
    ])?;
    Ok((width, height))
}

fn rfilter<'e>(b: &mut Builder<'e>, e: &'e Elem) -> Result<Node, SceneError> {
    let o = Obj::read(e)?;
    let pos = e.main_pos;
    let mut f = Node::table(pos);
    match o.plugin.as_str() {
        "box" | "tent" => {
            f.put("type", o.plugin.as_str(), pos);
            if let Some(r) = o.get("radius") {
                f.put("radius", r.f64()?, r.elem.main_pos);
            }
        }
        "gaussian" => {
            f.put("type", "gaussian", pos);
            let s = o.get("stddev").map_or(Ok(0.5), |p| p.f64())?;
            f.put("stddev", s, pos);
        }
        "mitchell" | "catmullrom" | "lanczos" => {
            b.warn(
                e,
                "type",
                format!(
                    "the `{}` filter is not rendered: a Gaussian (stddev 0.5) is used",
                    o.plugin
                ),
            );
            o.accept(&["B", "C", "lobes"]);
            return Ok(gaussian(pos));
        }
        k => {
            return Err(e.err_at(
                "type",
                "type",
                format!(
                "unknown rfilter `{k}` (valid: box, tent, gaussian, mitchell, catmullrom, lanczos)"
            ),
            ))
        }
    }
    o.finish(&["radius", "stddev"])?;
    Ok(f)
}

/// Every Mitsuba sampler draws unbiased samples; Irradia uses its own (stratified).
fn sampler<'e>(b: &mut Builder<'e>, e: &'e Elem) -> Result<(), SceneError> {
    let o = Obj::read(e)?;
    if ![
        "independent",
        "stratified",
        "multijitter",
        "orthogonal",
        "ldsampler",
    ]
    .contains(&o.plugin.as_str())
    {
        return Err(e.err_at("type", "type", format!("unknown sampler `{}` (valid: independent, stratified, multijitter, orthogonal, ldsampler)", o.plugin)));
    }
    let spp = o.get("sample_count").map_or(Ok(4), |p| p.int())?;
    if spp < 1 {
        return Err(o
            .get("sample_count")
            .unwrap()
            .err("sample_count must be at least 1"));
    }
    b.render.put("spp", spp, e.main_pos);
    if let Some(seed) = o.get("seed") {
        let v = seed.int()?;
        if !(0..=u32::MAX as i64).contains(&v) {
            return Err(seed.err("seed must be between 0 and 4294967295"));
        }
        b.render.put("seed", v, e.main_pos);
    }
    o.accept(&["jitter", "strength"]);
    o.finish(&["sample_count", "seed", "jitter", "strength"])?;
    Ok(())
}

pub fn integrator<'e>(b: &mut Builder<'e>, e: &'e Elem) -> Result<(), SceneError> {
    let o = Obj::read(e)?;
    let pos = e.main_pos;
    let kind = o.plugin.as_str();
    match kind {
        "moment" => {
            // Adds a variance image only; the wrapped integrator is what renders.
            b.notes.push("integrator `moment`: its nested integrator is rendered (the variance output is not written)".into());
            o.finish(&[])?;
            match o.nested.as_slice() {
                [inner] if inner.tag == "integrator" => return integrator(b, inner),
                _ => return Err(e.err("integrator", "`moment` wraps one <integrator>")),
            }
        }
        "path" | "volpath" | "volpathmis" | "ptracer" | "prb" | "prb_basic" => {
            if kind != "path" {
                b.notes.push(format!("integrator `{kind}` is rendered by the path tracer (the same image in expectation)"));
            }
            b.render.put("integrator", "path", pos);
            let depth = o.get("max_depth").map_or(Ok(-1), |p| p.int())?;
            let depth = if depth < 0 {
                b.notes.push("max_depth = -1 (unlimited) becomes 1024".into());
                1024
            } else {
                depth
            };
            b.render.put("max_depth", depth, pos);
            if let Some(r) = o.get("rr_depth") {
                if r.int()? != 5 {
                    b.warn(r.elem, "rr_depth", "Irradia's path tracer starts Russian roulette at depth 5; rr_depth is not rendered");
                }
            }
            if let Some(h) = o.get("hide_emitters") {
                if h.bool()? {
                    b.warn(h.elem, "hide_emitters", "hide_emitters is not rendered");
                }
            }
            o.accept(&["samples_per_pass", "timeout", "sample_emitters"]);
            o.finish(&["max_depth", "rr_depth", "hide_emitters"])?;
        }
        "direct" | "direct_projective" => {
            b.render.put("integrator", "direct", pos);
            for n in ["shading_samples", "emitter_samples", "bsdf_samples"] {
                if let Some(p) = o.get(n) {
                    b.render.put(n, p.int()?, p.elem.main_pos);
                }
            }
            if let Some(h) = o.get("hide_emitters") {
                if h.bool()? {
                    b.warn(h.elem, "hide_emitters", "hide_emitters is not rendered");
                }
            }
            o.finish(&["shading_samples", "emitter_samples", "bsdf_samples", "hide_emitters"])?;
        }
        "aov" | "depth" | "stokes" | "prb_projective" | "volprim_rf_basic" => {
            b.warn(e, "type", format!("the `{kind}` integrator is not rendered: the path tracer is used"));
            b.render.put("integrator", "path", pos);
        }
        k => {
            return Err(e.err_at("type", "type", format!("unknown integrator `{k}` (valid: path, direct, ptracer, volpath, volpathmis, moment, aov, depth, ...)")))
        }
    }
    Ok(())
}

/// A scene without a sensor: Mitsuba's default film and a camera at the origin
/// looking down +z.
pub fn default_sensor(b: &mut Builder) {
    let mut cam = Node::table(0);
    cam.put("eye", [0.0, 0.0, 0.0], 0)
        .put("look_at", [0.0, 0.0, 1.0], 0)
        .put("fov", 45.0, 0);
    b.camera = Some(cam);
    if b.image.get("width").is_none() {
        b.image.put("width", 768i64, 0).put("height", 576i64, 0);
        b.image.set("filter", gaussian(0));
    }
    b.notes.push(
        "the scene has no sensor: a camera at the origin looking down +z (45 degrees) was added"
            .into(),
    );
}
