//! The two precisions a scene is built and traced in, as numpy sees them.

use numpy::Element;
use smoothtri::Float;

/// `f32` or `f64`: the core's [`Float`] that is also a numpy element (`float32`, `float64`).
/// Vectors convert through [`Float`]'s own methods (`to_array3`, `from_array3`,
/// `from_dvec3`).
pub trait Prec:
    Float<Vec3: Send + Sync> + smoothtri_isa::Precision + Element + Send + Sync + 'static
{
    /// The numpy dtype name (`"float32"`, `"float64"`), for messages.
    const DTYPE: &'static str;
}

impl Prec for f32 {
    const DTYPE: &'static str = "float32";
}

impl Prec for f64 {
    const DTYPE: &'static str = "float64";
}
