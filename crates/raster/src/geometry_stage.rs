//! The geometry unit of the lecture's "Building Blocks": model-view-projection
//! transform, per-vertex lighting (Gouraud) or the attributes for per-pixel lighting
//! (Phong), homogeneous clipping, perspective divide, viewport mapping and back-face
//! culling. Its output, screen-space triangles, is what the rasterizer consumes.

use crate::binning::{band_count, push_to_bands};
use crate::clip::{ClipPlanes, ClipVertex};
use crate::depth_bounds::DepthBounds;
use crate::depth_snapshot::DepthSnapshot;
use crate::fragment::DepthFunc;
use crate::lighting::{EyeLights, Shading};
use crate::mesh::{Mesh, Triangle};
use crate::rasterizer::{candidate_of_snapped, snap, unsnap, Candidate, CullMode, Setup};
use crate::screen::{varying, Rect, ScreenTriangle, ScreenVertex, VARYINGS};
use glam::{Mat3, Mat4, Vec2, Vec3, Vec4};
use rayon::prelude::*;
use std::sync::atomic::{AtomicBool, Ordering};

use crate::binning::BATCH;
use crate::prefetch;
use crate::tiny::{self, Fragment, FRAGMENT_BIT};
use irradia_geometry::packet::SimdBuild;

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
    /// Bin triangles into bands while emitting them (for the fused render path).
    bin: bool,
    bands: usize,
    /// Shade triangles of a few pixel centres here and bin their fragments
    /// ([`crate::tiny`]); only when binning, for the interpolated-colour RGBA8 path.
    fragments: bool,
    /// Buffers of earlier frames to reuse.
    pool: Option<&'a BatchPool>,
    /// The depth test of the framebuffer that the grouped paths draw into, when
    /// triangles lit one by one may be tested against a snapshot of its depth before
    /// they are lit ([`GeometryStage::with_occlusion`]).
    occlusion: Option<DepthFunc>,
    /// The instruction set the per-batch loops are compiled for ([`crate::widest`]).
    build: SimdBuild,
}

