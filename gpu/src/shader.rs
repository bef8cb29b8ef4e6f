//! The shader and what it is compiled for: the WGSL source ([`SHADER`]), the kernel's sizes and
//! budgets (bracketing samples, traversal stack, iteration budgets, record and ray layouts), and
//! the shading normal a pipeline writes ([`Shading`]).

/// The shader (WGSL), as compiled by [`Gpu::new`](crate::Gpu::new): one file per stage in
/// `gpu/src/kernel/`, in the order of their dependencies as the core's layers are (the
/// parameters and bindings; the records and boxes; the surface's height; the clip; bracketing
/// and refinement; the exact normal; the flat baseline; the traversal; the seamless and Phong
/// shading normals; the batch entry points; the frame entry point).
pub const SHADER: &str = concat!(
    include_str!("kernel/params.wgsl"),
    "\n",
    include_str!("kernel/records.wgsl"),
    "\n",
    include_str!("kernel/surface.wgsl"),
    "\n",
    include_str!("kernel/clip.wgsl"),
    "\n",
    include_str!("kernel/refine.wgsl"),
    "\n",
    include_str!("kernel/normal.wgsl"),
    "\n",
    include_str!("kernel/flat.wgsl"),
    "\n",
    include_str!("kernel/traversal.wgsl"),
    "\n",
    include_str!("kernel/seams.wgsl"),
    "\n",
    include_str!("kernel/batch.wgsl"),
    "\n",
    include_str!("kernel/frame.wgsl"),
);

/// The scene update's passes (WGSL, one file per pass in `gpu/src/update/`), compiled after
/// [`SHADER`] with its patch records and nodes writable ([`GpuUpdate`](crate::GpuUpdate)).
pub const UPDATE_SHADER: &str = concat!(
    include_str!("update/patch.wgsl"),
    "\n",
    include_str!("update/cracks.wgsl"),
    "\n",
    include_str!("update/seams.wgsl"),
    "\n",
    include_str!("update/tree.wgsl"),
    "\n",
    include_str!("update/normals.wgsl"),
);

/// Interior bracketing samples `K` of the shader (the CPU's `DEFAULT_SAMPLES`): `K + 2 = 8`
/// points.
pub const SAMPLES: usize = 6;
/// Entries of the shader's traversal stack (the CPU's [`smoothtri::BVH_STACK`]).
pub const STACK: usize = smoothtri::BVH_STACK;
/// The refinement budget the demo uses by default on the GPU.
pub const DEFAULT_ITERATIONS: usize = 4;
/// Largest refinement budget a pipeline is built for: the CPU kernel's
/// [`smoothtri::MAX_ITERATIONS`].
pub const MAX_ITERATIONS: usize = smoothtri::MAX_ITERATIONS;
/// `vec4<f32>` per smooth patch record: 432 bytes (the patch data of
/// [`PatchData`](smoothtri::PatchData), the CPU kernel's per-patch precomputation and the
/// culling band).
pub const PATCH_VEC4: usize = 27;
/// `vec4<f32>` per flat triangle record (the three world vertices).
pub const FLAT_VEC4: usize = 3;
/// Bytes per ray uploaded (`origin, t_min, dir, t_max`).
pub const RAY_BYTES: usize = 32;
/// Bytes per hit read back.
pub const HIT_BYTES: usize = 64;
/// `vec4<f32>` per seam record (the seamless normal's coefficients of one patch,
/// [`seam_record`](crate::seam_record)): 160 bytes.
pub const SEAM_VEC4: usize = 10;
/// Invocations per workgroup.
pub(crate) const WORKGROUP: u32 = 64;

/// The shading normal a scene's closest hits and frames carry (the shader's `SHADING`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Shading {
    /// The geometric normal: the patch's exact normal, or the flat triangle's face normal.
    Geometric = 0,
    /// The seamless normal of smooth patches ([`smoothtri::mesh::Seam::correct`]).
    Seamless = 1,
    /// The flat triangles' interpolated vertex normals (Phong).
    Phong = 2,
}
