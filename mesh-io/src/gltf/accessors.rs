//! The accessor checks: what the `gltf` crate's reader trusts (type, count, strides, byte
//! ranges, sparse parts), checked before it reads.

use super::*;

/// What the loader reads from an accessor.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Want {
    /// `VEC3` of `FLOAT` (POSITION, NORMAL).
    Vec3F32,
    /// `SCALAR` of an unsigned integer type (indices).
    Index,
    /// Elements of `dims` of one of `types` (the animation's accessors); `expected` names them
    /// in the message.
    Of {
        dims: Dimensions,
        types: &'static [DataType],
        expected: &'static str,
    },
}

/// Checks that the `gltf` crate can read `acc` as `want` without panicking and without
/// falling short: element type, `count ≥ 1`, strides at least the element size, and every
/// byte read (base, sparse indices and sparse values) inside its buffer view and buffer.
pub(crate) fn check_accessor(
    acc: &::gltf::Accessor<'_>,
    want: Want,
    buffers: &[Vec<u8>],
) -> std::result::Result<(), String> {
    let i = acc.index();
    let (dims, ty) = (acc.dimensions(), acc.data_type());
    let (ok, expected) = match want {
        Want::Vec3F32 => (
            dims == Dimensions::Vec3 && ty == DataType::F32,
            "Vec3 of F32",
        ),
        Want::Index => (
            dims == Dimensions::Scalar
                && matches!(ty, DataType::U8 | DataType::U16 | DataType::U32),
            "Scalar of U8, U16 or U32",
        ),
        Want::Of {
            dims: d,
            types,
            expected,
        } => (dims == d && types.contains(&ty), expected),
    };
    if !ok {
        return Err(format!(
            "accessor {i} holds {dims:?} of {ty:?}, expected {expected}"
        ));
    }
    let count = acc.count();
    if count == 0 {
        return Err(format!("accessor {i} has count 0"));
    }
    let elem = acc.size();
    if let Some(view) = acc.view() {
        check_view(&view, acc.offset(), count, elem, buffers)
            .map_err(|m| format!("accessor {i}: {m}"))?;
    }
    if let Some(sparse) = acc.sparse() {
        let n = sparse.count();
        if n == 0 || n > count {
            return Err(format!(
                "accessor {i}: sparse count {n} is outside 1..={count}"
            ));
        }
        let ix = sparse.indices();
        check_view(&ix.view(), ix.offset(), n, ix.index_type().size(), buffers)
            .map_err(|m| format!("accessor {i}, sparse indices: {m}"))?;
        let vals = sparse.values();
        check_view(&vals.view(), vals.offset(), n, elem, buffers)
            .map_err(|m| format!("accessor {i}, sparse values: {m}"))?;
        check_sparse_indices(&ix, n, count, buffers)
            .map_err(|m| format!("accessor {i}, sparse indices: {m}"))?;
    }
    Ok(())
}

/// Checks that the `n` sparse indices are strictly increasing and below `count`, as the
/// specification requires (the `gltf` crate's reader would silently drop the values of
/// indices out of order or out of range). The caller has checked that they lie in their view.
pub(super) fn check_sparse_indices(
    ix: &::gltf::accessor::sparse::Indices<'_>,
    n: usize,
    count: usize,
    buffers: &[Vec<u8>],
) -> std::result::Result<(), String> {
    let view = ix.view();
    let size = ix.index_type().size();
    let stride = view.stride().unwrap_or(size);
    let data = buffers
        .get(view.buffer().index())
        .map_or(&[][..], Vec::as_slice);
    let base = view.offset().saturating_add(ix.offset());
    let mut prev: Option<u64> = None;
    for k in 0..n {
        let at = base.saturating_add(k.saturating_mul(stride));
        let Some(b) = data.get(at..at.saturating_add(size)) else {
            return Err(format!("index {k} lies outside its buffer"));
        };
        let v = b.iter().rev().fold(0u64, |acc, &x| acc << 8 | x as u64);
        if v >= count as u64 {
            return Err(format!(
                "index {k} is {v}, outside the accessor's 0..{count}"
            ));
        }
        if let Some(p) = prev.filter(|&p| p >= v) {
            return Err(format!(
                "index {k} is {v}, not above the previous {p} (they must strictly increase)"
            ));
        }
        prev = Some(v);
    }
    Ok(())
}

/// Checks that `count` elements of `elem` bytes, `offset` bytes into `view` and its stride
/// apart, lie inside the view, and the view inside its buffer's data (overflow-free).
pub(super) fn check_view(
    view: &::gltf::buffer::View<'_>,
    offset: usize,
    count: usize,
    elem: usize,
    buffers: &[Vec<u8>],
) -> std::result::Result<(), String> {
    let v = view.index();
    let stride = view.stride().unwrap_or(elem);
    if stride < elem {
        return Err(format!(
            "buffer view {v} has byteStride {stride}, less than the {elem}-byte elements"
        ));
    }
    let end = count
        .checked_sub(1)
        .and_then(|c| stride.checked_mul(c))
        .and_then(|n| n.checked_add(elem))
        .and_then(|n| n.checked_add(offset));
    if end.is_none_or(|e| e > view.length()) {
        return Err(format!(
            "{count} elements of {elem} bytes (stride {stride}) from byte {offset} do not fit \
             in buffer view {v} ({} bytes)",
            view.length()
        ));
    }
    let b = view.buffer().index();
    let have = buffers.get(b).map_or(0, Vec::len);
    if view
        .offset()
        .checked_add(view.length())
        .is_none_or(|e| e > have)
    {
        return Err(format!(
            "buffer view {v} ({} bytes from byte {}) reaches past the end of buffer {b} \
             ({have} bytes)",
            view.length(),
            view.offset()
        ));
    }
    Ok(())
}
