//! Scene upload: a [`GpuScene`] holds a scene's records (smooth patches or flat triangles), its
//! BVH nodes and order and its shading data in storage buffers on a [`Gpu`]'s device.

use std::fmt;
use std::sync::Arc;

use smoothtri::mesh::Seam;
use smoothtri::{Bvh, Patch, PatchData};

use crate::device::{Gpu, PipelineKey};
use crate::error::GpuError;
use crate::records::{GpuNode, flat_record, packed_bytes, seam_record, smooth_record};
use crate::shader::Shading;

/// What a scene's records are.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SceneKind {
    /// The smooth patches (the kernel).
    Smooth,
    /// The patches' flat triangles (Möller–Trumbore, the baseline), on the same traversal.
    Flat,
}

/// A scene uploaded to the GPU: patch records, BVH nodes and order.
pub struct GpuScene {
    pub(crate) gpu: Arc<Gpu>,
    pub(crate) kind: SceneKind,
    pub(crate) patches: wgpu::Buffer,
    pub(crate) nodes: wgpu::Buffer,
    pub(crate) order: wgpu::Buffer,
    pub(crate) counts: [u32; 3],
    pub(crate) bytes: u64,
    /// Some smooth patch has tilted sections (`smoothtri::LineField::Vertex`): traced by the
    /// pipeline with the tilted branches (`TILTED` in the shader), all others without them.
    pub(crate) tilted: bool,
    /// The shading normal of closest hits and frames, with its data (`shade_in`: seam records
    /// or vertex normals; one zero record for [`Shading::Geometric`]).
    pub(crate) shading: Shading,
    pub(crate) shade_in: wgpu::Buffer,
    /// How many times [`GpuScene::update`] rewrote the scene: a [`GpuUpdate`](crate::GpuUpdate)
    /// made before then would refit another tree's topology, so it refuses the scene.
    pub(crate) version: u64,
}

impl fmt::Debug for GpuScene {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("GpuScene")
            .field("kind", &self.kind)
            .field("patches", &self.counts[2])
            .field("nodes", &self.counts[0])
            .finish()
    }
}

impl GpuScene {
    /// Uploads the smooth patches and the BVH of `bvh`.
    pub fn smooth(gpu: &Arc<Gpu>, bvh: &Bvh<'_, f32>) -> Result<GpuScene, GpuError> {
        Self::from_bvh(gpu, SceneKind::Smooth, bvh)
    }

    /// Uploads the smooth patches and the BVH of `bvh` with the patches' seams (`seams[i]` the
    /// seam of `bvh.patches()[i]`, as `smoothtri::Scene::seams`): closest hits and frames then
    /// carry the seamless shading normal ([`Shading::Seamless`], the CPU's
    /// `Scene::shading_normal`). Returns [`GpuError::LengthMismatch`] when the lengths differ.
    pub fn smooth_seamless(
        gpu: &Arc<Gpu>,
        bvh: &Bvh<'_, f32>,
        seams: &[Seam<f32>],
    ) -> Result<GpuScene, GpuError> {
        if seams.len() != bvh.patches().len() {
            return Err(GpuError::LengthMismatch {
                rays: bvh.patches().len(),
                out: seams.len(),
            });
        }
        let data = packed_bytes(seams.iter().map(seam_record));
        Self::smooth(gpu, bvh)?.with_shading(Shading::Seamless, data)
    }

    /// Uploads the flat triangles of `bvh`'s patches with their world vertex normals: closest
    /// hits and frames carry the Phong normal ([`Shading::Phong`]: the vertex normals
    /// interpolated at the hit's barycentrics, normalised; the face normal where that vanishes).
    pub fn phong(gpu: &Arc<Gpu>, bvh: &Bvh<'_, f32>) -> Result<GpuScene, GpuError> {
        Self::flat(gpu, bvh)?.with_shading(Shading::Phong, phong_data(bvh))
    }

