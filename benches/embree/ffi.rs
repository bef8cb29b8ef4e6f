//! The few declarations of Embree 3's C API (`/usr/include/embree3`, Debian's `libembree-dev`,
//! 3.13) that the `embree` bench needs, and a small safe wrapper: a one-thread device, a scene
//! of one triangle mesh, closest hits. All of the bench's `unsafe` is in this module.

use std::ffi::{CStr, c_char, c_void};

use glam::Vec3;
use smoothtri::Ray;
use smoothtri_io::Mesh;
use std::sync::atomic::{AtomicI64, Ordering};

type RTCDevice = *mut c_void;
type RTCScene = *mut c_void;
type RTCGeometry = *mut c_void;

/// `RTC_GEOMETRY_TYPE_TRIANGLE` (`enum RTCGeometryType`).
const RTC_GEOMETRY_TYPE_TRIANGLE: u32 = 0;
/// `RTC_BUFFER_TYPE_INDEX`, `RTC_BUFFER_TYPE_VERTEX` (`enum RTCBufferType`).
const RTC_BUFFER_TYPE_INDEX: u32 = 0;
const RTC_BUFFER_TYPE_VERTEX: u32 = 1;
/// `RTC_FORMAT_UINT3`, `RTC_FORMAT_FLOAT3` (`enum RTCFormat`).
const RTC_FORMAT_UINT3: u32 = 0x5003;
const RTC_FORMAT_FLOAT3: u32 = 0x9003;
/// `RTC_INVALID_GEOMETRY_ID`.
pub const RTC_INVALID_GEOMETRY_ID: u32 = u32::MAX;
/// `RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT` (`enum RTCIntersectContextFlags`).
const RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT: u32 = 0;

/// `struct RTCRay` (`rtcore_ray.h`, `RTC_ALIGN(16)`): 48 bytes.
#[repr(C, align(16))]
#[derive(Clone, Copy, Debug, Default)]
pub struct RTCRay {
    pub org_x: f32,
    pub org_y: f32,
    pub org_z: f32,
    pub tnear: f32,
    pub dir_x: f32,
    pub dir_y: f32,
    pub dir_z: f32,
    pub time: f32,
    pub tfar: f32,
    pub mask: u32,
    pub id: u32,
    pub flags: u32,
}

/// `struct RTCHit` (`RTC_ALIGN(16)`, `RTC_MAX_INSTANCE_LEVEL_COUNT` = 1 in Debian's build):
/// 32 bytes.
#[repr(C, align(16))]
#[derive(Clone, Copy, Debug, Default)]
pub struct RTCHit {
    pub ng_x: f32,
    pub ng_y: f32,
    pub ng_z: f32,
    pub u: f32,
    pub v: f32,
    pub prim_id: u32,
    pub geom_id: u32,
    pub inst_id: [u32; 1],
}

/// `struct RTCRayHit`: 80 bytes, 16-byte aligned.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default)]
pub struct RTCRayHit {
    pub ray: RTCRay,
    pub hit: RTCHit,
}

/// `struct RTCIntersectContext` with `RTC_MAX_INSTANCE_LEVEL_COUNT` = 1 (no `instStackSize`)
/// and `RTC_MIN_WIDTH` = 0 (no `minWidthDistanceFactor`), as in Debian's `rtcore_config.h`.
#[repr(C)]
pub struct RTCIntersectContext {
    flags: u32,
    filter: Option<unsafe extern "C" fn(*const c_void)>,
    inst_id: [u32; 1],
}

const _: () = {
    // The sizes, alignments and offsets a C compiler gives the header's structs.
    assert!(size_of::<RTCRay>() == 48 && align_of::<RTCRay>() == 16);
    assert!(size_of::<RTCHit>() == 32 && align_of::<RTCHit>() == 16);
    assert!(size_of::<RTCRayHit>() == 80 && align_of::<RTCRayHit>() == 16);
    assert!(std::mem::offset_of!(RTCRayHit, hit) == 48);
    assert!(size_of::<RTCIntersectContext>() == 24);
};

impl RTCIntersectContext {
    /// `rtcInitIntersectContext` (an inline function of `rtcore_common.h`) for this
    /// configuration.
    pub fn new() -> Self {
        RTCIntersectContext {
            flags: RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT,
            filter: None,
            inst_id: [RTC_INVALID_GEOMETRY_ID],
        }
    }
}

type RTCMemoryMonitorFunction = unsafe extern "C" fn(*mut c_void, isize, bool) -> bool;

