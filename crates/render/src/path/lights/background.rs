//! The emitters at infinity (the constant environment: the background plus Mitsuba's
//! `constant` emitters, and Mitsuba's `envmap`) as the 8-wide path kernel of
//! [`crate::path::wide`] reads them: the scene's emitters split into facet emitters
//! (sampled by the kernel's vector stage) and emitters at infinity (sampled lane by
//! lane with the scalar code's arithmetic, so that samples agree with
//! [`LightSampler::sample`]'s bit for bit).

use super::{Emitter, FacetEmitter, LightSample, LightSampler};
use glam::Vec2;
use irradia_core::sampling;
use std::f32::consts::PI;

/// One of the scene's emitters as the 8-wide kernel handles it.
#[derive(Clone, Copy, Debug)]
pub(crate) enum WideEmitter<'a> {
    /// An emissive object sampled by its world-space facets.
    Facets(FacetEmitter<'a>),
    /// The constant environment or an environment map.
    AtInfinity,
}

/// The light one lane of the kernel samples: a facet of an emissive object (to be
/// warped into its triangle by the vector stage) or a direction towards an emitter at
/// infinity, sampled here.
#[derive(Clone, Copy, Debug)]
pub(crate) enum WideLight {
    /// (emitter, probability of choosing it, triangle of the emitter, the point of the
    /// unit square to warp with `uniform_triangle`), as [`LightSampler::pick_facet`].
    Facet(usize, f32, usize, Vec2),
    /// The sample [`LightSampler::sample`] gives for the same numbers.
    AtInfinity(LightSample),
}

impl LightSampler {
    /// The emitters, indexed like the light choice's, when each is an emissive object
    /// sampled by its facets or an emitter at infinity; `None` when some other kind is
    /// present (points, spots, rectangles, spheres sampled as shapes).
    pub(crate) fn wide_emitters(&self) -> Option<Vec<WideEmitter<'_>>> {
        self.emitters
            .iter()
            .zip(&self.probability)
            .map(|(e, &probability)| match e {
                Emitter::Object {
                    radiance,
                    two_sided,
                    world: Some(w),
                    ..
                } => Some(WideEmitter::Facets(FacetEmitter {
                    radiance: *radiance,
                    two_sided: *two_sided,
                    triangles: &w.triangles,
                    normals: &w.normals,
                    pdf_area: &w.pdf_area,
                    cdf: &w.cdf,
                    probability,
                })),
                Emitter::Environment { .. } | Emitter::Envmap { .. } => {
                    Some(WideEmitter::AtInfinity)
                }
                _ => None,
            })
            .collect()
    }

    /// The choice [`LightSampler::sample`] makes for `(u_pick, u)` in a scene of the
    /// emitters [`LightSampler::wide_emitters`] accepts: a facet, as
    /// [`LightSampler::pick_facet`], or the whole sample of an emitter at infinity
    /// (the same arithmetic as `sample`'s: a uniform direction on the sphere, density
    /// `pick / 4π`, for the constant environment; the map's importance sample, density
    /// `pick` times the map's, for an `envmap`). `None` where `sample` gives none.
    #[inline]
    pub(crate) fn pick_wide(&self, u_pick: f32, u: Vec2) -> Option<WideLight> {
        let (idx, pick) = self.pick(u_pick)?;
        match &self.emitters[idx] {
            Emitter::Object { world: Some(w), .. } => {
                let (i, u) = w.pick(u)?;
                Some(WideLight::Facet(idx, pick, i, u))
            }
            Emitter::Environment { radiance, .. } => Some(WideLight::AtInfinity(LightSample {
                wi: sampling::uniform_sphere(u),
                target: None,
                li: *radiance,
                pdf: pick / (4.0 * PI),
                delta: false,
            })),
            Emitter::Envmap { sampler, .. } => {
                let s = sampler.sample(u)?;
                Some(WideLight::AtInfinity(LightSample {
                    wi: s.wi,
                    target: None,
                    li: s.radiance,
                    pdf: pick * s.pdf,
                    delta: false,
                }))
            }
            _ => None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;
    use irradia_core::{Image, Rgb, Rng};
    use irradia_scene::{EnvMap, Light, Scene};
    use std::sync::Arc;

    /// `pick_wide` gives exactly `sample`'s light samples for emitters at infinity, and
    /// `pick_facet`'s choice for facets, in a scene with both.
    #[test]
    fn wide_choice_equals_the_scalar_sample() {
        let mut scene = irradia_scene::builtin::load("cornell").unwrap();
        let mut image = Image::filled(16, 8, Rgb::splat(0.2)).unwrap();
        image.set(5, 2, Rgb::new(8.0, 4.0, 1.0));
        image.set(11, 6, Rgb::new(0.5, 3.0, 6.0));
        let map = EnvMap {
            image: Arc::new(image),
            scale: 1.5,
            to_world: glam::Mat3::from_rotation_x(0.4),
            path: Default::default(),
        };
        scene.lights.push(Light::Envmap(Arc::new(map)));
        scene.lights.push(Light::Constant {
            radiance: Rgb::new(0.1, 0.2, 0.3),
        });
        let scene = Scene::new(
            scene.camera,
            scene.settings.clone(),
            scene.materials.clone(),
            scene.lights.clone(),
            scene.objects.clone(),
            scene.accel.instances().to_vec(),
        );
        let lights = LightSampler::new(&scene);
        let kinds = lights
            .wide_emitters()
            .expect("facets and emitters at infinity");
        let at_infinity = kinds
            .iter()
            .filter(|k| matches!(k, WideEmitter::AtInfinity))
            .count();
        assert_eq!(at_infinity, 2);
        let mut rng = Rng::new(3, 4);
        let (mut facets, mut far) = (0, 0);
        let p = Vec3::new(0.1, 0.2, 0.3);
        for _ in 0..2000 {
            let (up, u) = (rng.next_f32(), rng.next_2d());
            match lights.pick_wide(up, u) {
                Some(WideLight::Facet(e, pick, t, w)) => {
                    facets += 1;
                    assert_eq!(lights.pick_facet(up, u), Some((e, pick, t, w)));
                }
                Some(WideLight::AtInfinity(ls)) => {
                    far += 1;
                    let want = lights.sample(&scene, p, up, u).unwrap();
                    assert_eq!(ls.wi, want.wi);
                    assert_eq!(ls.li, want.li);
                    assert_eq!(ls.pdf.to_bits(), want.pdf.to_bits());
                    assert!(ls.target.is_none() && want.target.is_none());
                }
                None => assert!(lights.sample(&scene, p, up, u).is_none()),
            }
        }
        assert!(
            facets > 100 && far > 100,
            "{facets} facets, {far} at infinity"
        );
    }
}
