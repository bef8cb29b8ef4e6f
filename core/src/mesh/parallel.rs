//! The builder's per-edge scratch ([`EdgeWork`]), and the [`Executor`] a caller puts in its
//! [`BuildOptions`](crate::BuildOptions) to run the builder's work on its threads.
//!
//! Crack closure and the seam fit are computed edge by edge, each shared edge's result a pure
//! function of its two patches. The builder computes them in blocks of
//! [`SceneSizes::edge_work`](crate::SceneSizes::edge_work) edges into the caller's
//! [`EdgeWork`] storage, lets the executor spread each block over its threads, and applies the
//! results in edge order on the calling thread: the scene is bit for bit the same whatever the
//! executor, the thread count or the block length.

use super::seams::EdgeFit;
pub use crate::exec::Executor;
use crate::num::real::Float;

/// The builder's scratch for one shared edge: its crack gap, then its seam fits (opaque; the
/// caller provides [`SceneSizes::edge_work`](crate::SceneSizes::edge_work) of them, any
/// contents, e.g. [`EdgeWork::default`]).
///
/// Memory: 296 bytes in `f32`, 584 in `f64`.
#[derive(Clone, Copy, Debug, Default)]
pub struct EdgeWork<F: Float> {
    /// The widest gap between the two edge curves (world length).
    pub(crate) gap: f64,
    /// Both sides' seam fits, `None` where the edge gets no correction.
    pub(crate) fit: Option<(EdgeFit<F>, EdgeFit<F>)>,
}

/// The most edges per block, [`SceneSizes::edge_work`](crate::SceneSizes::edge_work): enough
/// to keep a thread pool busy between the serial steps (each edge costs microseconds), small
/// enough to stay in the caches (1.2 MB in `f32`).
pub const EDGE_WORK_BLOCK: usize = 4096;
