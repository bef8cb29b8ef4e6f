//! Jets: values with their partial derivatives in forward mode, over lanes (the exact normal's
//! derivatives of the lane formulas, `crate::surface::lanes`).

use crate::num::lane_vec::L3;
use crate::num::real::{Float, LaneOps};

/// A value with its partial derivatives (forward mode), over a [`LaneOps`] type `L` (one
/// point: [`One`](crate::num::lanes::One); eight-lane jets compile to functions too large to keep builds fast), and
/// [`Partials`] `D`: two by default. The height evaluation over it gives `σS` and
/// `∂σS/∂X1`, `∂σS/∂X2` for the exact normal, in one pass (no nested dual numbers: the edge
/// tangents inside are already derivatives written out); with one partial (`[L; 1]`), an
/// edge curve and its derivative by the edge parameter ([`Tangent`]).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Jet<L, D = [L; 2]> {
    /// Value.
    pub v: L,
    /// Partial derivatives.
    pub d: D,
}

/// The partial derivatives of a [`Jet`]: two (`[L; 2]`) or one (`[L; 1]`), each rule written
/// out per count (a loop over a const count compiled slowly: docs/MEASUREMENTS.md, "Notes
/// moved from the code").
pub(crate) trait Partials<L: LaneOps>: Copy {
    /// All zero.
    fn zero() -> Self;
    /// `a + b` per partial.
    fn add(self, o: Self) -> Self;
    /// `a − b` per partial.
    fn sub(self, o: Self) -> Self;
    /// `−a` per partial.
    fn neg(self) -> Self;
    /// `a·k` per partial.
    fn scale(self, k: L) -> Self;
    /// The product rule `a·ov + sv·b` per partial.
    fn product(self, ov: L, sv: L, o: Self) -> Self;
    /// The quotient rule `(a − v·b) / ov` per partial.
    fn quotient(self, v: L, o: Self, ov: L) -> Self;
    /// The reciprocal rule `−(v·a) / ov` per partial.
    fn reciprocal(self, v: L, ov: L) -> Self;
    /// `a` where `m`, else `b`, per partial.
    fn pick(m: L::Mask, a: Self, b: Self) -> Self;
    /// Whether every partial is finite, per lane.
    fn finite(self) -> L::Mask;
}

impl<L: LaneOps> Partials<L> for [L; 2] {
    #[inline(always)]
    fn zero() -> Self {
        let z = L::splat(L::F::ZERO);
        [z, z]
    }
    #[inline(always)]
    fn add(self, [b0, b1]: Self) -> Self {
        let [a0, a1] = self;
        [a0 + b0, a1 + b1]
    }
    #[inline(always)]
    fn sub(self, [b0, b1]: Self) -> Self {
        let [a0, a1] = self;
        [a0 - b0, a1 - b1]
    }
    #[inline(always)]
    fn neg(self) -> Self {
        let [a0, a1] = self;
        [-a0, -a1]
    }
    #[inline(always)]
    fn scale(self, k: L) -> Self {
        let [a0, a1] = self;
        [a0 * k, a1 * k]
    }
    #[inline(always)]
    fn product(self, ov: L, sv: L, [b0, b1]: Self) -> Self {
        let [a0, a1] = self;
        [a0 * ov + sv * b0, a1 * ov + sv * b1]
    }
    #[inline(always)]
    fn quotient(self, v: L, [b0, b1]: Self, ov: L) -> Self {
        let [a0, a1] = self;
        [(a0 - v * b0) / ov, (a1 - v * b1) / ov]
    }
    #[inline(always)]
    fn reciprocal(self, v: L, ov: L) -> Self {
        let [a0, a1] = self;
        [-(v * a0) / ov, -(v * a1) / ov]
    }
    #[inline(always)]
    fn pick(m: L::Mask, [a0, a1]: Self, [b0, b1]: Self) -> Self {
        [L::select(m, a0, b0), L::select(m, a1, b1)]
    }
    #[inline(always)]
    fn finite(self) -> L::Mask {
        let [a0, a1] = self;
        L::and(a0.finite(), a1.finite())
    }
}

