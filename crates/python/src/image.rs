//! `irradia.read_image` / `irradia.write_image`: PNG (8-bit sRGB), OpenEXR and PFM
//! (linear float) through the core crate's image files (`irradia_core::io`: chosen by
//! extension, written atomically), as float32 arrays of shape (height, width, 3) in
//! linear light.

use crate::errors;
use crate::render::image_array;
use irradia_core::{Image, Rgb};
use numpy::{PyReadonlyArrayDyn, PyUntypedArrayMethods};
use pyo3::prelude::*;
use std::path::PathBuf;

/// Reads a PNG, EXR, PFM (or Radiance .hdr) file as linear float32 (h, w, 3).
#[pyfunction]
pub fn read_image(py: Python<'_>, path: PathBuf) -> PyResult<PyObject> {
    if !path.is_file() {
        return Err(pyo3::exceptions::PyFileNotFoundError::new_err(format!(
            "{}: no such image file",
            path.display()
        )));
    }
    let image = py
        .allow_threads(|| irradia_core::io::load(&path))
        .map_err(errors::image)?;
    image_array(py, &image, 3)
}

/// The pixels of an (h, w), (h, w, 1) or (h, w, 3) array; `to_rgb` maps one pixel's
/// values (grey is repeated over the three channels).
fn pixels<T: numpy::Element + Copy>(
    a: &PyReadonlyArrayDyn<'_, T>,
    to_rgb: impl Fn([T; 3]) -> Rgb,
) -> PyResult<Image> {
    let shape = a.shape().to_vec();
    let (h, w, c) = match shape.as_slice() {
        [h, w] => (*h, *w, 1),
        [h, w, c @ (1 | 3)] => (*h, *w, *c),
        _ => {
            return Err(errors::input(format!(
                "image: expected an array of shape (height, width), (height, width, 1) or \
                 (height, width, 3), got {shape:?}"
            )))
        }
    };
    let (wu, hu) = (
        u32::try_from(w).unwrap_or(u32::MAX),
        u32::try_from(h).unwrap_or(u32::MAX),
    );
    irradia_core::image::check_size(wu, hu, 12).map_err(errors::image)?;
    let v = crate::convert::values(a);
    let px = v
        .chunks_exact(c)
        .map(|p| {
            to_rgb(if c == 1 {
                [p[0]; 3]
            } else {
                [p[0], p[1], p[2]]
            })
        })
        .collect();
    Ok(Image::from_pixels(wu, hu, px))
}

/// Writes an image file, its format by extension (.png, .exr, .pfm), atomically.
/// Float arrays are linear light (PNG stores them as sRGB); uint8 arrays are sRGB.
#[pyfunction]
pub fn write_image(py: Python<'_>, path: PathBuf, image: &Bound<'_, PyAny>) -> PyResult<()> {
    irradia_core::io::Format::from_path(&path).map_err(errors::image)?;
    let img = if let Ok(a) = image.extract::<PyReadonlyArrayDyn<'_, u8>>() {
        pixels(&a, Rgb::from_srgb8)?
    } else {
        let np = py.import("numpy")?;
        let a = np
            .call_method1("asarray", (image, "float32"))
            .map_err(|_| errors::input("image: expected a numeric array"))?;
        let a: PyReadonlyArrayDyn<'_, f32> = a.extract()?;
        pixels(&a, Rgb::from_array)?
    };
    py.allow_threads(|| irradia_core::io::save(&img, &path))
        .map_err(errors::image)
}
