//! The kernels per instruction set: the ray queries of [`Scene`](crate::Scene),
//! [`Bvh`](crate::Bvh) and [`Patch`](crate::Patch) with
//! the kernel's lane code compiled for an instruction set the build's target may lack, for
//! callers that choose one at run time (docs/METHOD.md §8, "Instruction sets").
//!
//! A build for baseline x86-64 (what a C library, a demo binary or a Python wheel is built for)
//! runs the kernel's eight-lane evaluations as two SSE2 halves. Each module here holds the same
//! queries compiled with more: [`avx2`] (AVX2 and FMA, one 256-bit register per eight `f32`
//! lanes) and [`avx512`] (AVX-512 F, VL, BW and DQ besides: mask registers and 32 vector
//! registers). The search around the lane calls (clip, bracket, refine, the BVH's traversal,
//! the hit normal) is compiled into each query with the same features.
//!
//! Every function is `#[target_feature]`: safe to call from code compiled with those features,
//! and `unsafe` to call elsewhere, where the caller must make sure that the CPU has them (the
//! crate is `no_std` and detects nothing). The workspace's `smoothtri-isa` crate detects the
//! CPU, honours the `SMOOTHTRI_ISA` override and makes the call. Each module's
//! `FEATURES` names the features it needs.
//!
//! # Accuracy
//! The same as the target's queries, bit for bit: the lane code is the same IEEE operations
//! in the same order at any width (no fused multiply-add: Rust never contracts `a·b + c`), so
//! every hit, `t_error`, normal and count equals [`Scene::closest_hit`](crate::Scene::closest_hit)'s and the others'
//! (`tests/suite/isa.rs` checks each instruction set the CPU has against them).
//!
//! # Panics
//! No function panics.

