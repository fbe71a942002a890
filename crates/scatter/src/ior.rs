//! Named indices of refraction, as Mitsuba 3: the dielectric table of
//! `include/mitsuba/render/ior.h` (Hecht, *Optics*, 4th ed.; measured at 0-20 °C near
//! 589 nm) and the complex indices `eta + i k` of conductors, reduced from the spectral
//! tables of `data/ior/<name>.{eta,k}.spd` to linear sRGB as Mitsuba's RGB variants do
//! (`spectrum_list_to_srgb` in `src/core/spectrum.cpp`, called by
//! `complex_ior_from_file`): the piecewise-linear spectrum, scaled by
//! `MI_CIE_Y_NORMALIZATION`, integrated against the CIE 1931 colour matching functions
//! by 1000 steps over 360-830 nm, converted from XYZ to linear sRGB and clamped at 0.
//! The .spd files are Mitsuba's (`mitsuba-data`, from the luxpop.com database and
//! Palik's *Handbook of Optical Constants of Solids*).

use irradia_core::Rgb;

/// Mitsuba's dielectric table: name and index of refraction.
pub const DIELECTRICS: &[(&str, f32)] = &[
    ("vacuum", 1.0),
    ("helium", 1.000036),
    ("hydrogen", 1.000132),
    ("air", 1.000277),
    ("carbon dioxide", 1.00045),
    ("water", 1.3330),
    ("acetone", 1.36),
    ("ethanol", 1.361),
    ("carbon tetrachloride", 1.461),
    ("glycerol", 1.4729),
    ("benzene", 1.501),
    ("silicone oil", 1.52045),
    ("bromine", 1.661),
    ("water ice", 1.31),
    ("fused quartz", 1.458),
    ("pyrex", 1.470),
    ("acrylic glass", 1.49),
    ("polypropylene", 1.49),
    ("bk7", 1.5046),
    ("sodium chloride", 1.544),
    ("amber", 1.55),
    ("pet", 1.5750),
    ("diamond", 2.419),
];

/// The index of refraction of a named dielectric (case-insensitive, as Mitsuba's
/// `lookup_ior`); `None` for a name not in [`DIELECTRICS`].
pub fn dielectric_ior(name: &str) -> Option<f32> {
    let lower = name.to_lowercase();
    DIELECTRICS
        .iter()
        .find(|(n, _)| *n == lower)
        .map(|&(_, v)| v)
}

/// The names [`dielectric_ior`] accepts, for error messages.
pub fn dielectric_names() -> Vec<&'static str> {
    DIELECTRICS.iter().map(|(n, _)| *n).collect()
}

/// Mitsuba's name of the perfect mirror: `eta = 0, k = 1` (F = 1 at every angle).
pub const PERFECT_MIRROR: &str = "none";

/// Declares the conductors with spectral data once: the list [`CONDUCTORS`] and the
/// lookup of their embedded tables (`conductor_spd`), so the two cannot disagree.
macro_rules! conductors {
    ($($n:literal),* $(,)?) => {
        /// The conductors with spectral data: every `<name>.eta.spd` / `<name>.k.spd` pair
        /// of Mitsuba's `data/ior` (names are case-sensitive, as Mitsuba's file names).
        pub const CONDUCTORS: &[&str] = &[$($n),*];

        /// The spectral tables of a conductor, embedded from `crates/scatter/data/ior`.
        fn conductor_spd(name: &str) -> Option<(&'static str, &'static str)> {
            match name {
                $($n => Some((
                    include_str!(concat!("../data/ior/", $n, ".eta.spd")),
                    include_str!(concat!("../data/ior/", $n, ".k.spd")),
                )),)*
                _ => None,
            }
        }
    };
}

conductors!(
    "Ag",
    "Al",
    "AlAs",
    "AlAs_palik",
    "AlSb",
    "AlSb_palik",
    "Au",
    "Be",
    "Be_palik",
    "Cr",
    "CsI",
    "CsI_palik",
    "Cu",
    "Cu2O",
    "Cu2O_palik",
    "CuO",
    "CuO_palik",
    "Cu_palik",
    "Hg",
    "HgTe",
    "HgTe_palik",
    "Hg_palik",
    "Ir",
    "Ir_palik",
    "K",
    "K_palik",
    "Li",
    "Li_palik",
    "MgO",
    "MgO_palik",
    "Mo",
    "Mo_palik",
    "Na_palik",
    "Nb",
    "Nb_palik",
    "Ni_palik",
    "Rh",
    "Rh_palik",
    "Se",
    "Se-e",
    "Se-e_palik",
    "Se_palik",
    "SiC",
    "SiC_palik",
    "SnTe",
    "SnTe_palik",
    "Ta",
    "Ta_palik",
    "Te",
    "Te-e",
    "Te-e_palik",
    "Te_palik",
    "ThF4",
    "ThF4_palik",
    "TiC",
    "TiC_palik",
    "TiN",
    "TiN_palik",
    "TiO2",
    "TiO2-e",
    "TiO2-e_palik",
    "TiO2_palik",
    "VC",
    "VC_palik",
    "VN",
    "VN_palik",
    "V_palik",
    "W",
    "a-C",
    "d-C",
    "d-C_palik",
);

