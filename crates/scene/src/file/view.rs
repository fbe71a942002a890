//! The `[camera]` (Mitsuba's `perspective`, `thinlens` and `orthographic` sensors),
//! `[image]` and `[render]` tables.

use super::reader::{Result, Table, Val};
use crate::camera::{Camera, FovAxis, Projection};
use crate::scene::{CropWindow, Integrator, LightSelection, PixelFilter, RenderSettings};
use glam::Vec3;

pub fn read_camera(v: Option<Val>, root: &Table) -> Result<Camera> {
    let Some(v) = v else {
        return Err(root.err("missing required table `camera`"));
    };
    let t = v.table()?;
    let kind = t.get("type").map_or(Ok("perspective"), |k| {
        k.choice(&["perspective", "thinlens", "orthographic"])
    })?;
    let eye = t.req("eye")?.vec3()?;
    let look_v = t.req("look_at")?;
    let look_at = look_v.vec3()?;
    let up_v = t.get("up");
    let up = up_v.as_ref().map_or(Ok(Vec3::Y), |u| u.direction())?;
    let forward = look_at - eye;
    if forward.length_squared() == 0.0 {
        return Err(look_v.err("look_at must differ from eye"));
    }
    if !forward.normalize().is_finite() {
        return Err(look_v.err("eye and look_at are too far apart to represent"));
    }
    if forward.normalize().cross(up.normalize()).length() < 1e-4 {
        let at = up_v.unwrap_or(look_v);
        return Err(at.err("up must not be parallel to the viewing direction"));
    }
    let projection = if kind == "orthographic" {
        Projection::Orthographic {
            height: t.req("height")?.positive()?,
        }
    } else {
        let (fov_degrees, axis) = read_fov(&t)?;
        if kind == "thinlens" {
            Projection::ThinLens {
                fov_degrees,
                axis,
                aperture_radius: t.req("aperture_radius")?.non_negative()?,
                focus_distance: t.req("focus_distance")?.positive()?,
            }
        } else {
            Projection::Perspective { fov_degrees, axis }
        }
    };
    let near_clip = t.non_negative_or("near_clip", 0.0)?;
    t.finish()?;
    Ok(Camera {
        eye,
        look_at,
        up,
        projection,
        near_clip,
    })
}

/// `fov` (degrees, default 60) and `fov_axis` (Mitsuba's names `x`, `y`, `diagonal`,
/// `smaller`, `larger`; `horizontal` and `vertical` mean `x` and `y`).
fn read_fov(t: &Table) -> Result<(f32, FovAxis)> {
    let fov = t.get("fov").map_or(Ok(60.0), |f| {
        let x = f.f32()?;
        if !(x > 0.0 && x < 180.0) {
            return Err(f.err(format!(
                "field of view must be between 0 and 180 degrees, exclusive (got {x})"
            )));
        }
        Ok(x)
    })?;
    let axis = match t.get("fov_axis").map_or(Ok("x"), |a| {
        a.choice(&[
            "x",
            "y",
            "diagonal",
            "smaller",
            "larger",
            "horizontal",
            "vertical",
        ])
    })? {
        "y" | "vertical" => FovAxis::Vertical,
        "diagonal" => FovAxis::Diagonal,
        "smaller" => FovAxis::Smaller,
        "larger" => FovAxis::Larger,
        _ => FovAxis::Horizontal,
    };
    Ok((fov, axis))
}

