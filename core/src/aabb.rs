//! Axis-aligned bounding boxes: the one box type of the crate, shared by patches (the box of
//! their shell), BVH nodes, and the kernel's first clip.

use crate::num::real::Float;
use crate::num::vec::V3;

/// An axis-aligned box `[min, max]` in world coordinates.
///
/// The empty box ([`Aabb::EMPTY`]) has `min > max` on every axis; it is the identity of
/// [`Aabb::union`] and no ray enters it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb<F: Float = f32> {
    pub(crate) lo: V3<F>,
    pub(crate) hi: V3<F>,
}

impl<F: Float> Default for Aabb<F> {
    /// The empty box.
    fn default() -> Self {
        Self::EMPTY
    }
}

impl<F: Float> Aabb<F> {
    /// The empty box: `min = +MAX`, `max = −MAX` on every axis.
    pub const EMPTY: Self = Aabb {
        lo: V3::new(F::MAX, F::MAX, F::MAX),
        hi: V3::new(F::MIN, F::MIN, F::MIN),
    };

    /// The box with corners `min` and `max` (not reordered: a box with `min > max` on some axis
    /// is empty).
    ///
    /// # Panics
    /// Never.
    pub fn new(min: F::Vec3, max: F::Vec3) -> Self {
        Aabb {
            lo: F::from_glam(min),
            hi: F::from_glam(max),
        }
    }

    #[inline(always)]
    pub(crate) fn from_corners(lo: V3<F>, hi: V3<F>) -> Self {
        Aabb { lo, hi }
    }

    /// The minimum corner.
    ///
    /// # Panics
    /// Never.
    pub fn min(&self) -> F::Vec3 {
        F::to_glam(self.lo)
    }

    /// The maximum corner.
    ///
    /// # Panics
    /// Never.
    pub fn max(&self) -> F::Vec3 {
        F::to_glam(self.hi)
    }

    /// The smallest box containing both.
    ///
    /// # Accuracy
    /// Exact (component-wise minimum and maximum).
    /// # Panics
    /// Never.
    #[inline(always)]
    pub fn union(&self, o: &Self) -> Self {
        Aabb {
            lo: vmin(self.lo, o.lo),
            hi: vmax(self.hi, o.hi),
        }
    }

    /// The smallest box containing `self` and the point `p`.
    #[inline(always)]
    pub(crate) fn grow(&self, p: V3<F>) -> Self {
        Aabb {
            lo: vmin(self.lo, p),
            hi: vmax(self.hi, p),
        }
    }

    /// The box's center `(min + max) / 2`.
    #[inline(always)]
    pub(crate) fn center(&self) -> V3<F> {
        (self.lo + self.hi) * F::from_f64(0.5)
    }

    /// Whether the box holds no point: `min > max` on some axis, or a corner is NaN.
    #[inline(always)]
    pub(crate) fn is_empty(&self) -> bool {
        !(self.lo.x <= self.hi.x && self.lo.y <= self.hi.y && self.lo.z <= self.hi.z)
    }

    /// Half the surface area, `xy + yz + zx` of the extents (0 for the empty box): the SAH's
    /// measure of how likely a random ray is to enter the box.
    #[inline(always)]
    pub(crate) fn half_area(&self) -> F {
        let e = self.hi - self.lo;
        if !(e.x >= F::ZERO && e.y >= F::ZERO && e.z >= F::ZERO) {
            return F::ZERO;
        }
        e.x * e.y + e.y * e.z + e.z * e.x
    }

