//! Headless (`--frames K`): after the K frames, the last one written (`--screenshot`, and its
//! primary-hit mask, `--mask`; a GPU frame read back first) and the frame rate printed.

use super::Viewer;
use super::gpu::GpuView;
use crate::error::{DemoError, Result};
use crate::gpu::read_frame;

impl Viewer {
    /// Headless: writes the last frame and its mask, and prints the frame rate.
    pub(super) fn write_outputs(&mut self) -> Result<()> {
        let Some(frame) = &self.last else {
            return Err(DemoError::Usage("view: no frame was rendered".into()));
        };
        let (image, hits) = match (&frame.pixels, &self.gpu) {
            (Some((image, hits)), _) => (image.clone(), hits.clone()),
            (
                None,
                Some(GpuView {
                    frame: Some((f, _, stats)),
                    ..
                }),
            ) => {
                let scene = self.scenes.get::<f32>(
                    &self.mesh,
                    self.options.field,
                    self.settings.seams(),
                )?;
                let r = read_frame(&scene, f, *stats)?;
                (r.image, r.hits)
            }
            _ => return Err(DemoError::Usage("view: no frame was rendered".into())),
        };
        let Some(frame) = &self.last else {
            return Err(DemoError::Usage("view: no frame was rendered".into()));
        };
        let (secs, rays) = self.totals;
        let k = f64::from(self.frames_done.max(1));
        println!(
            "view: {} frames of {}x{} ({}): {:.1} ms per frame ({:.1} frames/s), {:.2} Mrays/s",
            self.frames_done,
            frame.width,
            frame.height,
            self.title(frame, false)
                .split(" — ")
                .nth(1)
                .unwrap_or_default(),
            secs / k * 1e3,
            k / secs.max(1e-9),
            rays as f64 / secs.max(1e-9) / 1e6
        );
        if let Some(path) = &self.options.screenshot {
            image.write_png(path)?;
        }
        if let Some(path) = &self.options.mask {
            crate::output::write(
                path,
                crate::renderer::mask_pbm(image.width, image.height, &hits).as_bytes(),
            )?;
        }
        Ok(())
    }
}