    fn with_shading(mut self, shading: Shading, data: Vec<u8>) -> Result<GpuScene, GpuError> {
        self.bytes += data.len() as u64;
        self.shade_in = self.gpu.storage("shading", data)?;
        self.shading = shading;
        Ok(self)
    }

    /// The shading normal of the scene's closest hits and frames.
    pub fn shading(&self) -> Shading {
        self.shading
    }

    /// Uploads the flat triangles of `bvh`'s patches (their world vertices) with the same BVH:
    /// the baseline on the same traversal code.
    pub fn flat(gpu: &Arc<Gpu>, bvh: &Bvh<'_, f32>) -> Result<GpuScene, GpuError> {
        Self::from_bvh(gpu, SceneKind::Flat, bvh)
    }

    /// Uploads `bvh`'s patches as records of `kind`, with its nodes and order.
    fn from_bvh(gpu: &Arc<Gpu>, kind: SceneKind, bvh: &Bvh<'_, f32>) -> Result<GpuScene, GpuError> {
        let data: Vec<PatchData<f32>> = bvh.patches().iter().map(|p| p.data()).collect();
        let nodes: Vec<GpuNode> = bvh.nodes().iter().map(GpuNode::from_node).collect();
        Self::from_parts(gpu, kind, &data, &nodes, bvh.order())
    }

