//! The winit application: the window and how frames reach it (opened on `resumed`), its events
//! (close, resize, redraw, the keys and the mouse; headless, the frames counted and the outputs
//! written after the last) and the waits between frames.

use std::sync::Arc;
use std::time::Instant;

use smoothtri_gpu::GpuSurface;
use winit::application::ApplicationHandler;
use winit::dpi::PhysicalSize;
use winit::event::{ElementState, MouseButton, WindowEvent};
use winit::event_loop::{ActiveEventLoop, ControlFlow};
use winit::window::{Window, WindowId};

use super::Viewer;
use super::frame::Presenter;
use super::input::REST;
use crate::error::DemoError;
use crate::gpu::gpu_error;

impl Viewer {
    /// Keeps the first error and ends the event loop.
    fn fail(&mut self, e: DemoError, event_loop: &ActiveEventLoop) {
        self.error.get_or_insert(e);
        event_loop.exit();
    }
}

impl ApplicationHandler for Viewer {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.window.is_some() {
            return;
        }
        let attrs = Window::default_attributes()
            .with_title("smoothtri view")
            .with_inner_size(PhysicalSize::new(self.options.width, self.options.height));
        let window = match event_loop.create_window(attrs) {
            Ok(w) => Arc::new(w),
            Err(e) => {
                return self.fail(
                    DemoError::Usage(format!("view: cannot open a window: {e}")),
                    event_loop,
                );
            }
        };
        self.size = window.inner_size();
        if let Some(g) = self.gpu.as_mut() {
            let size = self.size;
            match GpuSurface::new(&g.gpu, Arc::clone(&window), size.width, size.height) {
                Ok(s) => {
                    g.surface = Some(s);
                    self.surface = Some(Presenter::Gpu);
                }
                Err(e) => return self.fail(gpu_error(e), event_loop),
            }
        } else {
            let surface = softbuffer::Context::new(Arc::clone(&window))
                .and_then(|c| softbuffer::Surface::new(&c, Arc::clone(&window)));
            match surface {
                Ok(s) => self.surface = Some(Presenter::Soft(s)),
                Err(e) => {
                    return self.fail(
                        DemoError::Usage(format!("view: cannot draw into the window: {e}")),
                        event_loop,
                    );
                }
            }
        }
        window.request_redraw();
        self.window = Some(window);
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _id: WindowId, event: WindowEvent) {
        let headless = self.options.frames.is_some();
        match event {
            WindowEvent::CloseRequested | WindowEvent::Destroyed => {
                // Drop the surfaces and the window first: a window destroyed by another client
                // must not be asked for its size again (winit's X11 backend panics on that).
                self.surface = None;
                if let Some(g) = self.gpu.as_mut() {
                    g.surface = None;
                }
                self.window = None;
                event_loop.exit();
            }
            WindowEvent::Resized(size) => {
                self.size = size;
                self.shown = None;
                if let Some(w) = &self.window {
                    w.request_redraw();
                }
            }
            WindowEvent::RedrawRequested => {
                if let Err(e) = self.redraw() {
                    return self.fail(e, event_loop);
                }
                if let Some(k) = self.options.frames {
                    self.frames_done += 1;
                    if self.frames_done >= k {
                        if let Err(e) = self.write_outputs() {
                            return self.fail(e, event_loop);
                        }
                        event_loop.exit();
                    } else if let Some(w) = &self.window {
                        w.request_redraw();
                    }
                }
            }
            _ if headless => {}
            WindowEvent::KeyboardInput { event, .. } if event.state == ElementState::Pressed => {
                self.key(&event.logical_key, event_loop);
            }
            WindowEvent::MouseInput {
                state,
                button: MouseButton::Left,
                ..
            } => {
                self.drag = (state == ElementState::Pressed).then_some(self.cursor);
            }
            WindowEvent::CursorMoved { position, .. } => self.cursor_moved(position.x, position.y),
            WindowEvent::MouseWheel { delta, .. } => self.wheel(delta),
            _ => {}
        }
    }

    fn about_to_wait(&mut self, event_loop: &ActiveEventLoop) {
        if self.options.frames.is_some() {
            return;
        }
        // A playing animation: the next frame at once.
        if self.playing.as_ref().is_some_and(|p| p.paused.is_none()) {
            if let Some(w) = &self.window {
                w.request_redraw();
            }
            event_loop.set_control_flow(ControlFlow::Wait);
            return;
        }
        // Once the camera rests, one full-resolution frame of what is shown.
        let size = self.window.as_ref().map(|_| self.size);
        let full = size.map(|s| (self.settings, s.width, s.height));
        if full.is_some() && full != self.shown {
            let rest_at = self.last_input + REST;
            if Instant::now() >= rest_at {
                if let Some(w) = &self.window {
                    w.request_redraw();
                }
                event_loop.set_control_flow(ControlFlow::Wait);
            } else {
                event_loop.set_control_flow(ControlFlow::WaitUntil(rest_at));
            }
        } else {
            event_loop.set_control_flow(ControlFlow::Wait);
        }
    }
}
