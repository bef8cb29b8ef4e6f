//! smoothtri beside the other smooth surfaces built from a triangle and its vertex normals,
//! Phong tessellation (α = 3/4 and 1) and Nagata patches (`smoothtri-peers`), and beside flat
//! triangles, on the same meshes and the same rays:
//!
//! ```text
//! cargo bench --bench peers                      # accuracy, speed (+ instructions), terminator
//! cargo bench --features embree --bench peers    # the same with Embree's flat rows
//! cargo bench --bench peers -- accuracy          # one table: accuracy, speed or terminator
//! ```
//!
//! - **Accuracy**: each surface sampled at 45 barycentric points per triangle (a grid of step
//!   1/8) on the 8×8 torus, the octahedron's unit sphere (radial normals), Newell's teapot
//!   (992 triangles with the Bézier patches' exact normals) and the scanned WusonOBJ: the largest
//!   and 99th-percentile distance to the true surface (torus and sphere analytic; the teapot's
//!   Bézier patches by Newton projection), the geometric and shading normals' angle to the true
//!   normal, the normal jump across shared edges (every mesh, WusonOBJ included), and the
//!   coarsest flat tessellation of the same generator whose largest distance is no larger.
//! - **Speed**: one thread, f32, 640×480 camera rays (`render`'s default view of each mesh) and
//!   as many random rays through the mesh's box, on the torus and WusonOBJ: flat triangles
//!   (Möller–Trumbore in smoothtri's BVH over the triangles' boxes; Embree with `--features
//!   embree`), the peers (their exact solver in smoothtri's BVH over their boxes), smoothtri at
//!   N = 0, 4, 8; every hit with its normal. Mrays/s is the median of interleaved rounds;
//!   instructions per camera ray come from callgrind (160×120 rays) when valgrind is installed.
//! - **Terminator**: the torus under `render`'s light, one shadow ray per lit hit, each surface
//!   beside the analytic torus rendered the same way (`smoothtri_demo::peers`): pixels whose
//!   lit/shadowed state differs, and the shading error in the band `|n·l| ≤ 0.4` around the true
//!   terminator; the row of images goes to `target/peers/terminator.png`.

use std::hint::black_box;

use smoothtri_peers::torus::Torus;

#[path = "peers/accuracy.rs"]
mod accuracy;
mod common;
#[cfg(feature = "embree")]
#[path = "embree/ffi.rs"]
#[allow(dead_code)]
mod ffi;
#[path = "peers/speed.rs"]
mod speed;
#[path = "peers/terminator.rs"]
mod terminator;
#[path = "peers/tracers.rs"]
mod tracers;
#[path = "peers/truth.rs"]
mod truth;

use accuracy::accuracy;
use speed::{run_case, speed};
use terminator::terminator;

/// The torus of the tables (the built-in scene's radii).
const TORUS: Torus = Torus {
    major: 1.0,
    minor: 0.4,
};

fn main() {
    let args: Vec<String> = std::env::args().collect();
    if let Some(i) = args.iter().position(|a| a == "--case") {
        println!("{}", black_box(run_case(&args[i + 1])));
        return;
    }
    if !args.iter().any(|a| a == "--bench") {
        eprintln!("run with `cargo bench --bench peers`");
        return;
    }
    let only: Vec<&str> = args
        .iter()
        .skip(1)
        .map(String::as_str)
        .filter(|a| !a.starts_with('-'))
        .collect();
    let want = |s: &str| only.is_empty() || only.contains(&s);
    if want("accuracy") {
        accuracy();
    }
    if want("speed") {
        speed();
    }
    if want("terminator") {
        terminator();
    }
}
