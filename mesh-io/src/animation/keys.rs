//! Keyframes and their interpolation: the `STEP`, `LINEAR` (spherical for rotations) and
//! `CUBICSPLINE` modes of the glTF 2.0 specification's Appendix C, on times in seconds.
//!
//! A sampler is evaluated at any finite time without allocating: before its first key it holds
//! the first value and after its last key the last one (the specification's clamping); at a key
//! time it returns that key's value as stored.

/// How a sampler interpolates between its keys.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Interpolation {
    /// The value of the key at or before the time.
    Step,
    /// Linear between the two keys around the time; for rotations the spherical linear
    /// interpolation of unit quaternions along the short arc.
    Linear,
    /// The cubic Hermite spline through the keys with their stored in- and out-tangents
    /// (scaled by the segment's duration); rotations are renormalised.
    CubicSpline,
}

/// The keys of one animation sampler, checked when read: at least one time (two for the cubic
/// spline), every time and value finite, the times strictly increasing, rotations unit
/// quaternions.
#[derive(Clone, Debug)]
pub(crate) struct Keys {
    /// Key times in seconds, strictly increasing.
    pub times: Vec<f64>,
    /// `width` numbers per key (`STEP`, `LINEAR`), or `3 · width` per key for `CUBICSPLINE`:
    /// the in-tangent, the value and the out-tangent, in that order.
    pub values: Vec<f64>,
    /// Numbers per value: 3 (translation, scale), 4 (rotation, `x y z w`), or the number of
    /// morph targets (weights).
    pub width: usize,
    /// The interpolation.
    pub interpolation: Interpolation,
    /// Whether the values are rotations (unit quaternions `x y z w`).
    pub rotation: bool,
}

/// Below this angle between two rotation keys (radians), spherical interpolation is replaced by
/// the normalised linear one: `sin(a)` loses its relative precision near zero, while the chord
/// and the arc then differ by less than `a³/24` (below 1e-13 here).
const SLERP_MIN_ANGLE: f64 = 1e-4;

impl Keys {
    /// The time of the last key (seconds): the sampler's contribution to its clip's duration.
    pub fn end(&self) -> f64 {
        self.times.last().copied().unwrap_or(0.0)
    }

    /// The stored value of key `k` (`width` numbers).
    fn value(&self, k: usize) -> &[f64] {
        let w = self.width;
        match self.interpolation {
            Interpolation::CubicSpline => &self.values[(3 * k + 1) * w..(3 * k + 2) * w],
            _ => &self.values[k * w..(k + 1) * w],
        }
    }

    /// Writes the value at `time` (seconds, finite) into `out[..width]`.
    ///
    /// # Panics
    /// When `out` is shorter than `width` (the caller sizes it to the widest sampler).
    pub fn sample(&self, time: f64, out: &mut [f64]) {
        let w = self.width;
        let out = &mut out[..w];
        let n = self.times.len();
        // The segment t_k <= time < t_{k+1}, or a clamped end.
        let after = self.times.partition_point(|&t| t <= time);
        if after == 0 {
            out.copy_from_slice(self.value(0));
            return;
        }
        if after >= n {
            out.copy_from_slice(self.value(n - 1));
            return;
        }
        let k = after - 1;
        let (t0, t1) = (self.times[k], self.times[k + 1]);
        let td = t1 - t0;
        let u = (time - t0) / td;
        let (a, b) = (self.value(k), self.value(k + 1));
        match self.interpolation {
            // At a key time, that key's value as stored.
            _ if u <= 0.0 => out.copy_from_slice(a),
            Interpolation::Step => out.copy_from_slice(a),
            Interpolation::Linear if self.rotation => slerp(a, b, u, out),
            Interpolation::Linear => {
                for ((o, &x), &y) in out.iter_mut().zip(a).zip(b) {
                    *o = (1.0 - u) * x + u * y;
                }
            }
            Interpolation::CubicSpline => {
                let out_tangent = &self.values[(3 * k + 2) * w..(3 * k + 3) * w];
                let in_tangent = &self.values[3 * (k + 1) * w..(3 * (k + 1) + 1) * w];
                let (u2, u3) = (u * u, u * u * u);
                let h00 = 2.0 * u3 - 3.0 * u2 + 1.0;
                let h10 = td * (u3 - 2.0 * u2 + u);
                let h01 = -2.0 * u3 + 3.0 * u2;
                let h11 = td * (u3 - u2);
                for (i, o) in out.iter_mut().enumerate() {
                    *o = h00 * a[i] + h10 * out_tangent[i] + h01 * b[i] + h11 * in_tangent[i];
                }
                if self.rotation {
                    normalise_or(out, a);
                }
            }
        }
    }
}

