//! Animated glTF 2.0 meshes: [`AnimatedMesh`] ([`load_animated`], [`parse_animated`]) poses a
//! file's mesh at any time of one of its animations ([`Clip`]), in the vertex order and with the
//! index buffer of the static [`load`](crate::load), without allocating per frame.
//!
//! What is animated, as the glTF 2.0 specification defines it:
//!
//! - **Node transforms**: `translation`, `rotation` and `scale` channels replace a node's own
//!   values; the world transforms are composed down the node hierarchy in `f64`.
//! - **Morph targets**: the primitive's `POSITION` and `NORMAL` plus the weighted sum of its
//!   targets' deltas, with the node's `weights` (else the mesh's, else zeros) animated by
//!   `weights` channels. Deltas are applied before skinning and node transforms.
//! - **Skins** (linear blend skinning): each joint's matrix is its node's world transform times
//!   its inverse bind matrix; a vertex moves by the weighted sum of its joints' matrices
//!   (`JOINTS_n`/`WEIGHTS_n`, every set the file has). The skinned mesh's own node transform is
//!   ignored, as the specification requires.
//! - **Samplers**: `STEP`, `LINEAR` (spherical for rotations) and `CUBICSPLINE`, clamped before
//!   the first and after the last key.
//!
//! Normals: a primitive with `NORMAL` has its normals morphed, then carried by the inverse
//! transpose of the vertex's matrix (the cofactor matrix where that matrix is singular, for example
//! a zero scale) and renormalised. A primitive without normals gets angle-weighted normals
//! ([`angle_weighted_normals_into`](crate::angle_weighted_normals_into)) of the posed positions in
//! every frame, as the static loader computes them from the file's.
//!
//! The rest pose ([`AnimatedMesh::pose_rest`]: no animation, default weights) equals the static
//! mesh bit for bit for a mesh without skin whose default morph weights are zero; a skinned
//! mesh's static load is its bind-pose geometry through its node (the loader does not skin), so
//! there the two differ by the joints' rest transforms times their inverse bind matrices.
//!
//! Malformed animation data is an [`Error`](crate::Error) naming the file and the animation,
//! channel, sampler, skin, node, mesh, primitive and accessor: joints out of range, weights that do
//! not sum to one (within [`WEIGHT_SUM_TOLERANCE`]), non-finite keys, matrices or deltas, sampler
//! input and output counts that do not match, key times that do not increase, accessors of the
//! wrong type or outside their buffers, and the specification's other rules on targets.
//!
//! The types and entry points are here; [`read`] builds an [`AnimatedMesh`] from a document
//! with the readers of its parts ([`rest`], [`skin`], [`morph`], [`channels`], every accessor
//! through [`numbers`]), [`keys`] interpolates a sampler, and [`pose`] writes a pose.
//!
//! ```no_run
//! use glam::DVec3;
//! let mut anim = smoothtri_io::load_animated("walk.gltf")?;
//! let clip = &anim.clips()[0];
//! println!("{:?}: {:.2} s", clip.name, clip.duration);
//! let n = anim.mesh().positions.len();
//! let (mut positions, mut normals) = (vec![DVec3::ZERO; n], vec![DVec3::ZERO; n]);
//! for frame in 0..60 {
//!     anim.pose(0, frame as f64 / 30.0, &mut positions, &mut normals)
//!         .expect("finite poses");
//!     // … build or update the scene from `positions`, `normals` and `anim.mesh().triangles`
//! }
//! # Ok::<(), smoothtri_io::Error>(())
//! ```

mod channels;
mod keys;
mod morph;
mod numbers;
mod pose;
mod read;
mod rest;
mod skin;

use std::fmt;
use std::ops::Range;

use glam::{DMat3, DMat4, DVec3};

use crate::error::Result;
use crate::gltf::Trs;
use crate::mesh::Mesh;
use crate::options::{Budget, LoadOptions, read_file};

use keys::Keys;

/// What the readers of animation data return: a message (without the file's name) on error.
type Msg<T> = std::result::Result<T, String>;

/// How far the skin weights of a vertex may sum from one, `|Σ w − 1|`, before the file is
/// rejected; within it they are divided by their sum, so that every blended matrix is an
/// affine combination of the joints'. Float weights normalised and rounded to `f32` are off by
/// about 1e-7 (the glTF validator allows 2e-7 per non-zero weight); this also accepts weights
/// written with three decimals. Normalised integer weights sum to exactly one when the file
/// follows the specification (255 or 65535 before normalisation).
pub const WEIGHT_SUM_TOLERANCE: f64 = 2e-3;

