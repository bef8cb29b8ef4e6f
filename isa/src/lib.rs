//! The kernel of `smoothtri` compiled per instruction set and chosen at run time.
//!
//! A binary built for baseline x86-64 (a C library, a demo, a Python wheel) runs the core's lane
//! code as SSE2. The core also compiles its queries for AVX2 + FMA and for AVX-512
//! ([`smoothtri::isa`]); this crate detects what the CPU has and calls them: [`Kernels`] holds
//! one instruction set the CPU has, [`kernels`] is the process's choice (the best the CPU has,
//! or the one `SMOOTHTRI_ISA` names), and [`Dispatch`] adds the dispatched queries to
//! [`Scene`], [`Bvh`] and [`Patch`]. The queries are compiled here, once per instruction set and
//! precision ([`Precision`]: `f32`, `f64`), for every crate that calls them.
//!
//! # Accuracy
//! Every query returns what the core's query of the same name returns, bit for bit, on every
//! instruction set: the lane code is the same IEEE operations in the same order at every width,
//! and no operation is fused (Rust never contracts `a·b + c` into a fused multiply-add, and the
//! core calls no `mul_add`), so the FMA feature changes nothing in the results
//! (docs/METHOD.md, "Instruction sets"; `tests/suite/isa.rs` checks it).
//!
//! # Panics
//! No function panics.

#![deny(missing_docs)]
#![deny(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use std::ffi::CStr;
use std::fmt;
use std::sync::OnceLock;

use smoothtri::{Bvh, Float, Hit, Patch, Ray, Scene, SceneHit};

/// The environment variable that overrides the choice of [`kernels`]: `sse2`, `avx2` or
/// `avx512` ([`Isa::name`]; `neon` or `baseline` for [`Isa::Baseline`] elsewhere).
pub const ENV: &str = "SMOOTHTRI_ISA";

/// An instruction set the kernel is compiled for.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Isa {
    /// The build's own target features: SSE2 in a default x86-64 build, NEON on aarch64.
    Baseline,
    /// AVX2 and FMA (x86-64-v3): eight `f32` lanes in one register.
    Avx2,
    /// AVX-512 F, VL, BW and DQ besides AVX2 and FMA (x86-64-v4): mask registers, 32 vector
    /// registers.
    Avx512,
}

impl Isa {
    /// Every instruction set, from the baseline to the widest.
    pub const ALL: [Isa; 3] = [Isa::Baseline, Isa::Avx2, Isa::Avx512];

    /// The name `SMOOTHTRI_ISA` takes and `st_get_isa()` returns: `sse2` (x86, x86-64), `neon`
    /// (aarch64) or `baseline` (elsewhere) for [`Isa::Baseline`]; `avx2`; `avx512`.
    pub fn name(self) -> &'static str {
        self.c_name().to_str().unwrap_or("baseline")
    }

    /// [`Isa::name`] as a NUL-terminated string with static lifetime (for the C API).
    pub fn c_name(self) -> &'static CStr {
        match self {
            Isa::Baseline if cfg!(any(target_arch = "x86", target_arch = "x86_64")) => c"sse2",
            Isa::Baseline if cfg!(target_arch = "aarch64") => c"neon",
            Isa::Baseline => c"baseline",
            Isa::Avx2 => c"avx2",
            Isa::Avx512 => c"avx512",
        }
    }

    /// The instruction set of a name ([`Isa::name`], ASCII case ignored; `baseline` names
    /// [`Isa::Baseline`] on every target), or `None`.
    pub fn parse(name: &str) -> Option<Isa> {
        let name = name.trim();
        Isa::ALL
            .into_iter()
            .find(|i| i.name().eq_ignore_ascii_case(name))
            .or_else(|| {
                name.eq_ignore_ascii_case("baseline")
                    .then_some(Isa::Baseline)
            })
    }

    /// The target features (as `#[target_feature]` names them) its kernels are compiled with:
    /// empty for [`Isa::Baseline`] (the build's own).
    pub fn features(self) -> &'static str {
        match self {
            Isa::Baseline => "",
            #[cfg(any(target_arch = "x86", target_arch = "x86_64"))]
            Isa::Avx2 => smoothtri::isa::avx2::FEATURES,
            #[cfg(any(target_arch = "x86", target_arch = "x86_64"))]
            Isa::Avx512 => smoothtri::isa::avx512::FEATURES,
            #[cfg(not(any(target_arch = "x86", target_arch = "x86_64")))]
            Isa::Avx2 | Isa::Avx512 => "",
        }
    }

    /// Whether this build has kernels for it and the CPU running it has every feature of
    /// [`Isa::features`] (detected at run time; the baseline always).
    pub fn supported(self) -> bool {
        match self {
            Isa::Baseline => true,
            _ if cfg!(any(target_arch = "x86", target_arch = "x86_64")) => {
                self.features().split(',').all(detected)
            }
            _ => false,
        }
    }

    /// The widest instruction set this CPU has.
    pub fn best() -> Isa {
        Isa::ALL
            .into_iter()
            .rev()
            .find(|i| i.supported())
            .unwrap_or(Isa::Baseline)
    }
}

