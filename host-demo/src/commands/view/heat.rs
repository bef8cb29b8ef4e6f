//! The CPU's error heat map (`H`, `--heat`): each pixel coloured by its certified `t_error`.

use crate::image::{Image, heat};
use crate::renderer::Rendered;

/// Each hit pixel coloured by its certified `t_error` relative to the scene's diagonal, on the
/// heat scale of `precision --strip` from 1e-9 (blue) to 1e-3 (red); misses black.
pub(super) fn heat_map(r: &Rendered, diag: f64) -> Image {
    let (w, h) = (r.image.width, r.image.height);
    let mut img = Image::new(w, h, [0, 0, 0]);
    for (i, p) in r.hits.iter().enumerate() {
        if !p.hit {
            continue;
        }
        let rel = (p.t_error / diag.max(f64::MIN_POSITIVE)).max(1e-12);
        let l = ((rel.log10() + 9.0) / 6.0).clamp(0.0, 1.0);
        let (x, y) = (i as u32 % w.max(1), i as u32 / w.max(1));
        img.put(i64::from(x), i64::from(y), heat(l));
    }
    img
}
