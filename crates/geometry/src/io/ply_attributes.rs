//! Mesh attributes among a PLY element's properties, named as Mitsuba 3's `ply`
//! plugin names them (the rules: [`super::ply`]'s module documentation).

use super::ply::Element;
use super::MeshFileError;
use crate::mesh::MeshAttribute;
use std::path::Path;

/// The properties of `el` that may be attributes: scalars not named in `reserved`
/// (`None` for the others).
pub(super) fn eligible<'e>(el: &'e Element, reserved: &[&str]) -> Vec<Option<&'e str>> {
    el.props
        .iter()
        .map(|p| {
            (p.list.is_none() && !reserved.contains(&p.name.as_str())).then_some(p.name.as_str())
        })
        .collect()
}

/// One mesh attribute found among an element's properties: its name and the
/// properties that hold its channels, in order.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct AttributeGroup {
    pub(super) name: String,
    pub(super) props: Vec<usize>,
}

/// The suffix series of Mitsuba's PLY attribute naming: `{prefix}_x, _y, _z`, ...
const SERIES: [[char; 4]; 4] = [
    ['x', 'y', 'z', 'w'],
    ['r', 'g', 'b', 'a'],
    ['0', '1', '2', '3'],
    ['1', '2', '3', '4'],
];

/// Groups the properties `props` (their names; `None` for ones that cannot be
/// attributes: the positions, normals, uv, lists) into attributes of `domain`
/// (`"vertex"` or `"face"`) by Mitsuba's rules (module documentation).
pub(super) fn attribute_groups(domain: &str, props: &[Option<&str>]) -> Vec<AttributeGroup> {
    let mut groups: Vec<AttributeGroup> = Vec::new();
    let mut used = vec![false; props.len()];
    let find = |n: &str| props.iter().position(|p| *p == Some(n));
    // The colour without a prefix.
    for (names, alpha) in [
        (["r", "g", "b"], "a"),
        (["red", "green", "blue"], "alpha"),
        (
            ["diffuse_red", "diffuse_green", "diffuse_blue"],
            "diffuse_alpha",
        ),
    ] {
        let found: Vec<Option<usize>> = names.iter().map(|n| find(n)).collect();
        if found.iter().all(Option::is_some) {
            let idx: Vec<usize> = found.into_iter().flatten().collect();
            for &k in idx.iter().chain(find(alpha).iter()) {
                used[k] = true;
            }
            groups.push(AttributeGroup {
                name: format!("{domain}_color"),
                props: idx,
            });
            break;
        }
    }
    // Runs of `{prefix}_{suffix}` with one suffix series.
    let mut seen: Vec<&str> = Vec::new();
    let mut run: Option<Run<'_>> = None;
    for (k, p) in props.iter().enumerate() {
        let Some(name) = *p else {
            continue;
        };
        if used[k] {
            continue;
        }
        let split = name
            .rsplit_once('_')
            .filter(|(_, suffix)| suffix.chars().count() == 1);
        let Some((prefix, suffix)) = split else {
            flush(domain, run.take(), &mut groups);
            continue;
        };
        let c = suffix.chars().next().unwrap_or(' ');
        if let Some(r) = run.as_mut().filter(|r| r.prefix == prefix) {
            match SERIES[r.series].get(r.props.len()) {
                Some(&expected) if expected == c => r.props.push(k),
                // Out of sequence: the whole attribute is skipped.
                _ => r.valid = false,
            }
            continue;
        }
        flush(domain, run.take(), &mut groups);
        if seen.contains(&prefix) {
            continue;
        }
        seen.push(prefix);
        if let Some(series) = SERIES.iter().position(|s| s[0] == c) {
            run = Some(Run {
                prefix,
                series,
                props: vec![k],
                valid: true,
            });
        }
    }
    flush(domain, run.take(), &mut groups);
    groups
}

/// A run of properties `{prefix}_{suffix}` being read: the suffix series (an index
/// of [`SERIES`]) and the properties so far.
struct Run<'p> {
    prefix: &'p str,
    series: usize,
    props: Vec<usize>,
    /// False once a suffix was out of sequence (the attribute is then skipped).
    valid: bool,
}

/// Ends `run`: a valid run of 1 or 3 properties becomes an attribute (unless one of
/// that name exists).
fn flush(domain: &str, run: Option<Run<'_>>, groups: &mut Vec<AttributeGroup>) {
    let Some(r) = run else {
        return;
    };
    if r.valid && (r.props.len() == 1 || r.props.len() == 3) {
        let color = if r.series == 1 { "_color" } else { "" };
        let name = format!("{domain}_{}{color}", r.prefix);
        if groups.iter().all(|g| g.name != name) {
            groups.push(AttributeGroup {
                name,
                props: r.props,
            });
        }
    }
}

