//! The scene in caller memory: its layout, the build into it, and the lookup of a scene from
//! the pointer C hands back.
//!
//! Layout of the memory given to `st_scene_build` (each part aligned for its type inside it,
//! whatever the memory's own alignment):
//!
//! ```text
//! [Stored<F>] [patches] [triangle ids] [BVH nodes] [BVH order] [seams] | scratch: [triangles]
//! [shared edges] [edge work] [vertex positions, normals, clamped normals, clamps]
//! ```
//!
//! Everything before `|` is the scene (`bytes_used`); the scratch is free once the build
//! returns, unless the scene is updatable ([`ST_BUILD_UPDATABLE`]): it then keeps the scratch
//! for its updates. `Stored` holds the core's `Scene` (or `DynamicScene`), which borrows the
//! parts after it: the borrow's lifetime is the caller's promise to keep the memory in place
//! while the scene is used.

use core::ffi::c_void;
use core::mem::{align_of, size_of};

use smoothtri::mesh::{Seam, SharedEdge, VertexClamp};
use smoothtri::{
    BuildError, BuildOptions, BvhNode, DynamicScene, EdgeWork, Float, LineField, Patch, PatchError,
    Scene, SceneSizes, SceneStorage, Vertices,
};

use crate::types::{
    ST_BUILD_SEAMS, ST_BUILD_SHARED_FIELD, ST_BUILD_UPDATABLE, ST_ERROR_BUFFER_TOO_SMALL,
    ST_ERROR_INDEX_OUT_OF_RANGE, ST_ERROR_INTERNAL, ST_ERROR_INVALID_ARGUMENT,
    ST_ERROR_NO_USABLE_TRIANGLES, ST_ERROR_NON_FINITE, ST_ERROR_NOT_UPDATABLE,
    ST_ERROR_NULL_ARGUMENT, ST_ERROR_TOO_LARGE, ST_ERROR_WRONG_SCENE, ST_INVALID_ID,
    ST_MAX_ITERATIONS, ST_OK, st_scene_info, st_status,
};

/// The precisions of the C API, each with the tag that marks its scenes.
pub(crate) trait Prec: Float + smoothtri_isa::Precision + 'static {
    /// The first eight bytes of a `Stored<Self>`.
    const MAGIC: u64;
}

impl Prec for f32 {
    const MAGIC: u64 = u64::from_le_bytes(*b"stScn-32");
}

impl Prec for f64 {
    const MAGIC: u64 = u64::from_le_bytes(*b"stScn-64");
}

/// A scene as built: fixed, or updatable ([`ST_BUILD_UPDATABLE`]).
enum Kept<F: Float + 'static> {
    /// A scene that never changes.
    Fixed(Scene<'static, F>),
    /// A scene that `st_scene_update` moves, with the number of its updates.
    Dynamic(DynamicScene<'static, F>, u32),
}

/// The head of a built scene, at the (aligned) start of the caller's memory.
#[repr(C)]
pub(crate) struct Stored<F: Float + 'static> {
    /// [`Prec::MAGIC`]: tells a scene of this precision from anything else.
    magic: u64,
    /// The scene; borrows the memory after this head.
    kept: Kept<F>,
    /// The kernel's refinement budget, at most [`smoothtri::MAX_ITERATIONS`].
    pub(crate) iterations: u32,
    /// The build flags.
    pub(crate) flags: u32,
    /// Bytes from the caller's `memory` to the end of the scene's parts.
    pub(crate) bytes_used: usize,
}

impl<F: Prec> Stored<F> {
    /// The scene behind a pointer from C: `None` for NULL, a misaligned pointer, or memory
    /// that does not start with this precision's tag.
    ///
    /// The pointer must be NULL or point to readable memory of at least 8 bytes (a scene from
    /// `st_scene_build` whose memory is still valid): the C API's contract.
    pub(crate) fn from_ptr<'a>(p: *const c_void) -> Option<&'a Stored<F>> {
        let p = p.cast::<Stored<F>>();
        if p.is_null() || !p.is_aligned() {
            return None;
        }
        // SAFETY: non-null, aligned for `Stored<F>` (so for its leading `u64`), and by the
        // contract readable; the tag is read as a plain `u64` before any reference of type
        // `Stored<F>` is made, so memory of another type is only ever read as an integer.
        let magic = unsafe { p.cast::<u64>().read() };
        if magic != F::MAGIC {
            return None;
        }
        // SAFETY: the tag says `st_scene_build` wrote a `Stored<F>` here (the tag is written
        // last, after the scene), and the caller keeps the memory valid and unchanged while the
        // scene is used; the scene is never written through after the build.
        Some(unsafe { &*p })
    }