impl<'a> GeometryStage<'a> {
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        view: Mat4,
        proj: Mat4,
        lights: &'a EyeLights,
        shading: Shading,
        cull: CullMode,
        width: u32,
        height: u32,
        bin: bool,
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
            bin,
            bands: band_count(height),
            fragments: false,
            pool: None,
            occlusion: None,
            build: SimdBuild::best(),
        }
    }

    /// Turns the binned triangles of at most [`tiny::MAX_CENTRES`] pixel centres into
    /// fragments when `on` (the caller draws into RGBA8 with interpolated colour).
    pub fn with_fragments(mut self, on: bool) -> Self {
        self.fragments = on && self.bin;
        self
    }

    /// Lets the grouped paths that light each triangle's corners themselves (soups,
    /// flat meshes, per-face materials, independent triangles) ask their sink to
    /// refresh a snapshot of the depth buffer ([`DepthSnapshot`]) when it draws a group
    /// and drop, before lighting them, the triangles of later groups that cannot pass
    /// `func` anywhere (hierarchical-z occlusion culling, Greene, Kass and Miller 1993).
    /// Exact: the test is the rasterizer's own depth-bound test
    /// ([`DepthSnapshot::hides`]) on the same depth plane, against bounds that only
    /// overestimate the depths stored when the triangle is drawn, so images are
    /// unchanged. Only for `Less` and `LessEqual`, and only when every fragment drawn
    /// is depth tested first (no blending pass).
    pub fn with_occlusion(mut self, func: DepthFunc) -> Self {
        self.occlusion = match func {
            DepthFunc::Less | DepthFunc::LessEqual if self.bin => Some(func),
            _ => None,
        };
        self
    }

    /// Compiles the per-batch loops for `build` instead of the widest one the CPU runs
    /// (tests compare the builds).
    #[cfg(test)]
    pub(crate) fn with_build(mut self, build: SimdBuild) -> Self {
        self.build = build;
        self
    }

    /// Takes output buffers from `pool` instead of allocating them.
    pub fn with_pool(mut self, pool: &'a BatchPool) -> Self {
        self.pool = Some(pool);
        self
    }

    /// Transforms and lights one vertex (Gouraud: with material `material`).
    #[inline(always)]
    fn vertex(&self, p: Vec3, n: Vec3, color: [f32; 4], uv: Vec2, material: u32) -> ClipVertex {
        ClipVertex {
            pos: self.clip_position(p),
            var: self.varyings(p, n, color, uv, material),
        }
    }

    /// The attributes of [`Self::vertex`]: the lit colour (Gouraud), the eye-space
    /// normal and base colour (Phong) or the colour (unlit), and the texture coordinate.
    #[inline(always)]
    fn varyings(
        &self,
        p: Vec3,
        n: Vec3,
        color: [f32; 4],
        uv: Vec2,
        material: u32,
    ) -> [f32; VARYINGS] {
        let mut var = [0.0; VARYINGS];
        match self.shading {
            Shading::Unlit => var[..4].copy_from_slice(&color),
            Shading::Gouraud => {
                let pe = self.view.transform_point3(p);
                let ne = (self.normal_matrix * n).normalize_or_zero();
                let c = self.lights.shade_with(
                    material,
                    pe,
                    ne,
                    Vec3::new(color[0], color[1], color[2]),
                );
                var[..4].copy_from_slice(&[c.x, c.y, c.z, color[3]]);
            }
            Shading::Phong => {
                let ne = (self.normal_matrix * n).normalize_or_zero();
                var[varying::NORMAL..varying::NORMAL + 3].copy_from_slice(&ne.to_array());
                var[varying::BASE_COLOR..varying::BASE_COLOR + 3].copy_from_slice(&color[..3]);
            }
        }
        var[varying::UV] = uv.x;
        var[varying::UV + 1] = uv.y;
        var
    }

    /// The clip-space position of object-space point `p` (the one function that makes
    /// it, so that clipping recomputes exactly what [`Self::vertex`] computed).
    #[inline(always)]
    fn clip_position(&self, p: Vec3) -> Vec4 {
        self.view_proj * p.extend(1.0)
    }

    /// Perspective divide and viewport: NDC x, y in [-1, 1] to pixels, y down.
    #[inline(always)]
    fn project(&self, c: &ClipVertex) -> ScreenVertex {
        self.project_with(c.pos, c.var)
    }

    /// [`Self::project`] of clip position `pos` with attributes `var`.
    #[inline(always)]
    fn project_with(&self, pos: Vec4, var: [f32; VARYINGS]) -> ScreenVertex {
        let inv_w = 1.0 / pos.w;
        ScreenVertex {
            x: (pos.x * inv_w * 0.5 + 0.5) * self.width,
            y: (0.5 - pos.y * inv_w * 0.5) * self.height,
            z: pos.z * inv_w,
            inv_w,
            var,
        }
    }

    /// One triangle whose corners are lit here (not shared with other triangles):
    /// object-space corners `p`, attributes `var(j)` of corner `j`. The corners are
    /// placed on screen and the triangle culled first, and only a survivor is lit:
    /// the same output as [`Self::prepare`] of [`Self::vertex`] of each corner and then
    /// [`Self::assemble`], without the lighting of triangles that leave nothing. With a
    /// depth snapshot (`hiz`, see [`Self::with_occlusion`]) a triangle that cannot pass
    /// the depth test anywhere leaves nothing either; `probe` turns the test off for
    /// the rest of a batch where it rarely finds one.
    #[inline(always)]
    fn lit_late(
        &self,
        p: impl Fn(usize) -> Vec3,
        var: impl Fn(usize) -> [f32; VARYINGS],
        id: (u32, u32),
        hiz: Option<&DepthSnapshot>,
        probe: &mut Probe,
        out: &mut Batch,
    ) {
        // Corner by corner from the caller's arrays: an array of `Vec3`s built here and
        // read back in 16-byte pieces stalled on store forwarding (twice a triangle).
        let pos: [Vec4; 3] = std::array::from_fn(|j| self.clip_position(p(j)));
        let codes = pos.map(|c| self.planes.outcode(c));
        if codes[0] & codes[1] & codes[2] != 0 {
            return; // all outside one plane
        }
        if codes[0] | codes[1] | codes[2] != 0 {
            // Clipped: the general path (it needs every corner's attributes).
            let v: [Prepared; 3] = std::array::from_fn(|j| {
                self.prepare(ClipVertex {
                    pos: pos[j],
                    var: var(j),
                })
            });
            self.assemble([&v[0], &v[1], &v[2]], p, id, out);
            return;
        }
        let mut s = pos.map(|c| self.project_with(c, [0.0; VARYINGS]));
        // As `prepare` stores and `Prepared::snapped` reads them.
        let on_grid = |v: &ScreenVertex| (snap(v.x) as i32 as i64, snap(v.y) as i32 as i64);
        let q = [on_grid(&s[0]), on_grid(&s[1]), on_grid(&s[2])];
        let Some(k) = candidate_of_snapped(q, self.cull, &self.screen) else {
            return;
        };
        if let (Some(b), Some(func)) = (hiz, self.occlusion) {
            if probe.on() {
                let st = Setup::edges([&s[0], &s[1], &s[2]], k.p, k.area).with_plane();
                let (x0, x1, y0, y1) = k.bounds;
                let hidden = b.hides(&st, func, x0, x1, y0, y1);
                probe.count(hidden);
                if hidden {
                    return;
                }
            }
        }
        for (j, v) in s.iter_mut().enumerate() {
            v.var = var(j);
        }
        self.emit_candidate([&s[0], &s[1], &s[2]], k, id, out);
    }

    /// A vertex with its clip outcode, projected and snapped to the rasterizer's
    /// fixed-point grid when it needs no clipping (see [`Prepared`]).
    #[inline(always)]
    fn prepare(&self, clip: ClipVertex) -> Prepared {
        let code = self.planes.outcode(clip.pos);
        let screen = if code == 0 {
            let mut s = self.project(&clip);
            // Inside the guard band: the fixed-point position fits an i32.
            s.x = f32::from_bits(snap(s.x) as i32 as u32);
            s.y = f32::from_bits(snap(s.y) as i32 as u32);
            s
        } else {
            // Not projected (it needs clipping): the clip position in place of the
            // screen one, and the attributes, which the clipper interpolates onto the
            // polygon's new vertices.
            ScreenVertex {
                x: clip.pos.x,
                y: clip.pos.y,
                z: clip.pos.z,
                inv_w: clip.pos.w,
                var: clip.var,
            }
        };
        Prepared { screen, code }
    }

    /// Culls, and bins or shades, the triangle of vertices `v` at the snapped positions
    /// `p` (the vertices' own `x` and `y` are not read: [`Prepared`] keeps the fixed-point
    /// position there).
    #[inline(always)]
    fn emit(&self, v: [&ScreenVertex; 3], p: [(i64, i64); 3], id: (u32, u32), out: &mut Batch) {
        // Cull before building the triangle: most rejected ones are never copied.
        let Some(k) = candidate_of_snapped(p, self.cull, &self.screen) else {
            return;
        };
        self.emit_candidate(v, k, id, out);
    }

    /// [`Self::emit`] of a triangle that survived culling as candidate `k`.
    #[inline(always)]
    fn emit_candidate(
        &self,
        v: [&ScreenVertex; 3],
        k: Candidate,
        (id, material): (u32, u32),
        out: &mut Batch,
    ) {
        let p = k.p;
        if k.centres() <= tiny::MAX_CENTRES {
            if self.fragments {
                // Shaded here; a triangle that covers no centre leaves no fragment.
                tiny::fragments(v, &k, |f| {
                    let i = out.frags.len() as u32 | FRAGMENT_BIT;
                    push_to_bands(&mut out.bins, i, f.y as i64, f.y as i64);
                    out.frags.push(f);
                });
                return;
            }
            if !k.covers_a_centre() {
                return;
            }
        }
        if self.bin {
            let (_, _, y0, y1) = k.bounds;
            push_to_bands(&mut out.bins, out.tris.len() as u32, y0, y1);
        }
        // The screen position on the grid: the rasterizer snaps it back to `p`.
        let on_grid = |j: usize| ScreenVertex {
            x: unsnap(p[j].0),
            y: unsnap(p[j].1),
            ..*v[j]
        };
        out.tris.push(ScreenTriangle {
            v: [on_grid(0), on_grid(1), on_grid(2)],
            id,
            material,
        });
    }

    /// Clips, projects and culls one triangle, appending what is left (one triangle, or
    /// a fan when clipping cut it into a polygon). `position(j)` is the object-space
    /// position of vertex `j`, asked for only when the triangle needs clipping (the
    /// clip position of a vertex inside every plane is not kept: recomputing it for the
    /// rare clipped triangle is cheaper than storing it for every vertex).
    #[inline(always)]
    fn assemble(
        &self,
        t: [&Prepared; 3],
        position: impl Fn(usize) -> Vec3,
        id: (u32, u32),
        out: &mut Batch,
    ) {
        let codes = [t[0].code, t[1].code, t[2].code];
        if codes[0] & codes[1] & codes[2] != 0 {
            return; // all outside one plane
        }
        let any = codes[0] | codes[1] | codes[2];
        if any == 0 {
            let p = [t[0].snapped(), t[1].snapped(), t[2].snapped()];
            self.emit([&t[0].screen, &t[1].screen, &t[2].screen], p, id, out);
            return;
        }
        let c: [ClipVertex; 3] = std::array::from_fn(|j| {
            let s = &t[j].screen;
            ClipVertex {
                pos: if t[j].code == 0 {
                    self.clip_position(position(j))
                } else {
                    Vec4::new(s.x, s.y, s.z, s.inv_w)
                },
                var: s.var,
            }
        });
        let poly = self.planes.clip([&c[0], &c[1], &c[2]], any);
        for i in 1..poly.len.saturating_sub(1) {
            let v = [
                self.project(&poly.v[0]),
                self.project(&poly.v[i]),
                self.project(&poly.v[i + 1]),
            ];
            let p = v.each_ref().map(|s| (snap(s.x), snap(s.y)));
            self.emit([&v[0], &v[1], &v[2]], p, id, out);
        }
    }

    fn new_batch(&self, capacity: usize) -> Batch {
        let mut b = self
            .pool
            .and_then(|p| p.0.lock().ok().and_then(|mut v| v.pop()))
            .unwrap_or(Batch {
                tris: Vec::new(),
                frags: Vec::new(),
                bins: Vec::new(),
            });
        b.tris.clear();
        b.tris.reserve(capacity);
        b.frags.clear();
        if self.fragments {
            b.frags.reserve(capacity);
        }
        let bands = if self.bin { self.bands } else { 0 };
        b.bins.resize_with(bands, Vec::new);
        b.bins.truncate(bands);
        for bin in &mut b.bins {
            bin.clear();
            // About one band in `bands` of the triangles, plus straddlers.
            bin.reserve(capacity / bands.max(1) * 2 + 16);
        }
        b
    }

    /// Independent triangles, in batches that keep the input order.
    pub fn triangles(&self, tris: &[Triangle]) -> Vec<Batch> {
        self.triangles_behind(tris, None)
    }

    /// [`Self::triangles`], dropping those `hiz` hides ([`Self::with_occlusion`]).
    fn triangles_behind(&self, tris: &[Triangle], hiz: Option<&DepthSnapshot>) -> Vec<Batch> {
        self.triangles_probed(tris, hiz, &AtomicBool::new(false))
    }

    /// [`Self::triangles_behind`], setting `paying` when a batch found the snapshot
    /// worth testing to its end ([`Probe`]).
    fn triangles_probed(
        &self,
        tris: &[Triangle],
        hiz: Option<&DepthSnapshot>,
        paying: &AtomicBool,
    ) -> Vec<Batch> {
        tris.par_chunks(BATCH)
            .map(|chunk| {
                let mut out = self.new_batch(chunk.len());
                let mut probe = Probe::default();
                self.build.run(
                    #[inline(always)]
                    || {
                        for t in chunk {
                            let p = |j: usize| t.v[j].position;
                            self.lit_late(
                                p,
                                // Inlined into the build's loop (widest.rs) with its lighting.
                                #[inline(always)]
                                |j: usize| {
                                    let v = &t.v[j];
                                    self.varyings(v.position, v.normal, v.color, v.uv, t.material)
                                },
                                (t.id, t.material),
                                hiz,
                                &mut probe,
                                &mut out,
                            );
                        }
                    },
                );
                probe.report(hiz.is_some(), paying);
                out
            })
            .collect()
    }

    /// Whether to ask for a depth snapshot after group `g` (`tested`: its batches had
    /// one; `paying`: one of them still found it worth testing at its end): always
    /// at first, then while it pays, and every [`RETRY_GROUPS`] groups to look again
    /// (a scene of little depth complexity does not read the whole depth buffer after
    /// every group for nothing).
    fn wants_snapshot(&self, g: usize, tested: bool, paying: &AtomicBool) -> bool {
        self.occlusion.is_some()
            && (!tested || paying.load(Ordering::Relaxed) || g % RETRY_GROUPS == RETRY_GROUPS - 1)
    }

    /// [`GeometryStage::triangles`] a group of `group` batches at a time: `sink` gets
    /// each group's batches (in order) while they are still in the cache, and can hand
    /// them back to the pool for the next group. Its second argument says whether the
    /// stage wants the depth snapshot `hiz` refreshed as the group is drawn
    /// ([`Self::with_occlusion`]); it returns whether it did.
    pub fn triangles_grouped(
        &self,
        tris: &[Triangle],
        group: usize,
        hiz: Option<&DepthSnapshot>,
        mut sink: impl FnMut(Vec<Batch>, bool) -> bool,
    ) {
        let group = Self::lit_late_group(group);
        let parts: Vec<&[Triangle]> = tris.chunks(group.saturating_mul(BATCH)).collect();
        self.grouped(
            parts.len(),
            hiz,
            |g, hiz, paying| self.triangles_probed(parts[g], hiz, paying),
            &mut sink,
        );
    }

    /// The batches in a group of the paths that light corners triangle by triangle
    /// (and test them against the depth snapshot): at least [`LIT_LATE_GROUP_BATCHES`],
    /// whatever smaller `group` the caller sized for the cache.
    fn lit_late_group(group: usize) -> usize {
        group.max(LIT_LATE_GROUP_BATCHES)
    }

    /// Makes the batches of groups `0..groups` (`geometry(g, snapshot, paying)`, the
    /// group's batches in parallel) and hands each group's to `sink` in order. Group
    /// `g + 1` is tested against the depth snapshot `hiz` when drawing group `g`
    /// refreshed it ([`crate::depth_snapshot`]; the bands refresh their tiles as they
    /// finish, so no pass of its own reads the depth buffer between the groups).
    fn grouped(
        &self,
        groups: usize,
        hiz: Option<&DepthSnapshot>,
        geometry: impl Fn(usize, Option<&DepthSnapshot>, &AtomicBool) -> Vec<Batch> + Sync,
        sink: &mut impl FnMut(Vec<Batch>, bool) -> bool,
    ) {
        // Whether the last group drawn refreshed the snapshot.
        let mut refreshed = false;
        for g in 0..groups {
            let tested = hiz.filter(|_| refreshed);
            let paying = AtomicBool::new(false);
            let batches = geometry(g, tested, &paying);
            let refresh = hiz.is_some() && self.wants_snapshot(g, tested.is_some(), &paying);
            refreshed = sink(batches, refresh);
        }
    }

    /// An indexed mesh (validated by the caller). With vertex normals every vertex is
    /// transformed, lit and projected once; without, each triangle is lit with its
    /// face normal.
    pub fn mesh(&self, mesh: &Mesh) -> Vec<Batch> {
        let mut all = Vec::new();
        self.mesh_grouped(mesh, usize::MAX, None, |b, _| {
            all.extend(b);
            false
        });
        all
    }

    /// [`GeometryStage::mesh`] a group of `group` batches at a time, handed to `sink` in
    /// order (see [`GeometryStage::triangles_grouped`]; snapshots are asked for only
    /// where the corners are lit triangle by triangle).
    pub fn mesh_grouped(
        &self,
        mesh: &Mesh,
        group: usize,
        hiz: Option<&DepthSnapshot>,
        mut sink: impl FnMut(Vec<Batch>, bool) -> bool,
    ) {
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
        // Flat meshes, and meshes that share few vertices (a triangle soup), are done
        // triangle by triangle: no per-vertex array to write and read back. So are
        // meshes with per-face materials under Gouraud shading, whose shared vertices
        // are lit once per material of the faces around them.
        let flat = mesh.normals.is_empty();
        let per_face_lighting = !mesh.materials.is_empty() && self.shading == Shading::Gouraud;
        let lit_late = flat || per_face_lighting || mesh.positions.len() >= 2 * mesh.indices.len();
        let group = if lit_late {
            Self::lit_late_group(group)
        } else {
            group.max(1)
        };
        let parts: Vec<&[[u32; 3]]> = mesh.indices.chunks(group.saturating_mul(BATCH)).collect();
        if lit_late {
            let geometry = |g: usize, hiz_ref: Option<&DepthSnapshot>, paying: &AtomicBool| {
                parts[g]
                    .par_chunks(BATCH)
                    .enumerate()
                    .map(|(c, chunk)| {
                        let c = g * group + c;
                        let mut out = self.new_batch(chunk.len());
                        let mut probe = Probe::default();
                        self.build.run(
                            #[inline(always)]
                            || {
                                for (k, idx) in chunk.iter().enumerate() {
                                    let p = |j: usize| mesh.positions[idx[j] as usize];
                                    let face = if flat {
                                        (p(1) - p(0)).cross(p(2) - p(0)).normalize_or_zero()
                                    } else {
                                        Vec3::ZERO
                                    };
                                    let t = c * BATCH + k;
                                    let material = mesh.material(t);
                                    let id = (mesh.id(t), material);
                                    self.lit_late(
                                        p,
                                        // Inlined into the build's loop (widest.rs) with
                                        // its lighting.
                                        #[inline(always)]
                                        |j: usize| {
                                            let i = idx[j] as usize;
                                            let n = if flat { face } else { mesh.normals[i] };
                                            self.varyings(p(j), n, color(i), uv(i), material)
                                        },
                                        id,
                                        hiz_ref,
                                        &mut probe,
                                        &mut out,
                                    );
                                }
                            },
                        );
                        probe.report(hiz_ref.is_some(), paying);
                        out
                    })
                    .collect()
            };
            self.grouped(parts.len(), hiz, geometry, &mut sink);
            return;
        }
        let mut verts: Vec<Prepared> = self
            .pool
            .and_then(|p| p.1.lock().ok().map(|mut v| std::mem::take(&mut *v)))
            .unwrap_or_default();
        // Every record is overwritten below: only a change of size writes filler.
        verts.resize(mesh.positions.len(), Prepared::default());
        verts
            .par_chunks_mut(VERTEX_CHUNK)
            .enumerate()
            .for_each(|(c, out)| {
                self.build.run(
                    #[inline(always)]
                    || {
                        for (k, r) in out.iter_mut().enumerate() {
                            let i = c * VERTEX_CHUNK + k;
                            let n = mesh.normals[i];
                            *r =
                                self.prepare(self.vertex(mesh.positions[i], n, color(i), uv(i), 0));
                        }
                    },
                )
            });
        let geometry = |g: usize, _: Option<&DepthSnapshot>, _: &AtomicBool| {
            parts[g]
                .par_chunks(BATCH)
                .enumerate()
                .map(|(c, chunk)| {
                    let c = g * group + c;
                    let mut out = self.new_batch(chunk.len());
                    self.build.run(
                        #[inline(always)]
                        || {
                            for (k, idx) in chunk.iter().enumerate() {
                                if let Some(ahead) = chunk.get(k + prefetch::VERTEX_AHEAD) {
                                    for &i in ahead {
                                        if let Some(r) = verts.get(i as usize) {
                                            prefetch::record(r);
                                        }
                                    }
                                }
                                let v = idx.map(|i| &verts[i as usize]);
                                let t = c * BATCH + k;
                                let position = |j: usize| mesh.positions[idx[j] as usize];
                                self.assemble(
                                    v,
                                    position,
                                    (mesh.id(t), mesh.material(t)),
                                    &mut out,
                                );
                            }
                        },
                    );
                    out
                })
                .collect()
        };
        // No snapshots: this path tests no triangle against one.
        let mut sink = |batches, _| sink(batches, false);
        self.grouped(parts.len(), None, geometry, &mut sink);
        if let Some(pool) = self.pool {
            if let Ok(mut v) = pool.1.lock() {
                *v = verts;
            }
        }
    }
}

