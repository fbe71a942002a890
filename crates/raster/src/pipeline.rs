//! The whole pipeline in one object: state (view, lights, material, shading, culling,
//! depth test) plus the two stages, callable separately (sort-first and sort-middle
//! rendering run them on different ranks) or together.

use crate::binning::{rasterize_batches, rasterize_binned, FragmentState};
use crate::depth_snapshot::DepthSnapshot;
use crate::fragment::{DepthFunc, Unproject};
use crate::framebuffer::Framebuffer;
use crate::geometry_stage::{Batch, BatchPool, GeometryStage};
use crate::lighting::{EyeLights, Lights, Material, Shading};
use crate::mesh::{Mesh, MeshError, Triangle};
use crate::rasterizer::CullMode;
use crate::screen::{Rect, ScreenTriangle};
use crate::texture::Texture;
use crate::transparency::split_transparent;
use crate::view::ViewParams;
use std::sync::Arc;
use thiserror::Error;

#[derive(Debug, Error, PartialEq)]
pub enum RasterError {
    #[error("invalid mesh: {0}")]
    Mesh(#[from] MeshError),
    #[error("the framebuffer is {fb_w}x{fb_h} but the pipeline renders {w}x{h}")]
    SizeMismatch {
        fb_w: u32,
        fb_h: u32,
        w: u32,
        h: u32,
    },
}

/// A software OpenGL-style pipeline for a `width` x `height` screen.
///
/// Work is spread over the current rayon thread pool (run it inside
/// `ThreadPool::install` to choose the thread count); the result does not depend on
/// the number of threads.
#[derive(Clone, Debug)]
pub struct Pipeline {
    pub width: u32,
    pub height: u32,
    pub view: ViewParams,
    pub lights: Lights,
    /// The material of every triangle whose index has no entry in `materials` (all of
    /// them when the table is empty, the default).
    pub material: Material,
    /// Per-object materials: a triangle with `material == i` is shaded with
    /// `materials[i]` (Gouraud at its vertices, Phong at its pixels). Materials that
    /// let light through (`transmission > 0`) are drawn after the opaque ones, back to
    /// front, blended ([`crate::transparency`]).
    pub materials: Vec<Material>,
    /// Image textures, named by `Material::texture` and looked up at every fragment.
    pub textures: Vec<Texture>,
    /// The colour behind everything (a scene's background), blended under transparent
    /// surfaces where nothing opaque was drawn; `None` (the default) blends them over
    /// transparent black, leaving the coverage in alpha for a later composite.
    pub background: Option<irradia_core::Rgb>,
    pub shading: Shading,
    pub cull: CullMode,
    pub depth_func: DepthFunc,
    /// Buffers reused from frame to frame (shared by clones).
    scratch: Arc<BatchPool>,
}

impl Pipeline {
    /// Defaults: [`ViewParams::default`] with the screen's aspect ratio, the default
    /// lights and material, Gouraud shading, no culling, depth test `Less`.
    pub fn new(width: u32, height: u32) -> Self {
        let view = ViewParams {
            proj: glam::Mat4::perspective_rh(
                45f32.to_radians(),
                width as f32 / height.max(1) as f32,
                0.1,
                100.0,
            ),
            ..ViewParams::default()
        };
        Self {
            width,
            height,
            view,
            lights: Lights::default(),
            material: Material::default(),
            materials: Vec::new(),
            textures: Vec::new(),
            background: None,
            shading: Shading::Gouraud,
            cull: CullMode::None,
            depth_func: DepthFunc::Less,
            scratch: Arc::default(),
        }
    }

    fn eye_lights(&self) -> EyeLights {
        EyeLights::with_materials(
            &self.lights,
            &self.materials,
            &self.material,
            self.view.view,
            self.view.is_orthographic(),
        )
    }

