//! [`MeshSource`]: a command's mesh, from a file (`--mesh PATH`) or a built-in scene
//! (`--scene NAME`), loaded and turned upright for the camera.

use smoothtri_host::scenes;
use smoothtri_io::Mesh;

use crate::error::{DemoError, Result};
use crate::up::{Up, builtin_up};

/// Where a command's mesh comes from: `--mesh PATH` or `--scene NAME` (at most one is set).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct MeshSource {
    /// A mesh file (OBJ, PLY, glTF or GLB).
    pub mesh: Option<String>,
    /// A built-in scene name (see [`scenes::SCENE_NAMES`]).
    pub scene: Option<String>,
    /// Whether a glTF file's buffers may lie outside its folder
    /// ([`smoothtri_io::LoadOptions::allow_outside_folder`], `--allow-outside-folder`).
    pub allow_outside_folder: bool,
}

impl MeshSource {
    /// Loads the mesh file or builds the scene, with its display name (the path, or
    /// `"NAME (built-in)"`). Notes about computed normals and warnings about skipped primitives
    /// go to stderr. With neither set, `default_torus` picks the torus scene; otherwise that is
    /// a usage error.
    pub fn load(&self, default_torus: bool) -> Result<(String, Mesh)> {
        if let Some(path) = &self.mesh {
            let loaded = smoothtri_io::load_with(path, &self.load_options())?;
            for w in &loaded.warnings {
                eprintln!("warning: {path}: {w}");
            }
            if loaded.computed_normals {
                eprintln!(
                    "note: {path} has no vertex normals (for some or all corners): computed angle-weighted normals"
                );
            }
            return Ok((path.clone(), loaded.mesh));
        }
        let name = match (&self.scene, default_torus) {
            (Some(s), _) => s.clone(),
            (None, true) => "torus".to_string(),
            (None, false) => {
                return Err(DemoError::Usage(
                    "one of --mesh PATH or --scene NAME is required".into(),
                ));
            }
        };
        let mesh = scenes::builtin(&name)
            .ok_or_else(|| DemoError::Usage(format!("unknown scene '{name}'")))?;
        Ok((format!("{name} (built-in)"), mesh))
    }

    /// The loaders' options for this source: the default budget, and buffers outside the
    /// file's folder as [`MeshSource::allow_outside_folder`] says.
    pub fn load_options(&self) -> smoothtri_io::LoadOptions {
        smoothtri_io::LoadOptions::default().with_allow_outside_folder(self.allow_outside_folder)
    }

    /// The up axis a camera uses for this source: `up` when given, otherwise `y` for mesh files
    /// and the scene's own axis ([`builtin_up`], `z`) for built-ins. glTF is y-up by
    /// specification, so `--up` other than `y` on a `.gltf`/`.glb` file is a usage error.
    pub fn up_axis(&self, up: Option<Up>) -> Result<Up> {
        if let Some(path) = &self.mesh {
            let gltf = smoothtri_io::extension(path).is_some_and(|e| e == "gltf" || e == "glb");
            return match up {
                Some(u) if gltf && u != Up::Y => Err(DemoError::Usage(format!(
                    "--up {u}: {path} is glTF, which is y-up by specification (leave --up out)"
                ))),
                Some(u) => Ok(u),
                None => Ok(Up::Y),
            };
        }
        let name = self.scene.as_deref().unwrap_or("torus");
        Ok(up.unwrap_or_else(|| builtin_up(name)))
    }

    /// [`MeshSource::load`], then the mesh turned so that its up axis ([`MeshSource::up_axis`])
    /// is `+z`, the camera's frame ([`Up::mesh_to_z_up`], exact). Returns the display name, the
    /// turned mesh and the axis used.
    pub fn load_upright(&self, default_torus: bool, up: Option<Up>) -> Result<(String, Mesh, Up)> {
        let up = self.up_axis(up)?;
        let (name, mesh) = self.load(default_torus)?;
        let mesh = if up == Up::Z {
            mesh
        } else {
            up.mesh_to_z_up(&mesh)
        };
        Ok((name, mesh, up))
    }
}
