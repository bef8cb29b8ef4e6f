//! Library side of the `smoothtri` demo: built-in scenes, mesh loading, scene building,
//! rendering and precision studies over the `smoothtri` core.

pub mod scenes;