    /// [`Stored::from_ptr`] for writing (`st_scene_update`).
    ///
    /// The pointer must be NULL or point to readable memory of at least 8 bytes, and while the
    /// returned reference lives nothing else may use the scene (no query on another thread):
    /// the C API's contract for `st_scene_update`.
    pub(crate) fn from_ptr_mut<'a>(p: *mut c_void) -> Option<&'a mut Stored<F>> {
        Stored::<F>::from_ptr(p)?;
        // SAFETY: `from_ptr` checked that `p` is non-null, aligned and holds a `Stored<F>`
        // written by `st_scene_build` into memory the caller gave for writing; the contract
        // gives this call the only access to it while the reference lives, so no other
        // reference to the head or to the parts it borrows is used meanwhile.
        Some(unsafe { &mut *p.cast::<Stored<F>>() })
    }

    /// The scene of a call that writes its answer to `out`: [`ST_ERROR_NULL_ARGUMENT`] when
    /// `scene` or `out` is NULL, [`ST_ERROR_WRONG_SCENE`] when `scene` is not a scene of this
    /// precision (the checks every such call makes first, in this order).
    ///
    /// `scene` must be NULL or point to readable memory of at least 8 bytes, as for
    /// [`Stored::from_ptr`].
    pub(crate) fn with_output<'a, T>(
        scene: *const c_void,
        out: *mut T,
    ) -> Result<&'a Stored<F>, st_status> {
        if scene.is_null() || out.is_null() {
            return Err(ST_ERROR_NULL_ARGUMENT);
        }
        Stored::from_ptr(scene).ok_or(ST_ERROR_WRONG_SCENE)
    }

    /// The scene, for queries.
    pub(crate) fn scene(&self) -> Scene<'_, F> {
        match &self.kept {
            Kept::Fixed(scene) => *scene,
            Kept::Dynamic(scene, _) => scene.scene(),
        }
    }
}

/// The build options a flag word asks for; `None` for unknown bits.
fn options(flags: u32) -> Option<BuildOptions> {
    if flags & !(ST_BUILD_SEAMS | ST_BUILD_SHARED_FIELD | ST_BUILD_UPDATABLE) != 0 {
        return None;
    }
    Some(BuildOptions {
        field: if flags & ST_BUILD_SHARED_FIELD != 0 {
            LineField::Vertex
        } else {
            LineField::Face
        },
        seams: flags & ST_BUILD_SEAMS != 0,
        ..BuildOptions::default()
    })
}

/// The bytes one part of `n` values of `T` may take, its worst-case alignment padding included.
fn part<T>(n: usize) -> Option<usize> {
    n.checked_mul(size_of::<T>())?
        .checked_add(align_of::<T>() - 1)
}

/// The bytes of the whole layout for `sizes` (see the module docs), padding included.
fn layout_bytes<F: Prec>(sizes: &SceneSizes) -> Option<usize> {
    [
        part::<Stored<F>>(1)?,
        part::<Patch<F>>(sizes.patches)?,
        part::<u32>(sizes.patches)?,
        part::<BvhNode<F>>(sizes.nodes)?,
        part::<u32>(sizes.patches)?,
        part::<Seam<F>>(sizes.seams)?,
        part::<[u32; 3]>(sizes.patches)?,
        part::<SharedEdge>(sizes.edges)?,
        part::<EdgeWork<F>>(sizes.edge_work)?,
        part::<F::Vec3>(sizes.vertices)?.checked_mul(3)?,
        part::<VertexClamp<F>>(sizes.vertices)?,
    ]
    .iter()
    .try_fold(0usize, |a, &b| a.checked_add(b))
    .filter(|&b| isize::try_from(b).is_ok())
}