impl fmt::Display for Isa {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// Whether the CPU has the target feature `name` (the names [`Isa::features`] uses; any other
/// name: `false`).
#[cfg(any(target_arch = "x86", target_arch = "x86_64"))]
fn detected(name: &str) -> bool {
    match name {
        "avx2" => std::arch::is_x86_feature_detected!("avx2"),
        "fma" => std::arch::is_x86_feature_detected!("fma"),
        "avx512f" => std::arch::is_x86_feature_detected!("avx512f"),
        "avx512vl" => std::arch::is_x86_feature_detected!("avx512vl"),
        "avx512bw" => std::arch::is_x86_feature_detected!("avx512bw"),
        "avx512dq" => std::arch::is_x86_feature_detected!("avx512dq"),
        _ => false,
    }
}

#[cfg(not(any(target_arch = "x86", target_arch = "x86_64")))]
fn detected(_: &str) -> bool {
    false
}

/// Why [`Kernels::new`] or [`Kernels::from_env`] refused an instruction set.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum IsaError {
    /// `SMOOTHTRI_ISA` names no instruction set (the value given).
    Unknown(String),
    /// The CPU (or this build's target) lacks the instruction set.
    Unsupported(Isa),
}

impl fmt::Display for IsaError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            IsaError::Unknown(v) => write!(
                f,
                "{ENV}={v:?} names no instruction set (use sse2, avx2 or avx512)"
            ),
            IsaError::Unsupported(i) => {
                write!(f, "{ENV}={i}: this CPU lacks it (it has {})", Isa::best())
            }
        }
    }
}

impl std::error::Error for IsaError {}

/// The queries of one instruction set the CPU has: made only by [`Kernels::new`] (which checks
/// the CPU), so every call runs instructions the CPU has.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Kernels {
    isa: Isa,
}

/// The precisions with kernels compiled in this crate: `f32` and `f64`.
///
/// Each query of the core's list without const parameters is compiled here once per
/// instruction set and precision, as a function of this crate, so that the crates calling
/// [`Kernels`] link to it rather than compile every instruction set's kernel again (the lane
/// code, the clip, the refinement and the traversal, inlined into each query). The queries
/// with const parameters ([`Kernels::patch_closest_hit_stats`]) are compiled where they are
/// called, for the parameters the caller names.
pub trait Precision: Float + queries::Queries<Self> {}

impl Precision for f32 {}
impl Precision for f64 {}

/// The queries per precision, sealed: [`Precision`]'s supertrait, implemented here only.
mod queries {
    use super::Isa;
    use smoothtri::Float;

