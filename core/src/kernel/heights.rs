//! How a patch test evaluates its function `f`: the lane calls of the kernel behind one trait,
//! so that one search (clip, bracket, refine, [`super::crossing`]) runs with the lane code
//! compiled for the build's target ([`target`]) or for an instruction set chosen at run time
//! ([`Calls`], made by `crate::isa`).
//!
//! Every implementation computes the same lanes with the same IEEE operations in the same
//! order (the lane code of [`Prepared::f`]), so the values are bit for bit the same whatever
//! the lane type and the instruction set (docs/METHOD.md §8, "Instruction sets").

use super::refine::ESTIMATE_POINTS;
use crate::num::lanes::{LANES, Lane, Lane4, LaneOps};
use crate::num::real::Float;
use crate::num::vec::V3;
use crate::surface::lanes::Prepared;

/// The parameters, or the values of `f`, of one four-point estimate step.
pub(crate) type Four<F> = [F; ESTIMATE_POINTS];

/// The lane calls of one patch test: `f(τ)` at the parameters `taus` of the local ray
/// `o + τ·r`, eight at a time (bracketing and refinement) or four (the estimate step).
pub(crate) trait Heights<F: Float> {
    /// `f` at eight parameters: one lane call.
    fn f8(&self, prep: &Prepared<F>, o: V3<F>, r: V3<F>, taus: [F; LANES]) -> [F; LANES];
    /// `f` at four parameters: the same values as the first four lanes of [`Heights::f8`]
    /// at them.
    fn f4(&self, prep: &Prepared<F>, o: V3<F>, r: V3<F>, taus: Four<F>) -> Four<F>;
}

/// The lane code compiled for the build's target: over [`Float::L8`] and [`Float::L4`], out
/// of line once per lane type ([`Prepared::f`]), as the lane calls of [`Calls`].
#[inline(always)]
pub(crate) fn target<F: Float>() -> impl Heights<F> {
    Calls(eight::<F, F::L8, false>, four::<F, F::L8, F::L4, false>)
}

/// Lane calls made by two functions (closures): the kernels per instruction set
/// (`crate::isa`) pass closures that call their out-of-line lane functions, compiled with
/// that instruction set's features.
pub(crate) struct Calls<A, B>(pub A, pub B);

impl<F, A, B> Heights<F> for Calls<A, B>
where
    F: Float,
    A: Fn(&Prepared<F>, V3<F>, V3<F>, [F; LANES]) -> [F; LANES],
    B: Fn(&Prepared<F>, V3<F>, V3<F>, Four<F>) -> Four<F>,
{
    #[inline(always)]
    fn f8(&self, prep: &Prepared<F>, o: V3<F>, r: V3<F>, taus: [F; LANES]) -> [F; LANES] {
        (self.0)(prep, o, r, taus)
    }
    #[inline(always)]
    fn f4(&self, prep: &Prepared<F>, o: V3<F>, r: V3<F>, taus: Four<F>) -> Four<F> {
        (self.1)(prep, o, r, taus)
    }
}

/// `[v.x, v.y, v.z]`, each in every lane.
#[inline(always)]
fn splat3<L: LaneOps>(v: V3<L::F>) -> [L; 3] {
    [L::splat(v.x), L::splat(v.y), L::splat(v.z)]
}

/// `f` at eight parameters over the lanes `L` (the ray splatted): the lane code out of line
/// ([`Prepared::f`]), or inlined into the caller when `INLINE` ([`Prepared::f_inline`]).
#[inline(always)]
pub(crate) fn eight<F: Float, L: Lane<F = F>, const INLINE: bool>(
    prep: &Prepared<F>,
    o: V3<F>,
    r: V3<F>,
    taus: [F; LANES],
) -> [F; LANES] {
    let (o8, r8, t) = (splat3::<L>(o), splat3::<L>(r), L::from_array(taus));
    if INLINE {
        prep.f_inline(o8, r8, t).to_array()
    } else {
        prep.f(o8, r8, t).to_array()
    }
}

/// `f` at four parameters: one call over the four lanes `L4` where they hold four values (bit
/// for bit the same lanes of an eight-lane call: the same operations per lane), else one call
/// over the eight lanes `L8` ([`eight`]).
#[inline(always)]
pub(crate) fn four<F: Float, L8: Lane<F = F>, L4: Lane4<F = F>, const INLINE: bool>(
    prep: &Prepared<F>,
    o: V3<F>,
    r: V3<F>,
    taus: [F; ESTIMATE_POINTS],
) -> [F; ESTIMATE_POINTS] {
    if L4::POINTS == ESTIMATE_POINTS {
        let (o4, r4, t) = (splat3::<L4>(o), splat3::<L4>(r), L4::from_array4(taus));
        let f = if INLINE {
            prep.f_inline(o4, r4, t)
        } else {
            prep.f(o4, r4, t)
        };
        return f.to_array4();
    }
    let [a, b, c, d] = taus;
    let [fa, fb, fc, fd, ..] = eight::<F, L8, INLINE>(prep, o, r, [a, b, c, d, d, d, d, d]);
    [fa, fb, fc, fd]
}
