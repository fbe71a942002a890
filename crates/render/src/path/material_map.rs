//! How a scene material (written for the Whitted tracer) becomes a physically based
//! BSDF, so that every scene renders in the path tracer without edits.
//!
//! | material field | path-tracer lobe |
//! |---|---|
//! | `diffuse * color` | Lambertian, albedo `diffuse * color` |
//! | `specular`, `shininess` | normalised Phong gloss, `ks = specular`, exponent `shininess` |
//! | `reflection` | perfect mirror (only when the surface does not transmit with Fresnel) |
//! | `transmission`, `ior`, `filter_color` | smooth dielectric (always Fresnel-weighted), tinted by the filter colour |
//! | `emission` | emitted radiance, one-sided (the side the surface normal points to) |
//! | `ambient` | ignored: the path tracer computes indirect light instead |
//!
//! If the weights add up to more than one (`max(diffuse*color) + specular +
//! max(reflection) + transmission > 1`), all are scaled down by the sum so that the
//! surface never reflects more energy than it receives.

use glam::{Vec2, Vec3};
use irradia_core::Rgb;
use irradia_scatter::bsdfs::{LectureLobe as Lobe, LectureMix};
use irradia_scene::Material;

/// The BSDF of `material` at world point `p` with surface coordinates `uv`.
pub fn bsdf_for(material: &Material, p: Vec3, uv: Vec2) -> LectureMix {
    let color = material.color.eval(p, uv);
    let albedo = color * material.diffuse;
    let transmits = material.transmission > 0.0;
    let mirror = if transmits && material.fresnel {
        Rgb::BLACK
    } else {
        material.reflection
    };
    let total =
        albedo.max_component() + material.specular + mirror.max_component() + material.transmission;
    let scale = if total > 1.0 { 1.0 / total } else { 1.0 };
    let mut bsdf = LectureMix::new()
        .with(Lobe::Lambert {
            albedo: albedo * scale,
        })
        .with(Lobe::Phong {
            ks: Rgb::splat(material.specular * scale),
            exponent: material.shininess.max(0.0),
        })
        .with(Lobe::Mirror { r: mirror * scale });
    if transmits {
        let tint = material.filter_color.unwrap_or(color);
        bsdf = bsdf.with(Lobe::Dielectric {
            eta: material.ior,
            tint,
            weight: material.transmission * scale,
        });
    }
    bsdf
}

#[cfg(test)]
mod tests {
    use super::*;
    use irradia_scene::Texture;

    #[test]
    fn over_bright_materials_are_scaled_to_conserve_energy() {
        let m = Material {
            color: Texture::Solid(Rgb::WHITE),
            diffuse: 0.9,
            specular: 0.5,
            reflection: Rgb::splat(0.4),
            ..Material::default()
        };
        let b = bsdf_for(&m, Vec3::ZERO, Vec2::ZERO);
        let wo = Vec3::new(0.3, 0.1, 0.9).normalize();
        let albedo: f32 = b.lobes().map(|l| l.albedo(wo, 4096).max_component()).sum();
        assert!(albedo <= 1.0 + 1e-3, "albedo {albedo}");
    }
}
