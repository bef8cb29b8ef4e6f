//! The kernel's two floating-point precisions: [`Precision`] names one at run time (the
//! `--precision` option), [`Prec`] is the type-level side that generic code runs on.

use smoothtri::Float;

/// Floating-point precision of the kernel, as chosen on the command line. Code generic over
/// [`Prec`] is reached with one `match` on this enum (`F32 => f::<f32>()`,
/// `F64 => f::<f64>()`); inside, [`Prec::PRECISION`] tells which one it runs in.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, clap::ValueEnum)]
pub enum Precision {
    /// Single precision (the real-time path).
    F32,
    /// Double precision.
    F64,
}

impl Precision {
    /// `"f32"` or `"f64"`, as in messages, tables and CSV.
    pub fn name(self) -> &'static str {
        match self {
            Precision::F32 => "f32",
            Precision::F64 => "f64",
        }
    }
}

impl std::fmt::Display for Precision {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.pad(self.name())
    }
}

impl From<Precision> for smoothtri_io::FloatWidth {
    /// The width a mesh writer stores numbers in, so that they read back exactly in `p`.
    fn from(p: Precision) -> Self {
        match p {
            Precision::F32 => smoothtri_io::FloatWidth::F32,
            Precision::F64 => smoothtri_io::FloatWidth::F64,
        }
    }
}

/// The two primitive precisions as the demo runs them: the core's [`Float`] (with its
/// conversions from and to `f64`: [`Float::from_dvec3`], [`Float::to_dvec3`],
/// [`Float::to_array3`]), the run-time name, printing and exact parsing.
pub trait Prec:
    Float + smoothtri_isa::Precision + Send + Sync + std::fmt::Display + 'static
{
    /// Which precision this is.
    const PRECISION: Precision;
    /// Parses a decimal number directly in this precision (so that printed values read back
    /// exactly); `None` when it is not a number.
    fn parse(tok: &str) -> Option<Self>;
}

impl Prec for f32 {
    const PRECISION: Precision = Precision::F32;
    fn parse(tok: &str) -> Option<f32> {
        tok.parse().ok()
    }
}

impl Prec for f64 {
    const PRECISION: Precision = Precision::F64;
    fn parse(tok: &str) -> Option<f64> {
        tok.parse().ok()
    }
}
