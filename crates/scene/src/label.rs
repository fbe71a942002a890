//! Captions drawn over the rendered image (the `[[labels]]` of a scene file), placed in
//! fractions of the image so they stay put when the resolution changes; the
//! `materials` built-in names each ball's BSDF with them, as Mitsuba's gallery does.

use irradia_core::Rgb;

/// One caption.
#[derive(Clone, Debug, PartialEq)]
pub struct Label {
    pub text: String,
    /// Centre of the text, as fractions of the image width and height from the top
    /// left.
    pub at: [f32; 2],
    /// Text height as a fraction of the image height.
    pub height: f32,
    /// Linear colour of the glyphs (drawn with a dark outline).
    pub color: Rgb,
}
