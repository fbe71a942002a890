//! The framebuffer: a colour buffer (RGBA8, RGBA32F, or an ID buffer of u32 item ids)
//! and a 32-bit float depth buffer, row-major with the origin at the top left.

use irradia_core::image::check_size;
use irradia_core::{Image, ImageError, Rgb};

/// What the colour buffer stores.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ColorFormat {
    /// 8 bits per channel; the shaded value clamped to [0, 1] and scaled to 255 with no
    /// transfer curve (as OpenGL does without an sRGB framebuffer).
    Rgba8,
    /// 32-bit float per channel, unclamped.
    Rgba32F,
    /// One u32 per pixel: the id of the nearest triangle, [`NO_ID`] where none is
    /// (item buffers for hemicubes and picking).
    Id,
}

/// The id of a pixel no triangle covers.
pub const NO_ID: u32 = u32::MAX;

#[derive(Clone, Debug, PartialEq)]
pub enum ColorBuffer {
    Rgba8(Vec<[u8; 4]>),
    Rgba32F(Vec<[f32; 4]>),
    Id(Vec<u32>),
}

/// Colour and depth of `width * height` pixels.
#[derive(Clone, Debug, PartialEq)]
pub struct Framebuffer {
    width: u32,
    height: u32,
    pub color: ColorBuffer,
    /// NDC depth in [0, 1]; cleared to 1 (the far plane).
    pub depth: Vec<f32>,
}

impl Framebuffer {
    /// A cleared framebuffer (black, transparent, depth 1, no ids). Fails without
    /// allocating when the size is zero or too large.
    pub fn new(width: u32, height: u32, format: ColorFormat) -> Result<Self, ImageError> {
        let bytes = 4 + match format {
            ColorFormat::Rgba8 | ColorFormat::Id => 4,
            ColorFormat::Rgba32F => 16,
        };
        let n = check_size(width, height, bytes)?;
        let color = match format {
            ColorFormat::Rgba8 => ColorBuffer::Rgba8(vec![[0; 4]; n]),
            ColorFormat::Rgba32F => ColorBuffer::Rgba32F(vec![[0.0; 4]; n]),
            ColorFormat::Id => ColorBuffer::Id(vec![NO_ID; n]),
        };
        Ok(Self {
            width,
            height,
            color,
            depth: vec![1.0; n],
        })
    }

    pub fn width(&self) -> u32 {
        self.width
    }

    pub fn height(&self) -> u32 {
        self.height
    }

    pub fn format(&self) -> ColorFormat {
        match self.color {
            ColorBuffer::Rgba8(_) => ColorFormat::Rgba8,
            ColorBuffer::Rgba32F(_) => ColorFormat::Rgba32F,
            ColorBuffer::Id(_) => ColorFormat::Id,
        }
    }

    /// Sets every pixel to `rgba` (or, for an ID buffer, [`NO_ID`]) and depth to 1.
    pub fn clear(&mut self, rgba: [f32; 4]) {
        match &mut self.color {
            ColorBuffer::Rgba8(c) => c.fill(to_rgba8(rgba)),
            ColorBuffer::Rgba32F(c) => c.fill(rgba),
            ColorBuffer::Id(c) => c.fill(NO_ID),
        }
        self.depth.fill(1.0);
    }

    #[inline]
    pub fn index(&self, x: u32, y: u32) -> usize {
        y as usize * self.width as usize + x as usize
    }

    pub fn depth_at(&self, x: u32, y: u32) -> f32 {
        self.depth[self.index(x, y)]
    }

    /// The colour of a pixel as RGBA floats (an id buffer gives the id in red).
    pub fn rgba_at(&self, x: u32, y: u32) -> [f32; 4] {
        let i = self.index(x, y);
        match &self.color {
            ColorBuffer::Rgba8(c) => c[i].map(|v| v as f32 / 255.0),
            ColorBuffer::Rgba32F(c) => c[i],
            ColorBuffer::Id(c) => [c[i] as f32, 0.0, 0.0, 1.0],
        }
    }

    /// The id at a pixel (`None` unless this is an ID buffer).
    pub fn id_at(&self, x: u32, y: u32) -> Option<u32> {
        match &self.color {
            ColorBuffer::Id(c) => Some(c[self.index(x, y)]),
            _ => None,
        }
    }

    /// The colour buffer as an RGB image in the values stored (RGBA8 divided by 255;
    /// an ID buffer maps each id to a repeatable pseudo-random colour, black for none).
    pub fn to_image(&self) -> Image {
        let pixels = match &self.color {
            ColorBuffer::Rgba8(c) => c
                .iter()
                .map(|p| {
                    Rgb::new(
                        p[0] as f32 / 255.0,
                        p[1] as f32 / 255.0,
                        p[2] as f32 / 255.0,
                    )
                })
                .collect(),
            ColorBuffer::Rgba32F(c) => c.iter().map(|p| Rgb::new(p[0], p[1], p[2])).collect(),
            ColorBuffer::Id(c) => c
                .iter()
                .map(|&id| {
                    if id == NO_ID {
                        Rgb::BLACK
                    } else {
                        let h = irradia_core::sampling::hash64(id as u64);
                        Rgb::new(
                            (h & 255) as f32 / 255.0,
                            ((h >> 8) & 255) as f32 / 255.0,
                            ((h >> 16) & 255) as f32 / 255.0,
                        )
                    }
                })
                .collect(),
        };
        Image::from_pixels(self.width, self.height, pixels)
    }

    /// The RGBA8 bytes, row-major (converting float or id buffers as [`to_image`] does).
    ///
    /// [`to_image`]: Framebuffer::to_image
    pub fn to_rgba8_bytes(&self) -> Vec<u8> {
        match &self.color {
            ColorBuffer::Rgba8(c) => c.iter().flatten().copied().collect(),
            ColorBuffer::Rgba32F(c) => c.iter().flat_map(|p| to_rgba8(*p)).collect(),
            ColorBuffer::Id(_) => self
                .to_image()
                .pixels()
                .iter()
                .flat_map(|p| to_rgba8([p.r, p.g, p.b, 1.0]))
                .collect(),
        }
    }
}

/// Clamps to [0, 1] and rounds to 8 bits per channel.
#[inline(always)]
pub fn to_rgba8(c: [f32; 4]) -> [u8; 4] {
    c.map(|v| (v.clamp(0.0, 1.0) * 255.0 + 0.5) as u8)
}
