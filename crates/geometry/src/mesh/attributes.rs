//! Mesh attributes: named per-vertex or per-face values carried by a triangle mesh,
//! Mitsuba 3's `Mesh::add_attribute` (its `mesh_attribute` texture plugin reads them).
//!
//! As in Mitsuba, the name says where the rows are: `vertex_*` has one row per vertex,
//! interpolated over a triangle with the hit's barycentric coordinates, `face_*` one
//! row per triangle, constant over it. A row has 1 or 3 channels (a number, or a
//! colour in linear RGB). The mesh readers fill them: PLY's extra properties
//! (`io::ply`), OBJ's `v x y z r g b` and glTF's `COLOR_0` as `vertex_color`.

use glam::Vec3;
use std::fmt;

/// Where an attribute's rows are, from its name's prefix.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AttributeDomain {
    /// `vertex_*`: one row per vertex, interpolated barycentrically.
    Vertex,
    /// `face_*`: one row per triangle, constant over it.
    Face,
}

impl AttributeDomain {
    /// The domain a name's prefix selects, `None` when it starts with neither
    /// `vertex_` nor `face_` (Mitsuba refuses those names).
    pub fn of(name: &str) -> Option<AttributeDomain> {
        if name.starts_with("vertex_") {
            Some(AttributeDomain::Vertex)
        } else if name.starts_with("face_") {
            Some(AttributeDomain::Face)
        } else {
            None
        }
    }
}

/// Why an attribute was refused.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum AttributeError {
    #[error("mesh attribute `{name}`: the name must start with `vertex_` or `face_`")]
    BadName { name: String },
    #[error("mesh attribute `{name}`: {channels} channels (1 or 3 are read)")]
    Channels { name: String, channels: usize },
    #[error("mesh attribute `{name}`: {values} values are not a whole number of {channels}-channel rows")]
    Ragged {
        name: String,
        values: usize,
        channels: usize,
    },
    #[error("mesh attribute `{name}`: {got} rows given for {expected} {per}")]
    Rows {
        name: String,
        got: usize,
        expected: usize,
        per: &'static str,
    },
    #[error("mesh attribute `{name}`: row {row} holds {value}, which is not finite")]
    NonFinite {
        name: String,
        row: usize,
        value: f32,
    },
    #[error("mesh attribute `{name}` is given twice")]
    Duplicate { name: String },
}

/// One named attribute: `channels` (1 or 3) values per row, rows in vertex or
/// triangle order.
#[derive(Clone, Debug, PartialEq)]
pub struct MeshAttribute {
    name: String,
    channels: usize,
    values: Vec<f32>,
}

impl MeshAttribute {
    /// Checks the name (`vertex_*` or `face_*`), the channel count (1 or 3), that the
    /// values fill whole rows and that every value is finite.
    pub fn new(
        name: impl Into<String>,
        channels: usize,
        values: Vec<f32>,
    ) -> Result<MeshAttribute, AttributeError> {
        let name = name.into();
        if AttributeDomain::of(&name).is_none() {
            return Err(AttributeError::BadName { name });
        }
        if channels != 1 && channels != 3 {
            return Err(AttributeError::Channels { name, channels });
        }
        if (values.len() / channels) * channels != values.len() {
            return Err(AttributeError::Ragged {
                name,
                values: values.len(),
                channels,
            });
        }
        if let Some(i) = values.iter().position(|v| !v.is_finite()) {
            return Err(AttributeError::NonFinite {
                name,
                row: i / channels,
                value: values[i],
            });
        }
        Ok(MeshAttribute {
            name,
            channels,
            values,
        })
    }

    /// A three-channel attribute from colours (or other vectors), one per row.
    pub fn from_vec3(
        name: impl Into<String>,
        rows: &[Vec3],
    ) -> Result<MeshAttribute, AttributeError> {
        MeshAttribute::new(name, 3, rows.iter().flat_map(|c| c.to_array()).collect())
    }

