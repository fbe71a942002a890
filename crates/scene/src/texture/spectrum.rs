//! Spectra written as wavelength:value lists, reduced to RGB the way Mitsuba 3's rgb
//! variants reduce a `<spectrum value="400:0.1, 500:0.2, ..."/>` given to a BSDF:
//! `spectrum_list_to_srgb(wavelengths, values, bounded = true, d65 = true)` in
//! Mitsuba's `src/core/spectrum.cpp`. The piecewise-linear spectrum, times the D65
//! illuminant, is integrated against the CIE 1931 colour matching functions at 1000
//! evenly spaced wavelengths over 360..830 nm (outside the listed range it counts as
//! zero), scaled by Mitsuba's `MI_CIE_Y_NORMALIZATION`, taken from XYZ to linear sRGB
//! and clamped to [0, 1].

use super::cie::{D65, D65_STEP};
use irradia_core::Rgb;
use irradia_scatter::ior::{cie1931_xyz, xyz_to_srgb, CIE_MAX, CIE_MIN};

/// Mitsuba's `MI_CIE_Y_NORMALIZATION` (1 / ∫ȳ over its table).
const CIE_Y_NORMALIZATION: f64 = 0.009_367_658_735_689_113;

/// D65 (scaled as Mitsuba) at wavelength `w` nm, linearly interpolated.
fn d65_at(w: f64) -> f64 {
    let t = ((w - CIE_MIN) / D65_STEP).clamp(0.0, (D65.len() - 1) as f64);
    let i = (t.floor() as usize).min(D65.len() - 2);
    let f = t - i as f64;
    f64::from(D65[i]) * (1.0 - f) + f64::from(D65[i + 1]) * f
}

/// Why a wavelength:value list is not a spectrum.
#[derive(Debug, PartialEq)]
pub enum SpectrumError {
    /// A `wavelength:value` entry that does not parse.
    Entry(String),
    TooFew,
    /// Wavelengths must increase strictly.
    NotIncreasing(f64, f64),
    Negative(f64),
}

impl std::fmt::Display for SpectrumError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            SpectrumError::Entry(e) => write!(
                f,
                "`{e}` is not `wavelength:value` (a spectrum is written \"400:0.1, 500:0.2, ...\", wavelengths in nm)"
            ),
            SpectrumError::TooFew => f.write_str("a spectrum needs at least two wavelength:value entries"),
            SpectrumError::NotIncreasing(a, b) => {
                write!(f, "wavelengths must increase ({b} nm follows {a} nm)")
            }
            SpectrumError::Negative(v) => write!(f, "spectrum values must not be negative (got {v})"),
        }
    }
}

/// Parses `"400:0.1, 500:0.2, ..."` into wavelengths (nm) and values.
pub fn parse_spectrum(text: &str) -> Result<(Vec<f64>, Vec<f64>), SpectrumError> {
    let mut wavelengths = Vec::new();
    let mut values = Vec::new();
    for entry in text.split(',').map(str::trim) {
        let bad = || SpectrumError::Entry(entry.to_string());
        let (w, v) = entry.split_once(':').ok_or_else(bad)?;
        let w: f64 = w.trim().parse().map_err(|_| bad())?;
        let v: f64 = v.trim().parse().map_err(|_| bad())?;
        if !w.is_finite() || !v.is_finite() {
            return Err(bad());
        }
        if v < 0.0 {
            return Err(SpectrumError::Negative(v));
        }
        if let Some(&last) = wavelengths.last() {
            if w <= last {
                return Err(SpectrumError::NotIncreasing(last, w));
            }
        }
        wavelengths.push(w);
        values.push(v);
    }
    if wavelengths.len() < 2 {
        return Err(SpectrumError::TooFew);
    }
    Ok((wavelengths, values))
}

