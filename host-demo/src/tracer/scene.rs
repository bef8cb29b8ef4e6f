//! [`Scene`]: a [`Mesh`] built by the core's scene builder ([`smoothtri::OwnedScene`]) in one
//! precision, with the list of rejected triangles and the normal the renders shade with.

use std::collections::BTreeMap;

use std::time::Instant;

use smoothtri::{
    BuildObserver, BuildOptions, BuildReport, BuildStage, Bvh, Float, Hit, LineField, OwnedScene,
    Patch, PatchError,
};
use smoothtri_host::RayonExecutor;
use smoothtri_io::Mesh;

use super::modes::Normals;
use super::precision::Prec;
use crate::error::{DemoError, Result};

/// A mesh's scene: the core's [`OwnedScene`] (patches, crack closure, optional seams, BVH),
/// the rejected triangles with their reasons, and the normal to shade with.
pub struct Scene<F: Float> {
    owned: OwnedScene<F>,
    /// Rejected triangles and why (only non-finite, degenerate or overflowing input: steep or
    /// back-facing normals are repaired by the core's documented remedy instead).
    pub rejected: Vec<(u32, PatchError)>,
    /// The normal [`Scene::shading_normal`] returns: seamless only when the scene was built
    /// with seams.
    pub normals: Normals,
    /// Wall-clock seconds of each step of the build, in order.
    pub stage_seconds: Vec<(BuildStage, f64)>,
}

/// Triangles from which a build shows a progress bar (on a terminal only).
const PROGRESS_FROM_TRIANGLES: usize = 20_000;

/// Records the rejected triangles, times the steps and draws the progress bar.
struct Recorder {
    rejected: Vec<(u32, PatchError)>,
    stages: Vec<(BuildStage, f64)>,
    current: Option<(BuildStage, Instant)>,
    bar: indicatif::ProgressBar,
}

impl BuildObserver for Recorder {
    fn rejected(&mut self, triangle: u32, why: PatchError) {
        self.rejected.push((triangle, why));
    }
    fn stage(&mut self, stage: BuildStage) {
        let now = Instant::now();
        if let Some((s, t)) = self.current.take() {
            self.stages.push((s, (now - t).as_secs_f64()));
        }
        if stage == BuildStage::Done {
            self.bar.finish_and_clear();
        } else {
            self.current = Some((stage, now));
            self.bar.set_message(format!("build: {}", stage.name()));
            self.bar.set_position(0);
        }
    }
    fn progress(&mut self, _stage: BuildStage, done: usize, total: usize) {
        self.bar.set_length(total as u64);
        self.bar.set_position(done as u64);
    }
}

impl<F: Prec> Scene<F> {
    /// The scene on the paper's line field, without seams (shades with the geometric normal).
    /// Fails only when no triangle is accepted.
    pub fn build(mesh: &Mesh) -> Result<Self> {
        Self::build_with(mesh, LineField::Face, false)
    }

    /// The scene on `field` ([`LineField::Vertex`]: neighbours share their edges' lines, so
    /// their edge curves meet; docs/METHOD.md §2), with the seamless shading normals when
    /// `seams` (what only shading needs: fitting costs `2·FIT_SAMPLES` = 16 normal evaluations
    /// per shared edge). Crack closure and the seam fit run on rayon's pool ([`RayonExecutor`]); the scene
    /// is the same bit for bit on any number of threads.
    pub fn build_with(mesh: &Mesh, field: LineField, seams: bool) -> Result<Self> {
        use std::io::IsTerminal;
        let bar =
            if mesh.triangles.len() >= PROGRESS_FROM_TRIANGLES && std::io::stderr().is_terminal() {
                let bar = indicatif::ProgressBar::new(mesh.triangles.len() as u64);
                if let Ok(style) =
                    indicatif::ProgressStyle::with_template("{msg:16} {wide_bar} {pos}/{len} {eta}")
                {
                    bar.set_style(style);
                }
                bar
            } else {
                indicatif::ProgressBar::hidden()
            };
        let mut rec = Recorder {
            rejected: Vec::new(),
            stages: Vec::new(),
            current: None,
            bar,
        };
        let owned: OwnedScene<F> = mesh
            .build_scene(&mut BuildOptions {
                field,
                seams,
                observer: &mut rec,
                executor: RayonExecutor,
            })
            .map_err(|e| DemoError::Empty { msg: e.to_string() })?;
        Ok(Scene {
            owned,
            rejected: rec.rejected,
            stage_seconds: rec.stages,
            normals: if seams {
                Normals::Seamless
            } else {
                Normals::Geometric
            },
        })
    }

    /// Moves the scene to `mesh`'s vertices in place ([`smoothtri::OwnedScene::update`]):
    /// `mesh` has the triangles the scene was built from (another pose of the same animation)
    /// and `field` and `seams` are those of the build. The rejected triangles and the step
    /// times become the update's. The scene equals a fresh build of `mesh` (hits within their
    /// `t_error` where the BVH was refitted).
    ///
    /// Returns [`DemoError::Empty`] with the core's message when the vertices do not fit the
    /// scene (another count, non-finite coordinates) or the options differ; the scene is then
    /// unchanged.
    pub fn update(&mut self, mesh: &Mesh, field: LineField, seams: bool) -> Result<()> {
        let mut rec = Recorder {
            rejected: Vec::new(),
            stages: Vec::new(),
            current: None,
            bar: indicatif::ProgressBar::hidden(),
        };
        mesh.update_scene(
            &mut self.owned,
            &mut BuildOptions {
                field,
                seams,
                observer: &mut rec,
                executor: RayonExecutor,
            },
        )
        .map_err(|e| DemoError::Empty { msg: e.to_string() })?;
        self.rejected = rec.rejected;
        self.stage_seconds = rec.stages;
        Ok(())
    }

