//! Record packing: the bytes the shader reads for one BVH node ([`GpuNode`]), one smooth patch
//! ([`smooth_record`]), one flat triangle ([`flat_record`]) and one patch's seam
//! ([`seam_record`]), each laid out as the shader (`gpu/src/kernel/records.wgsl`) loads it.

use smoothtri::PatchData;
use smoothtri::mesh::Seam;

use crate::shader::{FLAT_VEC4, PATCH_VEC4, SEAM_VEC4};

/// One BVH node as the shader reads it (128 bytes), as [`smoothtri::BvhNode`]: the four
/// children's boxes by coordinate, and per slot a child node (count 0), a leaf of `count`
/// patches (`order[child..]`), or [`smoothtri::BVH_EMPTY_SLOT`].
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct GpuNode {
    /// Minimum corners: `lo[axis][slot]`.
    pub lo: [[f32; 4]; 3],
    /// Maximum corners: `hi[axis][slot]`.
    pub hi: [[f32; 4]; 3],
    /// Per slot: the child node, the start of the leaf's range in the order, or
    /// [`smoothtri::BVH_EMPTY_SLOT`].
    pub child: [u32; 4],
    /// Per slot: patches of a leaf; 0 for a child node or an unused slot.
    pub count: [u32; 4],
}

impl GpuNode {
    /// The node of a CPU BVH.
    pub fn from_node(n: &smoothtri::BvhNode<f32>) -> Self {
        let b: [smoothtri::Aabb<f32>; 4] = std::array::from_fn(|k| n.bounds(k));
        GpuNode {
            lo: [0, 1, 2].map(|a| b.map(|b| b.min()[a])),
            hi: [0, 1, 2].map(|a| b.map(|b| b.max()[a])),
            child: std::array::from_fn(|k| n.child(k)),
            count: std::array::from_fn(|k| n.count(k)),
        }
    }
}

/// A record as the shader reads it: `BYTES` bytes in native order.
pub(crate) trait Packed {
    /// The record's size in bytes.
    const BYTES: usize;
    /// Appends the record's bytes to `out`.
    fn pack(&self, out: &mut Vec<u8>);
}

impl<const K: usize> Packed for [f32; K] {
    const BYTES: usize = 4 * K;
    #[inline]
    fn pack(&self, out: &mut Vec<u8>) {
        for x in self {
            out.extend_from_slice(&x.to_ne_bytes());
        }
    }
}

impl Packed for u32 {
    const BYTES: usize = 4;
    #[inline]
    fn pack(&self, out: &mut Vec<u8>) {
        out.extend_from_slice(&self.to_ne_bytes());
    }
}

impl Packed for GpuNode {
    const BYTES: usize = size_of::<GpuNode>();
    /// The shader's `Node`: lo[3], hi[3], child, count (vec4 each).
    #[inline]
    fn pack(&self, out: &mut Vec<u8>) {
        for x in self.lo.iter().chain(&self.hi) {
            x.pack(out);
        }
        for x in self.child.iter().chain(&self.count) {
            x.pack(out);
        }
    }
}

/// The bytes of `records`, back to back.
pub(crate) fn packed_bytes<R: Packed>(records: impl ExactSizeIterator<Item = R>) -> Vec<u8> {
    let mut out = Vec::with_capacity(records.len() * R::BYTES);
    for r in records {
        r.pack(&mut out);
    }
    out
}

