//! Why a BVH could not be built or traversed.

/// Why a BVH could not be built or traversed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BvhError {
    /// No patches.
    EmptyScene,
    /// The node storage holds fewer than [`Bvh::nodes_needed`](crate::Bvh::nodes_needed) nodes or the index storage
    /// fewer than `n`.
    StorageTooSmall {
        /// Nodes needed.
        nodes: usize,
        /// Indices needed.
        indices: usize,
    },
    /// More patches than `u32` can index.
    TooManyPatches,
    /// The traversal stack would overflow (only possible with storage not made by
    /// [`Bvh::build`](crate::Bvh::build)).
    StackOverflow,
    /// The traversal visited more nodes or tested more patches than the tree has, or a node or
    /// index points outside the storage (storage not made by [`Bvh::build`](crate::Bvh::build)).
    CorruptTree,
    /// An invariant of the builder failed. Not expected for any input: it would be a bug in
    /// this crate (reported as an error rather than a panic or a silently wrong tree).
    Internal,
}

impl core::fmt::Display for BvhError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            BvhError::EmptyScene => f.write_str("empty scene: no patches"),
            BvhError::StorageTooSmall { nodes, indices } => {
                write!(
                    f,
                    "BVH storage too small: need {nodes} nodes and {indices} indices"
                )
            }
            BvhError::TooManyPatches => f.write_str("more patches than u32 can index"),
            BvhError::StackOverflow => f.write_str("BVH traversal stack overflow"),
            BvhError::CorruptTree => f.write_str(
                "BVH storage is corrupt (a node is reached twice or points outside the storage)",
            ),
            BvhError::Internal => f.write_str("internal error of the BVH builder (a bug)"),
        }
    }
}

impl core::error::Error for BvhError {}
