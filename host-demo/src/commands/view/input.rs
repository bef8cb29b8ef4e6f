//! What the keys and the mouse change ([`Settings`]): the keys ([`KEYS`]), orbiting with the
//! left mouse button and zooming with the wheel.

use std::time::{Duration, Instant};

use winit::event::MouseScrollDelta;
use winit::event_loop::ActiveEventLoop;
use winit::keyboard::{Key, NamedKey};

use super::{Settings, ViewOptions, Viewer};
use crate::tracer::{Mode, Normals, Precision};

/// The keys of the viewer, as its help line and the README list them.
pub const KEYS: &[(&str, &str)] = &[
    ("M", "mode: smooth → flat → phong"),
    ("S", "shading normal: seamless ↔ geometric"),
    ("↑ / ↓", "N (refinement steps) up / down, 0..=16"),
    ("P", "precision: f32 ↔ f64 (CPU)"),
    ("H", "heat map of each pixel's certified t_error"),
    ("R", "reset the camera"),
    ("Space", "pause / play the animation (`--animate`)"),
    ("Esc / Q", "quit"),
];

/// Largest `N` the keys reach (the demo's kernels are compiled for every `N` up to it).
pub(super) const MAX_N: usize = 16;
/// How long after the last input the camera counts as resting.
pub(super) const REST: Duration = Duration::from_millis(150);
/// Degrees of orbit per pixel of mouse motion.
const ORBIT_DEG_PER_PX: f64 = 0.4;

impl Settings {
    /// The settings at start (and after `R`): those of the options, at zoom 1.
    pub(super) fn initial(o: &ViewOptions) -> Settings {
        Settings {
            mode: o.mode,
            n: o.iterations,
            precision: o.precision,
            normals: o.normals,
            heat: o.heat,
            az: o.view.0,
            el: o.view.1,
            zoom: 1.0,
        }
    }

    /// Whether the scene shown has seams: only the smooth mode shades with them.
    pub(super) fn seams(&self) -> bool {
        self.normals == Normals::Seamless && self.mode == Mode::Smooth
    }
}

impl Viewer {
    /// Notes an input that changes the view.
    pub(super) fn changed(&mut self) {
        self.last_input = Instant::now();
        if let Some(w) = &self.window {
            w.request_redraw();
        }
    }

    /// The mouse moved to `(x, y)`: while the left button is held, the camera orbits.
    pub(super) fn cursor_moved(&mut self, x: f64, y: f64) {
        self.cursor = (x, y);
        if let Some((x0, y0)) = self.drag {
            let s = &mut self.settings;
            s.az -= (x - x0) * ORBIT_DEG_PER_PX;
            s.el = (s.el + (y - y0) * ORBIT_DEG_PER_PX).clamp(-89.0, 89.0);
            self.drag = Some(self.cursor);
            self.changed();
        }
    }

    /// The wheel turned by `delta`: the camera zooms.
    pub(super) fn wheel(&mut self, delta: MouseScrollDelta) {
        let steps = match delta {
            MouseScrollDelta::LineDelta(_, y) => f64::from(y),
            MouseScrollDelta::PixelDelta(p) => p.y / 40.0,
        };
        let s = &mut self.settings;
        s.zoom = (s.zoom * 0.9f64.powf(steps)).clamp(0.05, 20.0);
        self.changed();
    }

    /// A key was pressed: changes the settings as [`KEYS`] says, or quits.
    pub(super) fn key(&mut self, key: &Key, event_loop: &ActiveEventLoop) {
        let s = &mut self.settings;
        match key {
            Key::Named(NamedKey::Escape) => event_loop.exit(),
            Key::Named(NamedKey::ArrowUp) => s.n = (s.n + 1).min(MAX_N),
            Key::Named(NamedKey::ArrowDown) => s.n = s.n.saturating_sub(1),
            Key::Character(c) => match c.to_ascii_lowercase().as_str() {
                "q" => event_loop.exit(),
                "m" => {
                    s.mode = match s.mode {
                        Mode::Smooth => Mode::Flat,
                        Mode::Flat => Mode::Phong,
                        Mode::Phong | Mode::PhongTess | Mode::Nagata => Mode::Smooth,
                    }
                }
                "s" => {
                    s.normals = match s.normals {
                        Normals::Seamless => Normals::Geometric,
                        Normals::Geometric => Normals::Seamless,
                    }
                }
                "p" if self.gpu.is_none() => {
                    s.precision = match s.precision {
                        Precision::F32 => Precision::F64,
                        Precision::F64 => Precision::F32,
                    }
                }
                "h" => s.heat = !s.heat,
                "r" => *s = Settings::initial(&self.options),
                _ => return,
            },
            Key::Named(NamedKey::Space) => match self.playing.as_mut() {
                Some(p) => p.toggle_pause(),
                None => return,
            },
            _ => return,
        }
        self.changed();
    }
}