/// The attribute of group `g` with `values` (a row per vertex or triangle).
pub(super) fn attribute(
    path: &Path,
    el: &Element,
    g: &AttributeGroup,
    values: Vec<f32>,
) -> Result<MeshAttribute, MeshFileError> {
    MeshAttribute::new(g.name.clone(), g.props.len(), values).map_err(|e| {
        let props: Vec<&str> = g.props.iter().map(|&k| el.props[k].name.as_str()).collect();
        MeshFileError::new(
            path,
            Some(el.line),
            Some(format!("element {}: {}", el.name, props.join(", "))),
            e.to_string(),
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The groups of `names` (all eligible) as (name, property indices).
    fn groups(domain: &str, names: &[&str]) -> Vec<(String, Vec<usize>)> {
        let props: Vec<Option<&str>> = names.iter().map(|n| Some(*n)).collect();
        attribute_groups(domain, &props)
            .into_iter()
            .map(|g| (g.name, g.props))
            .collect()
    }

    fn g(name: &str, props: &[usize]) -> (String, Vec<usize>) {
        (name.to_string(), props.to_vec())
    }

    /// Mitsuba's naming: suffix series grouped by prefix, the `r|g|b` series named
    /// `..._color`, the unprefixed colour `{domain}_color`, 1 or 3 channels only.
    #[test]
    fn properties_are_grouped_by_prefix_and_suffix_series() {
        assert_eq!(
            groups("vertex", &["color_0", "color_1", "color_2"]),
            [g("vertex_color", &[0, 1, 2])]
        );
        assert_eq!(
            groups("face", &["color_0", "color_1", "color_2", "weight_0"]),
            [g("face_color", &[0, 1, 2]), g("face_weight", &[3])]
        );
        assert_eq!(
            groups(
                "vertex",
                &["n_x", "n_y", "n_z", "albedo_r", "albedo_g", "albedo_b", "t_1", "t_2", "t_3"]
            ),
            [
                g("vertex_n", &[0, 1, 2]),
                g("vertex_albedo_color", &[3, 4, 5]),
                g("vertex_t", &[6, 7, 8])
            ]
        );
        // Unprefixed colours, with alpha dropped; they win over a later `color_*`.
        assert_eq!(
            groups(
                "vertex",
                &["red", "green", "blue", "alpha", "color_0", "color_1", "color_2"]
            ),
            [g("vertex_color", &[0, 1, 2])]
        );
        assert_eq!(
            groups("face", &["r", "g", "b"]),
            [g("face_color", &[0, 1, 2])]
        );
        // Skipped: two or four channels, out of sequence, no one-letter suffix, a
        // series that cannot start with its first suffix.
        assert_eq!(groups("vertex", &["uv_0", "uv_1"]), []);
        assert_eq!(groups("vertex", &["q_x", "q_y", "q_z", "q_w"]), []);
        assert_eq!(groups("vertex", &["q_0", "q_2", "q_1"]), []);
        assert_eq!(groups("vertex", &["flags", "confidence", "id_12"]), []);
        assert_eq!(groups("vertex", &["q_y", "q_z"]), []);
        // A prefix seen before is not read again.
        assert_eq!(
            groups("vertex", &["a_0", "b_0", "a_0"]),
            [g("vertex_a", &[0]), g("vertex_b", &[1])]
        );
        // Properties that cannot be attributes (`None`) are passed over.
        let props = [Some("x"), None, Some("w_0")];
        assert_eq!(
            attribute_groups("vertex", &props[1..]),
            [AttributeGroup {
                name: "vertex_w".into(),
                props: vec![1]
            }]
        );
    }

    /// A file with extra vertex and face properties: face rows repeat for each
    /// triangle a polygon is fanned into; integers are normalised and made linear.
    #[test]
    fn ply_properties_become_attributes() {
        let text = "ply\nformat ascii 1.0\nelement vertex 5\nproperty float x\nproperty float y\n\
            property float z\nproperty float nx\nproperty float ny\nproperty float nz\n\
            property float color_0\nproperty float color_1\nproperty float color_2\n\
            element face 2\nproperty list uchar int vertex_indices\nproperty float weight_0\n\
            property uchar grey_0\nend_header\n\
            0 0 0 0 0 1 0.1 0.2 0.3\n1 0 0 0 0 1 0.4 0.5 0.6\n1 1 0 0 0 1 0.7 0.8 0.9\n\
            0 1 0 0 0 1 1 1 1\n2 2 0 0 0 1 0 0 0\n4 0 1 2 3 0.25 255\n3 1 4 2 0.5 128\n";
        let m = super::super::ply::parse_ply(text.as_bytes(), Path::new("t.ply")).unwrap();
        assert_eq!(m.indices.len(), 3, "a quad (two triangles) and a triangle");
        let names: Vec<&str> = m.attributes.iter().map(|a| a.name()).collect();
        assert_eq!(names, ["vertex_color", "face_weight", "face_grey"]);
        let c = m.attributes.get("vertex_color").unwrap();
        assert_eq!((c.channels(), c.rows()), (3, 5));
        assert_eq!(c.row(1).unwrap(), &[0.4, 0.5, 0.6]);
        let w = m.attributes.get("face_weight").unwrap();
        assert_eq!(w.values(), &[0.25, 0.25, 0.5]);
        let grey = m.attributes.get("face_grey").unwrap().values();
        let half = irradia_core::color::srgb_to_linear(128.0 / 255.0);
        assert_eq!(grey[..2], [1.0, 1.0]);
        assert!((grey[2] - half).abs() < 1e-6, "{grey:?}");
        assert!(m.normals.is_some());
        // The mesh carries them.
        let mesh = m.into_mesh(Path::new("t.ply")).unwrap();
        assert_eq!(
            mesh.attributes().describe(),
            "vertex_color (3), face_weight (1), face_grey (1)"
        );
    }
}