/// The complex index of refraction `(eta, k)` of a named conductor in linear sRGB as
/// Mitsuba's RGB variants compute it, or `(0, 1)` for [`PERFECT_MIRROR`]; `None` for a
/// name not in [`conductor_names`].
pub fn conductor_ior(name: &str) -> Option<(Rgb, Rgb)> {
    if name == PERFECT_MIRROR {
        return Some((Rgb::BLACK, Rgb::WHITE));
    }
    let (eta, k) = conductor_spd(name)?;
    Some((spd_to_rgb(eta), spd_to_rgb(k)))
}

/// The names [`conductor_ior`] accepts, for error messages.
pub fn conductor_names() -> Vec<&'static str> {
    std::iter::once(PERFECT_MIRROR)
        .chain(CONDUCTORS.iter().copied())
        .collect()
}

/// Parses an .spd table: lines of `wavelength value` in nm, `#` comments.
pub fn parse_spd(text: &str) -> Result<Vec<(f64, f64)>, String> {
    let mut out = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let line = line.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let mut it = line.split_whitespace().map(str::parse::<f64>);
        match (it.next(), it.next(), it.next()) {
            (Some(Ok(w)), Some(Ok(v)), None) => out.push((w, v)),
            _ => return Err(format!("line {}: expected 'wavelength value'", i + 1)),
        }
    }
    if out.len() < 2 {
        return Err("fewer than two samples".into());
    }
    Ok(out)
}

/// The CIE 1931 colour matching functions at 5 nm over [`CIE_MIN`], [`CIE_MAX`].
const CIE_TABLE: &str = include_str!("../data/cie1931_xyz_5nm.csv");
/// Mitsuba's `MI_CIE_MIN` and `MI_CIE_MAX` (nm).
pub const CIE_MIN: f64 = 360.0;
pub const CIE_MAX: f64 = 830.0;
/// Mitsuba's `MI_CIE_Y_NORMALIZATION`: one over the integral of ȳ.
const CIE_Y_NORMALIZATION: f64 = 1.0 / 106.750_259_399_414_06;

/// The CIE 1931 colour matching functions (x̄, ȳ, z̄) at `lambda` nm, linearly
/// interpolated in the 5 nm table (0 outside [`CIE_MIN`], [`CIE_MAX`]).
pub fn cie1931_xyz(lambda: f64) -> [f64; 3] {
    thread_local! {
        static TABLE: Vec<[f64; 3]> = CIE_TABLE
            .lines()
            .filter(|l| !l.starts_with('#') && !l.trim().is_empty())
            .map(|l| {
                let v: Vec<f64> = l.split(',').map(|s| s.trim().parse().expect("cie table")).collect();
                [v[1], v[2], v[3]]
            })
            .collect();
    }
    if !(CIE_MIN..=CIE_MAX).contains(&lambda) {
        return [0.0; 3];
    }
    TABLE.with(|t| {
        let x = (lambda - CIE_MIN) / 5.0;
        let i = (x.floor() as usize).min(t.len() - 2);
        let f = x - i as f64;
        [0, 1, 2].map(|c| t[i][c] * (1.0 - f) + t[i + 1][c] * f)
    })
}

/// Linear sRGB (D65) from CIE XYZ, Mitsuba's `xyz_to_srgb` matrix.
pub fn xyz_to_srgb(xyz: [f64; 3]) -> [f64; 3] {
    let [x, y, z] = xyz;
    [
        3.240479 * x - 1.537150 * y - 0.498535 * z,
        -0.969256 * x + 1.875991 * y + 0.041556 * z,
        0.055648 * x - 0.204043 * y + 1.057311 * z,
    ]
}

/// A spectral table reduced to linear sRGB as Mitsuba's `spectrum_list_to_srgb`
/// (unbounded: only negative channels are clamped).
fn spd_to_rgb(text: &str) -> Rgb {
    let samples = parse_spd(text).expect("embedded .spd tables are well-formed");
    let mut xyz = [0.0f64; 3];
    const STEPS: usize = 1000;
    let (first, last) = (samples[0].0, samples[samples.len() - 1].0);
    for i in 0..STEPS {
        let x = CIE_MIN + (i as f64 / (STEPS - 1) as f64) * (CIE_MAX - CIE_MIN);
        if x < first || x > last {
            continue;
        }
        // The last sample with wavelength <= x, leaving room for its successor.
        let idx = samples
            .partition_point(|s| s.0 <= x)
            .saturating_sub(1)
            .min(samples.len() - 2);
        let ((x0, y0), (x1, y1)) = (samples[idx], samples[idx + 1]);
        let y = (y0 + (x - x0) / (x1 - x0) * (y1 - y0)) * CIE_Y_NORMALIZATION;
        let c = cie1931_xyz(x);
        for k in 0..3 {
            xyz[k] += c[k] * y;
        }
    }
    let scale = (CIE_MAX - CIE_MIN) / STEPS as f64;
    let rgb = xyz_to_srgb(xyz.map(|v| v * scale));
    Rgb::new(
        rgb[0].max(0.0) as f32,
        rgb[1].max(0.0) as f32,
        rgb[2].max(0.0) as f32,
    )
}