    /// The build's time per step, one line: `patches 0.012 s, cracks …; total 0.1 s (N
    /// triangles/s)`.
    pub fn timing_line(&self) -> String {
        let total: f64 = self.stage_seconds.iter().map(|(_, t)| t).sum();
        let parts: Vec<String> = self
            .stage_seconds
            .iter()
            .map(|(s, t)| format!("{} {t:.3} s", s.name()))
            .collect();
        let threads = rayon::current_num_threads();
        format!(
            "{}; total {total:.3} s ({:.0} triangles/s on {threads} thread{})",
            parts.join(", "),
            self.report().triangles as f64 / total.max(1e-9),
            if threads == 1 { "" } else { "s" }
        )
    }

    /// Bytes per input triangle of what the scene holds: `(patches, seams, BVH)`.
    pub fn bytes_per_triangle(&self) -> (f64, f64, f64) {
        let n = self.report().triangles.max(1) as f64;
        let b = self.bvh();
        (
            std::mem::size_of_val(self.patches()) as f64 / n,
            std::mem::size_of_val(self.seams()) as f64 / n,
            b.memory_bytes() as f64 / n,
        )
    }

    /// The core's scene, for queries.
    pub fn core(&self) -> smoothtri::Scene<'_, F> {
        self.owned.scene()
    }

    /// What the build did.
    pub fn report(&self) -> BuildReport {
        *self.owned.scene().report()
    }

    /// The accepted patches, in triangle order.
    pub fn patches(&self) -> &[Patch<F>] {
        self.owned.scene().patches()
    }

    /// The mesh triangle of each patch.
    pub fn tri_ids(&self) -> &[u32] {
        self.owned.scene().triangle_ids()
    }

    /// The patch index of mesh triangle `t`, `None` when it was rejected.
    pub fn patch_of_tri(&self, t: usize) -> Option<usize> {
        self.owned.scene().patch_index(u32::try_from(t).ok()?)
    }

    /// The seams (empty when built without).
    pub fn seams(&self) -> &[smoothtri::mesh::Seam<F>] {
        self.owned.scene().seams()
    }

    /// Triangles whose normals the per-patch remedy clamped, with the clamp angle in degrees.
    pub fn remedied(&self) -> Vec<(u32, f64)> {
        self.patches()
            .iter()
            .zip(self.tri_ids())
            .filter_map(|(p, &t)| p.normal_clamp().map(|d| (t, d)))
            .collect()
    }

    /// The normal to shade a smooth hit with: with [`Normals::Seamless`] (and seams) the
    /// hit's geometric normal corrected by its patch's seam, else the hit's normal as it is.
    /// Oriented like the vertex normals.
    pub fn shading_normal(&self, hit: &Hit<F>) -> F::Vec3 {
        match self.normals {
            Normals::Seamless => self.owned.scene().shading_normal(hit),
            Normals::Geometric => hit.normal,
        }
    }

    /// The BVH over [`Scene::patches`].
    pub fn bvh(&self) -> Bvh<'_, F> {
        *self.owned.scene().bvh()
    }

    /// Rejection counts by reason, for reports.
    pub fn rejected_summary(&self) -> BTreeMap<String, usize> {
        let mut m = BTreeMap::new();
        for (_, e) in &self.rejected {
            *m.entry(e.to_string()).or_insert(0) += 1;
        }
        m
    }

    /// The stderr note about skipped triangles, if any were.
    pub fn rejected_note(&self) -> Option<String> {
        let mut lines = Vec::new();
        let (remedied, triangles) = (self.remedied(), self.report().triangles);
        if !remedied.is_empty() {
            lines.push(format!(
                "note: {} of {} triangles have normals outside the method's domain; they were \
                 clamped toward the face normal ({}): {}",
                remedied.len(),
                triangles,
                F::PRECISION,
                self.remedied_summary()
            ));
        }
        if !self.rejected.is_empty() {
            let parts: Vec<String> = self
                .rejected_summary()
                .iter()
                .map(|(k, v)| format!("{v} × {k}"))
                .collect();
            lines.push(format!(
                "note: skipped {} of {} triangles that the core rejects ({}): {}",
                self.rejected.len(),
                triangles,
                F::PRECISION,
                parts.join("; ")
            ));
        }
        if lines.is_empty() {
            None
        } else {
            Some(lines.join("\n"))
        }
    }

    /// Remedied patches by clamp angle, e.g. `3 × 60°, 1 × 0° (flat)`.
    pub fn remedied_summary(&self) -> String {
        let mut m: BTreeMap<i64, usize> = BTreeMap::new();
        for (_, deg) in self.remedied() {
            *m.entry(-(deg as i64)).or_insert(0) += 1;
        }
        m.iter()
            .map(|(d, n)| {
                let flat = if *d == 0 { " (flat)" } else { "" };
                format!("{n} × {}°{flat}", -d)
            })
            .collect::<Vec<_>>()
            .join(", ")
    }
}