    pub fn name(&self) -> &str {
        &self.name
    }
    pub fn domain(&self) -> AttributeDomain {
        AttributeDomain::of(&self.name).unwrap_or(AttributeDomain::Vertex)
    }
    /// 1 or 3.
    pub fn channels(&self) -> usize {
        self.channels
    }
    pub fn rows(&self) -> usize {
        self.values.len() / self.channels
    }
    /// All values, row after row.
    pub fn values(&self) -> &[f32] {
        &self.values
    }
    /// Row `i` (`channels` values), `None` past the end.
    pub fn row(&self, i: usize) -> Option<&[f32]> {
        self.values.get(i * self.channels..(i + 1) * self.channels)
    }

    /// The attribute with its rows taken in the order `sources` lists them (row `k`
    /// of the result is row `sources[k]` here; rows out of range read as zero).
    pub fn gather(&self, sources: &[u32]) -> MeshAttribute {
        let c = self.channels;
        let mut values = Vec::with_capacity(sources.len() * c);
        for &s in sources {
            match self.row(s as usize) {
                Some(r) => values.extend_from_slice(r),
                None => values.resize(values.len() + c, 0.0),
            }
        }
        MeshAttribute {
            name: self.name.clone(),
            channels: c,
            values,
        }
    }
}

/// The attributes of one mesh, in the order they were added; names are unique.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MeshAttributes {
    list: Vec<MeshAttribute>,
}

impl MeshAttributes {
    /// Adds `a`; a second attribute of the same name is refused.
    pub fn insert(&mut self, a: MeshAttribute) -> Result<(), AttributeError> {
        if self.get(&a.name).is_some() {
            return Err(AttributeError::Duplicate { name: a.name });
        }
        self.list.push(a);
        Ok(())
    }

    pub fn get(&self, name: &str) -> Option<&MeshAttribute> {
        self.list.iter().find(|a| a.name == name)
    }

    pub fn is_empty(&self) -> bool {
        self.list.is_empty()
    }

    pub fn iter(&self) -> impl Iterator<Item = &MeshAttribute> {
        self.list.iter()
    }

    /// Removes and returns the attribute called `name`.
    pub fn remove(&mut self, name: &str) -> Option<MeshAttribute> {
        let i = self.list.iter().position(|a| a.name == name)?;
        Some(self.list.remove(i))
    }

    /// Checks that vertex attributes have `vertices` rows and face attributes
    /// `triangles` rows.
    pub fn check_rows(&self, vertices: usize, triangles: usize) -> Result<(), AttributeError> {
        for a in &self.list {
            let (expected, per) = match a.domain() {
                AttributeDomain::Vertex => (vertices, "vertices"),
                AttributeDomain::Face => (triangles, "triangles"),
            };
            if a.rows() != expected {
                return Err(AttributeError::Rows {
                    name: a.name.clone(),
                    got: a.rows(),
                    expected,
                    per,
                });
            }
        }
        Ok(())
    }

    /// The attributes with their vertices re-indexed: vertex `k` of the result is
    /// vertex `sources[k]` here (a mesh whose corners were split, for flat shading);
    /// face attributes are kept as they are.
    pub fn gather_vertices(&self, sources: &[u32]) -> MeshAttributes {
        MeshAttributes {
            list: self
                .list
                .iter()
                .map(|a| match a.domain() {
                    AttributeDomain::Vertex => a.gather(sources),
                    AttributeDomain::Face => a.clone(),
                })
                .collect(),
        }
    }

    /// "name (n channels), ..." for messages; "none" when empty.
    pub fn describe(&self) -> String {
        if self.list.is_empty() {
            return "none".into();
        }
        self.list
            .iter()
            .map(|a| format!("{} ({})", a.name, a.channels))
            .collect::<Vec<_>>()
            .join(", ")
    }
}

/// An attribute's value at a point: one number or three.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum AttributeValue {
    One(f32),
    Three(Vec3),
}

