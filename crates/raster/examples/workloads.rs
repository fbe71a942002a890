//! Renders the benchmark applications (random triangles, the Utah teapot, the gyroid,
//! metaballs) with the software pipeline, to look at them.
//!
//! `cargo run --release -p irradia-raster --example workloads -- OUT_DIR`

use glam::Vec3;
use irradia_core::Rgb;
use irradia_geometry::generators::gyroid::gyroid_mesh;
use irradia_geometry::generators::metaballs::{metaballs_mesh, random_balls};
use irradia_geometry::generators::random_triangles::{
    random_triangles, RandomTriangles, SizeDistribution,
};
use irradia_geometry::shapes::bezier::teapot_mesh;
use irradia_raster::{ColorFormat, Framebuffer, Material, Mesh, Pipeline, Shading, ViewParams};

fn main() {
    let out = std::env::args().nth(1).unwrap_or_else(|| ".".into());
    let (w, h) = (480, 360);
    let teapot = Mesh::from_triangle_mesh(&teapot_mesh(8));
    let scenes: Vec<(&str, Mesh, Vec3, Vec3)> = vec![
        (
            "teapot",
            teapot,
            Vec3::new(4.0, 4.0, 6.0),
            Vec3::new(0.0, 1.4, 0.0),
        ),
        (
            "gyroid",
            Mesh::from_mesh_data(gyroid_mesh(80)),
            Vec3::new(1.5, 1.1, 1.9),
            Vec3::ZERO,
        ),
        (
            "metaballs",
            Mesh::from_mesh_data(metaballs_mesh(&random_balls(12, 4), 96)),
            Vec3::new(0.0, 0.8, 2.8),
            Vec3::ZERO,
        ),
        (
            "random-triangles",
            Mesh::from_mesh_data(random_triangles(&RandomTriangles::new(
                20_000,
                SizeDistribution::Exponential { mean: 0.004 },
                1,
            ))),
            Vec3::new(0.0, 0.0, 3.5),
            Vec3::ZERO,
        ),
    ];
    for (name, mesh, eye, target) in scenes {
        let mut p = Pipeline::new(w, h);
        p.view = ViewParams::look_at_perspective(
            eye,
            target,
            Vec3::Y,
            45.0,
            w as f32 / h as f32,
            0.1,
            50.0,
        );
        p.material = Material {
            diffuse: Rgb::new(0.85, 0.6, 0.35),
            specular: Rgb::splat(0.4),
            shininess: 30.0,
            two_sided: true,
            ..Material::default()
        };
        p.shading = Shading::Phong;
        let mut fb = Framebuffer::new(w, h, ColorFormat::Rgba8).expect("framebuffer");
        fb.clear([0.1, 0.1, 0.12, 1.0]);
        p.render_mesh(&mesh, &mut fb).expect("render");
        let path = format!("{out}/{name}.png");
        image::save_buffer(&path, &fb.to_rgba8_bytes(), w, h, image::ColorType::Rgba8)
            .expect("write png");
        println!("wrote {path} ({} triangles)", mesh.triangle_count());
    }
}
