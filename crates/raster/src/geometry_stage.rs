//! The geometry unit of the lecture's "Building Blocks": model-view-projection
//! transform, per-vertex lighting (Gouraud) or the attributes for per-pixel lighting
//! (Phong), homogeneous clipping, perspective divide, viewport mapping and back-face
//! culling. Its output, screen-space triangles, is what the rasterizer consumes.

use crate::clip::{ClipPlanes, ClipVertex};
use crate::lighting::{EyeLights, Shading};
use crate::mesh::{Mesh, Triangle};
use crate::rasterizer::{may_cover, CullMode};
use crate::screen::{varying, Rect, ScreenTriangle, ScreenVertex, VARYINGS};
use glam::{Mat3, Mat4, Vec2, Vec3};
use rayon::prelude::*;

/// Triangles processed by one task; the output keeps the input order.
const BATCH: usize = 8192;

/// A configured geometry unit for one frame.
pub(crate) struct GeometryStage<'a> {
    view: Mat4,
    view_proj: Mat4,
    normal_matrix: Mat3,
    lights: &'a EyeLights,
    shading: Shading,
    cull: CullMode,
    width: f32,
    height: f32,
    planes: ClipPlanes,
    screen: Rect,
}

impl<'a> GeometryStage<'a> {
    pub fn new(
        view: Mat4,
        proj: Mat4,
        lights: &'a EyeLights,
        shading: Shading,
        cull: CullMode,
        width: u32,
        height: u32,
    ) -> Self {
        Self {
            view,
            view_proj: proj * view,
            normal_matrix: Mat3::from_mat4(view).inverse().transpose(),
            lights,
            shading,
            cull,
            width: width as f32,
            height: height as f32,
            planes: ClipPlanes::new(width, height),
            screen: Rect::full(width, height),
        }
    }

    /// Transforms and lights one vertex.
    #[inline(always)]
    fn vertex(&self, p: Vec3, n: Vec3, color: [f32; 4], uv: Vec2) -> ClipVertex {
        let pos = self.view_proj * p.extend(1.0);
        let mut var = [0.0; VARYINGS];
        match self.shading {
            Shading::Unlit => var[..4].copy_from_slice(&color),
            Shading::Gouraud => {
                let pe = self.view.transform_point3(p);
                let ne = (self.normal_matrix * n).normalize_or_zero();
                let c = self
                    .lights
                    .shade(pe, ne, Vec3::new(color[0], color[1], color[2]));
                var[..4].copy_from_slice(&[c.x, c.y, c.z, color[3]]);
            }
            Shading::Phong => {
                let pe = self.view.transform_point3(p);
                let ne = (self.normal_matrix * n).normalize_or_zero();
                var[varying::NORMAL..varying::NORMAL + 3].copy_from_slice(&ne.to_array());
                var[varying::VIEW_POS..varying::VIEW_POS + 3].copy_from_slice(&pe.to_array());
            }
        }
        var[varying::UV] = uv.x;
        var[varying::UV + 1] = uv.y;
        ClipVertex { pos, var }
    }

    /// Perspective divide and viewport: NDC x, y in [-1, 1] to pixels, y down.
    #[inline(always)]
    fn project(&self, c: &ClipVertex) -> ScreenVertex {
        let inv_w = 1.0 / c.pos.w;
        ScreenVertex {
            x: (c.pos.x * inv_w * 0.5 + 0.5) * self.width,
            y: (0.5 - c.pos.y * inv_w * 0.5) * self.height,
            z: c.pos.z * inv_w,
            inv_w,
            var: c.var,
        }
    }

    #[inline(always)]
    fn emit(
        &self,
        a: &ClipVertex,
        b: &ClipVertex,
        c: &ClipVertex,
        id: u32,
        out: &mut Vec<ScreenTriangle>,
    ) {
        let t = ScreenTriangle {
            v: [self.project(a), self.project(b), self.project(c)],
            id,
        };
        if may_cover(&t, self.cull, &self.screen) {
            out.push(t);
        }
    }

    /// Clips, projects and culls one triangle, appending what is left (one triangle, or
    /// a fan when clipping cut it into a polygon).
    #[inline(always)]
    pub fn assemble(&self, t: [&ClipVertex; 3], id: u32, out: &mut Vec<ScreenTriangle>) {
        let codes = [0, 1, 2].map(|k| self.planes.outcode(t[k].pos));
        if codes[0] & codes[1] & codes[2] != 0 {
            return; // all outside one plane
        }
        let any = codes[0] | codes[1] | codes[2];
        if any == 0 {
            self.emit(t[0], t[1], t[2], id, out);
            return;
        }
        let poly = self.planes.clip(t, any);
        for i in 1..poly.len.saturating_sub(1) {
            self.emit(&poly.v[0], &poly.v[i], &poly.v[i + 1], id, out);
        }
    }

    /// Independent triangles, in batches that keep the input order.
    pub fn triangles(&self, tris: &[Triangle]) -> Vec<Vec<ScreenTriangle>> {
        tris.par_chunks(BATCH)
            .map(|chunk| {
                let mut out = Vec::with_capacity(chunk.len());
                for t in chunk {
                    let v =
                        t.v.map(|v| self.vertex(v.position, v.normal, v.color, v.uv));
                    self.assemble([&v[0], &v[1], &v[2]], t.id, &mut out);
                }
                out
            })
            .collect()
    }

    /// An indexed mesh (validated by the caller). With vertex normals every vertex is
    /// transformed and lit once; without, each triangle is lit with its face normal.
    pub fn mesh(&self, mesh: &Mesh) -> Vec<Vec<ScreenTriangle>> {
        let color = |i: usize| {
            if mesh.colors.is_empty() {
                [1.0; 4]
            } else {
                mesh.colors[i]
            }
        };
        let uv = |i: usize| {
            if mesh.uvs.is_empty() {
                Vec2::ZERO
            } else {
                mesh.uvs[i]
            }
        };
        if mesh.normals.is_empty() {
            return mesh
                .indices
                .par_chunks(BATCH)
                .enumerate()
                .map(|(c, chunk)| {
                    let mut out = Vec::with_capacity(chunk.len());
                    for (k, idx) in chunk.iter().enumerate() {
                        let p = idx.map(|i| mesh.positions[i as usize]);
                        let n = (p[1] - p[0]).cross(p[2] - p[0]).normalize_or_zero();
                        let v = [0, 1, 2].map(|j| {
                            self.vertex(p[j], n, color(idx[j] as usize), uv(idx[j] as usize))
                        });
                        self.assemble([&v[0], &v[1], &v[2]], mesh.id(c * BATCH + k), &mut out);
                    }
                    out
                })
                .collect();
        }
        let verts: Vec<ClipVertex> = (0..mesh.positions.len())
            .into_par_iter()
            .with_min_len(4096)
            .map(|i| self.vertex(mesh.positions[i], mesh.normals[i], color(i), uv(i)))
            .collect();
        mesh.indices
            .par_chunks(BATCH)
            .enumerate()
            .map(|(c, chunk)| {
                let mut out = Vec::with_capacity(chunk.len());
                for (k, idx) in chunk.iter().enumerate() {
                    let v = idx.map(|i| &verts[i as usize]);
                    self.assemble(v, mesh.id(c * BATCH + k), &mut out);
                }
                out
            })
            .collect()
    }
}
