//! The update's shader and its compute pipelines, compiled once per device (`Gpu` keeps them).

use std::sync::LazyLock;

use crate::device::{compute_pipeline, wgsl_module};
use crate::shader::{SHADER, UPDATE_SHADER};

/// The update's shader: the kernel's (whose height evaluation the passes sample the surface
/// with) with its patch records and nodes writable, then the update's passes
/// ([`UPDATE_SHADER`]).
pub(crate) static BUILD_SHADER: LazyLock<String> = LazyLock::new(|| {
    let kernel = SHADER
        .replace(
            "var<storage, read> patches:",
            "var<storage, read_write> patches:",
        )
        .replace(
            "var<storage, read> nodes:",
            "var<storage, read_write> nodes:",
        );
    format!("{kernel}\n{UPDATE_SHADER}")
});

/// The update's five compute pipelines (compiled once per `Gpu`).
pub(crate) struct UpdatePipelines {
    pub(super) normals: wgpu::ComputePipeline,
    pub(super) patches: wgpu::ComputePipeline,
    pub(super) edges: wgpu::ComputePipeline,
    pub(super) boxes: wgpu::ComputePipeline,
    pub(super) refit: wgpu::ComputePipeline,
}

impl UpdatePipelines {
    /// The pipelines on `device`: call inside an error scope (`Gpu::update_pipelines`).
    pub(crate) fn new(device: &wgpu::Device) -> UpdatePipelines {
        let module = wgsl_module(device, "smoothtri update", BUILD_SHADER.as_str());
        // Every line field's sections: the records carry their own di.z.
        let make =
            |entry| compute_pipeline(device, entry, None, &module, entry, &[("TILTED", 1.0)]);
        UpdatePipelines {
            normals: make("vertex_normals"),
            patches: make("build_patches"),
            edges: make("close_edges"),
            boxes: make("fit_boxes"),
            refit: make("refit_nodes"),
        }
    }
}