    /// One query on the instruction set `isa`: `$core` on the baseline, the core's
    /// `#[target_feature]` function of that name otherwise.
    macro_rules! dispatch {
        ($isa:ident, $core:expr, $name:ident $(::<$k:ident>)? ($($arg:expr),*)) => {
            match $isa {
                Isa::Baseline => $core,
                // SAFETY: a `Kernels` holds `Avx2` only when the CPU has every feature of
                // `avx2::FEATURES` (`Kernels::new` checks `Isa::supported`), and `Kernels` is
                // the only caller: the one requirement of the core's `#[target_feature]`
                // functions.
                #[cfg(any(target_arch = "x86", target_arch = "x86_64"))]
                Isa::Avx2 => unsafe { smoothtri::isa::avx2::$name $(::<F, $k>)? ($($arg),*) },
                // SAFETY: as above, for `avx512::FEATURES`.
                #[cfg(any(target_arch = "x86", target_arch = "x86_64"))]
                Isa::Avx512 => unsafe { smoothtri::isa::avx512::$name $(::<F, $k>)? ($($arg),*) },
                #[cfg(not(any(target_arch = "x86", target_arch = "x86_64")))]
                Isa::Avx2 | Isa::Avx512 => $core,
            }
        };
    }

    /// From the core's list of queries (`smoothtri::for_each_query!`), one entry each: the
    /// trait [`Queries`] (the query with the instruction set first), its impls for `f32` and
    /// `f64` (each dispatching on `isa`; generated where `F` names the precision, so that the
    /// list's types, which name `F`, are that precision's), and [`Kernels`]' methods.
    macro_rules! queries {
        (
            ()
            $({ name: $name:ident, doc: $doc:literal, same: $same:literal, generics: [$($k:ident)?],
                params: ($($p:ident: $t:ty),* $(,)?), returns: $ret:ty, lanes: ($l:ident) $lanes:expr,
                core: $core:expr $(,)? })*
        ) => {
            /// The queries of the precision `F` on an instruction set the caller has checked.
            pub trait Queries<F: Float> {
                $(
                    #[doc = concat!("[`", $doc, "`](smoothtri::", $doc, ") on `isa`, which the CPU must have.")]
                    fn $name<$(const $k: usize)?>(isa: Isa, $($p: $t),*) -> $ret;
                )*
            }

            /// `impl Queries<F> for F` where `F` names the precision.
            macro_rules! bodies {
                () => {
                    impl Queries<F> for F {
                        $(
                            fn $name<$(const $k: usize)?>(isa: Isa, $($p: $t),*) -> $ret {
                                dispatch!(isa, $core, $name $(::<$k>)? ($($p),*))
                            }
                        )*
                    }
                };
            }

            /// The `f32` kernels.
            mod single {
                use super::{Isa, Queries};
                type F = f32;
                bodies!();
            }

            /// The `f64` kernels.
            mod double {
                use super::{Isa, Queries};
                type F = f64;
                bodies!();
            }

            /// The dispatched queries: each returns what the core's query of its `doc` returns.
            impl super::Kernels {
                $(
                    #[doc = concat!("[`", $doc, "`](smoothtri::", $doc, ") on this instruction set: ", $same, ".")]
                    #[inline]
                    pub fn $name<F: super::Precision $(, const $k: usize)?>(self, $($p: $t),*) -> $ret {
                        <F as Queries<F>>::$name $(::<$k>)? (self.isa, $($p),*)
                    }
                )*
            }
        };
    }
    smoothtri::for_each_query!(queries);
}

impl Kernels {
    /// The kernels of `isa`, or [`IsaError::Unsupported`] when the CPU lacks it.
    pub fn new(isa: Isa) -> Result<Kernels, IsaError> {
        if isa.supported() {
            Ok(Kernels { isa })
        } else {
            Err(IsaError::Unsupported(isa))
        }
    }

    /// The kernels of the widest instruction set the CPU has ([`Isa::best`]).
    pub fn best() -> Kernels {
        Kernels { isa: Isa::best() }
    }

    /// The kernels that `SMOOTHTRI_ISA` names, or the best when it is unset or empty; an error
    /// when it names no instruction set or one the CPU lacks.
    pub fn from_env() -> Result<Kernels, IsaError> {
        match std::env::var(ENV) {
            Ok(v) if !v.trim().is_empty() => {
                Kernels::new(Isa::parse(&v).ok_or(IsaError::Unknown(v))?)
            }
            _ => Ok(Kernels::best()),
        }
    }

    /// The instruction set these kernels run.
    pub fn isa(self) -> Isa {
        self.isa
    }
}