    /// The interval of `t` in `[t_min, t_max]` for which `o + t·d` is inside the box (slab
    /// test), or `None` when the ray misses it or the interval is not finite.
    ///
    /// A zero direction component keeps the whole range when the origin lies between the
    /// slabs of that axis, and rejects it otherwise. `inv` holds `1 / d` per axis where `d` is
    /// not zero (computed once per ray by the caller); `inv_finite` tells that each of those
    /// is finite (not so for a subnormal `d`).
    ///
    /// The slab products `(plane − o) · (1/d)` cannot be NaN when `inv` is finite and the box
    /// has no NaN corner (a patch's box is finite, the empty box's corners are `±MAX`), so
    /// comparisons order them (`minss`/`maxss` on x86) with the values of `min`/`max`; with an
    /// infinite `1/d` a product can be NaN (`0 · ∞`), and `min`/`max` skip it.
    #[inline(always)]
    pub(crate) fn ray_interval(
        &self,
        o: V3<F>,
        d: V3<F>,
        (inv, inv_finite): (V3<F>, bool),
        t_min: F,
        t_max: F,
    ) -> Option<(F, F)> {
        let mut a = t_min;
        let mut b = t_max;
        let axes = [
            (o.x, d.x, inv.x, self.lo.x, self.hi.x),
            (o.y, d.y, inv.y, self.lo.y, self.hi.y),
            (o.z, d.z, inv.z, self.lo.z, self.hi.z),
        ];
        for (oc, dc, ic, l, h) in axes {
            if dc == F::ZERO {
                if oc < l || oc > h {
                    return None;
                }
            } else {
                let t1 = (l - oc) * ic;
                let t2 = (h - oc) * ic;
                if inv_finite {
                    let (near, far) = if t2 < t1 { (t2, t1) } else { (t1, t2) };
                    a = if near > a { near } else { a };
                    b = if far < b { far } else { b };
                } else {
                    a = a.max(t1.min(t2));
                    b = b.min(t1.max(t2));
                }
            }
        }
        if a <= b && a.is_fin() && b.is_fin() {
            Some((a, b))
        } else {
            None
        }
    }

    /// `true` when both corners are finite.
    #[inline(always)]
    pub(crate) fn is_finite(&self) -> bool {
        self.lo.all_finite() && self.hi.all_finite()
    }
}

/// `1 / d` per axis, 0 where `d` is 0: the reciprocals of a ray direction for the slab tests
/// of [`Aabb::ray_interval`] and the BVH's node test, which must agree on them (a node's test
/// is conservative with respect to the kernel's box test because both form the same products
/// `(plane − o) · (1/d)`).
#[inline(always)]
pub(crate) fn reciprocal<F: Float>(d: V3<F>) -> V3<F> {
    let inv = |c: F| if c == F::ZERO { F::ZERO } else { F::ONE / c };
    V3::new(inv(d.x), inv(d.y), inv(d.z))
}

#[inline(always)]
fn vmin<F: Float>(a: V3<F>, b: V3<F>) -> V3<F> {
    V3::new(a.x.min(b.x), a.y.min(b.y), a.z.min(b.z))
}

#[inline(always)]
fn vmax<F: Float>(a: V3<F>, b: V3<F>) -> V3<F> {
    V3::new(a.x.max(b.x), a.y.max(b.y), a.z.max(b.z))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The comparison path of [`Aabb::ray_interval`] (finite `1/d`) gives the values of the
    /// `min`/`max` path, on random boxes and rays, with origins on the box's planes (ties,
    /// zero products), axis-parallel directions and the empty box. (It fails when the
    /// comparison path takes the wrong end of an axis.)
    #[test]
    fn comparisons_equal_min_max() {
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let mut next = move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        };
        let mut compared = 0;
        for case in 0..20_000 {
            let lo = V3::new(next() as f32, next() as f32, next() as f32);
            let hi = lo
                + V3::new(
                    next().abs() as f32,
                    next().abs() as f32,
                    next().abs() as f32,
                );
            let bx = if case % 97 == 0 {
                Aabb::EMPTY
            } else {
                Aabb { lo, hi }
            };
            let mut o = V3::new(next() as f32, next() as f32, next() as f32) * 3.0;
            let mut d = V3::new(next() as f32, next() as f32, next() as f32);
            match case % 5 {
                1 => o.x = lo.x,
                2 => o.y = hi.y,
                3 => d.z = 0.0,
                _ => {}
            }
            if d.length2() == 0.0 {
                continue;
            }
            let inv = reciprocal(d);
            assert!(inv.all_finite());
            let (t_min, t_max) = if case % 3 == 0 {
                (0.0, f32::MAX)
            } else {
                (-1.0, 2.0)
            };
            let fast = bx.ray_interval(o, d, (inv, true), t_min, t_max);
            let exact = bx.ray_interval(o, d, (inv, false), t_min, t_max);
            assert_eq!(fast, exact, "case {case}");
            compared += usize::from(exact.is_some());
        }
        assert!(compared > 200, "{compared} rays entered their box");
    }
}
