//! The whole pipeline in one object: state (view, lights, material, shading, culling,
//! depth test) plus the two stages, callable separately (sort-first and sort-middle
//! rendering run them on different ranks) or together.

use crate::binning::{rasterize_batches, FragmentState};
use crate::fragment::DepthFunc;
use crate::framebuffer::Framebuffer;
use crate::geometry_stage::GeometryStage;
use crate::lighting::{EyeLights, Lights, Material, Shading};
use crate::mesh::{Mesh, MeshError, Triangle};
use crate::rasterizer::CullMode;
use crate::screen::{Rect, ScreenTriangle};
use crate::view::ViewParams;
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
    pub material: Material,
    pub shading: Shading,
    pub cull: CullMode,
    pub depth_func: DepthFunc,
}

impl Pipeline {
    /// Defaults: [`ViewParams::default`] with the screen's aspect ratio, the default
    /// lights and material, Gouraud shading, no culling, depth test `Less`.
    pub fn new(width: u32, height: u32) -> Self {
        let mut view = ViewParams::default();
        view.proj = glam::Mat4::perspective_rh(
            45f32.to_radians(),
            width as f32 / height.max(1) as f32,
            0.1,
            100.0,
        );
        Self {
            width,
            height,
            view,
            lights: Lights::default(),
            material: Material::default(),
            shading: Shading::Gouraud,
            cull: CullMode::None,
            depth_func: DepthFunc::Less,
        }
    }

    fn eye_lights(&self) -> EyeLights {
        EyeLights::new(
            &self.lights,
            &self.material,
            self.view.view,
            self.view.is_orthographic(),
        )
    }

    fn stage<'a>(&self, lights: &'a EyeLights) -> GeometryStage<'a> {
        GeometryStage::new(
            self.view.view,
            self.view.proj,
            lights,
            self.shading,
            self.cull,
            self.width,
            self.height,
        )
    }

    /// The geometry stage on independent triangles: transformed, lit, clipped,
    /// culled, in screen space, in input order (a clipped triangle may become several).
    pub fn transform_and_light(&self, tris: &[Triangle]) -> Vec<ScreenTriangle> {
        let lights = self.eye_lights();
        self.stage(&lights).triangles(tris).concat()
    }

    /// The geometry stage on an indexed mesh.
    pub fn transform_mesh(&self, mesh: &Mesh) -> Result<Vec<ScreenTriangle>, RasterError> {
        mesh.validate()?;
        let lights = self.eye_lights();
        Ok(self.stage(&lights).mesh(mesh).concat())
    }

    /// The rasterizer: draws `tris` in order into `fb`, touching only pixels inside
    /// `region` (the whole screen when `None`).
    pub fn rasterize(
        &self,
        tris: &[ScreenTriangle],
        fb: &mut Framebuffer,
        region: Option<Rect>,
    ) -> Result<(), RasterError> {
        self.check(fb)?;
        let lights = self.eye_lights();
        let state = FragmentState {
            shading: self.shading,
            lights: &lights,
            depth_func: self.depth_func,
        };
        rasterize_batches(
            &[tris],
            fb,
            region.unwrap_or(Rect::full(self.width, self.height)),
            &state,
        );
        Ok(())
    }

    /// Both stages on an indexed mesh.
    pub fn render_mesh(&self, mesh: &Mesh, fb: &mut Framebuffer) -> Result<(), RasterError> {
        self.check(fb)?;
        mesh.validate()?;
        let lights = self.eye_lights();
        let batches = self.stage(&lights).mesh(mesh);
        let slices: Vec<&[ScreenTriangle]> = batches.iter().map(|b| b.as_slice()).collect();
        let state = FragmentState {
            shading: self.shading,
            lights: &lights,
            depth_func: self.depth_func,
        };
        rasterize_batches(&slices, fb, Rect::full(self.width, self.height), &state);
        Ok(())
    }

    /// Both stages on independent triangles.
    pub fn render_triangles(
        &self,
        tris: &[Triangle],
        fb: &mut Framebuffer,
    ) -> Result<(), RasterError> {
        self.check(fb)?;
        let lights = self.eye_lights();
        let batches = self.stage(&lights).triangles(tris);
        let slices: Vec<&[ScreenTriangle]> = batches.iter().map(|b| b.as_slice()).collect();
        let state = FragmentState {
            shading: self.shading,
            lights: &lights,
            depth_func: self.depth_func,
        };
        rasterize_batches(&slices, fb, Rect::full(self.width, self.height), &state);
        Ok(())
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