/// The process's kernels, chosen once (at the first call): those [`Kernels::from_env`] gives,
/// or the best the CPU has ([`Kernels::best`]) when `SMOOTHTRI_ISA` is invalid or names an
/// instruction set the CPU lacks (see [`Kernels::from_env`] to report that instead).
pub fn kernels() -> Kernels {
    static CHOSEN: OnceLock<Kernels> = OnceLock::new();
    *CHOSEN.get_or_init(|| Kernels::from_env().unwrap_or_else(|_| Kernels::best()))
}

/// The queries of [`Scene`], [`Bvh`] and [`Patch`] on the process's kernels ([`kernels`]):
/// `x.closest_hit_isa(…)` returns what `x.closest_hit(…)` returns, bit for bit.
pub trait Dispatch<F: Precision> {
    /// The closest hit's type: [`SceneHit`] of a scene, [`Hit`] of a BVH or a patch.
    type Hit;
    /// The closest hit of `ray` in `[t_min, t_max]` with a refinement budget of `n` steps (as
    /// the core's `closest_hit` / [`Patch::closest_hit`]), on [`kernels`].
    fn closest_hit_isa(&self, ray: &Ray<F>, t_min: F, t_max: F, n: usize) -> Option<Self::Hit>;
    /// Whether anything is hit in `[t_min, t_max]` (as the core's `any_hit`; for a patch,
    /// whether [`Dispatch::closest_hit_isa`] hits), on [`kernels`].
    fn any_hit_isa(&self, ray: &Ray<F>, t_min: F, t_max: F, n: usize) -> bool;
}

/// [`Dispatch`] for each queried type: its hit type and the [`Kernels`] queries that answer
/// for it, each called on [`kernels`].
macro_rules! dispatch {
    ($($t:ty => $hit:ty: $closest:path, $any:path;)+) => {$(
        impl<F: Precision> Dispatch<F> for $t {
            type Hit = $hit;
            #[inline]
            fn closest_hit_isa(&self, ray: &Ray<F>, t_min: F, t_max: F, n: usize) -> Option<$hit> {
                $closest(kernels(), self, ray, t_min, t_max, n)
            }
            #[inline]
            fn any_hit_isa(&self, ray: &Ray<F>, t_min: F, t_max: F, n: usize) -> bool {
                $any(kernels(), self, ray, t_min, t_max, n)
            }
        }
    )+};
}

dispatch! {
    Scene<'_, F> => SceneHit<F>: Kernels::scene_closest_hit, Kernels::scene_any_hit;
    Bvh<'_, F> => Hit<F>: Kernels::bvh_closest_hit, Kernels::bvh_any_hit;
    Patch<F> => Hit<F>: Kernels::patch_closest_hit, patch_any_hit;
}

/// Whether `patch` is hit in `[t_min, t_max]`: whether `k`'s closest-hit query of it hits (a
/// patch has no any-hit kernel of its own).
#[inline]
fn patch_any_hit<F: Precision>(
    k: Kernels,
    patch: &Patch<F>,
    ray: &Ray<F>,
    t_min: F,
    t_max: F,
    n: usize,
) -> bool {
    k.patch_closest_hit(patch, ray, t_min, t_max, n).is_some()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip_and_unknown_names_are_refused() {
        for isa in Isa::ALL {
            assert_eq!(Isa::parse(isa.name()), Some(isa));
            assert_eq!(Isa::parse(&isa.name().to_uppercase()), Some(isa));
            assert_eq!(isa.c_name().to_str().ok(), Some(isa.name()));
        }
        assert_eq!(Isa::parse("baseline"), Some(Isa::Baseline));
        assert_eq!(Isa::parse("avx"), None);
        assert_eq!(Isa::parse(""), None);
    }

    #[test]
    fn the_best_is_supported_and_unsupported_sets_are_refused() {
        assert!(Isa::best().supported());
        assert_eq!(Kernels::best().isa(), Isa::best());
        for isa in Isa::ALL {
            match Kernels::new(isa) {
                Ok(k) => assert!(isa.supported() && k.isa() == isa),
                Err(e) => assert!(!isa.supported() && e == IsaError::Unsupported(isa)),
            }
        }
        // Wider sets need every feature of the narrower ones.
        assert!(!Isa::Avx512.supported() || Isa::Avx2.supported());
    }
}
