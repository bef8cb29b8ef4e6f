//! The accessors of animation data as `f64` numbers: each [`Layout`] the specification allows
//! (key times, translations, rotations, morph weights, inverse bind matrices, joints and
//! weights), checked ([`crate::gltf::check_accessor`]) and charged to the budget before the
//! `gltf` crate reads it, normalised integers decoded, every number finite.

use ::gltf::accessor::DataType::{F32, I8, I16, U8, U16};
use ::gltf::accessor::Dimensions::{Mat4, Scalar, Vec3, Vec4};
use ::gltf::accessor::{DataType, Dimensions, Item, Iter};
use glam::DVec3;

use super::Msg;
use crate::gltf::{Want, check_accessor};
use crate::options::Budget;

/// What an accessor of animation data must hold: its dimensions and component types (named in
/// messages by `expected`), and whether its integers are normalised.
#[derive(Clone, Copy, Debug)]
pub(super) struct Layout {
    dims: Dimensions,
    types: &'static [DataType],
    expected: &'static str,
    normalized: bool,
}

impl Layout {
    /// `dims` of one of `types` (named by `expected`), integers normalised when `normalized`.
    const fn new(
        dims: Dimensions,
        types: &'static [DataType],
        expected: &'static str,
        normalized: bool,
    ) -> Self {
        Layout {
            dims,
            types,
            expected,
            normalized,
        }
    }
}

/// Floats only.
const FLOAT: &[DataType] = &[F32];

/// The floats or normalised integers a rotation or morph weight output may hold.
const NORMALIZED: &[DataType] = &[F32, I8, U8, I16, U16];

/// A sampler's key times.
pub(super) const TIMES: Layout = Layout::new(Scalar, FLOAT, "Scalar of F32", false);

/// Translations and scales (a sampler's output), morph target deltas.
pub(super) const VEC3: Layout = Layout::new(Vec3, FLOAT, "Vec3 of F32", false);

/// Rotations (a sampler's output), unit quaternions `x y z w`.
pub(super) const ROTATIONS: Layout = Layout::new(
    Vec4,
    NORMALIZED,
    "Vec4 of F32 or normalized I8, U8, I16 or U16",
    true,
);

/// Morph target weights (a sampler's output), one number per target and key.
pub(super) const MORPH_WEIGHTS: Layout = Layout::new(
    Scalar,
    NORMALIZED,
    "Scalar of F32 or normalized I8, U8, I16 or U16",
    true,
);

/// A skin's inverse bind matrices, column-major.
pub(super) const MATRICES: Layout = Layout::new(Mat4, FLOAT, "Mat4 of F32", false);

/// A vertex's joints (`JOINTS_n`), indices into its skin's joints.
pub(super) const JOINTS: Layout = Layout::new(Vec4, &[U8, U16], "Vec4 of U8 or U16", false);

/// A vertex's skin weights (`WEIGHTS_n`).
pub(super) const WEIGHTS: Layout = Layout::new(
    Vec4,
    &[F32, U8, U16],
    "Vec4 of F32 or normalized U8 or U16",
    true,
);

/// The elements of a checked accessor (zeros where it has no buffer view, as the
/// specification says, sparse values applied).
fn elements<E: Item + Copy>(acc: &::gltf::Accessor<'_>, buffers: &[Vec<u8>]) -> Msg<Vec<E>> {
    let count = acc.count();
    if acc.view().is_none() && acc.sparse().is_none() {
        return Ok(vec![E::zero(); count]);
    }
    let get = |b: ::gltf::Buffer<'_>| buffers.get(b.index()).map(Vec::as_slice);
    let items: Vec<E> = Iter::<E>::new(acc.clone(), get)
        .ok_or_else(|| format!("accessor {} could not be read", acc.index()))?
        .collect();
    if items.len() != count {
        return Err(format!(
            "accessor {} yields {} elements, not its count {count}",
            acc.index(),
            items.len()
        ));
    }
    Ok(items)
}

/// [`elements`] flattened to numbers, `dims` components each; a component is divided by
/// `norm` (the largest value of its integer type) when given, as the specification decodes
/// normalised integers (signed ones clamped at −1).
fn numbers<T: Item + Copy + Into<f64>>(
    acc: &::gltf::Accessor<'_>,
    dims: Dimensions,
    norm: Option<f64>,
    buffers: &[Vec<u8>],
) -> Msg<Vec<f64>> {
    let r = |c: T| {
        let x: f64 = c.into();
        norm.map_or(x, |m| (x / m).max(-1.0))
    };
    Ok(match dims {
        Dimensions::Scalar => elements::<T>(acc, buffers)?.into_iter().map(r).collect(),
        Dimensions::Vec3 => elements::<[T; 3]>(acc, buffers)?
            .into_iter()
            .flatten()
            .map(r)
            .collect(),
        Dimensions::Vec4 => elements::<[T; 4]>(acc, buffers)?
            .into_iter()
            .flatten()
            .map(r)
            .collect(),
        Dimensions::Mat4 => elements::<[[T; 4]; 4]>(acc, buffers)?
            .into_iter()
            .flatten()
            .flatten()
            .map(r)
            .collect(),
        other => return Err(format!("accessor {}: {other:?} is not read", acc.index())),
    })
}

/// The numbers of accessor `acc` after checking that it holds `layout` and that every one is
/// finite.
pub(super) fn read_numbers(
    acc: &::gltf::Accessor<'_>,
    layout: &Layout,
    buffers: &[Vec<u8>],
    budget: &Budget,
) -> Msg<Vec<f64>> {
    let Layout {
        dims,
        types,
        expected,
        normalized,
    } = *layout;
    check_accessor(
        acc,
        Want::Of {
            dims,
            types,
            expected,
        },
        buffers,
    )?;
    // Before anything is decoded: the elements (zeros where the accessor has no view, bounded
    // by nothing else) and the numbers they become, `f64` each.
    let per = acc.dimensions().multiplicity() as u64;
    let component = acc.data_type().size() as u64;
    budget.charge_msg(
        &format!("accessor {}", acc.index()),
        acc.count() as u64,
        per * (component + 8),
    )?;
    let norm = |max: f64| normalized.then_some(max);
    let v = match acc.data_type() {
        DataType::F32 => numbers::<f32>(acc, dims, None, buffers)?,
        DataType::U8 => numbers::<u8>(acc, dims, norm(255.0), buffers)?,
        DataType::U16 => numbers::<u16>(acc, dims, norm(65535.0), buffers)?,
        DataType::I8 => numbers::<i8>(acc, dims, norm(127.0), buffers)?,
        DataType::I16 => numbers::<i16>(acc, dims, norm(32767.0), buffers)?,
        other => return Err(format!("accessor {}: {other:?} is not read", acc.index())),
    };
    let per = v.len() / acc.count().max(1);
    if let Some(k) = v.iter().position(|x| !x.is_finite()) {
        return Err(format!(
            "accessor {}: element {} is not finite",
            acc.index(),
            k / per.max(1)
        ));
    }
    Ok(v)
}

/// `VEC3` float data ([`VEC3`]) as vectors.
pub(super) fn read_vec3(
    acc: &::gltf::Accessor<'_>,
    buffers: &[Vec<u8>],
    budget: &Budget,
) -> Msg<Vec<DVec3>> {
    let v = read_numbers(acc, &VEC3, buffers, budget)?;
    Ok(v.chunks_exact(3)
        .map(|c| DVec3::new(c[0], c[1], c[2]))
        .collect())
}
