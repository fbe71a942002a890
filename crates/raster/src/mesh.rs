//! The pipeline's input: independent triangles or an indexed mesh.

use glam::{Vec2, Vec3};
use irradia_geometry::Facets;
use thiserror::Error;

/// One corner of an input triangle, in world space.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Vertex {
    pub position: Vec3,
    /// Unit normal for lighting.
    pub normal: Vec3,
    /// Base colour (RGBA, linear); multiplied by the material's diffuse colour.
    pub color: [f32; 4],
    pub uv: Vec2,
}

/// An independent triangle with the item id written by the ID-buffer mode and the
/// index of its material in the pipeline's table (`Pipeline::materials`; 0 unless
/// set, and any index past the table's end means `Pipeline::material`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Triangle {
    pub v: [Vertex; 3],
    pub id: u32,
    pub material: u32,
}

impl Triangle {
    /// A flat triangle of one colour: the normal of every corner is the face normal
    /// (counter-clockwise winding faces the viewer).
    pub fn flat(p: [Vec3; 3], color: [f32; 4], id: u32) -> Self {
        let n = (p[1] - p[0]).cross(p[2] - p[0]).normalize_or_zero();
        let v = |position| Vertex {
            position,
            normal: n,
            color,
            uv: Vec2::ZERO,
        };
        Self {
            v: [v(p[0]), v(p[1]), v(p[2])],
            id,
            material: 0,
        }
    }
}

/// Why a mesh cannot be drawn.
#[derive(Debug, Error, PartialEq)]
pub enum MeshError {
    #[error("triangle {triangle} uses vertex {index}, but the mesh has only {vertices} vertices")]
    IndexOutOfRange {
        triangle: usize,
        index: u32,
        vertices: usize,
    },
    #[error("the mesh has {vertices} vertices but {count} {what}; give one per vertex or none")]
    AttributeCount {
        what: &'static str,
        count: usize,
        vertices: usize,
    },
    #[error("the mesh has {triangles} triangles but {count} ids; give one per triangle or none")]
    IdCount { count: usize, triangles: usize },
    #[error(
        "the mesh has {triangles} triangles but {count} material indices; give one per triangle or none"
    )]
    MaterialCount { count: usize, triangles: usize },
}

/// An indexed triangle mesh. Attribute arrays are either empty or one entry per vertex:
/// no normals means flat shading with face normals, no colours means white, no
/// texture coordinates means (0, 0); no ids means each triangle's id is its index.
/// `materials` is empty (every triangle uses material 0) or one index into the
/// pipeline's material table per triangle (an OBJ's `usemtl` groups, a PLY's face
/// property).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Mesh {
    pub positions: Vec<Vec3>,
    pub normals: Vec<Vec3>,
    pub colors: Vec<[f32; 4]>,
    pub uvs: Vec<Vec2>,
    pub indices: Vec<[u32; 3]>,
    pub ids: Vec<u32>,
    pub materials: Vec<u32>,
}

impl Mesh {
    pub fn new(positions: Vec<Vec3>, indices: Vec<[u32; 3]>) -> Self {
        Self {
            positions,
            indices,
            ..Self::default()
        }
    }

    pub fn triangle_count(&self) -> usize {
        self.indices.len()
    }

    /// Checks indices and attribute lengths.
    pub fn validate(&self) -> Result<(), MeshError> {
        let n = self.positions.len();
        for (what, count) in [
            ("normals", self.normals.len()),
            ("colours", self.colors.len()),
            ("uvs", self.uvs.len()),
        ] {
            if count != 0 && count != n {
                return Err(MeshError::AttributeCount {
                    what,
                    count,
                    vertices: n,
                });
            }
        }
        if !self.ids.is_empty() && self.ids.len() != self.indices.len() {
            return Err(MeshError::IdCount {
                count: self.ids.len(),
                triangles: self.indices.len(),
            });
        }
        if !self.materials.is_empty() && self.materials.len() != self.indices.len() {
            return Err(MeshError::MaterialCount {
                count: self.materials.len(),
                triangles: self.indices.len(),
            });
        }
        // The largest index in one branch-free pass (vectorised: this runs every frame
        // before the parallel stages); the offending triangle is looked for only then.
        let max = self.indices.as_flattened().iter().copied().max();
        if max.is_none_or(|m| (m as usize) < n) {
            return Ok(());
        }
        for (t, tri) in self.indices.iter().enumerate() {
            for &i in tri {
                if i as usize >= n {
                    return Err(MeshError::IndexOutOfRange {
                        triangle: t,
                        index: i,
                        vertices: n,
                    });
                }
            }
        }
        Ok(())
    }

