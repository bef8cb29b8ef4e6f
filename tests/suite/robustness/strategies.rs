//! Generators of hostile input for `tests/suite/robustness.rs` (and the scenes of
//! `tests/suite/regressions.rs`): patches of every shape, scale and offset with normals up to and
//! beyond 90°, fully wild coordinates, special values, and rays relative to a patch's box.
//!
//! Everything is generated in `f64`; the checks round to the precision under test.
#![allow(dead_code)]

use glam::DVec3;
use proptest::prelude::*;

/// Special values: NaN, infinities, signed zeros, the extremes of both precisions, subnormals.
pub fn special() -> impl Strategy<Value = f64> {
    prop_oneof![
        Just(f64::NAN),
        Just(f64::INFINITY),
        Just(f64::NEG_INFINITY),
        Just(0.0),
        Just(-0.0),
        Just(f64::MAX),
        Just(f64::MIN),
        Just(f64::MIN_POSITIVE),
        Just(5e-324),
        Just(f32::MAX as f64),
        Just(-(f32::MAX as f64)),
        Just(f32::MIN_POSITIVE as f64),
        Just(1e-45),
        Just(1e-20),
        Just(1e20),
        Just(-1e20),
    ]
}

/// `±10^e` with `e` in `[-20, 20]`.
pub fn magnitude() -> impl Strategy<Value = f64> {
    (any::<bool>(), -20.0..20.0f64)
        .prop_map(|(neg, e)| if neg { -1.0 } else { 1.0 } * 10f64.powf(e))
}

/// Any coordinate: ordinary, extreme magnitude, or special.
pub fn wild() -> impl Strategy<Value = f64> {
    prop_oneof![4 => -10.0..10.0f64, 3 => magnitude(), 1 => special()]
}

pub fn wild_vec() -> impl Strategy<Value = DVec3> {
    [wild(), wild(), wild()].prop_map(DVec3::from_array)
}

/// A unit vector from two angles.
pub fn unit_from(theta: f64, phi: f64) -> DVec3 {
    DVec3::new(
        theta.sin() * phi.cos(),
        theta.sin() * phi.sin(),
        theta.cos(),
    )
}

/// Parameters of a structured patch input: a triangle of a given shape, scale and offset, and
/// normals at given angles from its face normal.
#[derive(Clone, Debug)]
pub struct Structured {
    /// Apex of the 2D triangle `(0,0) (1,0) apex` (negative y: clockwise).
    pub apex: (f64, f64),
    /// Face normal angles.
    pub face: (f64, f64),
    /// Rotation of the triangle in its plane.
    pub spin: f64,
    /// log10 of the triangle's size.
    pub scale: f64,
    /// Offset direction and log10 of its length (`None`: at the origin).
    pub offset: Option<(DVec3, f64)>,
    /// Per vertex: angle from the face normal (degrees), azimuth, log10 of the length; `None`
    /// for a zero vector.
    pub normals: [Option<(f64, f64, f64)>; 3],
    /// One of the 18 input coordinates replaced by a special value.
    pub inject: Option<(usize, f64)>,
}

/// Apex heights: well-shaped, skinny (1:5…1:20), very skinny, near-collinear, collinear,
/// clockwise.
pub fn apex() -> impl Strategy<Value = (f64, f64)> {
    let x = -1.5..2.5f64;
    prop_oneof![
        12 => (x.clone(), 0.3..1.2f64),
        6 => (x.clone(), (0.7..1.3f64).prop_map(|e| 10f64.powf(-e))),
        2 => (x.clone(), (1.3..8.0f64).prop_map(|e| 10f64.powf(-e))),
        1 => (x.clone(), (8.0..20.0f64).prop_map(|e| 10f64.powf(-e))),
        1 => (x.clone(), Just(0.0)),
        1 => (x, -1.2..-0.001f64),
    ]
}

/// Angle of a normal from the face normal, degrees: ordinary, steep, near 90°, back-facing.
pub fn normal_angle() -> impl Strategy<Value = f64> {
    prop_oneof![
        12 => 0.0..45.0f64,
        4 => 45.0..80.0f64,
        2 => 80.0..89.9f64,
        1 => 89.9..90.1f64,
        1 => 90.0..180.0f64,
        1 => Just(0.0),
    ]
}

