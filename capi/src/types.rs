//! The C records: status codes, build flags, the Embree-shaped rays and hits (single rays,
//! packets of eight, `_f64` twins), the scene's summary and the opaque scene handles. Every
//! type here is `#[repr(C)]` (or opaque) and appears in `include/smoothtri.h` as declared.

/// A status code: [`ST_OK`] or one of the `ST_ERROR_…` values; `st_status_str` names it.
pub type st_status = u32;

/// Success: the outputs were written.
pub const ST_OK: st_status = 0;
/// A pointer argument that must not be NULL was NULL.
pub const ST_ERROR_NULL_ARGUMENT: st_status = 1;
/// An argument is out of its documented range: unknown flag bits, `iterations` above
/// [`ST_MAX_ITERATIONS`], a stride below three scalars or not a multiple of the scalar size, a
/// pointer not aligned to its element type.
pub const ST_ERROR_INVALID_ARGUMENT: st_status = 2;
/// The memory given to `st_scene_build` is shorter than `st_scene_required_bytes` says.
pub const ST_ERROR_BUFFER_TOO_SMALL: st_status = 3;
/// No triangle was given, or every triangle was rejected (degenerate, bad normals), so there
/// is nothing to trace.
pub const ST_ERROR_NO_USABLE_TRIANGLES: st_status = 4;
/// An index names a vertex at or beyond `vertex_count`, or a patch index is at or beyond the
/// scene's `patch_count`.
pub const ST_ERROR_INDEX_OUT_OF_RANGE: st_status = 5;
/// Every triangle was rejected and the first because of a NaN or infinite position or normal
/// (triangles with non-finite values among usable ones are skipped and counted in
/// [`st_scene_info::rejected_non_finite`]).
pub const ST_ERROR_NON_FINITE: st_status = 6;
/// A count is too large for this library (more than `2^32 − 1` vertices or triangles, or
/// storage beyond the address space).
pub const ST_ERROR_TOO_LARGE: st_status = 7;
/// The scene pointer is not a scene of this precision built by `st_scene_build` (an `f64`
/// scene given to an `f32` function, or the reverse).
pub const ST_ERROR_WRONG_SCENE: st_status = 8;
/// An internal failure that should not happen (a caught panic, an inconsistent BVH); please
/// report it.
pub const ST_ERROR_INTERNAL: st_status = 9;
/// `st_scene_update` was given a scene built without [`ST_BUILD_UPDATABLE`].
pub const ST_ERROR_NOT_UPDATABLE: st_status = 10;

/// The `prim_id` / `geom_id` of no hit (Embree's `RTC_INVALID_GEOMETRY_ID`).
pub const ST_INVALID_ID: u32 = 0xFFFF_FFFF;

/// Build flag: fit the seamless shading normals (`ns_x, ns_y, ns_z` of a hit are then
/// continuous across shared edges; without it they equal the geometric normal). Costs build
/// time (16 normal evaluations per shared edge) and 148 bytes per triangle in `f32`.
pub const ST_BUILD_SEAMS: u32 = 1;
/// Build flag: the shared line field (neighbours' edge curves meet exactly; adds a per-vertex
/// normal remedy). Without it, the paper's per-face field; the kernel closes the cracks.
pub const ST_BUILD_SHARED_FIELD: u32 = 2;
/// Build flag: the scene can be moved to new vertex positions and normals with
/// `st_scene_update` (skinned and morphed meshes). The scene then keeps the whole memory of
/// `st_scene_required_bytes`, the build's scratch included (`bytes_used` is all of it), and
/// finds the shared edges of the index buffer once, at the build.
pub const ST_BUILD_UPDATABLE: u32 = 4;

/// The largest refinement budget `iterations` that `st_scene_build` takes (the core's
/// `smoothtri::MAX_ITERATIONS`): any value from 0 to this one.
pub const ST_MAX_ITERATIONS: u32 = 64;
const _: () = assert!(ST_MAX_ITERATIONS as usize == smoothtri::MAX_ITERATIONS);

