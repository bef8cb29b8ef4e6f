//! The builder's work on large ranges in parts: bounds and SAH bins accumulated over
//! [`PARTS`] parts and merged exactly ([`in_parts`]), and the partition done part by part and
//! merged by rotations ([`partition_in_parts`]), each part a task of the executor, with the
//! same result on any executor.

use heapless::Vec as HVec;

use super::error::BvhError;
use crate::exec::Executor;

/// The smallest range of boxes built as a subtree of its own, one task of the executor (see
/// [`build_tree`](super::build::build_tree)).
pub(super) const SUBTREE_MIN: usize = 1024;
/// Boxes below which a range is bounded, binned and partitioned on the calling thread (see
/// [`examine`](super::build::examine)). Four times [`SUBTREE_MIN`]: the top of the tree stops
/// at ranges of `max(n / 32, SUBTREE_MIN)` boxes, so at most one level of it runs on one
/// thread, while a part (a sixteenth of the range, 256 boxes or more) stays large beside a
/// task's dispatch.
pub(super) const PARALLEL_MIN: usize = 4 * SUBTREE_MIN;
/// Parts of a range of at least [`PARALLEL_MIN`] boxes, each bounded, binned or partitioned as
/// one task; a fixed count, so that the parts (and the order their results merge in) do not
/// depend on the executor. Sixteen cover a sixteen-core machine; their SAH bins take
/// `16 × 3 × BINS` count-and-box pairs of stack (about 18 KiB for `f32`) while the top is built.
pub(super) const PARTS: usize = 16;

/// What can be accumulated over parts of a range and merged exactly.
pub(super) trait Merge: Copy + Send {
    /// `self` extended by `other` (a later part's).
    fn merge(&mut self, other: &Self);
}

/// What [`in_parts`] runs over each part: the accumulator and the part's indices.
pub(super) type Fold<'f, A> = dyn Fn(&mut A, &[u32]) -> Result<(), BvhError> + Sync + 'f;

/// `fold` over `range` from `init()`: in one piece on the calling thread below
/// [`PARALLEL_MIN`] boxes, otherwise over [`PARTS`] consecutive parts on `executor`, merged in
/// order. The first error of a part, in part order, is returned.
pub(super) fn in_parts<A: Merge>(
    range: &[u32],
    executor: &impl Executor,
    init: impl Fn() -> A,
    fold: &Fold<'_, A>,
) -> Result<A, BvhError> {
    let mut acc = init();
    if range.len() < PARALLEL_MIN {
        fold(&mut acc, range)?;
        return Ok(acc);
    }
    let size = range.len().div_ceil(PARTS);
    let mut parts: [(usize, A, Result<(), BvhError>); PARTS] =
        core::array::from_fn(|k| (k, init(), Ok(())));
    executor.run_chunks(&mut parts, 1, &|_, chunk| {
        for (k, a, result) in chunk.iter_mut() {
            let lo = (*k * size).min(range.len());
            let hi = (lo + size).min(range.len());
            *result = match range.get(lo..hi) {
                Some(part) => fold(a, part),
                None => Err(BvhError::Internal),
            };
        }
    });
    for (_, a, result) in parts.iter() {
        (*result)?;
        acc.merge(a);
    }
    Ok(acc)
}

/// [`partition`] of `range` by `pred`, below [`PARALLEL_MIN`] elements on the calling thread;
/// otherwise each of [`PARTS`] consecutive parts is partitioned in place on `executor`, then
/// neighbouring groups of parts are merged in four rounds (each merge rotates the left group's
/// rejected elements past the right group's accepted ones, by three reversals; the merges of a
/// round touch disjoint ranges and run on `executor`). Returns the number of elements
/// satisfying `pred`, moved to the front. The order within each side depends on the range and
/// `pred` alone, never on the executor; work `O(n log PARTS)` moves.
pub(super) fn partition_in_parts<P: Fn(u32) -> Result<bool, BvhError> + Sync>(
    range: &mut [u32],
    executor: &impl Executor,
    pred: &P,
) -> Result<usize, BvhError> {
    if range.len() < PARALLEL_MIN {
        return partition(range, pred);
    }
    let size = range.len().div_ceil(PARTS);
    // Each group's length and how many of its elements (at its front) satisfy `pred`.
    let mut groups: HVec<(usize, usize), PARTS> = HVec::new();
    let mut parts: HVec<(&mut [u32], Result<usize, BvhError>), PARTS> = HVec::new();
    for part in range.chunks_mut(size) {
        parts.push((part, Ok(0))).map_err(|_| BvhError::Internal)?;
    }
    executor.run_chunks(&mut parts, 1, &|_, chunk| {
        for (part, m) in chunk.iter_mut() {
            *m = partition(part, pred);
        }
    });
    for (part, m) in parts {
        groups
            .push((part.len(), m?))
            .map_err(|_| BvhError::Internal)?;
    }
    while groups.len() > 1 {
        // Neighbouring groups merged in pairs (an odd last group carried over).
        let mut merges: HVec<Merging<'_>, PARTS> = HVec::new();
        let mut next: HVec<(usize, usize), PARTS> = HVec::new();
        let mut rest: &mut [u32] = &mut *range;
        for pair in groups.chunks(2) {
            let (len, accepted) = match *pair {
                [(ll, ml), (rl, mr)] => {
                    let (slice, tail) = rest
                        .split_at_mut_checked(ll + rl)
                        .ok_or(BvhError::Internal)?;
                    rest = tail;
                    merges
                        .push((slice, [ll, ml, mr], Ok(())))
                        .map_err(|_| BvhError::Internal)?;
                    (ll + rl, ml + mr)
                }
                [(l, m)] => {
                    let (_, tail) = rest.split_at_mut_checked(l).ok_or(BvhError::Internal)?;
                    rest = tail;
                    (l, m)
                }
                _ => return Err(BvhError::Internal),
            };
            next.push((len, accepted)).map_err(|_| BvhError::Internal)?;
        }
        executor.run_chunks(&mut merges, 1, &|_, chunk| {
            for (slice, [ll, ml, mr], result) in chunk.iter_mut() {
                *result = merge_sides(slice, *ll, *ml, *mr);
            }
        });
        for (.., result) in merges {
            result?;
        }
        groups = next;
    }
    groups.first().map(|&(_, m)| m).ok_or(BvhError::Internal)
}

