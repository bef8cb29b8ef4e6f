//! Ray queries against a [`Scene`]: the smooth kernel at a run-time iteration budget (`N`), or
//! the flat and Phong baselines, chosen at run time by [`tracer`] ([`Mode`], the budget). The
//! precision-generic parts ([`Prec`], [`Precision`]), the scene build ([`Scene`]) and the
//! choices of the command line ([`Mode`], [`Field`], [`Normals`]) are in the submodules.

mod modes;
mod precision;
mod queries;
mod scene;

pub use modes::{Field, Mode, Normals};
pub use precision::{Prec, Precision};
pub use queries::{MAX_ITERATIONS, Tracer, smooth_tracer, tracer};
pub use scene::Scene;
