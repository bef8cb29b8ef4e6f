//! Library side of the `smoothtri` demo: built-in scenes, mesh loading, scene building,
//! rendering and precision studies over the `smoothtri` core.

pub mod cli;
pub mod csvio;
pub mod error;
pub mod image;
pub mod inspect;
pub mod mesh;
pub mod precision;
pub mod render;
pub mod scene;
pub mod scenes;
pub mod teapot_data;

pub use error::{DemoError, Result};
pub use scene::{Camera, Mode, Prec, Scene};
