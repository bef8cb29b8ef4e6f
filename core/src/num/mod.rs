//! The number layer (private): the scalar traits ([`real`]) and their `f32`/`f64` impls
//! ([`primitives`]), vectors, dual numbers, jets, intervals, lanes and three-vectors of lanes
//! and the optional `FastF32`. Imports nothing else of the crate.

pub(crate) mod dual;
#[cfg(feature = "micromath")]
pub(crate) mod fast;
pub(crate) mod interval;
pub(crate) mod jet;
pub(crate) mod lane_vec;
pub(crate) mod lanes;
pub(crate) mod math;
pub(crate) mod primitives;
pub(crate) mod real;
pub(crate) mod vec;
