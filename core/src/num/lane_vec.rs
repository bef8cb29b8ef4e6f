//! Three-vectors of lanes: the points, directions and normals that the lane formulas of the
//! surface (`crate::surface::lanes`) carry, one coordinate per lane vector.

use crate::num::real::{Float, LaneOps};
use crate::num::vec::V3;

/// A 3-vector of lanes.
#[derive(Clone, Copy)]
pub(crate) struct L3<L> {
    pub(crate) x: L,
    pub(crate) y: L,
    pub(crate) z: L,
}

impl<L: LaneOps> L3<L> {
    #[inline(always)]
    pub(crate) fn splat(v: V3<L::F>) -> Self {
        L3 {
            x: L::splat(v.x),
            y: L::splat(v.y),
            z: L::splat(v.z),
        }
    }
    #[inline(always)]
    pub(crate) fn dot(self, o: Self) -> L {
        self.x * o.x + self.y * o.y + self.z * o.z
    }
    #[inline(always)]
    pub(crate) fn sub(self, o: Self) -> Self {
        L3 {
            x: self.x - o.x,
            y: self.y - o.y,
            z: self.z - o.z,
        }
    }
    #[inline(always)]
    pub(crate) fn add(self, o: Self) -> Self {
        L3 {
            x: self.x + o.x,
            y: self.y + o.y,
            z: self.z + o.z,
        }
    }
    #[inline(always)]
    pub(crate) fn scale(self, s: L) -> Self {
        L3 {
            x: self.x * s,
            y: self.y * s,
            z: self.z * s,
        }
    }
    #[inline(always)]
    pub(crate) fn select(m: L::Mask, a: Self, b: Self) -> Self {
        L3 {
            x: L::select(m, a.x, b.x),
            y: L::select(m, a.y, b.y),
            z: L::select(m, a.z, b.z),
        }
    }
    /// `self · o` for data `o` ([`LaneOps::mul_p`]).
    #[inline(always)]
    pub(crate) fn dot_p(self, o: L3<L::Plain>) -> L {
        self.x.mul_p(o.x) + self.y.mul_p(o.y) + self.z.mul_p(o.z)
    }
    /// `self − o` for data `o`.
    #[inline(always)]
    pub(crate) fn sub_p(self, o: L3<L::Plain>) -> Self {
        L3 {
            x: self.x.sub_p(o.x),
            y: self.y.sub_p(o.y),
            z: self.z.sub_p(o.z),
        }
    }
    /// `o + v·s` for data `o` and `v` (the value bit for bit `o + v.scale(s)`'s).
    #[inline(always)]
    pub(crate) fn along(o: L3<L::Plain>, v: L3<L::Plain>, s: L) -> Self {
        L3 {
            x: s.mul_p(v.x).add_p(o.x),
            y: s.mul_p(v.y).add_p(o.y),
            z: s.mul_p(v.z).add_p(o.z),
        }
    }
}

#[inline(always)]
pub(crate) fn splat_f64<L: LaneOps>(x: f64) -> L {
    L::splat(L::F::from_f64(x))
}