#[link(name = "embree3")]
unsafe extern "C" {
    fn rtcNewDevice(config: *const c_char) -> RTCDevice;
    fn rtcReleaseDevice(device: RTCDevice);
    fn rtcGetDeviceError(device: RTCDevice) -> u32;
    fn rtcSetDeviceMemoryMonitorFunction(
        device: RTCDevice,
        monitor: Option<RTCMemoryMonitorFunction>,
        user: *mut c_void,
    );
    fn rtcNewScene(device: RTCDevice) -> RTCScene;
    fn rtcCommitScene(scene: RTCScene);
    fn rtcReleaseScene(scene: RTCScene);
    fn rtcNewGeometry(device: RTCDevice, kind: u32) -> RTCGeometry;
    fn rtcSetNewGeometryBuffer(
        geometry: RTCGeometry,
        kind: u32,
        slot: u32,
        format: u32,
        byte_stride: usize,
        item_count: usize,
    ) -> *mut c_void;
    fn rtcCommitGeometry(geometry: RTCGeometry);
    fn rtcAttachGeometry(scene: RTCScene, geometry: RTCGeometry) -> u32;
    fn rtcReleaseGeometry(geometry: RTCGeometry);
    fn rtcIntersect1(scene: RTCScene, context: *mut RTCIntersectContext, rayhit: *mut RTCRayHit);
}

/// Net bytes Embree reported through the memory monitor (allocations minus frees) and the
/// peak of that sum. Boxed so its address stays fixed while the device holds it.
#[derive(Default)]
pub struct Memory {
    pub net: AtomicI64,
    pub peak: AtomicI64,
}

/// The memory monitor: `bytes` > 0 for an allocation, < 0 for a free; each is reported once.
unsafe extern "C" fn monitor(user: *mut c_void, bytes: isize, _post: bool) -> bool {
    // SAFETY: `user` is the `Box<Memory>` of the `Device` that registered this callback, which
    // outlives the device (it is dropped after `rtcReleaseDevice`).
    let m = unsafe { &*(user as *const Memory) };
    let now = m.net.fetch_add(bytes as i64, Ordering::Relaxed) + bytes as i64;
    m.peak.fetch_max(now, Ordering::Relaxed);
    true
}

/// An Embree device with a memory monitor.
pub struct Device {
    raw: RTCDevice,
    pub memory: Box<Memory>,
}

impl Device {
    /// `rtcNewDevice(config)`, e.g. `"threads=1"`.
    pub fn new(config: &CStr) -> Device {
        // SAFETY: `config` is a NUL-terminated string that Embree only reads during the call.
        let raw = unsafe { rtcNewDevice(config.as_ptr()) };
        assert!(!raw.is_null(), "rtcNewDevice failed");
        let memory = Box::new(Memory::default());
        // SAFETY: `raw` is a live device; the user pointer is the boxed `Memory`, which lives as
        // long as the device (see `Drop`), and `monitor` only reads it through atomics.
        unsafe {
            rtcSetDeviceMemoryMonitorFunction(
                raw,
                Some(monitor),
                &*memory as *const Memory as *mut c_void,
            )
        };
        Device { raw, memory }
    }

    /// Net bytes allocated through the device so far.
    pub fn net_bytes(&self) -> i64 {
        self.memory.net.load(Ordering::Relaxed)
    }

    /// Peak of [`Device::net_bytes`] so far.
    pub fn peak_bytes(&self) -> i64 {
        self.memory.peak.load(Ordering::Relaxed)
    }

    fn check(&self, what: &str) {
        // SAFETY: `self.raw` is a live device.
        let e = unsafe { rtcGetDeviceError(self.raw) };
        assert_eq!(e, 0, "Embree error {e} after {what}");
    }
}

impl Drop for Device {
    fn drop(&mut self) {
        // SAFETY: every `Scene` borrows the device, so none outlives this call; the monitor's
        // user data (`self.memory`) is dropped only after it.
        unsafe { rtcReleaseDevice(self.raw) };
    }
}

/// Gives `geom` a new buffer of `kind` (`(buffer type, format, name for errors)`) holding a copy
/// of `items`: `rtcSetNewGeometryBuffer` with 12-byte items, checked.
///
/// # Safety
/// `geom` is a live geometry of `device`, and `T` is a 12-byte item of the format (`[f32; 3]`
/// for FLOAT3, `[u32; 3]` for UINT3).
unsafe fn new_buffer<T: Copy>(
    device: &Device,
    geom: RTCGeometry,
    (kind, format, name): (u32, u32, &str),
    items: &[T],
) {
    // SAFETY: as the caller promises; the buffer Embree returns has room for `items.len()`
    // items of 12 bytes and is 4-byte aligned (Embree aligns to 16), so the copy stays in
    // bounds.
    unsafe {
        let buffer = rtcSetNewGeometryBuffer(geom, kind, 0, format, 12, items.len()) as *mut T;
        device.check(&format!("rtcSetNewGeometryBuffer({name})"));
        assert!(!buffer.is_null());
        std::ptr::copy_nonoverlapping(items.as_ptr(), buffer, items.len());
    }
}