/// A ray, laid out as Embree 3's `RTCRay` (same fields, order, sizes and 16-byte alignment, so
/// a `RTCRay*` can be passed as an `st_ray*`). The ray is `org + t·dir` for `t` in
/// `[tnear, tfar]`; `dir` need not be unit length (`t` is in units of `dir`). `time`, `mask`,
/// `id` and `flags` are carried but not used.
#[repr(C, align(16))]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct st_ray {
    /// Origin, x.
    pub org_x: f32,
    /// Origin, y.
    pub org_y: f32,
    /// Origin, z.
    pub org_z: f32,
    /// Start of the ray interval.
    pub tnear: f32,
    /// Direction, x.
    pub dir_x: f32,
    /// Direction, y.
    pub dir_y: f32,
    /// Direction, z.
    pub dir_z: f32,
    /// Time (unused: scenes are static).
    pub time: f32,
    /// End of the ray interval; set to the hit's `t` by a hit, to `-INFINITY` by an occlusion.
    pub tfar: f32,
    /// Ray mask (unused).
    pub mask: u32,
    /// Ray id (unused, left as is).
    pub id: u32,
    /// Ray flags (unused).
    pub flags: u32,
}

/// A hit: Embree 3's `RTCHit` fields (without `instID`) followed by the shading normal and the
/// certified error bound.
#[repr(C, align(16))]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct st_hit {
    /// Geometric normal of the smooth surface at the hit, x (unit length, oriented like the
    /// vertex normals, not toward the ray).
    pub ng_x: f32,
    /// Geometric normal, y.
    pub ng_y: f32,
    /// Geometric normal, z.
    pub ng_z: f32,
    /// Barycentric coordinate of the triangle's vertex 1 at the hit.
    pub u: f32,
    /// Barycentric coordinate of the triangle's vertex 2 (vertex 0's is `1 − u − v`).
    pub v: f32,
    /// The input triangle hit (its index in the index buffer), [`ST_INVALID_ID`] on a miss.
    pub prim_id: u32,
    /// 0 for a hit of this scene ([`ST_INVALID_ID`] on a miss); the Embree plug-in writes its
    /// geometry's id.
    pub geom_id: u32,
    /// Shading normal, x: seamless across shared edges with [`ST_BUILD_SEAMS`], else the
    /// geometric normal. Unit length, oriented like the vertex normals.
    pub ns_x: f32,
    /// Shading normal, y.
    pub ns_y: f32,
    /// Shading normal, z.
    pub ns_z: f32,
    /// Certified bound on `|t − t_true|`, in units of the ray's `dir` (see the core's
    /// `Hit::t_error`).
    pub t_error: f32,
}

/// A ray and its hit, as Embree's `RTCRayHit` (the hit part longer by the shading normal and
/// `t_error`).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct st_rayhit {
    /// The ray; `tfar` becomes the hit's `t`.
    pub ray: st_ray,
    /// The hit, written on a hit.
    pub hit: st_hit,
}

/// Eight rays, structure of arrays (Embree's `RTCRay8` layout), 32-byte aligned.
#[repr(C, align(32))]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct st_ray8 {
    /// Origins, x.
    pub org_x: [f32; 8],
    /// Origins, y.
    pub org_y: [f32; 8],
    /// Origins, z.
    pub org_z: [f32; 8],
    /// Starts of the ray intervals.
    pub tnear: [f32; 8],
    /// Directions, x.
    pub dir_x: [f32; 8],
    /// Directions, y.
    pub dir_y: [f32; 8],
    /// Directions, z.
    pub dir_z: [f32; 8],
    /// Times (unused).
    pub time: [f32; 8],
    /// Ends of the ray intervals; a hit sets its lane's to `t`.
    pub tfar: [f32; 8],
    /// Masks (unused).
    pub mask: [u32; 8],
    /// Ids (unused).
    pub id: [u32; 8],
    /// Flags (unused).
    pub flags: [u32; 8],
}

