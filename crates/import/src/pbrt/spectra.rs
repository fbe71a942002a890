//! pbrt-v4's spectra as Irradia's RGB: blackbodies, pbrt's named spectra (metals,
//! glasses, standard illuminants) and sampled spectra.
//!
//! pbrt-v4 divides every light's spectrum by its luminance (`SpectrumToPhotometric`)
//! before applying `scale`, so an emission spectrum becomes the RGB of luminance 1 with
//! its chromaticity; an `rgb` light keeps its RGB (pbrt normalises by the colour space's
//! illuminant only). Reflectance-like spectra (a `spectrum` colour, `eta`, `k`) are
//! reduced with D65 as Mitsuba's rgb variants do, without clamping.

use irradia_scatter::ior::{cie1931_xyz, xyz_to_srgb, CIE_MAX, CIE_MIN};
use irradia_scene::texture::cie::{D65, D65_STEP};

/// CIE XYZ of an emission spectrum `f(λ)` (not weighted by an illuminant).
fn emission_xyz(f: impl Fn(f64) -> f64) -> [f64; 3] {
    let mut xyz = [0.0; 3];
    let mut w = CIE_MIN;
    while w <= CIE_MAX {
        let v = f(w);
        let c = cie1931_xyz(w);
        for k in 0..3 {
            xyz[k] += v * c[k];
        }
        w += 1.0;
    }
    xyz
}

/// The linear sRGB of emission spectrum `f`, scaled to luminance 1 (pbrt-v4's
/// normalisation of light spectra); `None` for a spectrum without luminance.
pub fn emission_rgb(f: impl Fn(f64) -> f64) -> Option<[f64; 3]> {
    let xyz = emission_xyz(f);
    if xyz[1] <= 0.0 || !xyz[1].is_finite() {
        return None;
    }
    Some(xyz_to_srgb(xyz.map(|c| c / xyz[1])).map(|c| c.max(0.0)))
}

/// Planck's law, in arbitrary units (only the chromaticity is used).
pub fn planck(lambda_nm: f64, t: f64) -> f64 {
    const C: f64 = 299_792_458.0;
    const H: f64 = 6.626_070_15e-34;
    const KB: f64 = 1.380_649e-23;
    let l = lambda_nm * 1e-9;
    2.0 * H * C * C / (l.powi(5) * ((H * C / (l * KB * t)).exp() - 1.0))
}

/// A blackbody's RGB of luminance 1.
pub fn blackbody_rgb(t: f64) -> Option<[f64; 3]> {
    if t.is_nan() || t <= 0.0 {
        return None;
    }
    emission_rgb(|w| planck(w, t))
}

/// Piecewise-linear lookup of (wavelength, value) samples, zero outside.
pub fn sample(s: &[(f64, f64)], w: f64) -> f64 {
    if s.is_empty() || w < s[0].0 || w > s[s.len() - 1].0 {
        return 0.0;
    }
    if s.len() == 1 {
        return s[0].1;
    }
    let k = s.partition_point(|p| p.0 <= w).clamp(1, s.len() - 1) - 1;
    let (w0, v0) = s[k];
    let (w1, v1) = s[k + 1];
    if w1 == w0 {
        return v0;
    }
    v0 + (v1 - v0) * (w - w0) / (w1 - w0)
}

/// The RGB of a reflectance-like spectrum under D65 (a constant 1 gives white), not
/// clamped (for indices of refraction and absorption).
pub fn reflectance_rgb(s: &[(f64, f64)]) -> [f64; 3] {
    let d65 = |w: f64| {
        let x = (w - CIE_MIN) / D65_STEP;
        let i = (x.floor() as usize).min(D65.len() - 2);
        let t = (x - i as f64).clamp(0.0, 1.0);
        D65[i] as f64 * (1.0 - t) + D65[i + 1] as f64 * t
    };
    let white = emission_xyz(d65);
    let xyz = emission_xyz(|w| d65(w) * sample(s, w));
    xyz_to_srgb(xyz.map(|c| c / white[1]))
}

