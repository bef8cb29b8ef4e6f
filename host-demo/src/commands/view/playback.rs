//! `--animate`: the clip's clock ([`Playing`]: playing, looping, paused) and posing the
//! viewer's mesh at the time of each frame.

use std::time::Instant;

use glam::DVec3;
use smoothtri_io::Mesh;

use super::Viewer;
use crate::animate::{Animation, FRAME_STEP};
use crate::error::Result;

/// The animation being played: the source, where it started and the clock, or the time it is
/// paused at.
pub(super) struct Playing {
    pub(super) animation: Animation,
    /// The clip time at `clock`'s start, seconds.
    offset: f64,
    clock: Instant,
    pub(super) paused: Option<f64>,
    /// The time of the pose in the viewer's mesh.
    pub(super) shown: f64,
}

impl Playing {
    /// Starts `animation` at clip time `start`: the mesh posed at that time, the sphere that
    /// frames the whole clip, and the clock from now.
    pub(super) fn start(
        mut animation: Animation,
        start: f64,
    ) -> Result<(Mesh, (DVec3, f64), Self)> {
        let sphere = animation.sphere()?;
        let mut mesh = animation.rest();
        let mut p = Playing {
            animation,
            offset: start,
            clock: Instant::now(),
            paused: None,
            shown: 0.0,
        };
        p.shown = p.wrap(start);
        p.animation.pose(p.shown, &mut mesh)?;
        Ok((mesh, sphere, p))
    }

    /// The clip time now (interactive: by the wall clock, looping over the clip).
    fn now(&self) -> f64 {
        let t = self
            .paused
            .unwrap_or_else(|| self.offset + self.clock.elapsed().as_secs_f64());
        self.wrap(t)
    }

    /// `t` looped into the clip (the twisting torus repeats with its period anyway).
    fn wrap(&self, t: f64) -> f64 {
        let d = self.animation.duration;
        if d > 0.0 { t % d } else { 0.0 }
    }

    /// Space: pauses at the time now, or plays on from the time paused at.
    pub(super) fn toggle_pause(&mut self) {
        match self.paused.take() {
            Some(t) => {
                self.offset = t;
                self.clock = Instant::now();
            }
            None => self.paused = Some(self.now()),
        }
    }
}

impl Viewer {
    /// `--animate`: poses the mesh at the animation's time for this frame (headless: frame
    /// `k` at `--time` + `k ·` [`FRAME_STEP`]) when that time changed; the scenes follow.
    pub(super) fn advance(&mut self) -> Result<()> {
        let headless = self.options.frames.is_some();
        let frame = f64::from(self.frames_done);
        let Some(p) = self.playing.as_mut() else {
            return Ok(());
        };
        let t = if headless {
            p.wrap(p.offset + frame * FRAME_STEP)
        } else {
            p.now()
        };
        if t == p.shown {
            return Ok(());
        }
        p.animation.pose(t, &mut self.mesh)?;
        p.shown = t;
        self.diag = self.mesh.diagonal();
        self.scenes.posed();
        if let Some(g) = self.gpu.as_mut() {
            g.posed();
        }
        Ok(())
    }
}