    fn stage<'a>(&self, lights: &'a EyeLights, bin: bool) -> GeometryStage<'a> {
        GeometryStage::new(
            self.view.view,
            self.view.proj,
            lights,
            self.shading,
            self.cull,
            self.width,
            self.height,
            bin,
        )
    }

    fn fragment_state<'a>(&'a self, lights: &'a EyeLights) -> FragmentState<'a> {
        FragmentState {
            shading: self.shading,
            lights,
            depth_func: self.depth_func,
            unproject: Unproject::new(self.view.proj, self.width, self.height),
            textures: &self.textures,
            blend: false,
            background: self.background.map(|c| [c.r, c.g, c.b, 1.0]),
        }
    }

    /// Whether some material lets light through, so that a colour buffer is drawn in
    /// two passes (opaque, then transparent back to front).
    pub fn has_transparency(&self) -> bool {
        self.material.is_transparent() || self.materials.iter().any(|m| m.is_transparent())
    }

    /// Whether `fb` needs the two passes.
    fn two_pass(&self, fb: &Framebuffer) -> bool {
        self.has_transparency() && !matches!(fb.color, crate::framebuffer::ColorBuffer::Id(_))
    }

    /// The geometry stage on independent triangles: transformed, lit, clipped,
    /// culled, in screen space, in input order (a clipped triangle may become several).
    pub fn transform_and_light(&self, tris: &[Triangle]) -> Vec<ScreenTriangle> {
        let lights = self.eye_lights();
        concat(self.stage(&lights, false).triangles(tris))
    }

    /// The geometry stage on an indexed mesh.
    pub fn transform_mesh(&self, mesh: &Mesh) -> Result<Vec<ScreenTriangle>, RasterError> {
        mesh.validate()?;
        let lights = self.eye_lights();
        Ok(concat(self.stage(&lights, false).mesh(mesh)))
    }

    /// The rasterizer: draws `tris` in order into `fb`, touching only pixels inside
    /// `region` (the whole screen when `None`). With transparent materials the opaque
    /// triangles are drawn first, in order, then the transparent ones back to front
    /// (an order that does not depend on which other triangles are given, so region
    /// servers holding part of the triangles draw the serial image's pixels).
    pub fn rasterize(
        &self,
        tris: &[ScreenTriangle],
        fb: &mut Framebuffer,
        region: Option<Rect>,
    ) -> Result<(), RasterError> {
        self.check(fb)?;
        let lights = self.eye_lights();
        let region = region.unwrap_or(Rect::full(self.width, self.height));
        let state = self.fragment_state(&lights);
        if !self.two_pass(fb) {
            rasterize_batches(&[tris], fb, region, &state);
            return Ok(());
        }
        let (opaque, clear) = split_transparent(tris, &lights);
        rasterize_batches(&[&opaque], fb, region, &state);
        let blend = FragmentState {
            blend: true,
            ..state
        };
        rasterize_batches(&[&clear], fb, region, &blend);
        Ok(())
    }

    /// Both stages on an indexed mesh (binning fused into the geometry stage).
    pub fn render_mesh(&self, mesh: &Mesh, fb: &mut Framebuffer) -> Result<(), RasterError> {
        self.check(fb)?;
        mesh.validate()?;
        if self.two_pass(fb) {
            let st = self.transform_mesh(mesh)?;
            return self.rasterize(&st, fb, None);
        }
        let lights = self.eye_lights();
        let hiz = DepthSnapshot::new(self.width, self.height);
        self.stage(&lights, true)
            .with_fragments(self.fragments_for(&lights, fb))
            .with_pool(&self.scratch)
            .with_occlusion(self.depth_func)
            .mesh_grouped(mesh, group_batches(), Some(&hiz), |batches, snapshot| {
                self.draw_batches(&lights, &batches, fb, snapshot.then_some(&hiz));
                self.scratch.give(batches);
                snapshot
            });
        Ok(())
    }

    /// Both stages on independent triangles.
    pub fn render_triangles(
        &self,
        tris: &[Triangle],
        fb: &mut Framebuffer,
    ) -> Result<(), RasterError> {
        self.check(fb)?;
        if self.two_pass(fb) {
            let st = self.transform_and_light(tris);
            return self.rasterize(&st, fb, None);
        }
        let lights = self.eye_lights();
        let hiz = DepthSnapshot::new(self.width, self.height);
        self.stage(&lights, true)
            .with_fragments(self.fragments_for(&lights, fb))
            .with_pool(&self.scratch)
            .with_occlusion(self.depth_func)
            .triangles_grouped(tris, group_batches(), Some(&hiz), |batches, snapshot| {
                self.draw_batches(&lights, &batches, fb, snapshot.then_some(&hiz));
                self.scratch.give(batches);
                snapshot
            });
        Ok(())
    }

    /// Draws a group of batches, refreshing `snapshot` band by band when given.
    fn draw_batches(
        &self,
        lights: &EyeLights,
        batches: &[Batch],
        fb: &mut Framebuffer,
        snapshot: Option<&DepthSnapshot>,
    ) {
        let pieces: Vec<&[ScreenTriangle]> = batches.iter().map(|b| b.tris.as_slice()).collect();
        let frags: Vec<&[_]> = batches.iter().map(|b| b.frags.as_slice()).collect();
        let bins: Vec<&[Vec<u32>]> = batches.iter().map(|b| b.bins.as_slice()).collect();
        rasterize_binned(
            &pieces,
            &frags,
            &bins,
            fb,
            Rect::full(self.width, self.height),
            &self.fragment_state(lights),
            snapshot,
        );
    }

    /// Whether the fused paths may turn tiny triangles into fragments
    /// ([`crate::tiny`]): only where the rasterizer draws them with interpolated colour
    /// into RGBA8 (the same conditions as its dispatch in `binning`).
    fn fragments_for(&self, lights: &EyeLights, fb: &Framebuffer) -> bool {
        matches!(fb.color, crate::framebuffer::ColorBuffer::Rgba8(_))
            && self.shading != Shading::Phong
            && !lights.needs_material_fragments()
            && !self.two_pass(fb)
    }

    fn check(&self, fb: &Framebuffer) -> Result<(), RasterError> {
        if fb.width() != self.width || fb.height() != self.height {
            return Err(RasterError::SizeMismatch {
                fb_w: fb.width(),
                fb_h: fb.height(),
                w: self.width,
                h: self.height,
            });
        }
        Ok(())
    }
}

/// How many batches the fused render paths transform before drawing them: a few per
/// thread, so that the screen triangles are drawn while they are still in the cache
/// (written by the geometry stage, read by every band they touch) instead of after the
/// whole frame's triangles went out to memory. Results do not depend on it (the
/// triangles are drawn in the same order).
fn group_batches() -> usize {
    rayon::current_num_threads() * 2
}

fn concat(batches: Vec<Batch>) -> Vec<ScreenTriangle> {
    let mut out = Vec::with_capacity(batches.iter().map(|b| b.tris.len()).sum());
    for b in batches {
        out.extend_from_slice(&b.tris);
    }
    out
}
