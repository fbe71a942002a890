//! MTL materials: checked here with positions, read by `tobj`, mapped to Mitsuba's
//! BSDFs by one rule:
//!
//! | MTL | BSDF |
//! |---|---|
//! | `illum` 4, 6, 7 or 9 (the transparent, refracting models), or `Ni` ≠ 1 with `d` < 1 | `dielectric`, `int_ior = Ni` (1.5 when absent) |
//! | `illum` 3 or 5 (ray-traced reflection) with `Kd` = 0 | `conductor` (a mirror), `specular_reflectance = Ks` |
//! | `Ks` > 0 and `illum` ≠ 0, 1 | `roughplastic`, `diffuse_reflectance = Kd` (or `map_Kd`), `specular_reflectance = Ks`, Beckmann `alpha = √(2 / (Ns + 2))` (Walter et al.'s Phong correspondence; `Ns` 10 when absent) |
//! | otherwise | `diffuse`, `reflectance = Kd` (0.8 when absent) or `map_Kd` |
//!
//! then, from the inside out: `bump`/`map_bump` wraps it in a `bumpmap` (the image as
//! a raw height, `scale` from `-bm`, else 1); `d` < 1 (or `Tr` > 0) that is not a
//! dielectric, or `map_d`, wraps it in a `mask` with that opacity; `Ke` > 0 is the
//! material's `emission`. `map_Kd` replaces `Kd` (as most renderers do). Texture
//! options (`-bm`, `-s`, ...) other than `-bm` are ignored, with a warning.

use crate::model::{color, num, rel_name};
use irradia_geometry::io::obj::tokens;
use irradia_scene::file::tree::Node;
use irradia_scene::SceneError;
use std::path::{Path, PathBuf};

/// An MTL file that passed [`check`]: its path and the names it defines.
#[derive(Clone, Debug)]
pub struct MtlFile {
    pub path: PathBuf,
    pub materials: Vec<String>,
}

/// Directives mapped to the BSDF.
const READ: &[&str] = &[
    "newmtl", "Kd", "Ks", "Ke", "Ns", "Ni", "d", "Tr", "illum", "map_Kd", "map_bump", "map_Bump",
    "bump", "map_d",
];
/// Directives of MTL (and its common PBR extension) that Irradia does not map.
const NOT_RENDERED: &[&str] = &[
    "Ka",
    "Tf",
    "map_Ka",
    "map_Ks",
    "map_Ke",
    "map_Ns",
    "disp",
    "decal",
    "refl",
    "sharpness",
    "Pr",
    "Pm",
    "Ps",
    "Pc",
    "Pcr",
    "aniso",
    "anisor",
    "map_Pr",
    "map_Pm",
    "map_Ps",
    "norm",
    "map_RMA",
    "map_ORM",
    "map_refl",
];

/// Checks MTL text: known directives, numbers where numbers belong (file, line and
/// column of the first problem); warnings for directives not rendered.
pub fn check(
    text: &str,
    path: &Path,
    warnings: &mut Vec<SceneError>,
) -> Result<MtlFile, SceneError> {
    let mut materials = Vec::new();
    let mut warned: Vec<String> = Vec::new();
    for (n, raw) in text.lines().enumerate() {
        let line = n + 1;
        let content = raw.split('#').next().unwrap_or("");
        let mut tok = tokens(content);
        let Some((col, key)) = tok.next() else {
            continue;
        };
        let err = |field: &str, col: usize, msg: String| {
            SceneError::input(field, msg).at(line, col).with_file(path)
        };
        let numbers =
            |tok: &mut dyn Iterator<Item = (usize, &str)>, count: usize, integer: bool| {
                let vals: Vec<(usize, &str)> = tok.collect();
                if vals.len() != count {
                    return Err(err(
                        key,
                        col,
                        format!(
                            "`{key}` takes {count} number{}, found {}",
                            if count > 1 { "s" } else { "" },
                            vals.len()
                        ),
                    ));
                }
                for (c, s) in vals {
                    let ok = if integer {
                        s.parse::<u8>().is_ok()
                    } else {
                        s.parse::<f32>().is_ok_and(f32::is_finite)
                    };
                    if !ok {
                        let what = if integer {
                            "an illumination model (0 to 10)"
                        } else {
                            "a finite number"
                        };
                        return Err(err(key, c, format!("'{s}' is not {what}")));
                    }
                }
                Ok(())
            };
        match key {
            "newmtl" => {
                let name = content.trim_start()[6..].trim();
                if name.is_empty() {
                    return Err(err(key, col, "a material name is missing".into()));
                }
                materials.push(name.to_string());
            }
            "Kd" | "Ks" | "Ke" => numbers(&mut tok, 3, false)?,
            "Ns" | "Ni" | "d" | "Tr" => numbers(&mut tok, 1, false)?,
            "illum" => numbers(&mut tok, 1, true)?,
            k if k.starts_with("map_") || k == "bump" => {
                if tok.next().is_none() {
                    return Err(err(key, col, format!("`{key}` needs a file name")));
                }
                if !READ.contains(&k) && !NOT_RENDERED.contains(&k) {
                    return Err(err(key, col, format!("unknown MTL directive `{key}`")));
                }
            }
            k if READ.contains(&k) => {}
            k if NOT_RENDERED.contains(&k) => {}
            _ => return Err(err(key, col, format!("unknown MTL directive `{key}`"))),
        }
        if NOT_RENDERED.contains(&key) && !warned.iter().any(|w| w == key) {
            warned.push(key.to_string());
            warnings.push(err(key, col, format!("`{key}` is not rendered (ignored)")));
        }
    }
    Ok(MtlFile {
        path: path.to_path_buf(),
        materials,
    })
}