/// Whether a batch still tests its triangles against the depth snapshot: after
/// [`DepthBounds::PROBATION`] tests, only while at least a quarter of them found the
/// triangle hidden (the test, a depth plane and four corner depths, costs far less than
/// lighting the three corners and drawing the triangle, which it saves; a scene of
/// little depth complexity stops paying for it).
#[derive(Default)]
struct Probe {
    tested: u32,
    hidden: u32,
}

/// The fewest batches in a group of the paths that light corners triangle by triangle
/// ([`GeometryStage::lit_late_group`]): every band computes its depth bounds and
/// refreshes its tiles of the snapshot once per group, and the threads wait for each
/// other once per group, so groups of 8 batches (65,536 triangles, at most 10 MB of
/// screen triangles) drew the random-triangle workload with 0.92 of the CPU time of
/// 2 batches at one thread and 0.97 of that of 4 at two threads (16 and 32 were slower
/// again). The shared-vertex path keeps the caller's smaller groups (the gyroid
/// workload took 1.03-1.04 of the time with 8).
const LIT_LATE_GROUP_BATCHES: usize = 8;

/// Vertices of a shared-vertex mesh transformed and lit by one task.
const VERTEX_CHUNK: usize = 4096;

/// Groups after which a depth snapshot is asked for again though the last one did
/// not pay ([`GeometryStage::wants_snapshot`]).
const RETRY_GROUPS: usize = 8;