/// Eight hits, structure of arrays (the fields of [`st_hit`], eight of each).
#[repr(C, align(32))]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct st_hit8 {
    /// Geometric normals, x.
    pub ng_x: [f32; 8],
    /// Geometric normals, y.
    pub ng_y: [f32; 8],
    /// Geometric normals, z.
    pub ng_z: [f32; 8],
    /// Barycentrics of vertex 1.
    pub u: [f32; 8],
    /// Barycentrics of vertex 2.
    pub v: [f32; 8],
    /// Input triangles hit, [`ST_INVALID_ID`] on a miss.
    pub prim_id: [u32; 8],
    /// 0 on a hit, [`ST_INVALID_ID`] on a miss.
    pub geom_id: [u32; 8],
    /// Shading normals, x.
    pub ns_x: [f32; 8],
    /// Shading normals, y.
    pub ns_y: [f32; 8],
    /// Shading normals, z.
    pub ns_z: [f32; 8],
    /// Certified bounds on `|t − t_true|`.
    pub t_error: [f32; 8],
}

/// Eight rays and their hits, structure of arrays, 32-byte aligned.
#[repr(C, align(32))]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct st_rayhit8 {
    /// The rays.
    pub ray: st_ray8,
    /// The hits.
    pub hit: st_hit8,
}

/// [`st_ray`] in double precision.
#[repr(C, align(16))]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct st_ray_f64 {
    /// Origin, x.
    pub org_x: f64,
    /// Origin, y.
    pub org_y: f64,
    /// Origin, z.
    pub org_z: f64,
    /// Start of the ray interval.
    pub tnear: f64,
    /// Direction, x.
    pub dir_x: f64,
    /// Direction, y.
    pub dir_y: f64,
    /// Direction, z.
    pub dir_z: f64,
    /// Time (unused).
    pub time: f64,
    /// End of the ray interval; set to the hit's `t` by a hit, to `-INFINITY` by an occlusion.
    pub tfar: f64,
    /// Ray mask (unused).
    pub mask: u32,
    /// Ray id (unused).
    pub id: u32,
    /// Ray flags (unused).
    pub flags: u32,
}

/// [`st_hit`] in double precision.
#[repr(C, align(16))]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct st_hit_f64 {
    /// Geometric normal, x.
    pub ng_x: f64,
    /// Geometric normal, y.
    pub ng_y: f64,
    /// Geometric normal, z.
    pub ng_z: f64,
    /// Barycentric coordinate of vertex 1.
    pub u: f64,
    /// Barycentric coordinate of vertex 2.
    pub v: f64,
    /// The input triangle hit, [`ST_INVALID_ID`] on a miss.
    pub prim_id: u32,
    /// 0 on a hit, [`ST_INVALID_ID`] on a miss.
    pub geom_id: u32,
    /// Shading normal, x.
    pub ns_x: f64,
    /// Shading normal, y.
    pub ns_y: f64,
    /// Shading normal, z.
    pub ns_z: f64,
    /// Certified bound on `|t − t_true|`.
    pub t_error: f64,
}

/// [`st_rayhit`] in double precision.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct st_rayhit_f64 {
    /// The ray.
    pub ray: st_ray_f64,
    /// The hit.
    pub hit: st_hit_f64,
}

/// [`st_ray8`] in double precision.
#[repr(C, align(32))]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct st_ray8_f64 {
    /// Origins, x.
    pub org_x: [f64; 8],
    /// Origins, y.
    pub org_y: [f64; 8],
    /// Origins, z.
    pub org_z: [f64; 8],
    /// Starts of the ray intervals.
    pub tnear: [f64; 8],
    /// Directions, x.
    pub dir_x: [f64; 8],
    /// Directions, y.
    pub dir_y: [f64; 8],
    /// Directions, z.
    pub dir_z: [f64; 8],
    /// Times (unused).
    pub time: [f64; 8],
    /// Ends of the ray intervals.
    pub tfar: [f64; 8],
    /// Masks (unused).
    pub mask: [u32; 8],
    /// Ids (unused).
    pub id: [u32; 8],
    /// Flags (unused).
    pub flags: [u32; 8],
}