/// A texture statement's file and `-bm` value (the file name is the last word).
fn texture_ref(spec: &str) -> (String, Option<f64>, bool) {
    let words: Vec<&str> = spec.split_whitespace().collect();
    let file = words.last().copied().unwrap_or("").to_string();
    let mut bm = None;
    let mut other = false;
    let mut i = 0;
    while i + 1 < words.len() {
        if words[i] == "-bm" {
            bm = words[i + 1].parse().ok();
            i += 2;
        } else {
            other |= words[i].starts_with('-');
            i += 1;
        }
    }
    (file, bm, other)
}

/// A bitmap texture for an MTL map; file names relative to the MTL file's folder
/// `mtl_dir` become relative to the scene's folder `scene_dir`.
fn bitmap(
    spec: &str,
    raw: bool,
    mtl_dir: &Path,
    scene_dir: &Path,
    warnings: &mut Vec<SceneError>,
    origin: &Path,
) -> (Node, Option<f64>) {
    let (file, bm, other) = texture_ref(spec);
    if other {
        warnings.push(
            SceneError::input(
                "",
                format!("texture options of `{spec}` other than -bm are ignored"),
            )
            .with_file(origin),
        );
    }
    let mut t = Node::table(0);
    t.put("type", "bitmap", 0).put(
        "filename",
        rel_name(&mtl_dir.join(file.replace('\\', "/")), scene_dir),
        0,
    );
    if raw {
        t.put("raw", true, 0);
    }
    (t, bm)
}

/// The BSDF of MTL material `m` (the rule of this module).
pub fn material(
    m: &tobj::Material,
    mtl_dir: &Path,
    scene_dir: &Path,
    warnings: &mut Vec<SceneError>,
    origin: &Path,
) -> Node {
    let kd = m.diffuse.unwrap_or([0.8; 3]);
    let ks = m.specular.unwrap_or([0.0; 3]);
    let illum = m.illumination_model.unwrap_or(2);
    let tr = m
        .unknown_param
        .get("Tr")
        .and_then(|s| s.trim().parse::<f32>().ok());
    let d = m
        .dissolve
        .or(tr.map(|t| 1.0 - t))
        .unwrap_or(1.0)
        .clamp(0.0, 1.0);
    let ni = m.optical_density;
    let diffuse_tex = |warnings: &mut Vec<SceneError>| match &m.diffuse_texture {
        Some(spec) => bitmap(spec, false, mtl_dir, scene_dir, warnings, origin).0,
        None => color(kd),
    };
    let dielectric = matches!(illum, 4 | 6 | 7 | 9) || (ni.is_some_and(|n| n != 1.0) && d < 1.0);
    let mut bsdf = Node::table(0);
    if dielectric {
        bsdf.put("type", "dielectric", 0).put(
            "int_ior",
            num(ni.filter(|n| *n > 0.0).unwrap_or(1.5)),
            0,
        );
    } else if matches!(illum, 3 | 5) && kd.iter().all(|&x| x == 0.0) {
        bsdf.put("type", "conductor", 0)
            .set("specular_reflectance", color(ks));
    } else if ks.iter().any(|&x| x > 0.0) && illum >= 2 {
        let ns = m.shininess.unwrap_or(10.0).max(0.0);
        let alpha = (2.0 / (ns + 2.0)).sqrt();
        bsdf.put("type", "roughplastic", 0)
            .set("diffuse_reflectance", diffuse_tex(warnings))
            .set("specular_reflectance", color(ks))
            .put("distribution", "beckmann", 0)
            .put("alpha", num(alpha), 0);
    } else {
        bsdf.put("type", "diffuse", 0)
            .set("reflectance", diffuse_tex(warnings));
    }
    if let Some(spec) = &m.normal_texture {
        let (tex, bm) = bitmap(spec, true, mtl_dir, scene_dir, warnings, origin);
        let mut bump = Node::table(0);
        bump.put("type", "bumpmap", 0)
            .set("texture", tex)
            .put("scale", bm.unwrap_or(1.0), 0)
            .set("bsdf", bsdf);
        bsdf = bump;
    }
    if !dielectric && (d < 1.0 || m.dissolve_texture.is_some()) {
        let opacity = match &m.dissolve_texture {
            Some(spec) => bitmap(spec, true, mtl_dir, scene_dir, warnings, origin).0,
            None => Node::new(num(d), 0),
        };
        let mut mask = Node::table(0);
        mask.put("type", "mask", 0)
            .set("opacity", opacity)
            .set("bsdf", bsdf);
        bsdf = mask;
    }
    if let Some(ke) = m.emissive.filter(|e| e.iter().any(|&x| x > 0.0)) {
        bsdf.set("emission", color(ke));
    }
    bsdf
}