/// `st_scene_required_bytes`.
///
/// # Safety
/// `bytes` is NULL or valid for one write.
pub(crate) unsafe fn required_bytes<F: Prec>(
    vertex_count: usize,
    triangle_count: usize,
    flags: u32,
    bytes: *mut usize,
) -> st_status {
    if bytes.is_null() {
        return ST_ERROR_NULL_ARGUMENT;
    }
    let Some(options) = options(flags) else {
        return ST_ERROR_INVALID_ARGUMENT;
    };
    let Some(needed) = SceneSizes::new(vertex_count, triangle_count, &options)
        .and_then(|sizes| layout_bytes::<F>(&sizes))
    else {
        return ST_ERROR_TOO_LARGE;
    };
    if !bytes.is_aligned() {
        return ST_ERROR_INVALID_ARGUMENT;
    }
    // SAFETY: non-null and aligned; writable by the contract.
    unsafe { bytes.write(needed) };
    ST_OK
}

/// The arguments of `st_scene_build` that describe the mesh.
pub(crate) struct Input<T> {
    /// The vertex arguments, as `st_scene_update` takes them too.
    pub(crate) vertices: VertexInput<T>,
    pub(crate) indices: *const u32,
    pub(crate) triangle_count: usize,
    pub(crate) flags: u32,
    pub(crate) iterations: u32,
}

/// A bump allocator over the caller's memory: hands out aligned, initialised, disjoint parts.
struct Arena {
    base: *mut u8,
    len: usize,
    used: usize,
}

impl Arena {
    /// Reserves room for one `T` (left uninitialised) and returns its offset from `base`.
    fn reserve<T>(&mut self) -> Option<usize> {
        let addr = (self.base as usize).checked_add(self.used)?;
        let start = self.used + (addr.checked_next_multiple_of(align_of::<T>())? - addr);
        let end = start.checked_add(size_of::<T>())?;
        if end > self.len {
            return None;
        }
        self.used = end;
        Some(start)
    }

    /// The next `n` values of `T`, each set to `fill`; `None` when they do not fit.
    fn take<T: Copy>(&mut self, n: usize, fill: T) -> Option<&'static mut [T]> {
        let addr = (self.base as usize).checked_add(self.used)?;
        let pad = addr.checked_next_multiple_of(align_of::<T>())? - addr;
        let start = self.used.checked_add(pad)?;
        let end = start.checked_add(n.checked_mul(size_of::<T>())?)?;
        if end > self.len {
            return None;
        }
        // SAFETY: `start..end` lies inside the caller's `len` writable bytes at `base` (checked
        // just above), starts aligned for `T`, and no earlier part overlaps it (`used` only
        // grows). Every value is written before the slice is made, so the slice is initialised.
        // The `'static` lifetime is the C contract: the memory outlives every use of the scene.
        let slice = unsafe {
            let p = self.base.add(start).cast::<T>();
            for i in 0..n {
                p.add(i).write(fill);
            }
            core::slice::from_raw_parts_mut(p, n)
        };
        self.used = end;
        Some(slice)
    }
}

/// The C status of a build error.
fn status_of(e: BuildError) -> st_status {
    match e {
        BuildError::NoTriangles => ST_ERROR_NO_USABLE_TRIANGLES,
        BuildError::NoUsableTriangles {
            first: PatchError::NonFinite,
            ..
        } => ST_ERROR_NON_FINITE,
        BuildError::NoUsableTriangles { .. } => ST_ERROR_NO_USABLE_TRIANGLES,
        BuildError::NonFiniteVertex { .. } => ST_ERROR_NON_FINITE,
        BuildError::IndexOutOfRange { .. } => ST_ERROR_INDEX_OUT_OF_RANGE,
        BuildError::VertexLayout { .. }
        | BuildError::VertexCountMismatch { .. }
        | BuildError::VertexCountChanged { .. } => ST_ERROR_INVALID_ARGUMENT,
        BuildError::StorageTooSmall { .. } => ST_ERROR_BUFFER_TOO_SMALL,
        BuildError::TooLarge => ST_ERROR_TOO_LARGE,
        _ => ST_ERROR_INTERNAL,
    }
}