/// `[image]` (size) and `[render]` (integrator settings) into one `RenderSettings`.
pub fn read_settings(image: Option<Val>, render: Option<Val>) -> Result<RenderSettings> {
    let mut s = RenderSettings::default();
    if let Some(v) = image {
        let t = v.table()?;
        let w = t.get("width");
        let h = t.get("height");
        if let Some(w) = &w {
            s.width = w.count()?;
        }
        if let Some(h) = &h {
            s.height = h.count()?;
        }
        if let Some(f) = t.get("filter") {
            s.filter = read_filter(&f)?;
        }
        let crop_keys = [
            "crop_offset_x",
            "crop_offset_y",
            "crop_width",
            "crop_height",
        ];
        let crop: Vec<Option<Val>> = crop_keys.iter().map(|&k| t.get(k)).collect();
        t.finish()?;
        // Checked before anything is allocated for the image.
        if let Err(e) = irradia_core::image::check_size(s.width, s.height, 12) {
            let at = w.or(h).unwrap_or(v);
            return Err(at.err(e.to_string()));
        }
        if let Some(at) = crop.iter().flatten().next() {
            // Mitsuba's defaults: offset 0, the rest of the image from the offset.
            let x = crop[0].as_ref().map_or(Ok(0), |v| v.u32())?;
            let y = crop[1].as_ref().map_or(Ok(0), |v| v.u32())?;
            let width = match &crop[2] {
                Some(v) => v.count()?,
                None => s.width.saturating_sub(x),
            };
            let height = match &crop[3] {
                Some(v) => v.count()?,
                None => s.height.saturating_sub(y),
            };
            s.crop = Some(CropWindow {
                x,
                y,
                width,
                height,
            });
            if let Err(m) = s.check_crop() {
                return Err(at.err(m));
            }
        }
    }
    if let Some(v) = render {
        let t = v.table()?;
        s.max_depth = t.u32_or("max_depth", s.max_depth)?;
        s.min_weight = t.non_negative_or("min_weight", s.min_weight)?;
        s.spp = t.count_or("spp", s.spp)?;
        s.seed = t.u32_or("seed", s.seed)?;
        if let Some(a) = t.get("adaptive_threshold") {
            s.adaptive_threshold = Some(a.positive()?);
        }
        s.background = t.rgb_or("background", s.background)?;
        s.ambient_light = t.rgb_or("ambient_light", s.ambient_light)?;
        if let Some(i) = t.get("integrator") {
            s.integrator = match i.choice(&["whitted", "path", "direct"])? {
                "path" => Integrator::Path,
                "direct" => Integrator::Direct {
                    emitter_samples: 1,
                    bsdf_samples: 1,
                },
                _ => Integrator::Whitted,
            };
        }
        if let Some(l) = t.get("light_selection") {
            s.light_selection = match l.choice(&["power", "uniform"])? {
                "uniform" => LightSelection::Uniform,
                _ => LightSelection::Power,
            };
        }
        // Mitsuba's `direct`: `shading_samples` sets both counts, the specific ones win.
        let shading = t.get("shading_samples");
        let emitter = t.get("emitter_samples");
        let bsdf = t.get("bsdf_samples");
        let any = [&shading, &emitter, &bsdf]
            .into_iter()
            .flatten()
            .next()
            .cloned();
        if let Some(at) = any {
            let Integrator::Direct {
                emitter_samples,
                bsdf_samples,
            } = &mut s.integrator
            else {
                return Err(at.err("emitter_samples, bsdf_samples and shading_samples belong to integrator = \"direct\""));
            };
            if let Some(v) = &shading {
                let n = v.u32()?;
                (*emitter_samples, *bsdf_samples) = (n, n);
            }
            if let Some(v) = &emitter {
                *emitter_samples = v.u32()?;
            }
            if let Some(v) = &bsdf {
                *bsdf_samples = v.u32()?;
            }
            if *emitter_samples + *bsdf_samples == 0 {
                return Err(at.err("emitter_samples and bsdf_samples must not both be 0"));
            }
        }
        t.finish()?;
    }
    Ok(s)
}

/// `filter = { type = "box" | "tent" | "gaussian", radius | stddev }`, Mitsuba's
/// reconstruction filters with their parameter names and defaults.
fn read_filter(v: &Val) -> Result<PixelFilter> {
    if v.is_str() {
        // `filter = "tent"`: the type with its default parameter.
        return Ok(match v.choice(&["box", "tent", "gaussian"])? {
            "tent" => PixelFilter::Tent { radius: 1.0 },
            "gaussian" => PixelFilter::Gaussian { stddev: 0.5 },
            _ => PixelFilter::Box { radius: 0.5 },
        });
    }
    let t = v.table()?;
    let kind = t.req("type")?.choice(&["box", "tent", "gaussian"])?;
    let f = match kind {
        "tent" => PixelFilter::Tent {
            radius: t.positive_or("radius", 1.0)?,
        },
        "gaussian" => PixelFilter::Gaussian {
            stddev: t.positive_or("stddev", 0.5)?,
        },
        _ => PixelFilter::Box {
            radius: t.positive_or("radius", 0.5)?,
        },
    };
    t.finish()?;
    // Wider filters than this would reach more than a few dozen pixels.
    let reach = match f {
        PixelFilter::Box { radius } | PixelFilter::Tent { radius } => radius,
        PixelFilter::Gaussian { stddev } => 4.0 * stddev,
    };
    if reach > 16.0 {
        return Err(v.err(format!(
            "the filter reaches {reach} pixels from the centre; at most 16 are allowed"
        )));
    }
    Ok(f)
}
