//! Animation in the demo (`render --time`, `view --animate`): an [`Animation`] poses a glTF
//! file's clip ([`smoothtri_io::AnimatedMesh`]) or the twisting torus
//! ([`smoothtri_host::twist`], `--scene twist`) into a mesh, frame by frame, turned upright
//! like the static mesh; [`Animation::sphere`] frames the whole clip for a camera that stays put;
//! [`scene_of_pose`](crate::commands::view::scene_of_pose) is the one place a posed mesh becomes a scene.

use glam::DVec3;
use smoothtri_host::Camera;
use smoothtri_host::twist::{TWIST_DEMO_SIDE, TWIST_PERIOD, twist_pose, twisting_torus};
use smoothtri_io::{AnimatedMesh, Mesh};

use crate::commands::MeshSource;
use crate::error::{DemoError, Result};
use crate::up::Up;

/// The time between two frames of the viewer's headless animation (`view --animate --frames
/// K`: frame `k` shows `--time` + `k · FRAME_STEP`), seconds.
pub const FRAME_STEP: f64 = 1.0 / 30.0;

/// Poses sampled over a clip, plus one, to frame it ([`Animation::sphere`]).
pub const FRAMING_SAMPLES: usize = 32;

/// What is animated.
enum Source {
    /// A glTF file's clip.
    Gltf {
        anim: Box<AnimatedMesh>,
        clip: usize,
    },
    /// The twisting torus on an `n × n` grid.
    Twist { n: usize },
}

/// An animated mesh source and its clip: poses it at any time, upright for the camera.
pub struct Animation {
    source: Source,
    up: Up,
    /// What the messages call it: the path and the clip, or the scene.
    pub name: String,
    /// The clip's length, seconds: the viewer loops over it, `render --time` clamps to it (the
    /// twisting torus repeats with this period).
    pub duration: f64,
}

impl Animation {
    /// The animation of `source` (`--mesh` a glTF file with animations, or `--scene twist`),
    /// clip `clip` (default the first), turned so that `up` (default: the source's) is `+z`.
    ///
    /// Returns a usage error for another source, a file without animations or a clip it does not
    /// have, and the loader's error for a malformed file.
    pub fn open(source: &MeshSource, up: Option<Up>, clip: Option<usize>) -> Result<Self> {
        let up = source.up_axis(up)?;
        if let Some(path) = &source.mesh {
            let is_gltf = smoothtri_io::extension(path).is_some_and(|e| e == "gltf" || e == "glb");
            if !is_gltf {
                return Err(DemoError::Usage(format!(
                    "{path} has no animation (animations come from glTF files, .gltf or .glb, \
                     or --scene twist)"
                )));
            }
            let anim = smoothtri_io::load_animated_with(path, &source.load_options())?;
            for w in anim.warnings() {
                eprintln!("warning: {path}: {w}");
            }
            let clips = anim.clips();
            if clips.is_empty() {
                return Err(DemoError::Usage(format!(
                    "{path} has no animation (no glTF animations entry)"
                )));
            }
            let c = clip.unwrap_or(0);
            let Some(found) = clips.get(c) else {
                return Err(DemoError::Usage(format!(
                    "--clip {c}: {path} has {} animation{} (0..{})",
                    clips.len(),
                    if clips.len() == 1 { "" } else { "s" },
                    clips.len()
                )));
            };
            let name = match &found.name {
                Some(n) => format!("{path}, clip {c} {n:?}"),
                None => format!("{path}, clip {c}"),
            };
            let duration = found.duration;
            return Ok(Animation {
                source: Source::Gltf {
                    anim: Box::new(anim),
                    clip: c,
                },
                up,
                name,
                duration,
            });
        }
        match (source.scene.as_deref(), clip) {
            (Some("twist"), None | Some(0)) => Ok(Animation {
                source: Source::Twist { n: TWIST_DEMO_SIDE },
                up,
                name: "twist (built-in)".into(),
                duration: TWIST_PERIOD,
            }),
            (Some("twist"), Some(c)) => Err(DemoError::Usage(format!(
                "--clip {c}: the twist scene has one animation (0)"
            ))),
            (s, _) => Err(DemoError::Usage(format!(
                "the {} scene has no animation (animated: --scene twist, or a glTF file with \
                 animations)",
                s.unwrap_or("torus")
            ))),
        }
    }