/// A vertex attribute read through a byte stride: the scalar stride, or `None` when the
/// stride or the pointer does not suit `T`.
fn scalar_stride<T>(ptr: *const T, stride_bytes: usize) -> Option<usize> {
    let size = size_of::<T>();
    let stride = if stride_bytes == 0 {
        3 * size
    } else {
        stride_bytes
    };
    (stride % size == 0 && stride >= 3 * size && ptr.is_aligned()).then_some(stride / size)
}

/// `vertex_count` vertices of one attribute, as the core reads them.
///
/// # Safety
/// `ptr` is non-null, aligned and readable for `vertex_count` vertices at `stride` scalars.
unsafe fn vertices<'a, T: Float>(
    ptr: *const T,
    stride: usize,
    vertex_count: usize,
) -> Result<Vertices<'a, T>, st_status> {
    let len = match vertex_count.checked_sub(1) {
        None => 0,
        Some(last) => last
            .checked_mul(stride)
            .and_then(|x| x.checked_add(3))
            .ok_or(ST_ERROR_TOO_LARGE)?,
    };
    if len
        .checked_mul(size_of::<T>())
        .is_none_or(|b| isize::try_from(b).is_err())
    {
        return Err(ST_ERROR_TOO_LARGE);
    }
    let data: &[T] = if len == 0 {
        &[]
    } else {
        // SAFETY: by the contract the caller's buffer holds `vertex_count` vertices at `stride`
        // scalars, so its first `len` scalars are readable; `ptr` is non-null (vertex_count >
        // 0) and aligned, and the length's bytes fit in `isize` (checked above).
        unsafe { core::slice::from_raw_parts(ptr, len) }
    };
    Vertices::strided(data, 0, stride, vertex_count).map_err(status_of)
}