impl Probe {
    /// Sets `paying` when the batch tested against a snapshot and still found it worth
    /// it at its end.
    #[inline]
    fn report(&self, had_snapshot: bool, paying: &AtomicBool) {
        if had_snapshot && self.on() {
            paying.store(true, Ordering::Relaxed);
        }
    }

    #[inline(always)]
    fn on(&self) -> bool {
        self.tested < DepthBounds::PROBATION || self.hidden * 4 >= self.tested
    }

    #[inline(always)]
    fn count(&mut self, hidden: bool) {
        self.tested += 1;
        self.hidden += hidden as u32;
    }
}

/// A transformed vertex: its outcode and, when inside every plane, its screen vertex
/// with the position already snapped to the rasterizer's fixed-point grid: `screen.x`
/// and `screen.y` then hold the bits of the i32 fixed-point coordinates
/// ([`Prepared::snapped`]), not pixels. A shared vertex of an indexed mesh is snapped
/// once here instead of once per triangle around it (about six on a closed mesh);
/// triangles leave the stage with `x` and `y` put back on the grid ([`unsnap`]), which
/// the rasterizer snaps to the same integers, so coverage is unchanged.
/// Otherwise (`code != 0`) `screen` holds the clip position (x, y, z, w in `x`, `y`,
/// `z`, `inv_w`). `screen.var` always holds the attributes. 52 bytes instead of the 80
/// with a separate clip position: the per-vertex pass of a large mesh writes these
/// records and the triangle pass reads them back through memory.
#[derive(Clone, Copy, Debug, Default)]
struct Prepared {
    screen: ScreenVertex,
    code: u8,
}

