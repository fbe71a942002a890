//! Labels drawn into an image: ASCII text in the 8x8 bitmap glyphs of the `font8x8`
//! crate (public-domain IBM PC glyphs), scaled by an integer factor, with a one-glyph-
//! pixel dark outline so the text reads on any background. Used for captions of
//! rendered galleries (the `materials` built-in scene), drawn after the render, in
//! linear light.

use crate::{Image, Rgb};
use font8x8::{UnicodeFonts, BASIC_FONTS};

/// Width (and height) of one glyph cell in font pixels.
pub const GLYPH: u32 = 8;

/// The size in image pixels of `text` drawn at `scale`: (width, height).
pub fn text_size(text: &str, scale: u32) -> (u32, u32) {
    let n = text.chars().count() as u32;
    (n * GLYPH * scale, GLYPH * scale)
}

/// Whether font pixel (gx, gy) of glyph `c` is set; characters without a glyph (outside
/// basic Latin) are drawn as '?'.
fn glyph_pixel(c: char, gx: u32, gy: u32) -> bool {
    let rows = BASIC_FONTS
        .get(c)
        .or_else(|| BASIC_FONTS.get('?'))
        .unwrap_or([0; 8]);
    rows[gy as usize] >> gx & 1 == 1
}

/// Draws `text` with its top-left corner at pixel (x, y), `scale` image pixels per
/// font pixel, in `color` with a black outline. Parts outside the image are clipped.
pub fn draw_text(image: &mut Image, text: &str, x: i64, y: i64, scale: u32, color: Rgb) {
    let scale = scale.max(1);
    let chars: Vec<char> = text.chars().collect();
    let (w, h) = (chars.len() as i64 * GLYPH as i64, GLYPH as i64);
    // Font-pixel coverage with a one-pixel border for the outline.
    let on = |fx: i64, fy: i64| -> bool {
        if fx < 0 || fy < 0 || fx >= w || fy >= h {
            return false;
        }
        let c = chars[(fx / GLYPH as i64) as usize];
        glyph_pixel(c, (fx % GLYPH as i64) as u32, fy as u32)
    };
    for fy in -1..=h {
        for fx in -1..=w {
            let value = if on(fx, fy) {
                color
            } else if (-1..=1).any(|dy| (-1..=1).any(|dx| on(fx + dx, fy + dy))) {
                Rgb::BLACK
            } else {
                continue;
            };
            for sy in 0..scale as i64 {
                for sx in 0..scale as i64 {
                    let px = x + fx * scale as i64 + sx;
                    let py = y + fy * scale as i64 + sy;
                    if px >= 0 && py >= 0 && px < image.width() as i64 && py < image.height() as i64
                    {
                        image.set(px as u32, py as u32, value);
                    }
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_letter_is_drawn_with_its_glyph_and_outline_and_clipped() {
        let mut img = Image::new(40, 20).unwrap();
        draw_text(&mut img, "I", 4, 4, 2, Rgb::WHITE);
        // font8x8's 'I' has its vertical bar in columns 2..=3 of rows 1..=5.
        assert_eq!(img.get(4 + 2 * 2, 4 + 2 * 3), Rgb::WHITE);
        let white = img.pixels().iter().filter(|p| **p == Rgb::WHITE).count();
        let expected: u32 = (0..8)
            .flat_map(|gy| (0..8).map(move |gx| (gx, gy)))
            .filter(|&(gx, gy)| glyph_pixel('I', gx, gy))
            .count() as u32
            * 4;
        assert_eq!(white as u32, expected);
        // Drawing past the edges clips without panicking.
        draw_text(&mut img, "clipped text", 30, 15, 3, Rgb::WHITE);
        draw_text(&mut img, "x", -100, -100, 1, Rgb::WHITE);
        assert_eq!(text_size("abc", 2), (48, 16));
    }
}