fn dot(a: [f32; 3], b: [f32; 3]) -> f32 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn sub(a: [f32; 3], b: [f32; 3]) -> [f32; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// The smooth record of one patch: its data and the CPU kernel's per-patch precomputation
/// (`core/src/surface/lanes/`, `Prepared`), in `f32` with the CPU's arithmetic; layout in
/// `gpu/src/kernel/records.wgsl` (`load_patch`).
pub fn smooth_record(pd: &PatchData<f32>) -> [f32; PATCH_VEC4 * 4] {
    let [p0, p1, p2] = pd.p;
    let [n0, n1, n2] = pd.n;
    let [d0, d1, d2] = pd.d;
    let longest = dot(sub(p1, p0), sub(p1, p0))
        .max(dot(sub(p2, p1), sub(p2, p1)))
        .max(dot(sub(p0, p2), sub(p0, p2)))
        .sqrt();
    let scale = longest * 4.0 + dot(pd.origin, pd.origin).sqrt();
    let [ex, ey, ez] = pd.axes;
    let [s_lo, s_hi] = pd.sigma;
    let mut r = [0.0f32; PATCH_VEC4 * 4];
    let head: [[f32; 4]; 10] = [
        [pd.origin[0], pd.origin[1], pd.origin[2], scale],
        [ex[0], ex[1], ex[2], s_lo],
        [ey[0], ey[1], ey[2], s_hi],
        [ez[0], ez[1], ez[2], p1[0]],
        [pd.bbox_min[0], pd.bbox_min[1], pd.bbox_min[2], p2[0]],
        [pd.bbox_max[0], pd.bbox_max[1], pd.bbox_max[2], p2[1]],
        [n0[0], n0[1], n0[2], d0[0]],
        [n1[0], n1[1], n1[2], d0[1]],
        [n2[0], n2[1], n2[2], d1[0]],
        [d1[1], d2[0], d2[1], 0.0],
    ];
    let ends = [(0usize, 1usize), (1, 2), (2, 0)];
    let mut edges = [[[0.0f32; 4]; 5]; 3];
    for (j, (slot, (i, k))) in edges.iter_mut().zip(ends).enumerate() {
        let (a, b, da, db, na, nb) = (pd.p[i], pd.p[k], pd.d[i], pd.d[k], pd.n[i], pd.n[k]);
        let [k1, k2] = pd.k[j];
        let e = sub(b, a);
        let gd = sub(db, da);
        let gg = [dot(da, da), 2.0 * dot(da, gd), dot(gd, gd)];
        let eg = [dot(e, da), dot(e, gd)];
        let ee = dot(e, e);
        *slot = [
            [e[0], e[1], gd[0], gd[1]],
            [k1, k2, ee, eg[0]],
            [eg[1], gg[0], gg[1], gg[2]],
            // The reach of wall j (opposite vertex j) rides in edge j's spare slot.
            [dot(da, na), dot(gd, na), dot(e, na), pd.reach[j]],
            // d_j.z (1 for parallel sections) rides in the last spare slot.
            [dot(da, nb), dot(gd, nb), dot(e, nb), da[2]],
        ];
    }
    // The culling band (core/src/surface/band.rs), in the last two vec4s.
    let [c0, c1, c2] = pd.band_fit;
    let [lo, hi, per_reach] = pd.band;
    let band = [[c0, c1, c2, lo], [hi, per_reach, 0.0, 0.0]];
    let all = head.iter().chain(edges.iter().flatten()).chain(band.iter());
    for (dst, src) in r.chunks_exact_mut(4).zip(all) {
        dst.copy_from_slice(src);
    }
    r
}

/// The flat record of one patch: its triangle's world vertices.
pub fn flat_record(pd: &PatchData<f32>) -> [f32; FLAT_VEC4 * 4] {
    let mut r = [0.0f32; FLAT_VEC4 * 4];
    let [ex, ey, ez] = pd.axes;
    for (dst, p) in r.chunks_exact_mut(4).zip(pd.p) {
        // The CPU's local_to_world: origin + ex·x + ey·y + ez·z.
        for (c, slot) in dst.iter_mut().take(3).enumerate() {
            *slot = pd.origin[c] + ex[c] * p[0] + ey[c] * p[1] + ez[c] * p[2];
        }
    }
    r
}

/// The seam record of one patch as the shader reads it ([`SEAM_VEC4`] vec4s): per edge `j` the
/// six coefficients of the common normal's tilt across the edge then the six along it; then
/// the three edges' `free` flags (1 or 0) and 1 for a non-zero seam (0: no correction).
pub fn seam_record(seam: &Seam<f32>) -> [f32; SEAM_VEC4 * 4] {
    let mut r = [0.0f32; SEAM_VEC4 * 4];
    let mut k = 0;
    for (common, along) in seam.common.iter().zip(&seam.common_along) {
        // The shader's TWIST_TERMS is 6: a change of smoothtri::mesh::TWIST_TERMS fails here.
        let (c, a): (&[f32; 6], &[f32; 6]) = (common, along);
        for (dst, src) in r.iter_mut().skip(k).zip(c.iter().chain(a)) {
            *dst = *src;
        }
        k += 12;
    }
    let flags = seam.free.map(|f| f32::from(u8::from(f)));
    let nonzero = f32::from(u8::from(!seam.is_zero()));
    for (dst, src) in r.iter_mut().skip(36).zip(flags.iter().chain([&nonzero])) {
        *dst = *src;
    }
    r
}
