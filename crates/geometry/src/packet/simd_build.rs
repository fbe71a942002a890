//! Which instruction set a hot loop is compiled for, chosen at run time.
//!
//! The crates are built for the x86-64 baseline (SSE2), so that one binary runs on any
//! x86-64 CPU. A loop that matters is compiled again inside functions marked
//! `#[target_feature]` for AVX2 + FMA (three-operand VEX forms, 256-bit registers) and
//! for AVX-512 (32 registers of 512 bits, mask registers for selects), and the widest
//! build the CPU runs is picked once ([`SimdBuild::best`]). The path tracer's wide
//! kernel (`irradia_render::path::wide`) and the rasterizer's geometry stage
//! (`irradia_raster`) both choose their build here.
//!
//! The builds differ only in instruction encodings: Rust never contracts a multiply
//! and an add into an FMA on its own (the `fma` feature only lets LLVM use the
//! instruction where the source asks for a fused multiply-add), so code that does not
//! call `mul_add` gives the same bits in every build.

/// Whether the AVX-512 (F, VL, DQ, BW) builds can run (checked once): Zen 4, Ice Lake
/// and later.
#[inline(always)]
pub fn has_avx512() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        use std::sync::OnceLock;
        static AVX512: OnceLock<bool> = OnceLock::new();
        *AVX512.get_or_init(|| {
            has_avx2()
                && is_x86_feature_detected!("avx512f")
                && is_x86_feature_detected!("avx512vl")
                && is_x86_feature_detected!("avx512dq")
                && is_x86_feature_detected!("avx512bw")
        })
    }
    #[cfg(not(target_arch = "x86_64"))]
    false
}

/// Whether the AVX2 + FMA builds can run (checked once).
#[inline(always)]
pub fn has_avx2() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        use std::sync::OnceLock;
        static AVX2: OnceLock<bool> = OnceLock::new();
        *AVX2.get_or_init(|| is_x86_feature_detected!("avx2") && is_x86_feature_detected!("fma"))
    }
    #[cfg(not(target_arch = "x86_64"))]
    false
}

/// A build of a loop: the same source compiled for one instruction set.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SimdBuild {
    /// The target's baseline (SSE2 on x86-64).
    Portable,
    /// AVX2 + FMA.
    Avx2,
    /// AVX2 + FMA + AVX-512 F/VL/DQ/BW.
    Avx512,
}

impl SimdBuild {
    /// Every build, narrowest first.
    pub const ALL: [SimdBuild; 3] = [SimdBuild::Portable, SimdBuild::Avx2, SimdBuild::Avx512];

    /// The widest build this CPU runs.
    pub fn best() -> Self {
        [SimdBuild::Avx512, SimdBuild::Avx2]
            .into_iter()
            .find(|b| b.available())
            .unwrap_or(SimdBuild::Portable)
    }

    /// [`Self::best`], unless the environment variable `var` names another build this
    /// CPU runs (`avx512`, `avx2` or `portable`): for A/B timings of the builds.
    pub fn chosen(var: &str) -> Self {
        let named = match std::env::var(var).as_deref() {
            Ok("avx512") => Some(SimdBuild::Avx512),
            Ok("avx2") => Some(SimdBuild::Avx2),
            Ok("portable") => Some(SimdBuild::Portable),
            _ => None,
        };
        named.filter(|b| b.available()).unwrap_or_else(Self::best)
    }

    /// Whether this CPU runs the build.
    pub fn available(self) -> bool {
        match self {
            SimdBuild::Portable => true,
            SimdBuild::Avx2 => has_avx2(),
            SimdBuild::Avx512 => has_avx512(),
        }
    }

    /// Runs `f`, inlined into a function compiled for this build. Mark `f` (and the
    /// closures it calls at more than one place) `#[inline(always)]`: LLVM otherwise
    /// may keep a large closure out of line, compiled for the baseline (measured in the
    /// rasterizer: its corner-lighting closure stayed a call until marked).
    ///
    /// # Panics
    /// When the CPU does not run the build ([`Self::available`]): running AVX-512
    /// instructions on a CPU without them would be undefined behaviour.
    #[inline(always)]
    pub fn run<R>(self, f: impl FnOnce() -> R) -> R {
        #[cfg(target_arch = "x86_64")]
        match self {
            // SAFETY: checked just above for the build's features.
            SimdBuild::Avx512 => {
                assert!(has_avx512(), "AVX-512 build on a CPU without it");
                return unsafe { avx512(f) };
            }
            SimdBuild::Avx2 => {
                assert!(has_avx2(), "AVX2 build on a CPU without it");
                return unsafe { avx2(f) };
            }
            SimdBuild::Portable => {}
        }
        f()
    }
}

/// `f` compiled with AVX2 and FMA.
///
/// # Safety
/// The CPU must have them.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn avx2<R>(f: impl FnOnce() -> R) -> R {
    f()
}

/// `f` compiled with AVX2, FMA and AVX-512 F/VL/DQ/BW.
///
/// # Safety
/// The CPU must have them.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma,avx512f,avx512vl,avx512dq,avx512bw")]
unsafe fn avx512<R>(f: impl FnOnce() -> R) -> R {
    f()
}

#[cfg(test)]
mod tests {
    use super::SimdBuild;

    #[test]
    fn the_best_build_is_available_and_no_narrower_than_any_available() {
        let best = SimdBuild::best();
        assert!(best.available());
        for b in SimdBuild::ALL.into_iter().filter(|b| b.available()) {
            assert!(
                b as u8 <= best as u8,
                "{b:?} runs here but best is {best:?}"
            );
        }
        assert!(SimdBuild::Portable.available());
    }

    #[test]
    fn every_available_build_runs_the_closure() {
        for b in SimdBuild::ALL.into_iter().filter(|b| b.available()) {
            assert_eq!(b.run(|| 6 * 7), 42, "{b:?}");
        }
    }

    #[test]
    fn an_unknown_or_unset_name_chooses_the_best() {
        std::env::set_var("IRRADIA_TEST_SIMD_BUILD", "sse9");
        assert_eq!(
            SimdBuild::chosen("IRRADIA_TEST_SIMD_BUILD"),
            SimdBuild::best()
        );
        std::env::set_var("IRRADIA_TEST_SIMD_BUILD", "portable");
        assert_eq!(
            SimdBuild::chosen("IRRADIA_TEST_SIMD_BUILD"),
            SimdBuild::Portable
        );
        assert_eq!(
            SimdBuild::chosen("IRRADIA_TEST_SIMD_BUILD_UNSET"),
            SimdBuild::best()
        );
    }
}