/// One animation of the file (a glTF `animations` entry): its name and duration. Pose it with
/// [`AnimatedMesh::pose`] by its index in [`AnimatedMesh::clips`].
#[derive(Clone, Debug)]
pub struct Clip {
    /// The animation's name in the file, if it has one.
    pub name: Option<String>,
    /// The time of its last key, seconds (0 for an animation without channels). Samplers hold
    /// their first value before their first key and their last value after their last.
    pub duration: f64,
    channels: Vec<Channel>,
}

/// What a channel animates.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Path {
    Translation,
    Rotation,
    Scale,
    Weights,
}

/// One channel: the node, the property and the keys.
#[derive(Clone, Debug)]
struct Channel {
    node: usize,
    path: Path,
    keys: Keys,
}

/// A node's rest state.
#[derive(Clone, Debug)]
struct NodeRest {
    /// Its local matrix as the static loader composes it.
    local: DMat4,
    /// Its translation, rotation (unit) and scale; `None` for a node with a `matrix` (which no
    /// channel may animate).
    trs: Option<Trs>,
    /// Its morph target weights in [`Scratch::weights`], when its mesh has morph targets.
    weights: Option<Range<usize>>,
}

/// A skin: its joints' nodes and inverse bind matrices, and where its joint matrices go in
/// [`Scratch::joints`].
#[derive(Clone, Debug)]
struct Skin {
    joints: Vec<usize>,
    inverse_bind: Vec<DMat4>,
    first: usize,
}

/// A morph target's deltas (each `None` when the target has no such attribute).
#[derive(Clone, Debug)]
struct Target {
    positions: Option<Vec<DVec3>>,
    normals: Option<Vec<DVec3>>,
}

/// The joints and weights of each vertex of a skinned primitive, `per_vertex` of each (four
/// per `JOINTS_n`/`WEIGHTS_n` set); zero weights are kept, their joints never read.
#[derive(Clone, Debug)]
struct Influences {
    per_vertex: usize,
    joints: Vec<u16>,
    weights: Vec<f64>,
    /// The largest joint index (checked against each skin that uses the primitive).
    max_joint: u16,
}

/// A primitive's rest data in its mesh's coordinates.
#[derive(Clone, Debug)]
struct Prim {
    positions: Vec<DVec3>,
    normals: Option<Vec<DVec3>>,
    targets: Vec<Target>,
    influences: Option<Influences>,
}

/// One primitive of one mesh placement (a [`crate::gltf`] instance).
#[derive(Clone, Debug)]
struct Part {
    /// The node that draws it (`None`: a file without nodes, drawn untransformed).
    node: Option<usize>,
    /// Its data in [`Rig::prims`].
    prim: usize,
    /// Its skin in [`Rig::skins`].
    skin: Option<usize>,
    /// Its morph weights in [`Scratch::weights`] (the node's, or the mesh's defaults).
    weights: Option<Range<usize>>,
}

/// Everything posing reads: the rest state and the mapping from the mesh's vertices to the
/// primitives they come from.
#[derive(Clone, Debug)]
struct Rig {
    nodes: Vec<NodeRest>,
    /// Every node whose world transform is needed, parents first, with its parent.
    order: Vec<(usize, Option<usize>)>,
    /// The rest morph weights of every weights range.
    rest_weights: Vec<f64>,
    skins: Vec<Skin>,
    prims: Vec<Prim>,
    parts: Vec<Part>,
    /// For each vertex of the mesh: its part and its index in the part's primitive.
    vertex: Vec<(u32, u32)>,
    /// Whether any vertex's normal is computed (its primitive has no `NORMAL`).
    computed: bool,
}

/// How one part is posed this frame: by its skin, or rigidly by its node's world matrix with
/// the matrix its normals are carried by.
#[derive(Clone, Copy, Debug)]
enum PartPose {
    Skinned,
    Rigid { m: DMat4, normal: DMat3 },
}

/// The per-frame state, allocated once.
#[derive(Clone, Debug)]
struct Scratch {
    trs: Vec<Trs>,
    animated: Vec<bool>,
    world: Vec<DMat4>,
    weights: Vec<f64>,
    joints: Vec<DMat4>,
    parts: Vec<PartPose>,
    computed: Vec<DVec3>,
    value: Vec<f64>,
}

