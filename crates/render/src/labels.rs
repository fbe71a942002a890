//! The scene's captions ([`irradia_scene::Label`]) drawn over a rendered image, after
//! the render and in linear light, with `irradia_core::text` (font8x8 glyphs with a
//! dark outline).

use irradia_core::text::{draw_text, text_size, GLYPH};
use irradia_core::Image;
use irradia_scene::Scene;

/// Draws every label of `scene` into `image` (of any size: labels are placed in
/// fractions of the image).
pub fn draw_labels(scene: &Scene, image: &mut Image) {
    let (w, h) = (image.width() as f32, image.height() as f32);
    for label in &scene.labels {
        let scale = ((label.height * h) / GLYPH as f32).round().max(1.0) as u32;
        let (tw, th) = text_size(&label.text, scale);
        let x = (label.at[0] * w - tw as f32 / 2.0).round() as i64;
        let y = (label.at[1] * h - th as f32 / 2.0).round() as i64;
        draw_text(image, &label.text, x, y, scale, label.color);
    }
}
