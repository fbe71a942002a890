//! Renders a sphere with Gouraud and with Phong shading, and its ID buffer, to PNGs.
//!
//! `cargo run --release -p irradia-raster --example sphere -- OUT_DIR`

use glam::Vec3;
use irradia_core::Rgb;
use irradia_geometry::shapes::Sphere;
use irradia_geometry::Shape;
use irradia_raster::{ColorFormat, Framebuffer, Material, Mesh, Pipeline, Shading, ViewParams};

fn main() {
    let out = std::env::args().nth(1).unwrap_or_else(|| ".".into());
    let (w, h) = (320, 240);
    let mesh = Mesh::from_facets(
        &Sphere::new(Vec3::ZERO, 1.0)
            .facets(24)
            .expect("sphere facets"),
    );
    let mut p = Pipeline::new(w, h);
    p.view = ViewParams::look_at_perspective(
        Vec3::new(0.0, 0.5, 3.0),
        Vec3::ZERO,
        Vec3::Y,
        45.0,
        w as f32 / h as f32,
        0.1,
        10.0,
    );
    p.material = Material {
        diffuse: Rgb::new(0.9, 0.5, 0.3),
        specular: Rgb::splat(0.6),
        shininess: 40.0,
        two_sided: false,
        ..Material::default()
    };
    for (name, shading, format) in [
        ("gouraud", Shading::Gouraud, ColorFormat::Rgba8),
        ("phong", Shading::Phong, ColorFormat::Rgba8),
        ("ids", Shading::Unlit, ColorFormat::Id),
    ] {
        p.shading = shading;
        let mut fb = Framebuffer::new(w, h, format).expect("framebuffer");
        p.render_mesh(&mesh, &mut fb).expect("render");
        let path = format!("{out}/sphere-{name}.png");
        image::save_buffer(&path, &fb.to_rgba8_bytes(), w, h, image::ColorType::Rgba8)
            .expect("write png");
        println!("wrote {path}");
    }
}