/// A point on a triangle of a mesh with attributes: what a `mesh_attribute` lookup
/// needs (Mitsuba's `si.prim_index` and barycentric coordinates).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AttributePoint<'a> {
    pub attributes: &'a MeshAttributes,
    /// The triangle (the row of face attributes).
    pub triangle: u32,
    /// Its three vertices (the rows of vertex attributes).
    pub corners: [u32; 3],
    /// The point's barycentric coordinates with respect to `corners` (summing to 1).
    pub barycentric: [f32; 3],
}

impl AttributePoint<'_> {
    /// The attribute `name` here: a face attribute's row for the triangle, a vertex
    /// attribute's rows at the corners blended barycentrically. `None` when the mesh
    /// has no such attribute.
    pub fn eval(&self, name: &str) -> Option<AttributeValue> {
        let a = self.attributes.get(name)?;
        let mut acc = [0.0f32; 3];
        match a.domain() {
            AttributeDomain::Face => {
                let r = a.row(self.triangle as usize)?;
                acc[..r.len()].copy_from_slice(r);
            }
            AttributeDomain::Vertex => {
                for (&v, &w) in self.corners.iter().zip(&self.barycentric) {
                    let r = a.row(v as usize)?;
                    for (s, x) in acc.iter_mut().zip(r) {
                        *s += w * x;
                    }
                }
            }
        }
        Some(match a.channels {
            1 => AttributeValue::One(acc[0]),
            _ => AttributeValue::Three(Vec3::from_array(acc)),
        })
    }
}

impl fmt::Display for AttributeDomain {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            AttributeDomain::Vertex => "vertex",
            AttributeDomain::Face => "face",
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_channels_and_rows_are_checked() {
        assert!(matches!(
            MeshAttribute::new("color", 3, vec![0.0; 3]),
            Err(AttributeError::BadName { .. })
        ));
        assert!(matches!(
            MeshAttribute::new("vertex_uv", 2, vec![0.0; 4]),
            Err(AttributeError::Channels { .. })
        ));
        assert!(matches!(
            MeshAttribute::new("face_w", 1, vec![0.0, f32::NAN]),
            Err(AttributeError::NonFinite { row: 1, .. })
        ));
        let mut set = MeshAttributes::default();
        set.insert(MeshAttribute::new("face_w", 1, vec![0.5, 0.25]).unwrap())
            .unwrap();
        assert!(set
            .insert(MeshAttribute::new("face_w", 1, vec![0.0; 2]).unwrap())
            .is_err());
        assert!(set.check_rows(10, 2).is_ok());
        assert!(matches!(
            set.check_rows(10, 3),
            Err(AttributeError::Rows {
                got: 2,
                expected: 3,
                ..
            })
        ));
        assert_eq!(set.describe(), "face_w (1)");
    }

    /// Face attributes are the triangle's row; vertex attributes blend the corners'
    /// rows with the barycentric coordinates (values worked out by hand).
    #[test]
    fn face_rows_are_constant_and_vertex_rows_interpolate() {
        let mut set = MeshAttributes::default();
        set.insert(
            MeshAttribute::new(
                "vertex_color",
                3,
                vec![1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 9.0, 9.0, 9.0],
            )
            .unwrap(),
        )
        .unwrap();
        set.insert(MeshAttribute::new("face_weight", 1, vec![0.25, 0.75]).unwrap())
            .unwrap();
        let p = AttributePoint {
            attributes: &set,
            triangle: 1,
            corners: [0, 1, 2],
            barycentric: [0.5, 0.3, 0.2],
        };
        assert_eq!(p.eval("face_weight"), Some(AttributeValue::One(0.75)));
        let Some(AttributeValue::Three(c)) = p.eval("vertex_color") else {
            panic!("three channels");
        };
        assert!(
            (c - Vec3::new(0.5, 0.3, 0.2)).abs().max_element() < 1e-6,
            "{c}"
        );
        assert_eq!(p.eval("vertex_normal"), None);
        let split = set.gather_vertices(&[3, 0]);
        assert_eq!(
            split.get("vertex_color").unwrap().values(),
            &[9.0, 9.0, 9.0, 1.0, 0.0, 0.0]
        );
        assert_eq!(split.get("face_weight").unwrap().rows(), 2);
    }
}