    /// Area-weighted vertex normals (replaces `normals`).
    pub fn compute_vertex_normals(&mut self) {
        let mut normals = vec![Vec3::ZERO; self.positions.len()];
        for t in &self.indices {
            let [a, b, c] = t.map(|i| self.positions[i as usize]);
            let n = (b - a).cross(c - a);
            for &i in t {
                normals[i as usize] += n;
            }
        }
        for n in &mut normals {
            *n = n.normalize_or_zero();
        }
        self.normals = normals;
    }

    /// The facets of a shape as a mesh (polygons split into fans); every triangle of
    /// face `f` gets id `f`.
    pub fn from_facets(f: &Facets) -> Self {
        let mut indices = Vec::new();
        let mut ids = Vec::new();
        for (k, face) in f.faces.iter().enumerate() {
            for i in 1..face.len().saturating_sub(1) {
                indices.push([face[0], face[i], face[i + 1]]);
                ids.push(k as u32);
            }
        }
        Self {
            positions: f.vertices.clone(),
            normals: f.normals.clone(),
            indices,
            ids,
            ..Self::default()
        }
    }

    /// A generator's output (random triangles, marching cubes, ...) with area-weighted
    /// vertex normals.
    pub fn from_mesh_data(m: irradia_geometry::generators::MeshData) -> Self {
        let mut mesh = Self::new(m.positions, m.indices);
        mesh.compute_vertex_normals();
        mesh
    }

    /// The triangles, vertex normals and texture coordinates of a geometry
    /// [`TriangleMesh`](irradia_geometry::TriangleMesh) (e.g. the tessellated teapot).
    pub fn from_triangle_mesh(m: &irradia_geometry::TriangleMesh) -> Self {
        Self {
            positions: m.positions().to_vec(),
            normals: m.normals().to_vec(),
            uvs: m.uvs().map(|u| u.to_vec()).unwrap_or_default(),
            indices: m.indices().to_vec(),
            ..Self::default()
        }
    }

    /// The id of triangle `t`.
    #[inline]
    pub fn id(&self, t: usize) -> u32 {
        if self.ids.is_empty() {
            t as u32
        } else {
            self.ids[t]
        }
    }

    /// The material index of triangle `t`.
    #[inline]
    pub fn material(&self, t: usize) -> u32 {
        self.materials.get(t).copied().unwrap_or(0)
    }

    /// The mesh as independent triangles.
    pub fn to_triangles(&self) -> Vec<Triangle> {
        self.indices
            .iter()
            .enumerate()
            .map(|(t, idx)| {
                let p = idx.map(|i| self.positions[i as usize]);
                let face = (p[1] - p[0]).cross(p[2] - p[0]).normalize_or_zero();
                let v = |k: usize| {
                    let i = idx[k] as usize;
                    Vertex {
                        position: p[k],
                        normal: if self.normals.is_empty() {
                            face
                        } else {
                            self.normals[i]
                        },
                        color: if self.colors.is_empty() {
                            [1.0; 4]
                        } else {
                            self.colors[i]
                        },
                        uv: if self.uvs.is_empty() {
                            Vec2::ZERO
                        } else {
                            self.uvs[i]
                        },
                    }
                };
                Triangle {
                    v: [v(0), v(1), v(2)],
                    id: self.id(t),
                    material: self.material(t),
                }
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The vectorised maximum only decides whether to look: an index out of range is
    /// reported with its triangle (the first such), and valid meshes pass.
    #[test]
    fn validate_finds_the_first_index_out_of_range() {
        let positions = vec![Vec3::ZERO; 4];
        let mut indices: Vec<[u32; 3]> = (0..1000).map(|t| [t % 4, (t + 1) % 4, 3]).collect();
        assert!(Mesh::new(positions.clone(), indices.clone())
            .validate()
            .is_ok());
        assert!(Mesh::new(positions.clone(), Vec::new()).validate().is_ok());
        indices[700][1] = 4;
        indices[900][2] = 77;
        let err = Mesh::new(positions, indices.clone()).validate();
        assert!(
            matches!(
                err,
                Err(MeshError::IndexOutOfRange {
                    triangle: 700,
                    index: 4,
                    vertices: 4
                })
            ),
            "{err:?}"
        );
        let err = Mesh::new(Vec::new(), indices).validate();
        assert!(
            matches!(
                err,
                Err(MeshError::IndexOutOfRange {
                    triangle: 0,
                    index: 0,
                    vertices: 0
                })
            ),
            "{err:?}"
        );
    }
}
