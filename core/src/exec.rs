//! Running the builder's work on the caller's threads: the [`Executor`] a caller puts in its
//! [`BuildOptions`](crate::BuildOptions) (the core has no threads of its own).
//!
//! Every parallel stage of the builder (the patches, the per-vertex remedy's checks, the shared
//! edges, the BVH's subtrees) hands the executor a slice of independent items and a pure
//! function of each: results are written into the items, then applied in index order on the
//! calling thread. So a scene is bit for bit the same whatever the executor, the thread count
//! or the chunking.

/// Runs a piece of the builder's work over chunks of a slice, on one thread (`()`) or on the
/// caller's thread pool (for example over rayon's `par_chunks_mut`).
pub trait Executor: Sync {
    /// Calls `work(start, chunk)` for consecutive chunks of `items` that together cover every
    /// element exactly once (`chunk` starts at index `start` of `items`), in any order, on any
    /// threads, possibly at the same time, and returns when every call has returned. `grain`
    /// is the smallest chunk worth a task (the caller's estimate: 1 for items that are each a
    /// large piece of work, more for small ones); an implementation may use larger chunks. An
    /// empty `items` may be skipped.
    ///
    /// # Panics
    /// Implementations must not panic (the core's never does).
    fn run_chunks<T: Send>(
        &self,
        items: &mut [T],
        grain: usize,
        work: &(dyn Fn(usize, &mut [T]) + Sync),
    );
}

/// One thread: a single call over the whole slice.
impl Executor for () {
    fn run_chunks<T: Send>(
        &self,
        items: &mut [T],
        _grain: usize,
        work: &(dyn Fn(usize, &mut [T]) + Sync),
    ) {
        work(0, items);
    }
}

/// An executor by reference (so options can borrow a pool).
impl<E: Executor> Executor for &E {
    fn run_chunks<T: Send>(
        &self,
        items: &mut [T],
        grain: usize,
        work: &(dyn Fn(usize, &mut [T]) + Sync),
    ) {
        (**self).run_chunks(items, grain, work);
    }
}