/// The RGB of a reflectance spectrum, as Mitsuba's rgb variants compute it (module doc).
/// `wavelengths` increase strictly and hold at least two entries.
pub fn spectrum_to_rgb(wavelengths: &[f64], values: &[f64]) -> Rgb {
    let rgb = spectrum_to_linear_srgb(wavelengths, values, d65_at);
    Rgb::new(
        rgb[0].clamp(0.0, 1.0) as f32,
        rgb[1].clamp(0.0, 1.0) as f32,
        rgb[2].clamp(0.0, 1.0) as f32,
    )
}

/// Mitsuba's `spectrum_list_to_srgb` without clamping: the piecewise-linear spectrum
/// times `weight(λ)` (D65 for reflectances, 1 for emitters) integrated against the CIE
/// 1931 matching functions at 1000 steps, Y-normalised, in linear sRGB.
pub fn spectrum_to_linear_srgb(
    wavelengths: &[f64],
    values: &[f64],
    weight: impl Fn(f64) -> f64,
) -> [f64; 3] {
    const STEPS: usize = 1000;
    let (first, last) = (wavelengths[0], wavelengths[wavelengths.len() - 1]);
    let mut xyz = [0.0f64; 3];
    for i in 0..STEPS {
        let w = CIE_MIN + (i as f64 / (STEPS - 1) as f64) * (CIE_MAX - CIE_MIN);
        if w < first || w > last {
            continue;
        }
        // The interval [w0, w1] holding w (the last one for w == last).
        let k = wavelengths
            .partition_point(|&x| x <= w)
            .clamp(1, wavelengths.len() - 1)
            - 1;
        let (w0, w1, v0, v1) = (wavelengths[k], wavelengths[k + 1], values[k], values[k + 1]);
        let v = ((w - w1) * v0 + (w0 - w) * v1) / (w0 - w1);
        let wv = weight(w) * v;
        for (acc, c) in xyz.iter_mut().zip(cie1931_xyz(w)) {
            *acc += c * wv;
        }
    }
    let scale = (CIE_MAX - CIE_MIN) / STEPS as f64 * CIE_Y_NORMALIZATION;
    xyz_to_srgb(xyz.map(|c| c * scale))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rgb(text: &str) -> Rgb {
        let (w, v) = parse_spectrum(text).unwrap();
        spectrum_to_rgb(&w, &v)
    }

    fn close(a: Rgb, b: [f32; 3]) {
        for k in 0..3 {
            assert!((a[k] - b[k]).abs() < 2e-5, "{a:?} vs {b:?}");
        }
    }

    /// Expected values: Mitsuba 3.9.1 scalar_rgb, `mi.load_dict({'type': 'diffuse',
    /// 'reflectance': {'type': 'spectrum', 'value': [(400, 0.1), ...]}})`, read back
    /// with `mi.traverse`.
    #[test]
    fn spectra_reduce_to_mitsubas_rgb() {
        close(
            rgb("400:0.1, 500:0.2, 600:0.3, 700:0.4"),
            [0.340779, 0.242912, 0.140304],
        );
        close(rgb("360:1, 830:1"), [0.998985, 0.998874, 0.998802]);
        close(
            rgb("450:0.9, 550:0.1, 650:0.5"),
            [0.234431, 0.267234, 0.438163],
        );
        // Out of gamut above 1: clamped, as Mitsuba does for reflectances.
        close(rgb("400:2, 700:2"), [1.0, 1.0, 1.0]);
    }

    #[test]
    fn malformed_spectra_are_named() {
        assert_eq!(parse_spectrum("400:0.1"), Err(SpectrumError::TooFew));
        assert_eq!(
            parse_spectrum("500:0.1, 400:0.2"),
            Err(SpectrumError::NotIncreasing(500.0, 400.0))
        );
        assert_eq!(
            parse_spectrum("400=0.1, 500:1"),
            Err(SpectrumError::Entry("400=0.1".into()))
        );
        assert_eq!(
            parse_spectrum("400:-1, 500:1"),
            Err(SpectrumError::Negative(-1.0))
        );
    }
}