    /// Uploads arbitrary parts: patch data, nodes and order (node 0 the root). Storage not
    /// made by [`Bvh::build`] is traced without any read outside the buffers: queries then
    /// return [`GpuError::CorruptTree`] or [`GpuError::StackOverflow`] where the shader notices,
    /// misses or wrong answers otherwise, never a panic or a device loss.
    pub fn from_parts(
        gpu: &Arc<Gpu>,
        kind: SceneKind,
        patches: &[PatchData<f32>],
        nodes: &[GpuNode],
        order: &[u32],
    ) -> Result<GpuScene, GpuError> {
        let too_many = |what: &'static str, n: usize| GpuError::TooLarge {
            what,
            bytes: n as u64,
            limit: u32::MAX as u64,
        };
        let count = |what, n: usize| u32::try_from(n).map_err(|_| too_many(what, n));
        let counts = [
            count("node", nodes.len())?,
            count("order", order.len())?,
            count("patch", patches.len())?,
        ];
        let (records, node_bytes, order_bytes) = pack(kind, patches, nodes, order);
        let bytes = (records.len() + node_bytes.len() + order_bytes.len()) as u64;
        Ok(GpuScene {
            gpu: Arc::clone(gpu),
            kind,
            patches: gpu.storage("patch", records)?,
            nodes: gpu.storage("node", node_bytes)?,
            order: gpu.storage("order", order_bytes)?,
            counts,
            bytes,
            tilted: tilted(kind, patches.iter().map(|pd| pd.d)),
            shading: Shading::Geometric,
            shade_in: gpu.storage("shading", Vec::new())?,
            version: 0,
        })
    }

    /// Moves the scene to `bvh`'s records in place: the patch records, the BVH's nodes and
    /// order and, for a scene with shading data, that data (`seams` for a
    /// [`GpuScene::smooth_seamless`] scene, `bvh`'s vertex normals for a [`GpuScene::phong`]
    /// one) are packed as the constructors pack them and written into the scene's buffers with
    /// the device queue. Meant for an animated mesh whose CPU scene was updated
    /// (`smoothtri::OwnedScene::update`): an update that refitted its tree keeps every length,
    /// so no buffer is allocated; a length that changed (a rebuilt tree with another node
    /// count) gets a new buffer of that kind. Queries and frames after the call see the new
    /// records (the queue orders the writes before later submissions); the result equals a
    /// fresh upload of `bvh` bit for bit.
    ///
    /// The scene keeps its kind and shading. Returns [`GpuError::SceneMismatch`] when `bvh`
    /// has another patch count than the scene, or when `seams` is missing or of another
    /// length for a seamless scene (`seams` is ignored otherwise); the scene is then unchanged.
    /// A device error is [`GpuError::Device`], after which the scene's contents are
    /// unspecified until a later update succeeds.
    ///
    /// # Panics
    ///
    /// Never.
    pub fn update(
        &mut self,
        bvh: &Bvh<'_, f32>,
        seams: Option<&[Seam<f32>]>,
    ) -> Result<(), GpuError> {
        let n = self.counts[2] as usize;
        let mismatch = |what, given| self.mismatch(what, given);
        let patches = bvh.patches();
        if patches.len() != n {
            return Err(mismatch("patch", patches.len()));
        }
        let seams = match (self.shading, seams) {
            (Shading::Seamless, Some(s)) if s.len() == n => s,
            (Shading::Seamless, other) => {
                return Err(mismatch("seam", other.map_or(0, <[_]>::len)));
            }
            _ => &[],
        };
        let count = |what, k: usize| u32::try_from(k).map_err(|_| mismatch(what, k));
        let counts = [
            count("node", bvh.nodes().len())?,
            count("order", bvh.order().len())?,
            self.counts[2],
        ];
        let gpu = Arc::clone(&self.gpu);
        let records = patches.iter().map(|p| p.data());
        let mut bytes = match self.kind {
            SceneKind::Smooth => {
                let records = records.map(|d| smooth_record(&d));
                gpu.rewrite(&mut self.patches, "patch", records)?
            }
            SceneKind::Flat => {
                gpu.rewrite(&mut self.patches, "patch", records.map(|d| flat_record(&d)))?
            }
        };
        let nodes = bvh.nodes().iter().map(GpuNode::from_node);
        bytes += gpu.rewrite(&mut self.nodes, "node", nodes)?;
        bytes += gpu.rewrite(&mut self.order, "order", bvh.order().iter().copied())?;
        bytes += match self.shading {
            Shading::Geometric => 0,
            Shading::Seamless => {
                gpu.rewrite(&mut self.shade_in, "shading", seams.iter().map(seam_record))?
            }
            Shading::Phong => {
                let normals = patches.iter().map(phong_record);
                gpu.rewrite(&mut self.shade_in, "shading", normals)?
            }
        };
        self.bytes = bytes;
        self.counts = counts;
        self.version += 1;
        self.tilted = tilted(self.kind, patches.iter().map(|p| p.data().d));
        Ok(())
    }

    /// Reads back the scene's patch records ([`PATCH_VEC4`](crate::PATCH_VEC4) `vec4<f32>`
    /// per patch, as `f32`; [`FLAT_VEC4`](crate::FLAT_VEC4) for a flat scene) and its BVH
    /// nodes, as the shader sees them. For tests and tools (a [`GpuUpdate`](crate::GpuUpdate)
    /// checked against the CPU's records); a frame reads nothing back.
    ///
    /// # Panics
    ///
    /// Never.
    pub fn read_back(&self) -> Result<(Vec<f32>, Vec<GpuNode>), GpuError> {
        let vec4 = match self.kind {
            SceneKind::Smooth => crate::PATCH_VEC4,
            SceneKind::Flat => crate::FLAT_VEC4,
        } as u64;
        let gpu = &self.gpu;
        let record_bytes = 16 * vec4 * u64::from(self.counts[2]);
        let records = gpu.read_words(&self.patches, record_bytes, f32::from_ne_bytes)?;
        let node_bytes = size_of::<GpuNode>() as u64;
        let words = gpu.read_words(&self.nodes, node_bytes * u64::from(self.counts[0]), |w| w)?;
        let nodes = words
            .chunks_exact(node_bytes as usize / 4)
            .map(|w| {
                let f = |k: usize| f32::from_ne_bytes(w[k]);
                let u = |k: usize| u32::from_ne_bytes(w[k]);
                GpuNode {
                    lo: std::array::from_fn(|a| std::array::from_fn(|s| f(4 * a + s))),
                    hi: std::array::from_fn(|a| std::array::from_fn(|s| f(12 + 4 * a + s))),
                    child: std::array::from_fn(|s| u(24 + s)),
                    count: std::array::from_fn(|s| u(28 + s)),
                }
            })
            .collect();
        Ok((records, nodes))
    }

    /// Reads back the scene's shading data as `f32`: the seam records
    /// ([`SEAM_VEC4`](crate::SEAM_VEC4) `vec4<f32>` per patch, [`seam_record`]'s layout) of a
    /// [`Shading::Seamless`] scene, the vertex normals of a [`Shading::Phong`] one, one zero
    /// record otherwise. For tests and tools, as [`GpuScene::read_back`].
    ///
    /// # Panics
    ///
    /// Never.
    pub fn read_shading(&self) -> Result<Vec<f32>, GpuError> {
        let per_patch = match self.shading {
            Shading::Seamless => 16 * crate::SEAM_VEC4 as u64,
            Shading::Phong => 48,
            Shading::Geometric => 0,
        };
        let bytes = (per_patch * u64::from(self.counts[2])).max(16);
        self.gpu
            .read_words(&self.shade_in, bytes, f32::from_ne_bytes)
    }

    /// [`GpuError::SceneMismatch`]: `given` items of `what` where the scene has its patch count.
    pub(crate) fn mismatch(&self, what: &'static str, given: usize) -> GpuError {
        GpuError::SceneMismatch {
            what,
            scene: self.counts[2] as usize,
            given,
        }
    }

    /// The pipeline key of this scene's queries.
    pub(crate) fn key(&self, n: usize, any: bool, frame: bool) -> PipelineKey {
        PipelineKey {
            n,
            flat: self.kind == SceneKind::Flat,
            any,
            tilted: self.tilted,
            shading: self.shading,
            frame,
        }
    }

    /// Whether the records are smooth patches or flat triangles.
    pub fn kind(&self) -> SceneKind {
        self.kind
    }

    /// Bytes uploaded (records, nodes, order).
    pub fn memory_bytes(&self) -> u64 {
        self.bytes
    }

    /// The device.
    pub fn gpu(&self) -> &Arc<Gpu> {
        &self.gpu
    }
}

