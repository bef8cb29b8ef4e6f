//! Figures measured on the suite's own test scenes (the torus, the teapot, random patches),
//! pinned so that any change of the construction or the kernel shows. They describe these
//! scenes, not guarantees of the crate (those are `smoothtri::accuracy`).

/// Fidelity of the 8×8 torus (major radius 1, minor 0.4, analytic normals, 128 triangles):
/// maximum distance of the surface to the true torus over 91 samples per triangle, measured
/// (to three digits; the test asserts it to 1 %, so that any change of the construction
/// shows; docs/METHOD.md's design value is 7.4e-3). Asserted by `tests/suite/torus.rs`.
pub const TORUS_8X8_DISTANCE: f64 = 7.36e-3;

/// As [`TORUS_8X8_DISTANCE`] for the 16×16 torus (512 triangles; docs/METHOD.md: 6.3e-4).
pub const TORUS_16X16_DISTANCE: f64 = 6.23e-4;

/// The shell is not tight by accident: on random well-shaped patches with normals up to 50°
/// (2000 patches, 861 points each), the surface stays at least this fraction of the height
/// range's width away from its faces. Measured: closest 0.169. Asserted by `tests/suite/shell.rs`.
pub const SHELL_CLEARANCE: f64 = 0.1;

/// The band that culls rays (`core/src/surface/band.rs`) is not tight by accident either: on
/// random well-shaped patches with normals within 45° of the face (the only ones with a band;
/// 861 points each), the surface stays at least this fraction of the band's width away from
/// its faces. Measured: closest 0.16. Asserted by `tests/suite/shell.rs`.
pub const BAND_CLEARANCE: f64 = 0.1;

/// The predictor's bound (`core/src/surface/predictor.rs`: six times the error at sixteen
/// held-out points plus an absolute term) holds with room: on random patches in its domain and
/// on the torus's and the teapot's (the degree-24 lattice of each), the error stays below the
/// bound by at least this fraction of it. Measured: the largest error is 0.294 of the bound
/// (clearance 0.706). Asserted by `tests/suite/shell.rs`.
pub const PREDICTOR_CLEARANCE: f64 = 0.5;

/// Bounds of one row of [`TORUS_F64_BY_ITERATIONS`]: the kernel's error at `n` refinement
/// iterations, as distances along the ray (`|t − t₄₀|·|dir|`, against the same kernel at
/// N = 40), on a torus of major radius 1.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct IterationBound {
    /// Refinement iterations `N`.
    pub n: usize,
    /// Largest error of a hit.
    pub max_error: f64,
    /// 99th percentile of the errors.
    pub p99_error: f64,
    /// Largest returned `t_error` (times `|dir|`).
    pub max_t_error: f64,
}

const fn row(n: usize, max_error: f64, p99_error: f64, max_t_error: f64) -> IterationBound {
    IterationBound {
        n,
        max_error,
        p99_error,
        max_t_error,
    }
}

/// Precision versus refinement steps, `f64`, torus 8×8 (major radius 1, minor 0.4), 1500
/// random rays from outside (1042 hits), closest hit over all patches, eight evaluations per
/// step (`kernel::refine`): per N, bounds of the error against N = 40 (every error is
/// also within the returned `t_error`, and no ray changes between hit and miss). Measured
/// (max / 99th pct / max `t_error`): N = 0: 2.24e-2 / 2.46e-3 / 1.27e-1; 1: 8.26e-4 /
/// 1.58e-7 / 1.62e-2; 2: 1.06e-7 / 1.12e-15 / 1.74e-3; 4: 4.9e-16 / 0 / 1.63e-12; 8, 16
/// and 24: 0 / 0 / 8.36e-13 (`t_error` is then the rounding allowance). The returned `t` is
/// the inverse-interpolation estimate inside the final bracket (`kernel::refine`), hence the
/// small 99th percentiles from N = 1. Asserted by `tests/suite/kernel.rs`.
pub const TORUS_F64_BY_ITERATIONS: [IterationBound; 7] = [
    row(0, 2.5e-2, 3.0e-3, 1.5e-1),
    row(1, 1.2e-3, 5.0e-7, 2.0e-2),
    row(2, 3.0e-7, 1.0e-14, 2.5e-3),
    row(4, 2e-15, 2e-15, 5.0e-12),
    row(8, 4e-15, 2e-15, 1.2e-12),
    row(16, 4e-15, 2e-15, 1.2e-12),
    row(24, 4e-15, 2e-15, 1.2e-12),
];

/// The 8×8 torus (major radius 1, minor 0.4): largest angle between the geometric normal of
/// [`Patch::point_normal`] and the true torus normal at the
/// nearest torus point, degrees, over 325 barycentric samples per triangle (41 600). Measured
/// (to 0.01°, as the test asserts): 5.80°. Asserted by `tests/suite/seam.rs`.
pub const TORUS_8X8_GEOMETRIC_NORMAL_MAX_DEG: f64 = 5.80;

/// As [`TORUS_8X8_GEOMETRIC_NORMAL_MAX_DEG`], the 99th percentile: 4.21°.
pub const TORUS_8X8_GEOMETRIC_NORMAL_P99_DEG: f64 = 4.21;

/// As [`TORUS_8X8_GEOMETRIC_NORMAL_MAX_DEG`] for the seamless shading normal of
/// [`Seam::shading_normal`]: 2.90° (mean 0.97° against 1.03°).
/// The common edge normal, the average of the two sides', is itself up to 2.9° off on the
/// diagonal edges, which bounds what any seam correction reaches (docs/METHOD.md).
pub const TORUS_8X8_SEAMLESS_NORMAL_MAX_DEG: f64 = 2.90;

/// As [`TORUS_8X8_SEAMLESS_NORMAL_MAX_DEG`], the 99th percentile: 2.55°.
pub const TORUS_8X8_SEAMLESS_NORMAL_P99_DEG: f64 = 2.55;
