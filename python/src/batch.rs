//! Batches on many threads: the thread pools of `threads=`, the split of a batch's outputs into
//! chunks that rayon runs where it likes, and the first bad input of a batch.

use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};

use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use rayon::ThreadPool;

/// Items per chunk below which a batch is not split further: big enough that rayon's hand-off
/// (about a microsecond) is lost in the chunk's work (a ray costs 0.1–1 µs), small enough
/// that a few thousand rays keep every core busy.
const GRAIN: usize = 256;

/// The most threads `threads=` accepts.
pub const MAX_THREADS: usize = 1024;

/// Where a batch runs.
pub enum Threads {
    /// The calling thread only (`threads=1`).
    One,
    /// rayon's global pool, one thread per core (`threads=None`).
    Global,
    /// A pool of its own with this many threads (`threads=k`, kept for later calls).
    Pool(Arc<ThreadPool>),
}

/// The pools made for `threads=k`, one per `k`, kept for the process's life.
static POOLS: Mutex<Vec<(usize, Arc<ThreadPool>)>> = Mutex::new(Vec::new());

impl Threads {
    /// The threads of `threads=`: `None` for every core, else `1..=MAX_THREADS`.
    pub fn new(threads: Option<i64>) -> PyResult<Threads> {
        let Some(k) = threads else {
            return Ok(Threads::Global);
        };
        let k = usize::try_from(k)
            .ok()
            .filter(|k| (1..=MAX_THREADS).contains(k))
            .ok_or_else(|| {
                PyValueError::new_err(format!(
                    "threads must be None (every core) or in 1..={MAX_THREADS}, got {k}"
                ))
            })?;
        if k == 1 {
            return Ok(Threads::One);
        }
        let mut pools = POOLS
            .lock()
            .map_err(|_| PyRuntimeError::new_err("the thread pools' lock is poisoned"))?;
        if let Some((_, p)) = pools.iter().find(|(n, _)| *n == k) {
            return Ok(Threads::Pool(p.clone()));
        }
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(k)
            .thread_name(|i| format!("smoothtri-{i}"))
            .build()
            .map_err(|e| PyRuntimeError::new_err(format!("cannot start {k} threads: {e}")))?;
        let pool = Arc::new(pool);
        pools.push((k, pool.clone()));
        Ok(Threads::Pool(pool))
    }

    /// The number of threads.
    pub fn count(&self) -> usize {
        match self {
            Threads::One => 1,
            Threads::Global => rayon::current_num_threads(),
            Threads::Pool(p) => p.current_num_threads(),
        }
    }

    /// Runs `f` inside this pool (rayon's parallel iterators in `f` use its threads).
    pub fn install<R: Send>(&self, f: impl FnOnce() -> R + Send) -> R {
        match self {
            Threads::One | Threads::Global => f(),
            Threads::Pool(p) => p.install(f),
        }
    }

    /// `f(0), f(1), … f(n − 1)` computed on this pool's threads, in index order.
    pub fn map<T: Send>(&self, n: usize, f: impl Fn(usize) -> T + Sync + Send) -> Vec<T> {
        use rayon::prelude::*;
        match self {
            Threads::One => (0..n).map(f).collect(),
            _ => self.install(|| (0..n).into_par_iter().map(f).collect()),
        }
    }

    /// Calls `work(start, chunk)` on consecutive chunks of `items` that together cover it
    /// once (`chunk` begins at item `start`), on this pool's threads (`One`: one call on the
    /// calling thread).
    pub fn for_chunks<S: Split>(&self, items: S, work: &(dyn Fn(usize, S) + Sync)) {
        match self {
            Threads::One => work(0, items),
            _ => self.install(|| split(items, 0, work)),
        }
    }
}

/// Halves `items` until the pieces hold at most [`GRAIN`] items, each half a rayon task.
fn split<S: Split>(items: S, start: usize, work: &(dyn Fn(usize, S) + Sync)) {
    let n = items.len();
    if n <= GRAIN {
        work(start, items);
        return;
    }
    let mid = n / 2;
    let (a, b) = items.split_at(mid);
    rayon::join(|| split(a, start, work), || split(b, start + mid, work));
}

/// Outputs (or any items) that split into two disjoint parts at an item index.
pub trait Split: Send + Sized {
    /// The number of items.
    fn len(&self) -> usize;
    /// Items `..mid` and `mid..`.
    fn split_at(self, mid: usize) -> (Self, Self);
}

/// [`Split`] for a struct of outputs whose fields (lifetime `'_`, element type `F`) are each a
/// [`Split`] over the same items: its items are the first field's, and every field splits at
/// the same item.
macro_rules! split_fields {
    ($out:ident: $first:ident $(, $field:ident)* $(,)?) => {
        impl<F: Send> $crate::batch::Split for $out<'_, F> {
            fn len(&self) -> usize {
                $crate::batch::Split::len(&self.$first)
            }
            fn split_at(self, mid: usize) -> (Self, Self) {
                let $first = $crate::batch::Split::split_at(self.$first, mid);
                $(let $field = $crate::batch::Split::split_at(self.$field, mid);)*
                (
                    $out { $first: $first.0, $($field: $field.0),* },
                    $out { $first: $first.1, $($field: $field.1),* },
                )
            }
        }
    };
}
pub(crate) use split_fields;

/// A range of item indices (work whose outputs are gathered elsewhere).
impl Split for std::ops::Range<usize> {
    fn len(&self) -> usize {
        self.end - self.start
    }
    fn split_at(self, mid: usize) -> (Self, Self) {
        let m = self.start + mid;
        (self.start..m, m..self.end)
    }
}

/// One value per item.
impl<T: Send> Split for &mut [T] {
    fn len(&self) -> usize {
        <[T]>::len(self)
    }
    fn split_at(self, mid: usize) -> (Self, Self) {
        self.split_at_mut(mid)
    }
}

/// `K` values per item (a row of an `(N, K)` array).
pub struct Rows<'a, T, const K: usize>(pub &'a mut [T]);

impl<T: Send, const K: usize> Split for Rows<'_, T, K> {
    fn len(&self) -> usize {
        self.0.len() / K
    }
    fn split_at(self, mid: usize) -> (Self, Self) {
        let (a, b) = self.0.split_at_mut(mid * K);
        (Rows(a), Rows(b))
    }
}

impl<T, const K: usize> Rows<'_, T, K> {
    /// Writes item `i`'s row.
    #[inline]
    pub fn set(&mut self, i: usize, v: [T; K]) {
        if let Some(row) = self.0.get_mut(i * K..(i + 1) * K) {
            for (slot, x) in row.iter_mut().zip(v) {
                *slot = x;
            }
        }
    }
}

/// The smallest index of a bad input in a batch whose chunks run at once.
pub struct FirstBad(AtomicUsize);

impl FirstBad {
    /// None yet.
    pub fn new() -> Self {
        FirstBad(AtomicUsize::new(usize::MAX))
    }
    /// Item `i` is bad.
    #[inline]
    pub fn report(&self, i: usize) {
        self.0.fetch_min(i, Ordering::Relaxed);
    }
    /// The first bad item, if any.
    pub fn get(&self) -> Option<usize> {
        match self.0.load(Ordering::Relaxed) {
            usize::MAX => None,
            i => Some(i),
        }
    }
}