impl<L: LaneOps> Partials<L> for [L; 1] {
    #[inline(always)]
    fn zero() -> Self {
        [L::splat(L::F::ZERO)]
    }
    #[inline(always)]
    fn add(self, [b]: Self) -> Self {
        let [a] = self;
        [a + b]
    }
    #[inline(always)]
    fn sub(self, [b]: Self) -> Self {
        let [a] = self;
        [a - b]
    }
    #[inline(always)]
    fn neg(self) -> Self {
        let [a] = self;
        [-a]
    }
    #[inline(always)]
    fn scale(self, k: L) -> Self {
        let [a] = self;
        [a * k]
    }
    #[inline(always)]
    fn product(self, ov: L, sv: L, [b]: Self) -> Self {
        let [a] = self;
        [a * ov + sv * b]
    }
    #[inline(always)]
    fn quotient(self, v: L, [b]: Self, ov: L) -> Self {
        let [a] = self;
        [(a - v * b) / ov]
    }
    #[inline(always)]
    fn reciprocal(self, v: L, ov: L) -> Self {
        let [a] = self;
        [-(v * a) / ov]
    }
    #[inline(always)]
    fn pick(m: L::Mask, [a]: Self, [b]: Self) -> Self {
        [L::select(m, a, b)]
    }
    #[inline(always)]
    fn finite(self) -> L::Mask {
        let [a] = self;
        a.finite()
    }
}

/// The sum and difference of jets: value and partials term by term.
macro_rules! jet_linear_ops {
    ($($tr:ident $m:ident $op:tt),*) => {
        $(
            impl<L: LaneOps, D: Partials<L>> core::ops::$tr for Jet<L, D> {
                type Output = Self;
                #[inline(always)]
                fn $m(self, o: Self) -> Self {
                    Jet {
                        v: self.v $op o.v,
                        d: self.d.$m(o.d),
                    }
                }
            }
        )*
    };
}
jet_linear_ops!(Add add +, Sub sub -);

impl<L: LaneOps, D: Partials<L>> core::ops::Mul for Jet<L, D> {
    type Output = Self;
    #[inline(always)]
    fn mul(self, o: Self) -> Self {
        Jet {
            v: self.v * o.v,
            d: self.d.product(o.v, self.v, o.d),
        }
    }
}

impl<L: LaneOps, D: Partials<L>> core::ops::Div for Jet<L, D> {
    type Output = Self;
    #[inline(always)]
    fn div(self, o: Self) -> Self {
        let v = self.v / o.v;
        Jet {
            v,
            d: self.d.quotient(v, o.d, o.v),
        }
    }
}

impl<L: LaneOps, D: Partials<L>> core::ops::Neg for Jet<L, D> {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        Jet {
            v: -self.v,
            d: self.d.neg(),
        }
    }
}

impl<L: LaneOps, D: Partials<L>> Jet<L, D> {
    /// `v` with zero derivatives.
    #[inline(always)]
    fn constant(v: L) -> Self {
        Jet { v, d: D::zero() }
    }

    /// Each part `a` where `m`, else `b`'s.
    #[inline(always)]
    fn pick(m: L::Mask, a: Self, b: Self) -> Self {
        Jet {
            v: L::select(m, a.v, b.v),
            d: D::pick(m, a.d, b.d),
        }
    }
}