    /// The mesh at rest (its triangles are every pose's), upright.
    pub fn rest(&self) -> Mesh {
        let m = match &self.source {
            Source::Gltf { anim, .. } => anim.mesh().clone(),
            Source::Twist { n } => twisting_torus(*n, 0.0),
        };
        if self.up == Up::Z {
            m
        } else {
            self.up.mesh_to_z_up(&m)
        }
    }

    /// Whether the source has no normals at all, so that every pose's normals are computed
    /// from its positions (angle-weighted): a device may then compute them itself.
    pub fn normals_from_positions(&self) -> bool {
        match &self.source {
            Source::Gltf { anim, .. } => anim.all_normals_computed(),
            Source::Twist { .. } => false,
        }
    }

    /// Writes the pose at `time` seconds into `mesh` (a mesh of [`Animation::rest`]'s
    /// triangles), upright. Times past the clip hold its last pose (glTF clamps); the twisting
    /// torus repeats.
    ///
    /// Returns a usage error for a non-finite pose (the file's transforms overflow).
    pub fn pose(&mut self, time: f64, mesh: &mut Mesh) -> Result<()> {
        match &mut self.source {
            Source::Gltf { anim, clip } => anim
                .pose(*clip, time, &mut mesh.positions, &mut mesh.normals)
                .map_err(|e| DemoError::Usage(format!("{}: at {time} s: {e}", self.name)))?,
            Source::Twist { n } => twist_pose(*n, time, &mut mesh.positions, &mut mesh.normals),
        }
        if self.up != Up::Z {
            for v in mesh.positions.iter_mut().chain(mesh.normals.iter_mut()) {
                *v = self.up.to_z_up(*v);
            }
        }
        Ok(())
    }

    /// The sphere around the whole clip (the centre of the bounding box of
    /// [`FRAMING_SAMPLES`] + 1 poses evenly over it, and its half diagonal, enlarged by 10% as
    /// the camera of a static mesh is): the camera of `render --time` and `view --animate`,
    /// the same at every time.
    ///
    /// Returns the error of [`Animation::pose`].
    pub fn sphere(&mut self) -> Result<(DVec3, f64)> {
        let mut m = self.rest();
        let (mut lo, mut hi) = m.bounds();
        for k in 0..=FRAMING_SAMPLES {
            self.pose(self.duration * k as f64 / FRAMING_SAMPLES as f64, &mut m)?;
            let (a, b) = m.bounds();
            (lo, hi) = (lo.min(a), hi.max(b));
        }
        Ok(((lo + hi) * 0.5, (hi - lo).length() * 0.5 * 1.1))
    }
}

/// Checks a `--time` value: a finite number of seconds, at least 0.
pub fn check_time(t: f64) -> Result<f64> {
    if t.is_finite() && t >= 0.0 {
        Ok(t)
    } else {
        Err(DemoError::Usage(format!(
            "--time {t}: expected a finite number of seconds, at least 0"
        )))
    }
}

/// One frame of `source`'s animation for `render --time`: the pose at `time` (checked by
/// [`check_time`]) of clip `clip`, upright, and the camera from `view` (azimuth, elevation)
/// framing the whole clip ([`Animation::sphere`]) for a `width`×`height` image.
///
/// Returns the errors of [`Animation::open`], [`check_time`] and [`Animation::pose`].
pub fn frame(
    source: &MeshSource,
    up: Option<Up>,
    clip: Option<usize>,
    time: f64,
    view: (f64, f64),
    size: (u32, u32),
) -> Result<(Mesh, Camera)> {
    let time = check_time(time)?;
    let mut anim = Animation::open(source, up, clip)?;
    let (c, r) = anim.sphere()?;
    let mut mesh = anim.rest();
    anim.pose(time, &mut mesh)?;
    let cam = Camera::look_at_sphere(c, r, view.0, view.1, size.0, size.1);
    Ok((mesh, cam))
}