/// pbrt's metals whose `metal-X-eta` / `metal-X-k` spectra have a Mitsuba conductor of
/// the same name (`material = "X"`).
pub const MITSUBA_METALS: &[&str] = &["Ag", "Al", "Au", "Cu", "MgO", "TiO2"];

/// Brass (`metal-CuZn-*`), which Mitsuba's tables lack: RGB (eta, k) at 650, 550,
/// 450 nm from pbrt-v4's tabulated spectra.
pub const CUZN: ([f64; 3], [f64; 3]) = ([0.444, 0.527, 1.094], [3.695, 2.765, 1.829]);

/// `metal-X-eta` → `("X", "eta")`.
pub fn metal(name: &str) -> Option<(&str, &str)> {
    let rest = name.strip_prefix("metal-")?;
    let (metal, which) = rest.rsplit_once('-')?;
    if !(which == "eta" || which == "k") {
        return None;
    }
    if MITSUBA_METALS.contains(&metal) || metal == "CuZn" {
        Some((metal, which))
    } else {
        None
    }
}

/// The index of refraction (at the d line, 587.6 nm) of pbrt's named glasses.
pub fn glass_ior(name: &str) -> Option<f64> {
    Some(match name {
        "glass-BK7" => 1.5168,
        "glass-BAF10" => 1.6700,
        "glass-FK51A" => 1.4866,
        "glass-LASF9" => 1.8503,
        "glass-F5" => 1.6727,
        "glass-F10" => 1.7283,
        "glass-F11" => 1.7847,
        _ => return None,
    })
}

/// A named illuminant as the RGB of luminance 1: D65 is white; the others are
/// approximated by a blackbody of their correlated colour temperature.
pub fn illuminant_rgb(name: &str) -> Option<[f64; 3]> {
    let cct = match name {
        "stdillum-D65" => return Some([1.0, 1.0, 1.0]),
        "stdillum-D50" => 5003.0,
        "illum-acesD60" => 6000.0,
        "stdillum-A" => 2856.0,
        "stdillum-F1" => 6430.0,
        "stdillum-F2" => 4230.0,
        "stdillum-F3" => 3450.0,
        "stdillum-F4" => 2940.0,
        "stdillum-F5" => 6350.0,
        "stdillum-F6" => 4150.0,
        "stdillum-F7" => 6500.0,
        "stdillum-F8" => 5000.0,
        "stdillum-F9" => 4150.0,
        "stdillum-F10" => 5000.0,
        "stdillum-F11" => 4000.0,
        "stdillum-F12" => 3000.0,
        _ => return None,
    };
    blackbody_rgb(cct)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn blackbodies_have_luminance_one_and_the_right_tint() {
        let warm = blackbody_rgb(2700.0).unwrap();
        let cool = blackbody_rgb(10000.0).unwrap();
        assert!(warm[0] > warm[2] && cool[2] > cool[0], "{warm:?} {cool:?}");
        let d = blackbody_rgb(6504.0).unwrap();
        let y = 0.2126 * d[0] + 0.7152 * d[1] + 0.0722 * d[2];
        assert!((y - 1.0).abs() < 0.01, "{d:?}");
        for c in d {
            assert!((c - 1.0).abs() < 0.15, "{d:?}");
        }
    }

    #[test]
    fn a_constant_spectrum_is_white_under_d65() {
        let rgb = reflectance_rgb(&[(360.0, 2.0), (830.0, 2.0)]);
        for c in rgb {
            assert!((c - 2.0).abs() < 0.02, "{rgb:?}");
        }
    }

    #[test]
    fn names() {
        assert_eq!(metal("metal-Au-eta"), Some(("Au", "eta")));
        assert_eq!(metal("metal-CuZn-k"), Some(("CuZn", "k")));
        assert_eq!(metal("metal-Xx-k"), None);
        assert_eq!(glass_ior("glass-BK7"), Some(1.5168));
    }
}