/// The specification's spherical linear interpolation of the unit quaternions `a` and `b` at
/// `u` in `(0, 1)`, along the short arc (`b` negated when `a · b < 0`), into `out`.
fn slerp(a: &[f64], b: &[f64], u: f64, out: &mut [f64]) {
    let dot: f64 = a.iter().zip(b).map(|(x, y)| x * y).sum();
    let s = if dot < 0.0 { -1.0 } else { 1.0 };
    let angle = dot.abs().min(1.0).acos();
    let (wa, wb) = if angle < SLERP_MIN_ANGLE {
        (1.0 - u, s * u)
    } else {
        let sin = angle.sin();
        ((angle * (1.0 - u)).sin() / sin, s * (angle * u).sin() / sin)
    };
    for ((o, &x), &y) in out.iter_mut().zip(a).zip(b) {
        *o = wa * x + wb * y;
    }
    normalise_or(out, a);
}

/// Scales `q` to unit length; when its length is zero or not finite, copies `fallback`.
fn normalise_or(q: &mut [f64], fallback: &[f64]) {
    let len = q.iter().map(|x| x * x).sum::<f64>().sqrt();
    if len > 0.0 && len.is_finite() {
        for x in q.iter_mut() {
            *x /= len;
        }
    } else {
        q.copy_from_slice(fallback);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn keys(times: &[f64], values: &[f64], width: usize, i: Interpolation, rot: bool) -> Keys {
        Keys {
            times: times.to_vec(),
            values: values.to_vec(),
            width,
            interpolation: i,
            rotation: rot,
        }
    }

    fn at(k: &Keys, t: f64) -> Vec<f64> {
        let mut out = vec![f64::NAN; k.width];
        k.sample(t, &mut out);
        out
    }

    #[test]
    fn step_holds_each_key_until_the_next() {
        let k = keys(
            &[1.0, 2.0, 4.0],
            &[10.0, 20.0, 40.0],
            1,
            Interpolation::Step,
            false,
        );
        assert_eq!(at(&k, -5.0), [10.0]);
        assert_eq!(at(&k, 1.0), [10.0]);
        assert_eq!(at(&k, 1.999), [10.0]);
        assert_eq!(at(&k, 2.0), [20.0]);
        assert_eq!(at(&k, 3.9), [20.0]);
        assert_eq!(at(&k, 4.0), [40.0]);
        assert_eq!(at(&k, 1e9), [40.0]);
    }

    #[test]
    fn linear_interpolates_and_clamps() {
        let k = keys(
            &[0.0, 2.0],
            &[0.0, 1.0, -2.0, 4.0, 5.0, 6.0],
            3,
            Interpolation::Linear,
            false,
        );
        assert_eq!(at(&k, 0.5), [1.0, 2.0, 0.0]);
        assert_eq!(at(&k, -1.0), [0.0, 1.0, -2.0]);
        assert_eq!(at(&k, 2.0), [4.0, 5.0, 6.0]);
        assert_eq!(at(&k, 7.0), [4.0, 5.0, 6.0]);
        // One key: constant.
        let one = keys(&[3.0], &[7.0], 1, Interpolation::Linear, false);
        assert_eq!(at(&one, 0.0), [7.0]);
        assert_eq!(at(&one, 9.0), [7.0]);
    }

    /// The quaternion of a turn by `deg` degrees about z, `x y z w`.
    fn about_z(deg: f64) -> [f64; 4] {
        let h = deg.to_radians() / 2.0;
        [0.0, 0.0, h.sin(), h.cos()]
    }

    #[test]
    fn rotations_slerp_at_constant_angular_speed_on_the_short_arc() {
        let (a, b) = (about_z(10.0), about_z(130.0));
        let k = keys(
            &[0.0, 1.0],
            &[a, b].concat(),
            4,
            Interpolation::Linear,
            true,
        );
        for (u, deg) in [(0.25, 40.0), (0.5, 70.0), (0.75, 100.0)] {
            let q = at(&k, u);
            let want = about_z(deg);
            for i in 0..4 {
                assert!((q[i] - want[i]).abs() < 1e-15, "{u}: {q:?} vs {want:?}");
            }
        }
        // The same end rotation stored as -b: the short arc is still taken (a rotation, not the
        // quaternion, is interpolated), so the halfway value is the 70° turn up to sign.
        let nb = b.map(|x| -x);
        let k = keys(
            &[0.0, 1.0],
            &[a, nb].concat(),
            4,
            Interpolation::Linear,
            true,
        );
        let q = at(&k, 0.5);
        let want = about_z(70.0);
        let dot: f64 = q.iter().zip(want).map(|(x, y)| x * y).sum();
        assert!((dot.abs() - 1.0).abs() < 1e-15, "{q:?}");
        // Keys a hair apart: the linear branch, still unit length.
        let k = keys(
            &[0.0, 1.0],
            &[about_z(5.0), about_z(5.000_001)].concat(),
            4,
            Interpolation::Linear,
            true,
        );
        let q = at(&k, 0.5);
        let len: f64 = q.iter().map(|x| x * x).sum::<f64>().sqrt();
        assert!((len - 1.0).abs() < 1e-15);
        assert!((q[2] - about_z(5.000_000_5)[2]).abs() < 1e-15);
    }

    #[test]
    fn cubic_spline_is_the_hermite_curve_of_the_stored_tangents() {
        // x(t) = t³ on [0, 2] sampled at t = 0, 2 with the derivatives 0 and 12 as tangents
        // (in-tangent, value, out-tangent per key): the Hermite cubic through those is t³
        // itself, scaled by the segment length the specification multiplies tangents with.
        let k = keys(
            &[0.0, 2.0],
            &[0.0, 0.0, 0.0, 12.0, 8.0, 0.0],
            1,
            Interpolation::CubicSpline,
            false,
        );
        for t in [0.0, 0.3, 1.0, 1.7, 2.0] {
            let x = at(&k, t)[0];
            assert!((x - t * t * t).abs() < 1e-13, "{t}: {x}");
        }
        assert_eq!(at(&k, 5.0), [8.0]);
        // Two numbers per value (two morph targets): each follows its own curve.
        let k = keys(
            &[1.0, 3.0],
            &[
                0.0, 0.0, 1.0, 5.0, 0.0, 0.0, // key 0: a (2), v (2), b (2)
                0.0, 0.0, 1.0, 5.0, 0.0, 0.0, // key 1
            ],
            2,
            Interpolation::CubicSpline,
            false,
        );
        assert_eq!(at(&k, 2.0), [1.0, 5.0]);
    }

    #[test]
    fn cubic_spline_rotations_are_renormalised() {
        // Zero tangents between two turns about z: the curve bends inside the unit sphere and is
        // pushed back onto it.
        let (a, b) = (about_z(0.0), about_z(90.0));
        let z = [0.0; 4];
        let k = keys(
            &[0.0, 1.0],
            &[z, a, z, z, b, z].concat(),
            4,
            Interpolation::CubicSpline,
            true,
        );
        let q = at(&k, 0.5);
        let len: f64 = q.iter().map(|x| x * x).sum::<f64>().sqrt();
        assert!((len - 1.0).abs() < 1e-15, "{q:?}");
        // Halfway along a symmetric curve: the 45° turn.
        let want = about_z(45.0);
        for i in 0..4 {
            assert!((q[i] - want[i]).abs() < 1e-15, "{q:?}");
        }
    }
}