#[cfg(any(target_arch = "x86", target_arch = "x86_64"))]
macro_rules! kernels {
    ($name:ident, $features:literal, $doc:literal) => {
        #[doc = $doc]
        pub mod $name {
            use crate::kernel::heights::{self, Calls};
            use crate::kernel::refine::ESTIMATE_POINTS;
            use crate::kernel::{Heights, KernelStats, intersect_stats};
            use crate::num::lanes::LANES;
            use crate::num::real::Float;
            use crate::num::vec::V3;
            use crate::surface::lanes::Prepared;
            use crate::{Bvh, Hit, Patch, Ray, Scene, SceneHit, kernel::DEFAULT_SAMPLES};

            /// The target features this module's functions are compiled with, as
            /// `#[target_feature(enable = …)]` names them: the CPU must have every one.
            pub const FEATURES: &str = $features;

            /// One lane call over eight array lanes, compiled with [`FEATURES`].
            #[target_feature(enable = $features)]
            #[inline(never)]
            fn f8<F: Float>(
                prep: &Prepared<F>,
                o: V3<F>,
                r: V3<F>,
                taus: [F; LANES],
            ) -> [F; LANES] {
                heights::eight::<F, F::A8, true>(prep, o, r, taus)
            }

            /// One four-point call (the estimate step), compiled with [`FEATURES`].
            #[target_feature(enable = $features)]
            #[inline(never)]
            fn f4<F: Float>(
                prep: &Prepared<F>,
                o: V3<F>,
                r: V3<F>,
                taus: [F; ESTIMATE_POINTS],
            ) -> [F; ESTIMATE_POINTS] {
                heights::four::<F, F::A8, F::A4, true>(prep, o, r, taus)
            }

            /// The lane calls of this instruction set: closures defined here inherit its
            /// features, so they may call [`f8`] and [`f4`].
            #[target_feature(enable = $features)]
            #[inline]
            fn lanes<F: Float>() -> impl Heights<F> {
                Calls(
                    |p: &Prepared<F>, o: V3<F>, r: V3<F>, t: [F; LANES]| f8(p, o, r, t),
                    |p: &Prepared<F>, o: V3<F>, r: V3<F>, t: [F; ESTIMATE_POINTS]| f4(p, o, r, t),
                )
            }

            /// [`Scene::closest_hit`] compiled with [`FEATURES`]: the same hit, bit for bit.
            ///
            /// # Safety
            /// Safe to call from code compiled with [`FEATURES`]; elsewhere the call is
            /// `unsafe`, and the CPU must have every feature of [`FEATURES`] (running an
            /// instruction the CPU lacks is undefined behaviour).
            /// # Panics
            /// Never.
            #[target_feature(enable = $features)]
            pub fn scene_closest_hit<F: Float>(
                scene: &Scene<'_, F>,
                ray: &Ray<F>,
                t_min: F,
                t_max: F,
                n: usize,
            ) -> Option<SceneHit<F>> {
                scene.closest_hit_with(ray, [t_min, t_max], n, &lanes())
            }

            /// [`Scene::any_hit`] compiled with [`FEATURES`]: the same answer.
            ///
            /// # Safety
            /// Safe to call from code compiled with [`FEATURES`]; elsewhere the call is
            /// `unsafe`, and the CPU must have every feature of [`FEATURES`] (running an
            /// instruction the CPU lacks is undefined behaviour).
            /// # Panics
            /// Never.
            #[target_feature(enable = $features)]
            pub fn scene_any_hit<F: Float>(
                scene: &Scene<'_, F>,
                ray: &Ray<F>,
                t_min: F,
                t_max: F,
                n: usize,
            ) -> bool {
                scene.any_hit_with(ray, [t_min, t_max], n, &lanes())
            }

            /// [`Bvh::closest_hit`] compiled with [`FEATURES`]: the same hit, bit for bit.
            ///
            /// # Safety
            /// Safe to call from code compiled with [`FEATURES`]; elsewhere the call is
            /// `unsafe`, and the CPU must have every feature of [`FEATURES`] (running an
            /// instruction the CPU lacks is undefined behaviour).
            /// # Panics
            /// Never.
            #[target_feature(enable = $features)]
            pub fn bvh_closest_hit<F: Float>(
                bvh: &Bvh<'_, F>,
                ray: &Ray<F>,
                t_min: F,
                t_max: F,
                n: usize,
            ) -> Option<Hit<F>> {
                bvh.closest_hit_with(ray, [t_min, t_max], n, &lanes())
            }

            /// [`Bvh::any_hit`] compiled with [`FEATURES`]: the same answer.
            ///
            /// # Safety
            /// Safe to call from code compiled with [`FEATURES`]; elsewhere the call is
            /// `unsafe`, and the CPU must have every feature of [`FEATURES`] (running an
            /// instruction the CPU lacks is undefined behaviour).
            /// # Panics
            /// Never.
            #[target_feature(enable = $features)]
            pub fn bvh_any_hit<F: Float>(
                bvh: &Bvh<'_, F>,
                ray: &Ray<F>,
                t_min: F,
                t_max: F,
                n: usize,
            ) -> bool {
                bvh.any_hit_with(ray, [t_min, t_max], n, &lanes())
            }

            /// [`Patch::intersect`] compiled with [`FEATURES`]: the same hit, bit for bit.
            ///
            /// # Safety
            /// Safe to call from code compiled with [`FEATURES`]; elsewhere the call is
            /// `unsafe`, and the CPU must have every feature of [`FEATURES`] (running an
            /// instruction the CPU lacks is undefined behaviour).
            /// # Panics
            /// Never.
            #[target_feature(enable = $features)]
            pub fn patch_intersect<F: Float>(
                patch: &Patch<F>,
                ray: &Ray<F>,
                t_min: F,
                t_max: F,
                n: usize,
            ) -> Option<Hit<F>> {
                intersect_stats::<F, DEFAULT_SAMPLES>(patch, ray, [t_min, t_max], n, &lanes()).0
            }

            /// [`Patch::intersect_stats`] compiled with [`FEATURES`]: the same hit and
            /// statistics, bit for bit.
            ///
            /// # Safety
            /// Safe to call from code compiled with [`FEATURES`]; elsewhere the call is
            /// `unsafe`, and the CPU must have every feature of [`FEATURES`] (running an
            /// instruction the CPU lacks is undefined behaviour).
            /// # Panics
            /// Never.
            #[target_feature(enable = $features)]
            pub fn patch_intersect_stats<F: Float, const K: usize>(
                patch: &Patch<F>,
                ray: &Ray<F>,
                t_min: F,
                t_max: F,
                n: usize,
            ) -> (Option<Hit<F>>, KernelStats) {
                intersect_stats::<F, K>(patch, ray, [t_min, t_max], n, &lanes())
            }
        }
    };
}

#[cfg(any(target_arch = "x86", target_arch = "x86_64"))]
kernels!(
    avx2,
    "avx2,fma",
    "The queries compiled for AVX2 and FMA (x86-64-v3): eight `f32` lanes in one register."
);
#[cfg(any(target_arch = "x86", target_arch = "x86_64"))]
kernels!(
    avx512,
    "avx512f,avx512vl,avx512bw,avx512dq,avx2,fma",
    "The queries compiled for AVX-512 (F, VL, BW, DQ; x86-64-v4) besides AVX2 and FMA: mask \
     registers and 32 vector registers."
);