/// A glTF mesh with its animations: the static mesh (the index buffer and the rest data of
/// [`load`](crate::load)) and what poses it at any time of any clip. Built by
/// [`load_animated`] or [`parse_animated`]; posed by [`AnimatedMesh::pose`] and
/// [`AnimatedMesh::pose_rest`], which allocate nothing.
#[derive(Clone, Debug)]
pub struct AnimatedMesh {
    mesh: Mesh,
    computed_normals: bool,
    warnings: Vec<String>,
    clips: Vec<Clip>,
    rig: Rig,
    scratch: Scratch,
}

/// Why a pose could not be written. Its `Display` is one line.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum PoseError {
    /// The clip index is not one of [`AnimatedMesh::clips`].
    NoClip {
        /// The index asked for.
        clip: usize,
        /// How many clips the file has.
        clips: usize,
    },
    /// The time is NaN or infinite.
    Time(f64),
    /// The output buffers do not have one element per vertex of the mesh.
    Buffers {
        /// The mesh's vertices.
        vertices: usize,
        /// The positions buffer's length.
        positions: usize,
        /// The normals buffer's length.
        normals: usize,
    },
    /// A posed position is not finite (the transforms overflow `f64`); the buffers then hold
    /// a partial pose.
    NonFinite {
        /// The first such vertex.
        vertex: usize,
    },
}

impl fmt::Display for PoseError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            PoseError::NoClip { clip, clips } => match clips {
                0 => write!(f, "clip {clip}: the file has no animation"),
                _ => write!(f, "clip {clip}: the file has {clips} (0..{clips})"),
            },
            PoseError::Time(t) => write!(f, "time {t} s is not a finite number"),
            PoseError::Buffers {
                vertices,
                positions,
                normals,
            } => write!(
                f,
                "the mesh has {vertices} vertices; the buffers hold {positions} positions and \
                 {normals} normals"
            ),
            PoseError::NonFinite { vertex } => {
                write!(f, "the pose of vertex {vertex} is not finite")
            }
        }
    }
}

impl std::error::Error for PoseError {}

/// Reads a `.gltf` or `.glb` file with its animations ([`parse_animated`]), within the default
/// [`LoadOptions`] ([`load_animated_with`]).
///
/// Returns [`Error::Io`](crate::Error::Io) when the file cannot be read, and the errors of
/// [`parse_animated`].
pub fn load_animated(path: &str) -> Result<AnimatedMesh> {
    load_animated_with(path, &LoadOptions::default())
}

/// [`load_animated`] within `options` (see [`LoadOptions`]): the file's size is checked against
/// the budget before it is read.
///
/// Returns [`Error::Io`](crate::Error::Io) when the file cannot be read or is not a regular file,
/// [`Error::Budget`](crate::Error::Budget) when it is larger than the budget, and the errors of
/// [`parse_animated_with`].
pub fn load_animated_with(path: &str, options: &LoadOptions) -> Result<AnimatedMesh> {
    let (bytes, budget) = read_file(path, options)?;
    parse_animated_budgeted(&bytes, path, options, &budget)
}

/// Parses a glTF or GLB file (as [`gltf::parse`](crate::gltf::parse) does) with its skins,
/// morph targets and animations. A file without animations gives an [`AnimatedMesh`] without
/// clips, which poses its rest pose only.
///
/// Returns the static loader's errors, [`Error::NoTriangles`](crate::Error::NoTriangles), or an
/// [`Error::Format`](crate::Error::Format) naming the malformed animation data (see the module
/// documentation).
pub fn parse_animated(bytes: &[u8], path: &str) -> Result<AnimatedMesh> {
    parse_animated_with(bytes, path, &LoadOptions::default())
}

/// [`parse_animated`] within `options` (see [`LoadOptions`]; `bytes` count against the
/// budget).
///
/// Returns the errors of [`parse_animated`], [`Error::Budget`](crate::Error::Budget) when the file
/// and what it decodes to (the mesh, skins, morph targets, animation keys) would take more than
/// `options.max_bytes`, and for external buffers
/// [`Error::OutsideFolder`](crate::Error::OutsideFolder) and
/// [`Error::Resource`](crate::Error::Resource).
pub fn parse_animated_with(
    bytes: &[u8],
    path: &str,
    options: &LoadOptions,
) -> Result<AnimatedMesh> {
    parse_animated_budgeted(
        bytes,
        path,
        options,
        &Budget::charged(path, options, bytes)?,
    )
}