/// `st_scene_build` in precision `F`, with input of the same precision.
///
/// # Safety
/// As `st_scene_build`: `memory` NULL or writable for `bytes`; the input NULL or readable as
/// described; `out` NULL or writable; no overlap between the input and `memory`.
pub(crate) unsafe fn build_into<F: Prec>(
    memory: *mut c_void,
    bytes: usize,
    input: &Input<F>,
    out: *mut *mut Stored<F>,
) -> st_status {
    let (vertices, tc) = (&input.vertices, input.triangle_count);
    let vc = vertices.vertex_count;
    if memory.is_null()
        || out.is_null()
        || vertices.any_null()
        || (tc > 0 && input.indices.is_null())
    {
        return ST_ERROR_NULL_ARGUMENT;
    }
    let Some(options) = options(input.flags) else {
        return ST_ERROR_INVALID_ARGUMENT;
    };
    if input.iterations > ST_MAX_ITERATIONS || !out.is_aligned() {
        return ST_ERROR_INVALID_ARGUMENT;
    }
    if tc == 0 {
        return ST_ERROR_NO_USABLE_TRIANGLES;
    }
    let Some(strides) = vertices.strides() else {
        return ST_ERROR_INVALID_ARGUMENT;
    };
    if !input.indices.is_aligned() {
        return ST_ERROR_INVALID_ARGUMENT;
    }
    let Some(sizes) = SceneSizes::new(vc, tc, &options) else {
        return ST_ERROR_TOO_LARGE;
    };
    let Some(needed) = layout_bytes::<F>(&sizes) else {
        return ST_ERROR_TOO_LARGE;
    };
    if bytes < needed {
        return ST_ERROR_BUFFER_TOO_SMALL;
    }
    if tc
        .checked_mul(12)
        .is_none_or(|b| isize::try_from(b).is_err())
    {
        return ST_ERROR_TOO_LARGE;
    }
    // SAFETY: the strides are `strides()`'s, no pointer is NULL (checked above), and the
    // contract makes each attribute readable.
    let (positions, normals) = match unsafe { vertices.read(strides) } {
        Ok(v) => v,
        Err(e) => return e,
    };
    // SAFETY: `indices` is non-null, aligned for `u32` (so for `[u32; 3]`, which has the same
    // alignment) and readable for `3 · tc` values by the contract; the byte length fits in
    // `isize` (checked above).
    let indices = unsafe { core::slice::from_raw_parts(input.indices.cast::<[u32; 3]>(), tc) };

    let mut arena = Arena {
        base: memory.cast(),
        len: bytes,
        used: 0,
    };
    let zero = F::from_dvec3(glam::DVec3::ZERO);
    // The head first: its address is the scene's; it is written once the scene is built.
    let parts = (|| {
        let head_at = arena.reserve::<Stored<F>>()?;
        let patches = arena.take(sizes.patches, Patch::<F>::default())?;
        let triangle_ids = arena.take(sizes.patches, 0u32)?;
        let nodes = arena.take(sizes.nodes, BvhNode::<F>::default())?;
        let order = arena.take(sizes.patches, 0u32)?;
        let seams = arena.take(sizes.seams, Seam::<F>::default())?;
        let used = arena.used;
        let storage = SceneStorage {
            patches,
            triangle_ids,
            nodes,
            order,
            seams,
            triangles: arena.take(sizes.patches, [0u32; 3])?,
            edges: arena.take(sizes.edges, SharedEdge::default())?,
            edge_work: arena.take(sizes.edge_work, EdgeWork::<F>::default())?,
            vertex_positions: arena.take(sizes.vertices, zero)?,
            vertex_normals: arena.take(sizes.vertices, zero)?,
            clamped_normals: arena.take(sizes.vertices, zero)?,
            vertex_clamps: arena.take(sizes.vertices, VertexClamp::<F>::default())?,
        };
        Some((head_at, used, storage))
    })();
    let Some((head_at, bytes_used, storage)) = parts else {
        // `layout_bytes` counts every part with its padding, so this cannot happen.
        return ST_ERROR_INTERNAL;
    };
    let mut options = options;
    let (kept, bytes_used) = if input.flags & ST_BUILD_UPDATABLE != 0 {
        match DynamicScene::build(positions, normals, indices, &mut options, storage) {
            Ok(scene) => (Kept::Dynamic(scene, 0), arena.used),
            Err(e) => return status_of(e),
        }
    } else {
        match Scene::build(positions, normals, indices, &mut options, storage) {
            Ok(scene) => (Kept::Fixed(scene), bytes_used),
            Err(e) => return status_of(e),
        }
    };
    let stored = Stored {
        magic: F::MAGIC,
        kept,
        iterations: input.iterations,
        flags: input.flags,
        bytes_used,
    };
    // SAFETY: `head_at .. head_at + size_of::<Stored<F>>()` lies inside the memory (checked by
    // the arena), is aligned for `Stored<F>`, and no other part overlaps it; `out` is non-null,
    // aligned and writable by the contract. The tag goes in with the rest of the head, before
    // the pointer is handed out.
    unsafe {
        let head = memory.cast::<u8>().add(head_at).cast::<Stored<F>>();
        head.write(stored);
        out.write(head);
    }
    ST_OK
}

/// `st_scene_get_info`.
///
/// # Safety
/// `scene` NULL or a scene (see [`Stored::from_ptr`]); `info` NULL or writable.
pub(crate) unsafe fn info<F: Prec>(scene: *const c_void, info: *mut st_scene_info) -> st_status {
    let stored = match Stored::<F>::with_output(scene, info) {
        Ok(stored) => stored,
        Err(e) => return e,
    };
    if !info.is_aligned() {
        return ST_ERROR_INVALID_ARGUMENT;
    }
    let scene = stored.scene();
    let r = scene.report();
    let j = &r.rejected;
    let value = st_scene_info {
        triangle_count: r.triangles,
        patch_count: r.patches,
        rejected_count: r.triangles - r.patches,
        rejected_non_finite: j.non_finite,
        rejected_degenerate: j.degenerate,
        rejected_other: j.zero_normal + j.back_facing + j.invalid_shell + j.out_of_range,
        first_rejected: r.first_rejected.map_or(ST_INVALID_ID, |(t, _)| t),
        iterations: stored.iterations,
        remedied_count: r.remedied,
        seam_edge_count: r.seam_edges.unwrap_or(0),
        bvh_node_count: r.bvh_nodes,
        bytes_used: stored.bytes_used,
        flags: stored.flags,
        update_count: match stored.kept {
            Kept::Dynamic(_, n) => n,
            Kept::Fixed(_) => 0,
        },
        bvh_refitted: u32::from(r.bvh_refitted),
    };
    // SAFETY: non-null, aligned, writable by the contract.
    unsafe { info.write(value) };
    ST_OK
}