pub fn normal_param() -> impl Strategy<Value = Option<(f64, f64, f64)>> {
    let log_len = prop_oneof![4 => -1.0..1.0f64, 1 => -20.0..20.0f64];
    prop_oneof![
        40 => (normal_angle(), 0.0..std::f64::consts::TAU, log_len).prop_map(Some),
        1 => Just(None),
    ]
}

pub fn structured() -> impl Strategy<Value = Structured> {
    let scale = prop_oneof![4 => -2.0..2.0f64, 2 => -20.0..20.0f64];
    let offset = prop_oneof![
        2 => Just(None),
        3 => ([-1.0..1.0f64, -1.0..1.0f64, -1.0..1.0f64], -2.0..2.0f64)
            .prop_map(|(d, e)| Some((DVec3::from_array(d), e))),
        2 => ([-1.0..1.0f64, -1.0..1.0f64, -1.0..1.0f64], -20.0..20.0f64)
            .prop_map(|(d, e)| Some((DVec3::from_array(d), e))),
    ];
    let inject = prop_oneof![9 => Just(None), 1 => (0..18usize, special()).prop_map(Some)];
    (
        apex(),
        (0.0..std::f64::consts::PI, 0.0..std::f64::consts::TAU),
        0.0..std::f64::consts::TAU,
        scale,
        offset,
        [normal_param(), normal_param(), normal_param()],
        inject,
    )
        .prop_map(
            |(apex, face, spin, scale, offset, normals, inject)| Structured {
                apex,
                face,
                spin,
                scale,
                offset,
                normals,
                inject,
            },
        )
}

impl Structured {
    pub fn build(&self) -> ([DVec3; 3], [DVec3; 3]) {
        let nf = unit_from(self.face.0, self.face.1);
        let u0 = nf.any_orthonormal_vector();
        let v0 = nf.cross(u0);
        let (c, s) = (self.spin.cos(), self.spin.sin());
        let (u, v) = (u0 * c + v0 * s, v0 * c - u0 * s);
        let size = 10f64.powf(self.scale);
        let off = self.offset.map_or(DVec3::ZERO, |(d, e)| d * 10f64.powf(e));
        let q = |x: f64, y: f64| off + (u * x + v * y) * size;
        let p = [q(0.0, 0.0), q(1.0, 0.0), q(self.apex.0, self.apex.1)];
        let mut n = [DVec3::ZERO; 3];
        for (nk, par) in n.iter_mut().zip(self.normals) {
            if let Some((deg, az, len)) = par {
                let th = deg.to_radians();
                *nk = (nf * th.cos() + (u * az.cos() + v * az.sin()) * th.sin()) * 10f64.powf(len);
            }
        }
        let mut flat = [p[0], p[1], p[2], n[0], n[1], n[2]].map(|v| v.to_array());
        if let Some((k, x)) = self.inject
            && let Some(c) = flat.get_mut(k / 3).and_then(|a| a.get_mut(k % 3))
        {
            *c = x;
        }
        let v = flat.map(DVec3::from_array);
        ([v[0], v[1], v[2]], [v[3], v[4], v[5]])
    }
}

/// A patch input: mostly structured (many accepted), sometimes fully wild coordinates.
#[derive(Clone, Debug)]
pub enum Input {
    Structured(Structured),
    Wild([DVec3; 3], [DVec3; 3]),
}

impl Input {
    pub fn build(&self) -> ([DVec3; 3], [DVec3; 3]) {
        match self {
            Input::Structured(s) => s.build(),
            Input::Wild(p, n) => (*p, *n),
        }
    }
}

pub fn input() -> impl Strategy<Value = Input> {
    prop_oneof![
        5 => structured().prop_map(Input::Structured),
        1 => ([wild_vec(), wild_vec(), wild_vec()], [wild_vec(), wild_vec(), wild_vec()])
            .prop_map(|(p, n)| Input::Wild(p, n)),
    ]
}