/// [`parse_animated_with`] of bytes already charged to `budget`.
fn parse_animated_budgeted(
    bytes: &[u8],
    path: &str,
    options: &LoadOptions,
    budget: &Budget,
) -> Result<AnimatedMesh> {
    let (doc, buffers) = crate::gltf::open(bytes, path, options, budget)?;
    let walk = crate::gltf::walk(&doc, &buffers, path, budget)?;
    read::animated(&doc, &buffers, budget, walk, path)
}

impl AnimatedMesh {
    /// The static mesh: the same vertices, normals and triangles as
    /// [`load`](crate::load) of the file. Every pose has its vertex order and index buffer.
    pub fn mesh(&self) -> &Mesh {
        &self.mesh
    }

    /// `true` when some or all normals are computed (angle-weighted, in every pose) because
    /// the file has none for them.
    pub fn computed_normals(&self) -> bool {
        self.computed_normals
    }

    /// `true` when every normal is computed (the file has normals for none of its vertices), so
    /// a renderer may compute them itself from the posed positions, as [`AnimatedMesh::pose`]
    /// does (a GPU's own pass, for example).
    pub fn all_normals_computed(&self) -> bool {
        !self.rig.prims.is_empty() && self.rig.prims.iter().all(|p| p.normals.is_none())
    }

    /// The static loader's warnings and the animation reader's (a morph target's normals
    /// ignored where the primitive has none, and the like), one line each.
    pub fn warnings(&self) -> &[String] {
        &self.warnings
    }

    /// The file's animations, in file order (empty for a file without).
    pub fn clips(&self) -> &[Clip] {
        &self.clips
    }

    /// Whether the mesh is skinned or morphed (in part or whole).
    pub fn is_deformable(&self) -> bool {
        self.rig
            .parts
            .iter()
            .any(|p| p.skin.is_some() || !self.rig.prims[p.prim].targets.is_empty())
    }

    /// Writes the pose at `time` seconds of clip `clip` into `positions` and `normals` (unit
    /// length, or zero where the pose degenerates), one per vertex of [`AnimatedMesh::mesh`]
    /// in its order. Channels of the clip set their nodes' properties and weights; the rest
    /// keep their rest values. Times outside the clip's keys clamp to its ends. Allocates
    /// nothing.
    ///
    /// Accuracy: in `f64` from the file's `f32` data, the interpolation exact up to rounding.
    ///
    /// Returns [`PoseError::NoClip`], [`PoseError::Time`] for a non-finite time,
    /// [`PoseError::Buffers`] when a buffer's length is not the vertex count, and
    /// [`PoseError::NonFinite`] when a posed position overflows.
    pub fn pose(
        &mut self,
        clip: usize,
        time: f64,
        positions: &mut [DVec3],
        normals: &mut [DVec3],
    ) -> Result<(), PoseError> {
        if clip >= self.clips.len() {
            return Err(PoseError::NoClip {
                clip,
                clips: self.clips.len(),
            });
        }
        if !time.is_finite() {
            return Err(PoseError::Time(time));
        }
        self.pose_at(Some((clip, time)), positions, normals)
    }

    /// Writes the rest pose (every node's own transform, the default morph weights, the skin's
    /// rest joints) as [`AnimatedMesh::pose`] writes a pose.
    ///
    /// Returns [`PoseError::Buffers`] or [`PoseError::NonFinite`] as [`AnimatedMesh::pose`].
    pub fn pose_rest(
        &mut self,
        positions: &mut [DVec3],
        normals: &mut [DVec3],
    ) -> Result<(), PoseError> {
        self.pose_at(None, positions, normals)
    }

    /// [`AnimatedMesh::pose`] (or the rest pose) into a new [`Mesh`] with the static mesh's
    /// triangles: convenient, but it allocates.
    ///
    /// Returns the errors of [`AnimatedMesh::pose`].
    pub fn posed_mesh(&mut self, clip: Option<usize>, time: f64) -> Result<Mesh, PoseError> {
        let n = self.mesh.positions.len();
        let mut m = Mesh {
            positions: vec![DVec3::ZERO; n],
            normals: vec![DVec3::ZERO; n],
            triangles: self.mesh.triangles.clone(),
        };
        match clip {
            Some(c) => self.pose(c, time, &mut m.positions, &mut m.normals)?,
            None => self.pose_rest(&mut m.positions, &mut m.normals)?,
        }
        Ok(m)
    }
}

#[cfg(test)]
mod error_tests;
#[cfg(test)]
mod tests;