impl Prepared {
    /// The fixed-point screen position of a vertex inside every plane (`code == 0`).
    #[inline(always)]
    fn snapped(&self) -> (i64, i64) {
        debug_assert_eq!(self.code, 0);
        (
            self.screen.x.to_bits() as i32 as i64,
            self.screen.y.to_bits() as i32 as i64,
        )
    }
}

/// Screen triangles (and fragments of tiny ones) of one batch, in input order, and (when binning) for each band of
/// the screen the indices of the triangles touching it.
pub(crate) struct Batch {
    pub tris: Vec<ScreenTriangle>,
    /// The fragments of tiny triangles ([`crate::tiny`]), indexed by bin entries with
    /// [`FRAGMENT_BIT`] set.
    pub frags: Vec<Fragment>,
    pub bins: Vec<Vec<u32>>,
}

/// Batches kept between frames so that their memory is reused (fresh allocations of
/// hundreds of megabytes per frame cost page faults).
#[derive(Default)]
pub(crate) struct BatchPool(
    pub std::sync::Mutex<Vec<Batch>>,
    std::sync::Mutex<Vec<Prepared>>,
);

impl BatchPool {
    /// Returns batches for reuse.
    pub fn give(&self, batches: Vec<Batch>) {
        if let Ok(mut v) = self.0.lock() {
            v.extend(batches);
        }
    }
}

impl std::fmt::Debug for BatchPool {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("BatchPool")
    }
}