/// A ray relative to the patch's box: origin on a sphere of radius `10^dist × diagonal` around
/// the box centre, aimed at a surface point lifted by `lift × diagonal` along the face normal;
/// direction length `10^len`; a ray-range kind; optionally a special value injected.
#[derive(Clone, Debug)]
pub struct RayParam {
    /// Direction of the origin from the box centre (polar and azimuthal angles).
    pub from: (f64, f64),
    /// log10 of the origin's distance from the box centre, in box diagonals.
    pub dist: f64,
    /// Barycentrics of the aimed surface point.
    pub aim: (f64, f64),
    /// Lift of the aimed point along the face normal, in box diagonals.
    pub lift: f64,
    /// log10 of the direction's length relative to the origin–target distance.
    pub len: f64,
    /// Ray-range kind ([`ray_range`]).
    pub range: u8,
    /// One of the 6 ray coordinates replaced by a special value.
    pub inject: Option<(usize, f64)>,
}

pub fn ray_param() -> impl Strategy<Value = RayParam> {
    (
        (0.0..std::f64::consts::PI, 0.0..std::f64::consts::TAU),
        prop_oneof![3 => -1.0..1.5f64, 1 => -4.0..4.0f64],
        (-0.2..1.2f64, -0.2..1.2f64),
        prop_oneof![3 => Just(0.0), 3 => -0.05..0.05f64, 1 => -3.0..3.0f64],
        prop_oneof![3 => -1.0..1.0f64, 1 => -20.0..20.0f64],
        0..16u8,
        prop_oneof![8 => Just(None), 1 => (0..6usize, special()).prop_map(Some)],
    )
        .prop_map(|(from, dist, aim, lift, len, range, inject)| RayParam {
            from,
            dist,
            aim,
            lift,
            len,
            range,
            inject,
        })
}

/// Ray ranges: ordinary, infinite both ways, empty, reversed, NaN, huge, a thin slice.
pub fn ray_range(kind: u8, scale: f64) -> (f64, f64) {
    match kind {
        0 => (f64::MIN_POSITIVE, f64::MAX),
        3 => (f64::NEG_INFINITY, f64::INFINITY),
        4 => (0.5, 0.5),
        5 => (1.0, 0.0),
        6 => (f64::NAN, 1.0),
        7 => (0.0, f64::NAN),
        8 => (-1e30, 1e30),
        9 => (0.999 * scale, 1.001 * scale),
        _ => (0.0, f64::INFINITY),
    }
}

impl RayParam {
    /// World ray (f64) and range for a patch with box `(lo, hi)`, face normal `nf` and the
    /// aimed surface point `target`.
    pub fn build(
        &self,
        lo: DVec3,
        hi: DVec3,
        nf: DVec3,
        target: DVec3,
    ) -> (DVec3, DVec3, f64, f64) {
        let centre = (lo + hi) * 0.5;
        let diag = (hi - lo).length();
        let o = centre + unit_from(self.from.0, self.from.1) * diag * 10f64.powf(self.dist);
        let aim = target + nf * diag * self.lift;
        let d = (aim - o) * 10f64.powf(self.len);
        let (t0, t1) = ray_range(self.range, 10f64.powf(-self.len));
        let mut flat = [o.x, o.y, o.z, d.x, d.y, d.z];
        if let Some((k, x)) = self.inject
            && let Some(c) = flat.get_mut(k)
        {
            *c = x;
        }
        (
            DVec3::new(flat[0], flat[1], flat[2]),
            DVec3::new(flat[3], flat[4], flat[5]),
            t0,
            t1,
        )
    }
}

/// An `f64` vector rounded to precision `F`.
pub fn to_f<F: smoothtri::Float>(v: DVec3) -> F::Vec3 {
    F::from_dvec3(v)
}

/// The accepted patches of `inputs`, patch `i` shifted by `(i, 7i mod 5, 3i mod 4)·10^spread`
/// (a scene scale).
pub fn scene<F: smoothtri::Float>(inputs: &[Structured], spread: f64) -> Vec<smoothtri::Patch<F>> {
    inputs
        .iter()
        .enumerate()
        .filter_map(|(i, s)| {
            let (p, n) = s.build();
            let shift =
                DVec3::new(i as f64, (i * 7 % 5) as f64, (i * 3 % 4) as f64) * 10f64.powf(spread);
            smoothtri::Patch::<F>::new(p.map(|x| to_f::<F>(x + shift)), n.map(to_f::<F>)).ok()
        })
        .collect()
}
