//! Mitsuba 3's image-based emitters in `[[lights]]`: `envmap` (a latitude-longitude
//! environment map) and `projector` (an image projected from a point).

use super::lights::position_and_axis;
use super::reader::{Result, Table, Val};
use super::transform::read_transform;
use crate::camera::FovAxis;
use crate::envmap::EnvMap;
use crate::light::Light;
use crate::projector::Projector;
use glam::Vec3;
use irradia_core::{Image, Rgb};
use std::sync::Arc;

/// An image file named by `v` (relative to the scene's folder; in a built-in scene, a file
/// embedded in the binary when one has that name): PNG (sRGB), EXR, HDR or
/// PFM (linear).
fn read_image(v: &Val, what: &str) -> Result<(Arc<Image>, std::path::PathBuf)> {
    let name = v.str()?;
    if v.doc.is_builtin() {
        if let Some(bytes) = crate::builtin::asset(name) {
            let image = irradia_core::io::decode_float(bytes, name)
                .map_err(|e| v.err(format!("cannot load the {what}: {e}")))?;
            return Ok((Arc::new(image), std::path::PathBuf::from(name)));
        }
    }
    let path = v.doc.resolve(name);
    let image =
        irradia_core::io::load(&path).map_err(|e| v.err(format!("cannot load the {what}: {e}")))?;
    Ok((Arc::new(image), path))
}

/// `type = "envmap"`: `filename` (a 2:1 latitude-longitude image), `scale` (1) and
/// `to_world` (a list of transform steps; rotations only).
pub(super) fn read_envmap(t: &Table) -> Result<Light> {
    let file_v = t.req("filename")?;
    let (image, path) = read_image(&file_v, "environment map")?;
    if image.width() != 2 * image.height() || image.height() < 3 {
        return Err(file_v.err(format!(
            "{}: an environment map must be a latitude-longitude image twice as wide as \
             it is high, at least 6x3 (got {}x{})",
            path.display(),
            image.width(),
            image.height()
        )));
    }
    let scale = t.non_negative_or("scale", 1.0)?;
    let to_world_v = t.get("to_world");
    let m = read_transform(to_world_v.clone())?.matrix3;
    let m = glam::Mat3::from(m);
    let orthonormal = (m.transpose() * m - glam::Mat3::IDENTITY)
        .to_cols_array()
        .iter()
        .all(|x| x.abs() < 1e-4)
        && m.determinant() > 0.0;
    if !orthonormal {
        let at = to_world_v.unwrap_or(file_v);
        return Err(at.err("an environment map's to_world must be a rotation"));
    }
    Ok(Light::Envmap(Arc::new(EnvMap {
        image,
        scale,
        to_world: m,
        path,
    })))
}

/// `type = "projector"`: `position`, `look_at` or `direction`, `up` ([0, 1, 0]), `fov`
/// (degrees, required) across `fov_axis` ("x") of the image, `irradiance` (an image
/// file or a colour, 1) and `scale` (1).
pub(super) fn read_projector(t: &Table) -> Result<Light> {
    let (position, direction) = position_and_axis(t)?;
    let up_v = t.get("up");
    let up = up_v.as_ref().map_or(Ok(Vec3::Y), |u| u.direction())?;
    if direction.cross(up.normalize()).length() < 1e-4 {
        let at = match up_v {
            Some(u) => u,
            None => t
                .get("look_at")
                .or(t.get("direction"))
                .unwrap_or(t.req("position")?),
        };
        return Err(
            at.err("up must not be parallel to the projector's axis (give an `up` across it)")
        );
    }
    let fov_v = t.req("fov")?;
    let fov = fov_v.f32()?;
    if !(fov > 0.0 && fov < 180.0) {
        return Err(fov_v.err(format!(
            "field of view must be between 0 and 180 degrees, exclusive (got {fov})"
        )));
    }
    let axis = match t.get("fov_axis").map_or(Ok("x"), |a| {
        a.choice(&["x", "y", "diagonal", "smaller", "larger"])
    })? {
        "y" => FovAxis::Vertical,
        "diagonal" => FovAxis::Diagonal,
        "smaller" => FovAxis::Smaller,
        "larger" => FovAxis::Larger,
        _ => FovAxis::Horizontal,
    };
    let irradiance = match t.get("irradiance") {
        Some(v) if v.is_str() => {
            let path = v.doc.resolve(v.str()?);
            if irradia_core::io::Format::from_path(&path).is_ok() || v.doc.is_builtin() {
                read_image(&v, "projector image")?.0
            } else {
                // Other formats (BMP, JPEG, ...) as the `bitmap` texture decodes them.
                let t = crate::texture::bitmap::read_texels(&path, false)
                    .map_err(|e| v.err(format!("cannot load the projector image: {e}")))?;
                let px = (0..t.height)
                    .flat_map(|y| (0..t.width).map(move |x| (x, y)))
                    .map(|(x, y)| t.get(x, y))
                    .collect();
                Arc::new(Image::from_pixels(t.width, t.height, px))
            }
        }
        Some(v) => Arc::new(Image::from_pixels(1, 1, vec![v.rgb()?])),
        None => Arc::new(Image::from_pixels(1, 1, vec![Rgb::WHITE])),
    };
    Ok(Light::Projector(Arc::new(Projector::new(
        position,
        position + direction,
        up,
        fov,
        axis,
        irradiance,
        t.non_negative_or("scale", 1.0)?,
    ))))
}
