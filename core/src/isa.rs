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

/// The one list of the kernel's ray queries, from which the per-instruction-set entry points
/// (this module), the run-time dispatch (`smoothtri-isa`'s `Kernels`) and the tests that hold
/// every instruction set to the same bits (`tests/suite/isa.rs`) are generated. Not part of the
/// public API: its form may change with any release.
///
/// `for_each_query!(callback, extra tokens…)` invokes `callback! { (extra tokens…) entries… }`
/// with one entry per query of its table, in this form:
///
/// ```text
/// { name: scene_closest_hit, doc: "Scene::closest_hit", same: "the same hit, bit for bit",
///   generics: [], params: (scene: &Scene<'_, F>, ray: &Ray<F>, …), returns: Option<…>,
///   lanes: (l) scene.closest_hit_with(ray, [t_min, t_max], n, l),
///   core: scene.closest_hit(ray, t_min, t_max, n) }
/// ```
///
/// `name` is the entry point's name in every layer; `doc` the core query it equals (`same` says
/// how); `generics` the query's `const … : usize` parameters besides the precision `F`;
/// `params` and `returns` its signature; `lanes` its body given the lane calls `l`
/// (`&impl Heights<F>`) of an instruction set; `core` the core's own query, which the
/// baseline runs. Adding a query is one entry here (CONTRIBUTING.md, "Adding a query").
#[doc(hidden)]
#[macro_export]
macro_rules! for_each_query {
    ($callback:ident $(, $($extra:tt)*)?) => {
        // The table: name, the core query it equals and how, const generics besides `F`, the
        // receiver, the answer, the body over lane calls `l`, the core's own query. Every query
        // also takes the parameters in brackets.
        $crate::for_each_query! { @entries $callback ($($($extra)*)?)
            [ray: &$crate::Ray<F>, t_min: F, t_max: F, n: usize] []
            scene_closest_hit "Scene::closest_hit" "the same hit, bit for bit" []
                (scene: &$crate::Scene<'_, F>) -> Option<$crate::SceneHit<F>>,
                (l) scene.closest_hit_with(ray, [t_min, t_max], n, l),
                scene.closest_hit(ray, t_min, t_max, n);
            scene_any_hit "Scene::any_hit" "the same answer" []
                (scene: &$crate::Scene<'_, F>) -> bool,
                (l) scene.any_hit_with(ray, [t_min, t_max], n, l),
                scene.any_hit(ray, t_min, t_max, n);
            bvh_closest_hit "Bvh::closest_hit" "the same hit, bit for bit" []
                (bvh: &$crate::Bvh<'_, F>) -> Option<$crate::Hit<F>>,
                (l) bvh.closest_hit_with(ray, [t_min, t_max], n, l),
                bvh.closest_hit(ray, t_min, t_max, n);
            bvh_any_hit "Bvh::any_hit" "the same answer" []
                (bvh: &$crate::Bvh<'_, F>) -> bool,
                (l) bvh.any_hit_with(ray, [t_min, t_max], n, l),
                bvh.any_hit(ray, t_min, t_max, n);
            patch_closest_hit "Patch::closest_hit" "the same hit, bit for bit" []
                (patch: &$crate::Patch<F>) -> Option<$crate::Hit<F>>,
                (l) $crate::kernel::closest_hit_stats::<F, { $crate::kernel::DEFAULT_SAMPLES }>(
                    patch, ray, [t_min, t_max], n, l).0,
                patch.closest_hit(ray, t_min, t_max, n);
            patch_closest_hit_stats "Patch::closest_hit_stats"
                "the same hit and statistics, bit for bit" [K]
                (patch: &$crate::Patch<F>) -> (Option<$crate::Hit<F>>, $crate::KernelStats),
                (l) $crate::kernel::closest_hit_stats::<F, K>(patch, ray, [t_min, t_max], n, l),
                patch.closest_hit_stats::<K>(ray, t_min, t_max, n);
        }
    };
    // One table row at a time into the entry form, the rows done in the second brackets.
    (@entries $callback:ident ($($extra:tt)*) [$($common:tt)*] [$($done:tt)*]
        $name:ident $doc:literal $same:literal [$($k:ident)?]
        ($recv:ident: $rt:ty) -> $ret:ty, ($l:ident) $lanes:expr, $core:expr; $($rest:tt)*
    ) => {
        $crate::for_each_query! { @entries $callback ($($extra)*) [$($common)*] [$($done)* {
            name: $name, doc: $doc, same: $same, generics: [$($k)?],
            params: ($recv: $rt, $($common)*), returns: $ret, lanes: ($l) $lanes, core: $core,
        }] $($rest)* }
    };
    (@entries $callback:ident ($($extra:tt)*) [$($common:tt)*] [$($done:tt)*]) => {
        $callback! { ($($extra)*) $($done)* }
    };
}

/// The entry points of one instruction set, from [`for_each_query!`]'s list: each query
/// compiled with the features `$features`, its lane calls those of `lanes()`.
#[cfg(any(target_arch = "x86", target_arch = "x86_64"))]
macro_rules! entry_points {
    (
        ($features:literal)
        $({ name: $name:ident, doc: $doc:literal, same: $same:literal, generics: [$($k:ident)?],
            params: ($($p:ident: $t:ty),* $(,)?), returns: $ret:ty, lanes: ($l:ident) $lanes:expr,
            core: $core:expr $(,)? })*
    ) => {
        $(
            #[doc = concat!("[`", $doc, "`](crate::", $doc, ") compiled with [`FEATURES`]: ", $same, ".")]
            ///
            /// # Safety
            /// Safe to call from code compiled with [`FEATURES`]; elsewhere the call is
            /// `unsafe`, and the CPU must have every feature of [`FEATURES`] (running an
            /// instruction the CPU lacks is undefined behaviour).
            /// # Panics
            /// Never.
            #[target_feature(enable = $features)]
            pub fn $name<F: Float $(, const $k: usize)?>($($p: $t),*) -> $ret {
                let $l = &lanes();
                $lanes
            }
        )*
    };
}

#[cfg(any(target_arch = "x86", target_arch = "x86_64"))]
macro_rules! kernels {
    ($name:ident, $features:literal, $doc:literal) => {
        #[doc = $doc]
        pub mod $name {
            use crate::kernel::Heights;
            use crate::kernel::heights::{self, Calls};
            use crate::kernel::refine::ESTIMATE_POINTS;
            use crate::num::lanes::LANES;
            use crate::num::real::Float;
            use crate::num::vec::V3;
            use crate::surface::lanes::Prepared;

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

            crate::for_each_query!(entry_points, $features);
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
