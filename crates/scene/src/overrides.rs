//! Overriding a loaded scene's image settings (`--width`, `--height`, `--spp`,
//! `--integrator`, `--max-depth` on the command line; the keyword arguments of the
//! Python binding): applied in one place, with the image size checked before any
//! memory is allocated.

use crate::error::SceneError;
use crate::scene::{Integrator, Scene};

/// Settings to replace in a scene; `None` keeps the scene's own.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Overrides {
    pub width: Option<u32>,
    pub height: Option<u32>,
    pub spp: Option<u32>,
    pub integrator: Option<Integrator>,
    pub max_depth: Option<u32>,
}

impl Overrides {
    /// Sets the given values in `scene`, then refuses (bad input) an image size whose
    /// pixel buffer cannot be allocated.
    pub fn apply(&self, scene: &mut Scene) -> Result<(), SceneError> {
        let s = &mut scene.settings;
        if let Some(w) = self.width {
            s.width = w;
        }
        if let Some(h) = self.height {
            s.height = h;
        }
        if let Some(n) = self.spp {
            s.spp = n;
        }
        if let Some(i) = self.integrator {
            s.integrator = i;
        }
        if let Some(d) = self.max_depth {
            s.max_depth = d;
        }
        irradia_core::image::check_size(s.width, s.height, 12)
            .map_err(|e| SceneError::input("", e.to_string()))?;
        Ok(())
    }
}
