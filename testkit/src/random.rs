//! Random numbers and random geometry for the tests, with no dependency beyond glam and std:
//! the suite (`tests/suite`), the GPU tests (`gpu/tests`) and the benchmarks use it through this
//! crate, and the core's own `FastF32` test (`core/tests/fast.rs`), which cannot depend on a
//! crate above the core, includes this file by path.

use glam::DVec3;

/// A tiny deterministic PRNG (SplitMix64) so tests are reproducible without extra crates; the
/// field is the state (any seed).
pub struct Rng(pub u64);
impl Rng {
    /// The next 64 random bits.
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
    /// Uniform in `[a, b)`.
    pub fn range(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * self.f()
    }
    /// Uniform on the unit sphere.
    pub fn unit(&mut self) -> DVec3 {
        loop {
            let v = DVec3::new(
                self.range(-1.0, 1.0),
                self.range(-1.0, 1.0),
                self.range(-1.0, 1.0),
            );
            let l = v.length();
            if l > 1e-3 && l <= 1.0 {
                return v / l;
            }
        }
    }
}

/// A random well-shaped triangle (all angles ≥ 25°), counter-clockwise about its returned face
/// normal, size `size`, centred near `offset`.
pub fn well_shaped(rng: &mut Rng, size: f64, offset: DVec3) -> ([DVec3; 3], DVec3) {
    loop {
        let nf = rng.unit();
        let u = nf.any_orthonormal_vector();
        let v = nf.cross(u);
        let mut p = [DVec3::ZERO; 3];
        for (k, pk) in p.iter_mut().enumerate() {
            let a = k as f64 * std::f64::consts::TAU / 3.0 + rng.range(-0.35, 0.35);
            let r = size * rng.range(0.45, 0.6);
            *pk = offset + (u * a.cos() + v * a.sin()) * r;
        }
        if min_angle(&p) >= 25f64.to_radians() {
            return (p, nf);
        }
    }
}

/// Smallest interior angle of a triangle, radians.
pub fn min_angle(p: &[DVec3; 3]) -> f64 {
    (0..3)
        .map(|i| {
            let a = p[(i + 1) % 3] - p[i];
            let b = p[(i + 2) % 3] - p[i];
            a.angle_between(b)
        })
        .fold(f64::INFINITY, f64::min)
}

/// A random vector at angle ≤ `max_deg` from the unit `axis`, with length in [0.5, 2].
pub fn tilted(rng: &mut Rng, axis: DVec3, max_deg: f64) -> DVec3 {
    let th = rng.range(0.0, max_deg.to_radians());
    let u = axis.any_orthonormal_vector();
    let v = axis.cross(u);
    let ph = rng.range(0.0, std::f64::consts::TAU);
    (axis * th.cos() + (u * ph.cos() + v * ph.sin()) * th.sin()) * rng.range(0.5, 2.0)
}

/// A random patch input: well-shaped triangle, normals within `max_deg` of the face normal.
pub fn random_patch(rng: &mut Rng, max_deg: f64) -> ([DVec3; 3], [DVec3; 3]) {
    let size = 10f64.powf(rng.range(-2.0, 1.7));
    let off = DVec3::new(
        rng.range(-3.0, 3.0),
        rng.range(-3.0, 3.0),
        rng.range(-3.0, 3.0),
    );
    let (p, nf) = well_shaped(rng, size, off);
    let n = [
        tilted(rng, nf, max_deg),
        tilted(rng, nf, max_deg),
        tilted(rng, nf, max_deg),
    ];
    (p, n)
}

/// A random well-shaped triangle on a sphere (centre `o`, radius `r`) with radial unit normals,
/// counter-clockwise seen from outside; spans up to `cap_deg` degrees of arc.
pub fn sphere_patch(rng: &mut Rng, o: DVec3, r: f64, cap_deg: f64) -> [DVec3; 3] {
    loop {
        let c = rng.unit();
        let mut q = [DVec3::ZERO; 3];
        for qk in q.iter_mut() {
            *qk = tilted(rng, c, cap_deg).normalize();
        }
        if min_angle(&q) < 25f64.to_radians() {
            continue;
        }
        if (q[1] - q[0]).cross(q[2] - q[0]).dot(c) < 0.0 {
            q.swap(1, 2);
        }
        return q.map(|d| o + d * r);
    }
}

/// A random ray of the kernel's sphere tests (`tests/suite/kernel.rs`, `gpu/tests`): from 4–8
/// away from the origin, aimed within `target_radius` of it, the direction not of unit length
/// on purpose. Returns `(origin, direction)`.
pub fn random_ray(rng: &mut Rng, target_radius: f64) -> (DVec3, DVec3) {
    let o = rng.unit() * rng.range(4.0, 8.0);
    let aim = rng.unit() * target_radius * rng.f().cbrt();
    let d = (aim - o) * rng.range(0.3, 3.0);
    (o, d)
}

/// Barycentric sample points on a grid of `m` subdivisions (inclusive of the boundary).
pub fn bary_grid(m: usize) -> Vec<(f64, f64)> {
    let mut out = Vec::new();
    for i in 0..=m {
        for j in 0..=(m - i) {
            out.push((i as f64 / m as f64, j as f64 / m as f64));
        }
    }
    out
}