/// Two neighbouring groups' slice, the left one's length and both groups' accepted counts,
/// and the merge's outcome ([`merge_sides`]).
type Merging<'s> = (&'s mut [u32], [usize; 3], Result<(), BvhError>);

/// Merges two partitioned neighbours in `slice`: the first `left` elements are the left
/// group (its first `ml` satisfy the predicate), the rest the right group (its first `mr`).
/// Rotates the left group's rejected elements past the right group's accepted ones (three
/// reversals), so that the `ml + mr` accepted elements come first, each side in its order.
fn merge_sides(slice: &mut [u32], left: usize, ml: usize, mr: usize) -> Result<(), BvhError> {
    let rejected = left.checked_sub(ml).ok_or(BvhError::Internal)?;
    let middle = slice.get_mut(ml..left + mr).ok_or(BvhError::Internal)?;
    let (a, b) = middle
        .split_at_mut_checked(rejected)
        .ok_or(BvhError::Internal)?;
    a.reverse();
    b.reverse();
    middle.reverse();
    Ok(())
}

/// In-place partition; returns the number of elements satisfying `pred` (moved to the front).
pub(super) fn partition(
    range: &mut [u32],
    pred: impl Fn(u32) -> Result<bool, BvhError>,
) -> Result<usize, BvhError> {
    let mut m = 0usize;
    for j in 0..range.len() {
        // j < len: the split and `tail`'s first element always exist.
        let (head, tail) = range.split_at_mut_checked(j).ok_or(BvhError::Internal)?;
        let x = tail.first_mut().ok_or(BvhError::Internal)?;
        if pred(*x)? {
            // m ≤ j: for m < j swap with the first element not satisfying `pred`; for m = j
            // the element is already in place.
            if let Some(y) = head.get_mut(m) {
                core::mem::swap(x, y);
            }
            m += 1;
        }
    }
    Ok(m)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Runs chunks of one item each, last first: the most different order from one call that
    /// a thread pool could produce.
    struct Backwards;

    impl Executor for Backwards {
        fn run_chunks<T: Send>(
            &self,
            items: &mut [T],
            _grain: usize,
            work: &(dyn Fn(usize, &mut [T]) + Sync),
        ) {
            for k in (0..items.len()).rev() {
                if let Some(chunk) = items.get_mut(k..k + 1) {
                    work(k, chunk);
                }
            }
        }
    }

    const N: usize = 2 * PARALLEL_MIN + 7;

    /// [`partition_in_parts`] moves exactly the elements satisfying the predicate to the front,
    /// keeps every element, keeps the accepted side in its order, and gives the same result on
    /// any executor; below [`PARALLEL_MIN`] it is [`partition`] itself. (It fails when a merge
    /// rotates by the wrong amount or a part's count is dropped.)
    #[test]
    fn partition_in_parts_splits_by_the_predicate_on_any_executor() -> Result<(), BvhError> {
        for len in [PARALLEL_MIN - 1, PARALLEL_MIN, PARALLEL_MIN + 1, N] {
            for modulus in [1u32, 2, 3, 7, 1000, u32::MAX] {
                let pred = |i: u32| Ok(i.wrapping_mul(2_654_435_761).is_multiple_of(modulus));
                let accepted = |i: &u32| pred(*i) == Ok(true);
                let mut all: [[u32; N]; 3] = [core::array::from_fn(|k| k as u32); 3];
                let [a, b, c] = &mut all;
                fn cut(x: &mut [u32; N], len: usize) -> Result<&mut [u32], BvhError> {
                    x.get_mut(..len).ok_or(BvhError::Internal)
                }
                let (a, b, c) = (cut(a, len)?, cut(b, len)?, cut(c, len)?);
                let m = partition_in_parts(a, &(), &pred)?;
                let m_back = partition_in_parts(b, &Backwards, &pred)?;
                assert_eq!((m, &*a), (m_back, &*b));
                let want = (0..len as u32).filter(accepted).count();
                assert_eq!(m, want, "len {len} modulus {modulus}");
                let (front, back) = a.split_at_mut_checked(m).ok_or(BvhError::Internal)?;
                assert!(front.iter().all(accepted));
                assert!(!back.iter().any(accepted));
                assert!(front.windows(2).all(|w| w.first() < w.get(1)));
                if len < PARALLEL_MIN {
                    assert_eq!(partition(c, pred)?, m);
                    assert_eq!(&*c, &*a);
                }
                a.sort_unstable();
                assert!(a.iter().enumerate().all(|(k, &i)| i == k as u32));
            }
        }
        Ok(())
    }
}