/// [`st_hit8`] in double precision.
#[repr(C, align(32))]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct st_hit8_f64 {
    /// Geometric normals, x.
    pub ng_x: [f64; 8],
    /// Geometric normals, y.
    pub ng_y: [f64; 8],
    /// Geometric normals, z.
    pub ng_z: [f64; 8],
    /// Barycentrics of vertex 1.
    pub u: [f64; 8],
    /// Barycentrics of vertex 2.
    pub v: [f64; 8],
    /// Input triangles hit, [`ST_INVALID_ID`] on a miss.
    pub prim_id: [u32; 8],
    /// 0 on a hit, [`ST_INVALID_ID`] on a miss.
    pub geom_id: [u32; 8],
    /// Shading normals, x.
    pub ns_x: [f64; 8],
    /// Shading normals, y.
    pub ns_y: [f64; 8],
    /// Shading normals, z.
    pub ns_z: [f64; 8],
    /// Certified bounds on `|t − t_true|`.
    pub t_error: [f64; 8],
}

/// [`st_rayhit8`] in double precision.
#[repr(C, align(32))]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct st_rayhit8_f64 {
    /// The rays.
    pub ray: st_ray8_f64,
    /// The hits.
    pub hit: st_hit8_f64,
}

/// What a build did, filled by `st_scene_get_info`.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct st_scene_info {
    /// Triangles given.
    pub triangle_count: usize,
    /// Patches built (accepted triangles): valid `prim` arguments of `st_patch_bounds` and
    /// `st_patch_intersect` are `0 .. patch_count`.
    pub patch_count: usize,
    /// Triangles rejected (skipped), all reasons: `triangle_count − patch_count`.
    pub rejected_count: usize,
    /// Of them, with a NaN or infinite position or normal.
    pub rejected_non_finite: usize,
    /// Of them, degenerate (zero or tiny area, repeated indices).
    pub rejected_degenerate: usize,
    /// Of them, with a zero normal or normals facing away from the triangle, or whose curved
    /// shell could not be bounded.
    pub rejected_other: usize,
    /// The first rejected triangle, [`ST_INVALID_ID`] when none was.
    pub first_rejected: u32,
    /// The kernel's refinement steps `N` given to the build (0 to [`ST_MAX_ITERATIONS`]).
    pub iterations: u32,
    /// Patches whose normals the steep-normal remedy clamped (still traced; smooth, slightly
    /// flatter near the clamped vertex).
    pub remedied_count: usize,
    /// Shared edges with a fitted seamless normal (0 without [`ST_BUILD_SEAMS`]).
    pub seam_edge_count: usize,
    /// Nodes of the BVH.
    pub bvh_node_count: usize,
    /// Bytes at the start of the build's memory that the scene keeps; the rest of it
    /// (scratch during the build) is free again for the caller.
    pub bytes_used: usize,
    /// The flags given to the build.
    pub flags: u32,
    /// Updates that succeeded since the build ([`ST_BUILD_UPDATABLE`]).
    pub update_count: u32,
    /// 1 when the last update refitted the BVH's boxes to the moved patches, 0 when it built
    /// the tree anew (a refitted tree whose cost grew past the core's `REBUILD_COST_RATIO`
    /// times a fresh one's, or the build itself).
    pub bvh_refitted: u32,
}

/// A built scene in single precision (opaque; it lives inside the memory given to
/// `st_scene_build`).
///
/// Threads: the one allowed pattern of concurrent use. Between updates a scene is immutable:
/// any number of threads may query it at once (`st_intersect1`, `st_occluded1`,
/// `st_intersect8`, `st_intersect1M`, `st_patch_bounds`, `st_patch_intersect`,
/// `st_patch_of_triangle`, `st_scene_get_info`), with no lock. `st_scene_update` needs the
/// scene alone: call it between frames, after every query on that scene has returned (join
/// the tracing threads, or wait at a barrier), and start queries again only after it has
/// returned. Not allowed, and not detected (the library takes no lock; in C it is a data
/// race, undefined behaviour): an update while another thread queries the same scene, two
/// updates of one scene at once, and freeing or reusing the scene's memory while any call on
/// it runs. Different scenes are independent: each may be updated while others are queried.
pub struct st_scene {
    _opaque: [u8; 0],
}

/// A built scene in double precision (opaque; see [`st_scene`]).
pub struct st_scene_f64 {
    _opaque: [u8; 0],
}