/// A committed scene holding one triangle mesh.
pub struct Scene<'d> {
    raw: RTCScene,
    _device: &'d Device,
}

impl<'d> Scene<'d> {
    /// Builds and commits a scene of the triangles `indices` over `positions`.
    pub fn triangles(device: &'d Device, positions: &[[f32; 3]], indices: &[[u32; 3]]) -> Self {
        // SAFETY: `device.raw` is live. Each buffer Embree returns has room for `item_count`
        // items of `byte_stride` bytes (Embree pads vertex buffers itself), so the copies stay in
        // bounds; the `[f32; 3]`/`[u32; 3]` items match FLOAT3/UINT3 with stride 12, and the
        // buffers are 4-byte aligned (Embree aligns them to 16). The geometry is released after
        // the scene takes its own reference in `rtcAttachGeometry`.
        unsafe {
            let scene = rtcNewScene(device.raw);
            let geom = rtcNewGeometry(device.raw, RTC_GEOMETRY_TYPE_TRIANGLE);
            device.check("rtcNewGeometry");
            let vertex = (RTC_BUFFER_TYPE_VERTEX, RTC_FORMAT_FLOAT3, "vertex");
            new_buffer(device, geom, vertex, positions);
            let index = (RTC_BUFFER_TYPE_INDEX, RTC_FORMAT_UINT3, "index");
            new_buffer(device, geom, index, indices);
            rtcCommitGeometry(geom);
            rtcAttachGeometry(scene, geom);
            rtcReleaseGeometry(geom);
            rtcCommitScene(scene);
            device.check("rtcCommitScene");
            Scene {
                raw: scene,
                _device: device,
            }
        }
    }

    /// [`Scene::triangles`] of `mesh`'s triangles over its vertices rounded to `f32`.
    pub fn of_mesh(device: &'d Device, mesh: &Mesh) -> Self {
        let positions: Vec<[f32; 3]> = mesh
            .positions
            .iter()
            .map(|p| p.as_vec3().to_array())
            .collect();
        Self::triangles(device, &positions, &mesh.triangles)
    }

    /// `rtcIntersect1`: fills `rh.ray.tfar` and `rh.hit` on a hit (`rh.hit.geom_id` must be
    /// [`RTC_INVALID_GEOMETRY_ID`] on entry).
    #[inline]
    pub fn intersect1(&self, ctx: &mut RTCIntersectContext, rh: &mut RTCRayHit) {
        // SAFETY: the scene is committed and live; `ctx` and `rh` are valid, exclusive and
        // laid out as the header's structs (checked above), `rh` 16-byte aligned.
        unsafe { rtcIntersect1(self.raw, ctx, rh) }
    }
}

impl Drop for Scene<'_> {
    fn drop(&mut self) {
        // SAFETY: the scene is live and released once.
        unsafe { rtcReleaseScene(self.raw) };
    }
}

/// The Embree ray of `r` (`tnear` 0, `tfar` f32::MAX as smoothtri's query), no hit yet.
pub fn rtc_ray(r: &Ray) -> RTCRayHit {
    let mut rh = RTCRayHit::default();
    rh.ray.org_x = r.origin.x;
    rh.ray.org_y = r.origin.y;
    rh.ray.org_z = r.origin.z;
    rh.ray.dir_x = r.dir.x;
    rh.ray.dir_y = r.dir.y;
    rh.ray.dir_z = r.dir.z;
    rh.ray.tnear = 0.0;
    rh.ray.tfar = f32::MAX;
    rh.ray.mask = u32::MAX;
    rh.hit.geom_id = RTC_INVALID_GEOMETRY_ID;
    rh.hit.inst_id = [RTC_INVALID_GEOMETRY_ID];
    rh
}

/// Closest hit of `r` on the Embree scene with its interpolated (Phong) unit normal.
#[inline]
pub fn embree_hit(
    scene: &Scene<'_>,
    ctx: &mut RTCIntersectContext,
    indices: &[[u32; 3]],
    normals: &[Vec3],
    r: &Ray,
) -> Option<(f32, Vec3)> {
    let mut rh = rtc_ray(r);
    scene.intersect1(ctx, &mut rh);
    if rh.hit.geom_id == RTC_INVALID_GEOMETRY_ID {
        return None;
    }
    let [a, b, c] = indices[rh.hit.prim_id as usize].map(|i| normals[i as usize]);
    let (u, v) = (rh.hit.u, rh.hit.v);
    let n = (a * (1.0 - u - v) + b * u + c * v).normalize();
    Some((rh.ray.tfar, n))
}
