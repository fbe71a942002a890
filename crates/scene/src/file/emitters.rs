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
    let (mut image, path) = read_image(&file_v, "environment map")?;
    let equal_area = match t.get("mapping") {
        Some(m) => m.choice(&["latlong", "equal_area"])? == "equal_area",
        None => false,
    };
    if equal_area {
        if image.width() != image.height() || image.width() < 2 {
            return Err(file_v.err(format!(
                "{}: an equal-area environment map must be square (got {}x{})",
                path.display(),
                image.width(),
                image.height()
            )));
        }
        image = Arc::new(equal_area_to_latlong(&image));
    }
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
    // A rotation, or a rotation and a mirror (a scene imported from a left-handed
    // format): directions are carried by `to_world` and back by its transpose.
    let orthonormal = (m.transpose() * m - glam::Mat3::IDENTITY)
        .to_cols_array()
        .iter()
        .all(|x| x.abs() < 1e-4);
    if !orthonormal {
        let at = to_world_v.unwrap_or(file_v);
        return Err(
            at.err("an environment map's to_world must be a rotation (or a rotation and a mirror)")
        );
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

/// pbrt-v4's equal-area octahedral square map (Clarberg's mapping,
/// `EqualAreaSphereToSquare`) resampled to a latitude-longitude map of twice its side by
/// its side. The square's `+z` pole is the map frame's `+y`: the square is read at the
/// direction `(x, −z, y)` for the map-frame direction `(x, y, z)`.
pub fn equal_area_to_latlong(square: &Image) -> Image {
    let n = square.width();
    let (w, h) = (2 * n, n.max(3));
    let mut out = Vec::with_capacity((w * h) as usize);
    for y in 0..h {
        let theta = std::f32::consts::PI * y as f32 / (h - 1) as f32;
        for x in 0..w {
            let phi = 2.0 * std::f32::consts::PI * (x as f32 + 0.5) / w as f32;
            let (st, ct) = theta.sin_cos();
            let d = Vec3::new(st * phi.sin(), ct, -st * phi.cos());
            let uv = equal_area_sphere_to_square(Vec3::new(d.x, -d.z, d.y));
            out.push(bilerp(square, uv));
        }
    }
    Image::from_pixels(w, h, out)
}

/// pbrt-v4's `EqualAreaSphereToSquare`: a unit direction to `[0, 1]²`.
pub fn equal_area_sphere_to_square(d: Vec3) -> glam::Vec2 {
    let (x, y, z) = (d.x.abs(), d.y.abs(), d.z.abs());
    let r = (1.0 - z).max(0.0).sqrt();
    let a = x.max(y);
    let b = if a == 0.0 { 0.0 } else { x.min(y) / a };
    let mut phi = b.atan() * 2.0 / std::f32::consts::PI;
    if x < y {
        phi = 1.0 - phi;
    }
    let mut v = phi * r;
    let mut u = r - v;
    if d.z < 0.0 {
        std::mem::swap(&mut u, &mut v);
        u = 1.0 - u;
        v = 1.0 - v;
    }
    u = u.copysign(d.x);
    v = v.copysign(d.y);
    glam::Vec2::new(0.5 * (u + 1.0), 0.5 * (v + 1.0))
}

/// Bilinear lookup at `uv` in `[0, 1]²` (texel centres at half-integers, clamped).
fn bilerp(img: &Image, uv: glam::Vec2) -> Rgb {
    let (w, h) = (img.width() as f32, img.height() as f32);
    let x = (uv.x * w - 0.5).clamp(0.0, w - 1.0);
    let y = (uv.y * h - 0.5).clamp(0.0, h - 1.0);
    let (x0, y0) = (x.floor() as u32, y.floor() as u32);
    let (x1, y1) = (
        (x0 + 1).min(img.width() - 1),
        (y0 + 1).min(img.height() - 1),
    );
    let (fx, fy) = (x - x0 as f32, y - y0 as f32);
    let lerp = |a: Rgb, b: Rgb, t: f32| a * (1.0 - t) + b * t;
    lerp(
        lerp(img.get(x0, y0), img.get(x1, y0), fx),
        lerp(img.get(x0, y1), img.get(x1, y1), fx),
        fy,
    )
}

#[cfg(test)]
mod equal_area_tests {
    use super::*;

    #[test]
    fn poles_and_equator_land_where_pbrt_puts_them() {
        let c = |d: Vec3| equal_area_sphere_to_square(d.normalize());
        assert!((c(Vec3::Z) - glam::Vec2::splat(0.5)).length() < 1e-6);
        // -z: a corner of the square.
        let s = c(-Vec3::Z);
        assert!((s.x - 0.5).abs() > 0.49 && (s.y - 0.5).abs() > 0.49, "{s}");
        // The equator is the square's inner diamond |u - 1/2| + |v - 1/2| = 1/2.
        for d in [Vec3::X, Vec3::Y, -Vec3::X, Vec3::new(1.0, 1.0, 0.0)] {
            let p = c(d) - glam::Vec2::splat(0.5);
            assert!((p.x.abs() + p.y.abs() - 0.5).abs() < 1e-5, "{d} {p}");
        }
    }

    #[test]
    fn a_constant_square_resamples_to_a_constant_map() {
        let sq = Image::filled(8, 8, Rgb::new(0.25, 0.5, 1.0)).unwrap();
        let ll = equal_area_to_latlong(&sq);
        assert_eq!((ll.width(), ll.height()), (16, 8));
        for p in ll.pixels() {
            assert!((p.r - 0.25).abs() < 1e-6 && (p.b - 1.0).abs() < 1e-6);
        }
    }
}