/// The vertex arguments of `st_scene_build` and `st_scene_update`: positions and normals,
/// `vertex_count` of each at their byte strides.
pub(crate) struct VertexInput<T> {
    pub(crate) positions: *const T,
    pub(crate) position_stride: usize,
    pub(crate) normals: *const T,
    pub(crate) normal_stride: usize,
    pub(crate) vertex_count: usize,
}

impl<F: Float> VertexInput<F> {
    /// Whether a pointer that is read is NULL (no vertex, nothing is read).
    fn any_null(&self) -> bool {
        self.vertex_count > 0 && (self.positions.is_null() || self.normals.is_null())
    }

    /// The strides of the positions and normals in scalars; `None` when one of them or its
    /// pointer does not suit `F` (see [`scalar_stride`]).
    fn strides(&self) -> Option<(usize, usize)> {
        Some((
            scalar_stride(self.positions, self.position_stride)?,
            scalar_stride(self.normals, self.normal_stride)?,
        ))
    }

    /// The positions and normals as the core reads them, at their scalar strides.
    ///
    /// # Safety
    /// `strides` is what [`VertexInput::strides`] returned; no pointer is NULL
    /// ([`VertexInput::any_null`]); each attribute is readable for `vertex_count` vertices at
    /// its stride (the C API's contract).
    unsafe fn read<'a>(
        &self,
        (ps, ns): (usize, usize),
    ) -> Result<(Vertices<'a, F>, Vertices<'a, F>), st_status> {
        let vc = self.vertex_count;
        // SAFETY: the contract makes each attribute readable for `vc` vertices at its stride;
        // the pointers are non-null (vc > 0) or unused (vc == 0 reads nothing) and aligned
        // (checked by `strides`).
        let (positions, normals) = unsafe {
            (
                vertices(self.positions, ps, vc),
                vertices(self.normals, ns, vc),
            )
        };
        Ok((positions?, normals?))
    }
}

/// `st_scene_update` in precision `F`.
///
/// # Safety
/// As `st_scene_update`: `scene` NULL or a scene whose memory is valid, used by nothing else
/// during the call; the vertices NULL or readable as described, not overlapping the scene's
/// memory.
pub(crate) unsafe fn update<F: Prec>(scene: *mut c_void, moved: &VertexInput<F>) -> st_status {
    if scene.is_null() || moved.any_null() {
        return ST_ERROR_NULL_ARGUMENT;
    }
    let Some(stored) = Stored::<F>::from_ptr_mut(scene) else {
        return ST_ERROR_WRONG_SCENE;
    };
    let Some(mut options) = options(stored.flags) else {
        return ST_ERROR_INTERNAL;
    };
    let Kept::Dynamic(dynamic, count) = &mut stored.kept else {
        return ST_ERROR_NOT_UPDATABLE;
    };
    let Some(strides) = moved.strides() else {
        return ST_ERROR_INVALID_ARGUMENT;
    };
    // SAFETY: the strides are `strides()`'s, no pointer is NULL (checked above), and the
    // contract makes each attribute readable.
    let (positions, normals) = match unsafe { moved.read(strides) } {
        Ok(v) => v,
        Err(e) => return e,
    };
    match dynamic.update(positions, normals, &mut options) {
        Ok(_) => {
            *count = count.saturating_add(1);
            ST_OK
        }
        Err(e) => status_of(e),
    }
}
