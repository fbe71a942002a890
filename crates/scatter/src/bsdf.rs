//! The one BSDF interface: what an integrator asks of any surface's scattering.

use crate::bsdfs::*;
use glam::{Vec2, Vec3};
use irradia_core::Rgb;
use std::ops::BitOr;

/// Which kinds of scattering a BSDF (or one sampled direction) has, as Mitsuba 3's
/// `BSDFFlags` and pbrt-v4's `BxDFFlags`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct LobeFlags(pub u32);

impl LobeFlags {
    pub const NONE: Self = Self(0);
    /// Light passes straight through without scattering (a mask's hole).
    pub const NULL: Self = Self(1);
    pub const DIFFUSE_REFLECTION: Self = Self(1 << 1);
    pub const DIFFUSE_TRANSMISSION: Self = Self(1 << 2);
    pub const GLOSSY_REFLECTION: Self = Self(1 << 3);
    pub const GLOSSY_TRANSMISSION: Self = Self(1 << 4);
    pub const DELTA_REFLECTION: Self = Self(1 << 5);
    pub const DELTA_TRANSMISSION: Self = Self(1 << 6);
    /// The lobe depends on the azimuth (anisotropic roughness).
    pub const ANISOTROPIC: Self = Self(1 << 7);
    /// The BSDF scatters light arriving on the front side (+z).
    pub const FRONT_SIDE: Self = Self(1 << 8);
    /// The BSDF scatters light arriving on the back side (-z).
    pub const BACK_SIDE: Self = Self(1 << 9);

    pub const DIFFUSE: Self = Self(Self::DIFFUSE_REFLECTION.0 | Self::DIFFUSE_TRANSMISSION.0);
    pub const GLOSSY: Self = Self(Self::GLOSSY_REFLECTION.0 | Self::GLOSSY_TRANSMISSION.0);
    pub const DELTA: Self =
        Self(Self::DELTA_REFLECTION.0 | Self::DELTA_TRANSMISSION.0 | Self::NULL.0);
    pub const SMOOTH: Self = Self(Self::DIFFUSE.0 | Self::GLOSSY.0);
    pub const REFLECTION: Self =
        Self(Self::DIFFUSE_REFLECTION.0 | Self::GLOSSY_REFLECTION.0 | Self::DELTA_REFLECTION.0);
    pub const TRANSMISSION: Self = Self(
        Self::DIFFUSE_TRANSMISSION.0
            | Self::GLOSSY_TRANSMISSION.0
            | Self::DELTA_TRANSMISSION.0
            | Self::NULL.0,
    );

    /// Whether any flag of `other` is set.
    #[inline]
    pub fn intersects(self, other: Self) -> bool {
        self.0 & other.0 != 0
    }

    /// Whether the BSDF has a lobe that light sampling can hit (not only delta lobes).
    #[inline]
    pub fn has_smooth(self) -> bool {
        self.intersects(Self::SMOOTH)
    }

    /// Whether the flags are delta lobes only (a sampled mirror or refraction direction).
    #[inline]
    pub fn is_delta(self) -> bool {
        self.intersects(Self::DELTA) && !self.has_smooth()
    }
}

impl BitOr for LobeFlags {
    type Output = Self;
    #[inline]
    fn bitor(self, rhs: Self) -> Self {
        Self(self.0 | rhs.0)
    }
}

/// A sampled incident direction.
#[derive(Clone, Copy, Debug)]
pub struct BsdfSample {
    pub wi: Vec3,
    /// `f |cos θi| / pdf`.
    pub weight: Rgb,
    /// Solid-angle density of `wi` for smooth lobes; the discrete probability of the
    /// chosen delta lobe otherwise.
    pub pdf: f32,
    /// The lobe the direction came from (one of the `*_REFLECTION`, `*_TRANSMISSION`
    /// flags, or `NULL`).
    pub lobe: LobeFlags,
    /// The relative index of refraction along the sampled path (`eta_t / eta_i`, 1 for
    /// reflection), for Russian roulette that ignores radiance compression.
    pub eta: f32,
}

impl BsdfSample {
    /// Whether the direction came from a delta lobe (light sampling cannot produce it).
    #[inline]
    pub fn is_delta(&self) -> bool {
        self.lobe.intersects(LobeFlags::DELTA)
    }
}

/// What every BSDF answers. Directions are in the local shading frame (see the crate
/// documentation for the conventions).
pub trait Scatter {
    /// The lobes this BSDF has.
    fn flags(&self) -> LobeFlags;
    /// f(wo, wi), without the cosine factor; black for delta lobes.
    fn eval(&self, wo: Vec3, wi: Vec3) -> Rgb;
    /// The solid-angle density with which [`Scatter::sample`] produces `wi` through the
    /// smooth lobes (0 for directions only a delta lobe reaches).
    fn pdf(&self, wo: Vec3, wi: Vec3) -> f32;
    /// Samples `wi` given `wo`: `u_lobe` picks a lobe, `u` a direction in it.
    fn sample(&self, wo: Vec3, u_lobe: f32, u: Vec2) -> Option<BsdfSample>;
}

/// Declares [`Bsdf`], the value an integrator holds at a surface point, with one variant
/// per BSDF of [`crate::bsdfs`], and forwards [`Scatter`] to the variant (a `match`, no
/// dynamic dispatch).
macro_rules! bsdf_enum {
    ($($variant:ident($ty:ty)),* $(,)?) => {
        /// One surface point's BSDF, any of [`crate::bsdfs`].
        #[derive(Clone, Debug)]
        pub enum Bsdf {
            $($variant($ty),)*
        }

        impl Scatter for Bsdf {
            #[inline]
            fn flags(&self) -> LobeFlags {
                match self { $(Bsdf::$variant(b) => b.flags(),)* }
            }
            #[inline]
            fn eval(&self, wo: Vec3, wi: Vec3) -> Rgb {
                match self { $(Bsdf::$variant(b) => b.eval(wo, wi),)* }
            }
            #[inline]
            fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
                match self { $(Bsdf::$variant(b) => b.pdf(wo, wi),)* }
            }
            #[inline]
            fn sample(&self, wo: Vec3, u_lobe: f32, u: Vec2) -> Option<BsdfSample> {
                match self { $(Bsdf::$variant(b) => b.sample(wo, u_lobe, u),)* }
            }
        }

        $(impl From<$ty> for Bsdf {
            fn from(b: $ty) -> Self {
                Bsdf::$variant(b)
            }
        })*
    };
}

// One line per BSDF; boxed for the wrappers that hold other BSDFs.
bsdf_enum! {
    Diffuse(Diffuse),
    LectureMix(LectureMix),
    Conductor(Conductor),
    RoughConductor(RoughConductor),
    Dielectric(Dielectric),
    RoughDielectric(RoughDielectric),
    ThinDielectric(ThinDielectric),
    Plastic(Plastic),
    RoughPlastic(RoughPlastic),
    Principled(Principled),
    PrincipledThin(PrincipledThin),
    Blend(Blend),
    Mask(Mask),
    TwoSided(TwoSided),
    NormalMap(NormalMap),
}