/// The Phong scene's shading data: each patch's three world vertex normals, a `vec4` each.
fn phong_data(bvh: &Bvh<'_, f32>) -> Vec<u8> {
    packed_bytes(bvh.patches().iter().map(phong_record))
}

/// One patch's Phong shading record: its three world vertex normals, a `vec4` each.
fn phong_record(p: &Patch<f32>) -> [f32; 12] {
    let [a, b, c] = p.normals();
    [a.x, a.y, a.z, 0.0, b.x, b.y, b.z, 0.0, c.x, c.y, c.z, 0.0]
}

/// Whether some smooth patch has tilted sections (`TILTED` in the shader).
fn tilted(kind: SceneKind, mut ds: impl Iterator<Item = [[f32; 3]; 3]>) -> bool {
    kind == SceneKind::Smooth && ds.any(|d| d.iter().any(|d| d[2] != 1.0))
}

/// The bytes of a scene's records, nodes and order, as the shader reads them.
fn pack(
    kind: SceneKind,
    patches: &[PatchData<f32>],
    nodes: &[GpuNode],
    order: &[u32],
) -> (Vec<u8>, Vec<u8>, Vec<u8>) {
    let records = match kind {
        SceneKind::Smooth => packed_bytes(patches.iter().map(smooth_record)),
        SceneKind::Flat => packed_bytes(patches.iter().map(flat_record)),
    };
    let node_bytes = packed_bytes(nodes.iter().copied());
    let order_bytes = packed_bytes(order.iter().copied());
    (records, node_bytes, order_bytes)
}
