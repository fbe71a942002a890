//! irradia-scene: the validated, in-memory scene every integrator renders, the scene
//! file formats (TOML and JSON, one schema) that produce it, and the built-in scenes.
//!
//! Integrators never parse files; they receive a [`Scene`].

pub mod bsdf;
pub mod builtin;
pub mod camera;
pub mod envmap;
pub mod error;
pub mod file;
pub mod label;
pub mod light;
pub mod material;
pub mod overrides;
pub mod projector;
pub mod scene;
pub mod texture;

pub use bsdf::BsdfDesc;
pub use camera::{Camera, FovAxis, Projection};
pub use envmap::EnvMap;
pub use error::{ErrorKind, SceneError};
pub use file::{load_file, load_str, load_tree, SceneSyntax};
pub use label::Label;
pub use light::{spot_falloff, Light, SpotProfile, SpotTexture};
pub use material::{image_texel, Material, ShadingModel, Texture};
pub use overrides::Overrides;
pub use projector::{Projector, ProjectorSample};
pub use scene::{
    CropWindow, Integrator, LightSelection, Object, PixelFilter, RenderSettings, Scene,
};
