//! Image files: PNG (8-bit sRGB), OpenEXR and PFM (linear float), chosen by extension,
//! always written atomically (a temporary file in the same folder, then a rename), so a
//! crash or a full disk never leaves a truncated image over a good one.

use crate::color::Rgb;
use crate::image::{Image, ImageError};
use std::io::{BufRead, BufReader, Write};
use std::path::Path;

/// File formats Irradia reads and writes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    Png,
    Exr,
    Pfm,
}

impl Format {
    /// The format named by a path's extension (case-insensitive).
    pub fn from_path(path: &Path) -> Result<Format, ImageError> {
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .map(|e| e.to_ascii_lowercase());
        match ext.as_deref() {
            Some("png") => Ok(Format::Png),
            Some("exr") => Ok(Format::Exr),
            Some("pfm") => Ok(Format::Pfm),
            _ => Err(ImageError::UnknownFormat {
                path: path.display().to_string(),
            }),
        }
    }
}

fn file_err(path: &Path, e: impl std::fmt::Display) -> ImageError {
    ImageError::File {
        path: path.display().to_string(),
        message: e.to_string(),
    }
}

/// Writes `bytes` to `path` atomically: into a hidden temporary file beside it, flushed
/// and synced, then renamed over the target.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    let dir = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => std::path::PathBuf::from("."),
    };
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| "out".into());
    let tmp = dir.join(format!(".{name}.tmp{}", std::process::id()));
    let result = (|| {
        let mut f = std::fs::File::create(&tmp)?;
        f.write_all(bytes)?;
        f.sync_all()?;
        std::fs::rename(&tmp, path)
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result
}

/// Encodes an image in the given format.
pub fn encode(image: &Image, format: Format) -> Result<Vec<u8>, String> {
    match format {
        Format::Png => encode_png(image),
        Format::Pfm => Ok(encode_pfm(image)),
        Format::Exr => encode_exr(image),
    }
}

/// Writes an image to `path`, in the format its extension names, atomically.
pub fn save(image: &Image, path: &Path) -> Result<(), ImageError> {
    let format = Format::from_path(path)?;
    let bytes = encode(image, format).map_err(|e| file_err(path, e))?;
    write_atomic(path, &bytes).map_err(|e| file_err(path, e))
}

/// Reads a PNG, EXR, PFM or Radiance HDR (`.hdr`, read only) file into linear RGB (PNG
/// is decoded from sRGB).
pub fn load(path: &Path) -> Result<Image, ImageError> {
    let hdr = path
        .extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("hdr"));
    if hdr {
        return load_float(path);
    }
    match Format::from_path(path)? {
        Format::Pfm => {
            let f = std::fs::File::open(path).map_err(|e| file_err(path, e))?;
            decode_pfm(BufReader::new(f)).map_err(|e| file_err(path, e))
        }
        Format::Png => {
            let im = ::image::open(path)
                .map_err(|e| file_err(path, e))?
                .to_rgb8();
            let (w, h) = im.dimensions();
            let px = im.pixels().map(|p| Rgb::from_srgb8(p.0)).collect();
            Ok(Image::from_pixels(w, h, px))
        }
        Format::Exr => load_float(path),
    }
}

/// A linear floating-point image (EXR or Radiance HDR, by the extension of `name`) held
/// in memory, e.g. a file embedded in the binary.
pub fn decode_float(bytes: &[u8], name: &str) -> Result<Image, ImageError> {
    let err = |e: ::image::ImageError| file_err(Path::new(name), e);
    let format = ::image::ImageFormat::from_path(name).map_err(err)?;
    let im = ::image::load_from_memory_with_format(bytes, format)
        .map_err(err)?
        .to_rgb32f();
    let (w, h) = im.dimensions();
    let px = im.pixels().map(|p| Rgb::from_array(p.0)).collect();
    Ok(Image::from_pixels(w, h, px))
}

/// A linear floating-point image file (EXR, HDR) read by the `image` crate.
fn load_float(path: &Path) -> Result<Image, ImageError> {
    let im = ::image::open(path)
        .map_err(|e| file_err(path, e))?
        .to_rgb32f();
    let (w, h) = im.dimensions();
    let px = im.pixels().map(|p| Rgb::from_array(p.0)).collect();
    Ok(Image::from_pixels(w, h, px))
}

fn encode_png(image: &Image) -> Result<Vec<u8>, String> {
    let mut out = Vec::new();
    let enc = ::image::codecs::png::PngEncoder::new_with_quality(
        &mut out,
        ::image::codecs::png::CompressionType::Fast,
        ::image::codecs::png::FilterType::Adaptive,
    );
    ::image::ImageEncoder::write_image(
        enc,
        &image.to_srgb8(),
        image.width(),
        image.height(),
        ::image::ExtendedColorType::Rgb8,
    )
    .map_err(|e| e.to_string())?;
    Ok(out)
}

