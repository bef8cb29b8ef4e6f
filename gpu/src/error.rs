//! [`GpuError`]: every failure of the crate, never a panic.

use std::fmt;

use crate::shader::MAX_ITERATIONS;

/// Why a GPU query could not run. Every failure of this crate is one of these.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum GpuError {
    /// No Vulkan adapter (GPU, or a software one such as Mesa's lavapipe) was found.
    NoAdapter,
    /// The adapter refused to create a device.
    RequestDevice(String),
    /// The shader or a pipeline failed to compile or validate on this device.
    Shader(String),
    /// A buffer would exceed the device's limits.
    TooLarge {
        /// Which buffer.
        what: &'static str,
        /// Bytes needed.
        bytes: u64,
        /// The device's limit.
        limit: u64,
    },
    /// The output slice's length differs from the ray slice's.
    LengthMismatch {
        /// Rays given.
        rays: usize,
        /// Output slots given.
        out: usize,
    },
    /// [`GpuScene::update`](crate::GpuScene::update) was given another mesh: `given` patches
    /// (or seams) for a scene of `scene` patches.
    SceneMismatch {
        /// What was counted: `"patch"`, `"seam"`, `"node"` or `"order"`.
        what: &'static str,
        /// The scene's patches.
        scene: usize,
        /// The count given.
        given: usize,
    },
    /// An iteration budget above [`MAX_ITERATIONS`](crate::MAX_ITERATIONS).
    Iterations(usize),
    /// The shader found a node or patch index outside the uploaded buffers, a node reached more
    /// often than the tree has nodes, or a leaf longer than the order (storage not made by
    /// [`Bvh::build`](smoothtri::Bvh::build)). The affected rays were reported as misses.
    CorruptTree,
    /// The traversal stack would have overflowed (only possible with a tree deeper than
    /// [`STACK`](crate::STACK), i.e. storage not made by [`Bvh::build`](smoothtri::Bvh::build)).
    StackOverflow,
    /// A device error while tracing (validation, out of memory, lost device, mapping).
    Device(String),
    /// The mesh given to a [`GpuUpdate`](crate::GpuUpdate) has a vertex index at or above the
    /// vertex count, or repeated in a triangle.
    Mesh(smoothtri::mesh::MeshError),
    /// The device cannot do what was asked for this input (for example, build patches on a line
    /// field whose remedy runs on the CPU).
    Unsupported(&'static str),
    /// A vertex buffer of `given` values where `expected` (three per vertex) were needed.
    VertexCount {
        /// Values needed.
        expected: usize,
        /// Values given.
        given: usize,
    },
    /// The device cannot present to the window (no surface for it, no format in common, a
    /// surface lost for good).
    Surface(String),
}

impl fmt::Display for GpuError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            GpuError::NoAdapter => f.write_str(
                "no GPU adapter: no Vulkan device found (install a driver, or Mesa's software \
                 Vulkan, Debian package mesa-vulkan-drivers)",
            ),
            GpuError::RequestDevice(m) => write!(f, "the GPU adapter refused a device: {m}"),
            GpuError::Shader(m) => write!(f, "the GPU kernel failed to compile: {m}"),
            GpuError::TooLarge { what, bytes, limit } => write!(
                f,
                "the {what} buffer needs {bytes} bytes, over the device's limit of {limit}"
            ),
            GpuError::LengthMismatch { rays, out } => {
                write!(f, "{rays} rays but {out} output slots")
            }
            GpuError::SceneMismatch { what, scene, given } => write!(
                f,
                "the update gives {given} {what} records for a scene of {scene} patches"
            ),
            GpuError::Iterations(n) => write!(
                f,
                "iteration budget {n} is above the largest supported, {MAX_ITERATIONS}"
            ),
            GpuError::CorruptTree => f.write_str(
                "the BVH uploaded to the GPU is corrupt (an index outside the storage, or a \
                 node reached twice)",
            ),
            GpuError::StackOverflow => f.write_str("GPU BVH traversal stack overflow"),
            GpuError::Device(m) => write!(f, "GPU device error: {m}"),
            GpuError::Mesh(e) => write!(f, "the mesh cannot be updated on the GPU: {e}"),
            GpuError::Unsupported(m) => write!(f, "not supported on the GPU: {m}"),
            GpuError::VertexCount { expected, given } => write!(
                f,
                "a vertex buffer of {given} values where {expected} (three per vertex) are needed"
            ),
            GpuError::Surface(m) => write!(f, "cannot present to the window on the GPU: {m}"),
        }
    }
}

impl std::error::Error for GpuError {}
