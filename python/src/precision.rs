//! The two precisions a scene is built and traced in, as numpy sees them.

use glam::{DVec3, Vec3};
use numpy::Element;
use smoothtri::Float;

/// `f32` or `f64`: the core's [`Float`] that is also a numpy element (`float32`, `float64`).
pub trait Prec: Float<Vec3: Send + Sync> + Element + Send + Sync + 'static {
    /// The numpy dtype name (`"float32"`, `"float64"`), for messages.
    const DTYPE: &'static str;
    /// The components of a vector.
    fn arr(v: Self::Vec3) -> [Self; 3];
    /// The vector of three components.
    fn from_arr(v: [Self; 3]) -> Self::Vec3;
    /// The vector of three `f64` components, each rounded once to this precision.
    fn vec(v: [f64; 3]) -> Self::Vec3 {
        Self::from_dvec3(DVec3::from_array(v))
    }
}

impl Prec for f32 {
    const DTYPE: &'static str = "float32";
    fn arr(v: Vec3) -> [f32; 3] {
        v.to_array()
    }
    fn from_arr(v: [f32; 3]) -> Vec3 {
        Vec3::from_array(v)
    }
}

impl Prec for f64 {
    const DTYPE: &'static str = "float64";
    fn arr(v: DVec3) -> [f64; 3] {
        v.to_array()
    }
    fn from_arr(v: [f64; 3]) -> DVec3 {
        DVec3::from_array(v)
    }
}
