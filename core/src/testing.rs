//! Helpers shared by the crate's unit tests: a reproducible random generator and random
//! patches.

use crate::patch::Patch;
use crate::surface::field::LineField;
use glam::DVec3;

/// SplitMix64, for reproducible random patches without extra dependencies.
pub(crate) struct Rng(pub(crate) u64);
impl Rng {
    pub(crate) fn unit(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }
    pub(crate) fn vec(&mut self) -> DVec3 {
        DVec3::new(self.unit(), self.unit(), self.unit()) * 2.0 - DVec3::ONE
    }
}

/// The accepted patches among `count` random triangles (size ~3, normals up to ~30° from
/// the face), with their longest edge from `P0`.
pub(crate) fn random_patches(seed: u64, count: usize) -> impl Iterator<Item = (Patch<f64>, f64)> {
    random_patches_on(seed, count, LineField::Face)
}

/// [`random_patches`] on the line field `field`.
pub(crate) fn random_patches_on(
    seed: u64,
    count: usize,
    field: LineField,
) -> impl Iterator<Item = (Patch<f64>, f64)> {
    let mut rng = Rng(seed);
    (0..count).filter_map(move |_| {
        let p = [rng.vec() * 3.0, rng.vec() * 3.0, rng.vec() * 3.0];
        let nf = (p[1] - p[0]).cross(p[2] - p[0]).normalize_or_zero();
        let n = [0, 1, 2].map(|_| (nf + rng.vec() * 0.6).normalize_or_zero());
        let size = (p[1] - p[0]).length().max((p[2] - p[0]).length());
        Patch::<f64>::with_field(p, n, field)
            .ok()
            .map(|patch| (patch, size))
    })
}