impl<L: LaneOps<Plain = L>, D: Partials<L>> LaneOps for Jet<L, D> {
    type F = L::F;
    type Mask = L::Mask;
    type Plain = L;
    #[inline(always)]
    fn lift(p: L) -> Self {
        Jet::constant(p)
    }
    #[inline(always)]
    fn mul_p(self, p: L) -> Self {
        Jet {
            v: self.v * p,
            d: self.d.scale(p),
        }
    }
    #[inline(always)]
    fn add_p(self, p: L) -> Self {
        Jet {
            v: self.v + p,
            d: self.d,
        }
    }
    #[inline(always)]
    fn sub_p(self, p: L) -> Self {
        Jet {
            v: self.v - p,
            d: self.d,
        }
    }
    #[inline(always)]
    fn rsub_p(self, p: L) -> Self {
        Jet {
            v: p - self.v,
            d: self.d.neg(),
        }
    }
    #[inline(always)]
    fn rdiv_p(self, p: L) -> Self {
        let v = p / self.v;
        Jet {
            v,
            d: self.d.reciprocal(v, self.v),
        }
    }
    #[inline(always)]
    fn splat(x: L::F) -> Self {
        Jet::constant(L::splat(x))
    }
    /// The square root; its derivative is 0 where the value is not positive (as the dual
    /// numbers' `sqrt0`: the kernel only takes roots of clamped discriminants).
    #[inline(always)]
    fn sqrt(self) -> Self {
        let z = L::splat(L::F::ZERO);
        let pos = self.v.gt(z);
        let r = L::select(pos, self.v, L::splat(L::F::ONE)).sqrt();
        let k = L::splat(L::F::ONE) / (r + r);
        let root = Jet {
            v: r,
            d: self.d.scale(k),
        };
        Self::pick(pos, root, Jet::constant(z))
    }
    #[inline(always)]
    fn abs(self) -> Self {
        Self::pick(self.v.lt(L::splat(L::F::ZERO)), -self, self)
    }
    #[inline(always)]
    fn lt(self, o: Self) -> L::Mask {
        self.v.lt(o.v)
    }
    #[inline(always)]
    fn le(self, o: Self) -> L::Mask {
        self.v.le(o.v)
    }
    #[inline(always)]
    fn gt(self, o: Self) -> L::Mask {
        self.v.gt(o.v)
    }
    #[inline(always)]
    fn eq(self, o: Self) -> L::Mask {
        self.v.eq(o.v)
    }
    #[inline(always)]
    fn finite(self) -> L::Mask {
        L::and(self.v.finite(), self.d.finite())
    }
    #[inline(always)]
    fn select(m: L::Mask, a: Self, b: Self) -> Self {
        Self::pick(m, a, b)
    }
    #[inline(always)]
    fn and(a: L::Mask, b: L::Mask) -> L::Mask {
        L::and(a, b)
    }
    #[inline(always)]
    fn or(a: L::Mask, b: L::Mask) -> L::Mask {
        L::or(a, b)
    }
    #[inline(always)]
    fn not(a: L::Mask) -> L::Mask {
        L::not(a)
    }
    #[inline(always)]
    fn any_set(m: L::Mask) -> bool {
        L::any_set(m)
    }
}

/// A jet with one partial: by an edge parameter.
pub(crate) type Tangent<L> = Jet<L, [L; 1]>;

/// The jets of a point or normal `q` given with its derivative by the edge parameter, at
/// points whose edge-parameter jets are `t`: `∂q/∂Xk = (dq/dt)·(∂t/∂Xk)`.
#[inline(always)]
pub(crate) fn chained<L: LaneOps>(q: L3<Tangent<L>>, t: Jet<L>) -> L3<Jet<L>> {
    let [t1, t2] = t.d;
    let one = |q: Tangent<L>| {
        let [dt] = q.d;
        Jet {
            v: q.v,
            d: [dt * t1, dt * t2],
        }
    };
    L3 {
        x: one(q.x),
        y: one(q.y),
        z: one(q.z),
    }
}

/// The seeds of the jets of barycentrics `x` (`X0 = 1 − X1 − X2`): value and the partials by
/// `X1` and `X2`.
#[inline(always)]
pub(crate) fn seeds<L: LaneOps>([x0, x1, x2]: [L; 3]) -> [Jet<L>; 3] {
    let (one, zero) = (L::splat(L::F::ONE), L::splat(L::F::ZERO));
    let mone = zero - one;
    [
        Jet {
            v: x0,
            d: [mone, mone],
        },
        Jet {
            v: x1,
            d: [one, zero],
        },
        Jet {
            v: x2,
            d: [zero, one],
        },
    ]
}