fn encode_exr(image: &Image) -> Result<Vec<u8>, String> {
    let data: Vec<f32> = image.pixels().iter().flat_map(|p| p.to_array()).collect();
    let buf =
        ::image::Rgb32FImage::from_raw(image.width(), image.height(), data).ok_or("bad buffer")?;
    let mut cursor = std::io::Cursor::new(Vec::new());
    ::image::DynamicImage::ImageRgb32F(buf)
        .write_to(&mut cursor, ::image::ImageFormat::OpenExr)
        .map_err(|e| e.to_string())?;
    Ok(cursor.into_inner())
}

/// Portable float map: "PF", size, scale (negative = little-endian), rows bottom to top.
pub fn encode_pfm(image: &Image) -> Vec<u8> {
    let (w, h) = (image.width() as usize, image.height() as usize);
    let mut out = format!("PF\n{w} {h}\n-1.0\n").into_bytes();
    out.reserve(w * h * 12);
    for y in (0..h).rev() {
        for p in &image.pixels()[y * w..(y + 1) * w] {
            for v in p.to_array() {
                out.extend_from_slice(&v.to_le_bytes());
            }
        }
    }
    out
}

/// Reads a colour ("PF") or grey ("Pf") portable float map.
pub fn decode_pfm(mut r: impl BufRead) -> Result<Image, String> {
    let mut header = Vec::new();
    let mut line = String::new();
    while header.len() < 4 {
        line.clear();
        if r.read_line(&mut line).map_err(|e| e.to_string())? == 0 {
            return Err("truncated PFM header".into());
        }
        header.extend(line.split_whitespace().map(str::to_owned));
    }
    let channels = match header[0].as_str() {
        "PF" => 3,
        "Pf" => 1,
        other => return Err(format!("not a PFM file (magic {other:?})")),
    };
    let w: u32 = header[1].parse().map_err(|_| "bad PFM width")?;
    let h: u32 = header[2].parse().map_err(|_| "bad PFM height")?;
    let scale: f32 = header[3].parse().map_err(|_| "bad PFM scale")?;
    let n = crate::image::check_size(w, h, 12).map_err(|e| e.to_string())?;
    let mut data = vec![0u8; n * channels * 4];
    r.read_exact(&mut data)
        .map_err(|_| format!("PFM data shorter than {w}x{h}"))?;
    let mut px = vec![Rgb::BLACK; n];
    for (i, chunk) in data.chunks_exact(4 * channels).enumerate() {
        let v = |k: usize| {
            let b = [
                chunk[4 * k],
                chunk[4 * k + 1],
                chunk[4 * k + 2],
                chunk[4 * k + 3],
            ];
            if scale < 0.0 {
                f32::from_le_bytes(b)
            } else {
                f32::from_be_bytes(b)
            }
        };
        let c = if channels == 3 {
            Rgb::new(v(0), v(1), v(2))
        } else {
            Rgb::splat(v(0))
        };
        let (x, y) = (i % w as usize, h as usize - 1 - i / w as usize);
        px[y * w as usize + x] = c;
    }
    Ok(Image::from_pixels(w, h, px))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample() -> Image {
        let mut im = Image::new(5, 3).unwrap();
        for y in 0..3 {
            for x in 0..5 {
                im.set(x, y, Rgb::new(x as f32 * 0.25, y as f32 * 0.5, 2.5));
            }
        }
        im
    }

    #[test]
    fn pfm_and_exr_round_trip_exactly() {
        let dir = tempfile::tempdir().unwrap();
        for ext in ["pfm", "exr"] {
            let p = dir.path().join(format!("a.{ext}"));
            save(&sample(), &p).unwrap();
            assert_eq!(load(&p).unwrap(), sample(), "{ext}");
        }
    }

    #[test]
    fn png_round_trips_within_quantisation() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("a.png");
        let im = Image::from_pixels(
            5,
            3,
            sample().pixels().iter().map(|c| c.clamp01()).collect(),
        );
        save(&im, &p).unwrap();
        assert!(load(&p).unwrap().max_abs_diff(&im) < 0.01);
    }

    #[test]
    fn unknown_extension_is_an_error_and_nothing_is_left_behind() {
        let dir = tempfile::tempdir().unwrap();
        assert!(matches!(
            save(&sample(), &dir.path().join("a.jpg")),
            Err(ImageError::UnknownFormat { .. })
        ));
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
    }

    #[test]
    fn truncated_pfm_is_reported() {
        let bytes = b"PF\n4 4\n-1.0\n\0\0\0\0".to_vec();
        assert!(decode_pfm(&bytes[..]).unwrap_err().contains("shorter"));
    }
}
