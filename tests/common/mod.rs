//! Shared helpers of the integration tests: approximate assertions, random geometry, reference
//! data loading.
#![allow(dead_code)]

use glam::DVec3;

/// Asserts `|a − b| ≤ tol`, printing both values (glam's `assert_approx_eq!` style).
#[macro_export]
macro_rules! assert_close {
    ($a:expr, $b:expr, $tol:expr) => {{
        let (a, b, tol) = ($a, $b, $tol);
        let d = (a - b).abs();
        assert!(d <= tol, "{} = {:?}\n{} = {:?}\n|diff| = {:e} > {:e}", stringify!($a), a, stringify!($b), b, d, tol);
    }};
    ($a:expr, $b:expr, $tol:expr, $($msg:tt)+) => {{
        let (a, b, tol) = ($a, $b, $tol);
        let d = (a - b).abs();
        assert!(d <= tol, "{} = {:?}\n{} = {:?}\n|diff| = {:e} > {:e}: {}", stringify!($a), a, stringify!($b), b, d, tol, format!($($msg)+));
    }};
}

/// Asserts `|a − b| ≤ tol` for vectors (Euclidean distance), printing both.
#[macro_export]
macro_rules! assert_vec_close {
    ($a:expr, $b:expr, $tol:expr) => {{
        let (a, b, tol) = ($a, $b, $tol);
        let d = (a - b).length();
        assert!(d <= tol, "{} = {:?}\n{} = {:?}\n|diff| = {:e} > {:e}", stringify!($a), a, stringify!($b), b, d, tol);
    }};
    ($a:expr, $b:expr, $tol:expr, $($msg:tt)+) => {{
        let (a, b, tol) = ($a, $b, $tol);
        let d = (a - b).length();
        assert!(d <= tol, "{} = {:?}\n{} = {:?}\n|diff| = {:e} > {:e}: {}", stringify!($a), a, stringify!($b), b, d, tol, format!($($msg)+));
    }};
}

/// Directory of the read-only shared reference data (`../shared/reference` beside the repo).
pub fn reference_dir() -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../shared/reference")
}

/// Parses a CSV of floats with a header; returns (header, rows).
pub fn read_csv(name: &str) -> (Vec<String>, Vec<Vec<f64>>) {
    let path = reference_dir().join(name);
    let text = std::fs::read_to_string(&path)
        .unwrap_or_else(|e| panic!("cannot read {}: {e}", path.display()));
    let mut lines = text.lines();
    let header: Vec<String> = lines.next().unwrap_or("").split(',').map(str::to_owned).collect();
    let rows = lines
        .filter(|l| !l.trim().is_empty())
        .map(|l| l.split(',').map(|x| x.trim().parse::<f64>().unwrap_or(f64::NAN)).collect())
        .collect();
    (header, rows)
}

/// A tiny deterministic PRNG (SplitMix64) so tests are reproducible without extra crates.
pub struct Rng(pub u64);
impl Rng {
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    /// Uniform in [0, 1).
    pub fn f(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }
    pub fn range(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * self.f()
    }
    /// Uniform on the unit sphere.
    pub fn unit(&mut self) -> DVec3 {
        loop {
            let v = DVec3::new(self.range(-1.0, 1.0), self.range(-1.0, 1.0), self.range(-1.0, 1.0));
            let l = v.length();
            if l > 1e-3 && l <= 1.0 {
                return v / l;
            }
        }
    }
}
