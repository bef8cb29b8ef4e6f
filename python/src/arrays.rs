//! numpy arrays in and out: shapes, dtypes and flags checked with messages that name the
//! argument, input read where it lies (any strides, `float32` and `float64` without a copy),
//! outputs allocated or checked (`out=`).

use numpy::ndarray::{ArrayView1, ArrayView2};
use numpy::{
    Element, PyArray, PyArrayDescrMethods, PyArrayMethods, PyReadonlyArray, PyReadonlyArray1,
    PyReadonlyArray2, PyReadwriteArray, PyUntypedArray, PyUntypedArrayMethods,
};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;

/// Whether `a` can be read in place: aligned, every stride a whole number of elements (a
/// field of a structured array may be neither).
fn readable_in_place(a: &Bound<'_, PyUntypedArray>) -> bool {
    let size = a.dtype().itemsize() as isize;
    a.is_aligned() && size > 0 && a.strides().iter().all(|s| s % size == 0)
}

/// `obj` as a numpy array that can be read in place: itself when it is one (subclasses
/// included) with aligned whole-element strides, else `numpy.asarray` (a copy where the
/// layout asks for one).
fn ndarray<'py>(obj: &Bound<'py, PyAny>, name: &str) -> PyResult<Bound<'py, PyUntypedArray>> {
    if let Ok(a) = obj.cast::<PyUntypedArray>()
        && readable_in_place(a)
    {
        return Ok(a.clone());
    }
    let np = numpy::get_array_module(obj.py())?;
    let a = np
        .call_method1("asarray", (obj,))
        .map_err(|e| PyTypeError::new_err(format!("{name} must be an array of numbers ({e})")))?;
    let a = a
        .cast_into::<PyUntypedArray>()
        .map_err(|_| PyTypeError::new_err(format!("{name} must be an array of numbers")))?;
    if readable_in_place(&a) {
        return Ok(a);
    }
    let copy = np.call_method1("ascontiguousarray", (a,))?;
    Ok(copy.cast_into::<PyUntypedArray>()?)
}

/// The dtype of `a` as numpy prints it (`float32`, `complex128`, `<U3`).
fn dtype_name(a: &Bound<'_, PyUntypedArray>) -> String {
    a.dtype()
        .str()
        .map(|s| s.to_string())
        .unwrap_or_else(|_| "?".into())
}

/// A number as Python's `repr` writes it, near enough for messages: `nan`, `inf`, `0.5`,
/// `1e39`.
pub fn num(x: f64) -> String {
    if x.is_nan() {
        "nan".into()
    } else if x.is_infinite() {
        if x > 0.0 { "inf" } else { "-inf" }.into()
    } else {
        format!("{x:?}")
    }
}

/// `(2, 3)`, as numpy prints shapes.
pub fn shape_text(shape: &[usize]) -> String {
    match shape {
        [n] => format!("({n},)"),
        _ => format!(
            "({})",
            shape
                .iter()
                .map(|n| n.to_string())
                .collect::<Vec<_>>()
                .join(", ")
        ),
    }
}

/// Checks that `a` has `ndim` dimensions, the last of length `cols` when given.
fn check_shape(
    a: &Bound<'_, PyUntypedArray>,
    name: &str,
    ndim: usize,
    cols: Option<usize>,
    want: &str,
) -> PyResult<()> {
    let shape = a.shape();
    let ok = shape.len() == ndim && cols.is_none_or(|c| shape.get(1) == Some(&c));
    if ok {
        Ok(())
    } else {
        Err(PyValueError::new_err(format!(
            "{name} must have shape {want}, got {}",
            shape_text(shape)
        )))
    }
}

/// Checks that `a` holds real numbers: floats of any width, or integers (converted exactly
/// where they fit).
fn check_real(a: &Bound<'_, PyUntypedArray>, name: &str) -> PyResult<()> {
    match a.dtype().kind() {
        b'f' | b'i' | b'u' => Ok(()),
        _ => Err(PyTypeError::new_err(format!(
            "{name} must hold real numbers, got dtype {}",
            dtype_name(a)
        ))),
    }
}

/// `a` cast by numpy to `T` (`astype`, a copy) unless it already holds `T` in native byte
/// order.
fn as_type<'py, T: Element, D: numpy::ndarray::Dimension>(
    a: &Bound<'py, PyUntypedArray>,
    numpy_name: &str,
) -> PyResult<Bound<'py, PyArray<T, D>>> {
    if let Ok(x) = a.cast::<PyArray<T, D>>() {
        return Ok(x.clone());
    }
    let x = a.call_method1("astype", (numpy_name,))?;
    Ok(x.cast_into::<PyArray<T, D>>()?)
}

fn borrow_error(name: &str, e: numpy::BorrowError) -> PyErr {
    PyValueError::new_err(format!("{name}: {e}"))
}

/// `a` (of the shape wanted) checked to hold real numbers and borrowed for reading where it
/// lies: `float32` as given (`f32`), any other real dtype as `float64` (`f64`, converted by
/// numpy unless it is `float64` already).
fn read_reals<'py, D: numpy::ndarray::Dimension, R>(
    a: &Bound<'py, PyUntypedArray>,
    name: &str,
    f32: impl FnOnce(PyReadonlyArray<'py, f32, D>) -> R,
    f64: impl FnOnce(PyReadonlyArray<'py, f64, D>) -> R,
) -> PyResult<R> {
    check_real(a, name)?;
    if let Ok(x) = a.cast::<PyArray<f32, D>>() {
        return x.try_readonly().map(f32).map_err(|e| borrow_error(name, e));
    }
    let x = as_type::<f64, D>(a, "float64")?;
    x.try_readonly().map(f64).map_err(|e| borrow_error(name, e))
}

/// A 2-D array of real numbers read where it lies: `float32` or `float64` as given, any other
/// real dtype converted to `float64`.
pub enum Reals2<'py> {
    /// `float32` input.
    F32(PyReadonlyArray2<'py, f32>),
    /// `float64` input, or another real dtype converted.
    F64(PyReadonlyArray2<'py, f64>),
}

impl<'py> Reals2<'py> {
    /// `obj` as an array of shape `(N, cols)`; `want` names that shape in messages.
    pub fn new(obj: &Bound<'py, PyAny>, name: &str, cols: usize, want: &str) -> PyResult<Self> {
        let mut a = ndarray(obj, name)?;
        if a.ndim() == 1 && a.len() == 0 {
            // `[]` and `np.array([])`: no rows.
            let empty = a.call_method1("reshape", (0, cols))?;
            a = empty.cast_into::<PyUntypedArray>()?;
        }
        check_shape(&a, name, 2, Some(cols), want)?;
        read_reals(&a, name, Reals2::F32, Reals2::F64)
    }

    /// The rows.
    pub fn len(&self) -> usize {
        self.view().len()
    }

    /// A view for reading without the GIL: the elements as one slice when the array is
    /// C-contiguous (the common case, read fastest), else a strided view.
    pub fn view(&self) -> Rows<'_> {
        let cols = match self {
            Reals2::F32(a) => a.as_array().ncols(),
            Reals2::F64(a) => a.as_array().ncols(),
        };
        match self {
            // `to_slice` is `Some` for C order only (numpy's `as_slice` would also take
            // Fortran order, whose elements are not row after row).
            Reals2::F32(a) => match a.as_array().to_slice() {
                Some(s) => Rows::F32Packed(s, cols),
                None => Rows::F32(a.as_array()),
            },
            Reals2::F64(a) => match a.as_array().to_slice() {
                Some(s) => Rows::F64Packed(s, cols),
                None => Rows::F64(a.as_array()),
            },
        }
    }
}

/// The rows of a [`Reals2`], readable from any thread (the caller keeps the arrays unchanged
/// while a query runs).
#[derive(Clone, Copy)]
pub enum Rows<'a> {
    /// `float32` rows, any strides.
    F32(ArrayView2<'a, f32>),
    /// `float64` rows, any strides.
    F64(ArrayView2<'a, f64>),
    /// `float32` rows of this many columns, packed row after row.
    F32Packed(&'a [f32], usize),
    /// `float64` rows of this many columns, packed row after row.
    F64Packed(&'a [f64], usize),
}

impl Rows<'_> {
    /// The number of rows.
    pub fn len(&self) -> usize {
        match self {
            Rows::F32(a) => a.nrows(),
            Rows::F64(a) => a.nrows(),
            Rows::F32Packed(s, c) => s.len() / (*c).max(1),
            Rows::F64Packed(s, c) => s.len() / (*c).max(1),
        }
    }

    /// Element `(i, j)` widened to `f64` (exact); NaN out of range (never asked).
    #[inline(always)]
    pub fn at(&self, i: usize, j: usize) -> f64 {
        let packed = |c: usize| i * c + j;
        match self {
            Rows::F32(a) => a.get((i, j)).map_or(f64::NAN, |&x| f64::from(x)),
            Rows::F64(a) => a.get((i, j)).copied().unwrap_or(f64::NAN),
            Rows::F32Packed(s, c) => s.get(packed(*c)).map_or(f64::NAN, |&x| f64::from(x)),
            Rows::F64Packed(s, c) => s.get(packed(*c)).copied().unwrap_or(f64::NAN),
        }
    }

    /// Row `i`'s first three elements widened to `f64`; NaN out of range (never asked).
    #[inline(always)]
    pub fn row3(&self, i: usize) -> [f64; 3] {
        match self {
            Rows::F32Packed(s, 3) => match s.get(3 * i..3 * i + 3) {
                Some(&[x, y, z]) => [f64::from(x), f64::from(y), f64::from(z)],
                _ => [f64::NAN; 3],
            },
            Rows::F64Packed(s, 3) => match s.get(3 * i..3 * i + 3) {
                Some(&[x, y, z]) => [x, y, z],
                _ => [f64::NAN; 3],
            },
            _ => [self.at(i, 0), self.at(i, 1), self.at(i, 2)],
        }
    }
}

/// Two arrays of shape `(N, 3)` (`want` names it in messages) with as many rows each, `a` and
/// `b` checked in that order; `mismatch(a rows, b rows)` words the error when the counts
/// differ.
pub fn paired_rows<'py>(
    (a, a_name): (&Bound<'py, PyAny>, &str),
    (b, b_name): (&Bound<'py, PyAny>, &str),
    want: &str,
    mismatch: impl FnOnce(usize, usize) -> String,
) -> PyResult<(Reals2<'py>, Reals2<'py>)> {
    let a = Reals2::new(a, a_name, 3, want)?;
    let b = Reals2::new(b, b_name, 3, want)?;
    if a.len() != b.len() {
        return Err(PyValueError::new_err(mismatch(a.len(), b.len())));
    }
    Ok((a, b))
}

/// A 1-D array of real numbers, read as [`Reals2`] reads.
pub enum Reals1<'py> {
    /// `float32` input.
    F32(PyReadonlyArray1<'py, f32>),
    /// `float64` input, or another real dtype converted.
    F64(PyReadonlyArray1<'py, f64>),
}

impl<'py> Reals1<'py> {
    /// `obj` as an array of shape `(len,)`.
    pub fn new(obj: &Bound<'py, PyAny>, name: &str, len: usize) -> PyResult<Self> {
        let a = ndarray(obj, name)?;
        check_shape(&a, name, 1, None, &format!("({len},)"))?;
        if a.shape().first() != Some(&len) {
            return Err(PyValueError::new_err(format!(
                "{name} must have shape ({len},) (one per ray), got {}",
                shape_text(a.shape())
            )));
        }
        read_reals(&a, name, Reals1::F32, Reals1::F64)
    }

    /// A view for reading without the GIL.
    pub fn view(&self) -> Column<'_> {
        match self {
            Reals1::F32(a) => Column::F32(a.as_array()),
            Reals1::F64(a) => Column::F64(a.as_array()),
        }
    }
}

/// The elements of a [`Reals1`], readable from any thread.
#[derive(Clone, Copy)]
pub enum Column<'a> {
    /// `float32` elements.
    F32(ArrayView1<'a, f32>),
    /// `float64` elements.
    F64(ArrayView1<'a, f64>),
}

impl Column<'_> {
    /// Element `i` widened to `f64`; NaN out of range (never asked).
    #[inline]
    pub fn at(&self, i: usize) -> f64 {
        match self {
            Column::F32(a) => a.get(i).map_or(f64::NAN, |&x| f64::from(x)),
            Column::F64(a) => a.get(i).copied().unwrap_or(f64::NAN),
        }
    }
}

/// A scalar or one value per ray (`t_min`, `t_max`).
#[derive(Clone, Copy)]
pub enum PerRay<'a> {
    /// The same value for every ray.
    All(f64),
    /// One value per ray.
    Each(Column<'a>),
}

impl PerRay<'_> {
    /// The value of ray `i`.
    #[inline]
    pub fn at(&self, i: usize) -> f64 {
        match self {
            PerRay::All(x) => *x,
            PerRay::Each(c) => c.at(i),
        }
    }
}

/// A Python float, or an array of one value per ray.
pub enum Bound1<'py> {
    /// A float.
    All(f64),
    /// An array.
    Each(Reals1<'py>),
}

impl<'py> Bound1<'py> {
    /// `obj` as a float (anything `float()` takes, 0-d arrays included) or an array of `rays`
    /// values.
    pub fn new(obj: &Bound<'py, PyAny>, name: &str, rays: usize) -> PyResult<Self> {
        if let Ok(a) = obj.cast::<PyUntypedArray>() {
            if a.ndim() > 0 {
                return Reals1::new(obj, name, rays).map(Bound1::Each);
            }
        } else if let Ok(x) = obj.extract::<f64>() {
            return Ok(Bound1::All(x));
        } else if obj.hasattr("__len__")? {
            return Reals1::new(obj, name, rays).map(Bound1::Each);
        }
        obj.extract::<f64>()
            .map(Bound1::All)
            .map_err(|_| PyTypeError::new_err(format!("{name} must be a float or an array")))
    }

    /// A view for reading without the GIL.
    pub fn view(&self) -> PerRay<'_> {
        match self {
            Bound1::All(x) => PerRay::All(*x),
            Bound1::Each(a) => PerRay::Each(a.view()),
        }
    }
}

/// An integer array of shape `(N, cols)` (or `(N,)` when `cols` is `None`), every element in
/// `0..limit`, as `u32`. `what` names the elements in the range message ("vertex index",
/// "triangle index"), `of` what they index ("the mesh has 10 vertices").
pub fn indices(
    obj: &Bound<'_, PyAny>,
    name: &str,
    cols: Option<usize>,
    want: &str,
    limit: usize,
    what: &str,
    of: &str,
) -> PyResult<Vec<u32>> {
    let a = ndarray(obj, name)?;
    check_shape(&a, name, if cols.is_some() { 2 } else { 1 }, cols, want)?;
    let width = cols.unwrap_or(1);
    let convert = |values: &mut dyn Iterator<Item = i128>| -> PyResult<Vec<u32>> {
        let mut out = Vec::with_capacity(a.len());
        for (k, v) in values.enumerate() {
            match u32::try_from(v) {
                Ok(i) if (i as usize) < limit => out.push(i),
                _ => {
                    let at = if cols.is_some() {
                        format!("{name}[{}, {}]", k / width, k % width)
                    } else {
                        format!("{name}[{k}]")
                    };
                    return Err(PyValueError::new_err(format!(
                        "{at} = {v} is not a {what} ({of})"
                    )));
                }
            }
        }
        Ok(out)
    };
    match a.dtype().kind() {
        b'i' => {
            let x = as_type::<i64, numpy::IxDyn>(&a, "int64")?;
            let r = x.try_readonly().map_err(|e| borrow_error(name, e))?;
            convert(&mut r.as_array().iter().map(|&v| i128::from(v)))
        }
        b'u' => {
            let x = as_type::<u64, numpy::IxDyn>(&a, "uint64")?;
            let r = x.try_readonly().map_err(|e| borrow_error(name, e))?;
            convert(&mut r.as_array().iter().map(|&v| i128::from(v)))
        }
        _ => Err(PyTypeError::new_err(format!(
            "{name} must hold integers, got dtype {}",
            dtype_name(&a)
        ))),
    }
}

/// An output array: a new zeroed array of `shape`, or the caller's `out` checked to be a
/// writeable C-contiguous array of that shape and dtype.
pub fn output<'py, T: Element, D: numpy::ndarray::Dimension>(
    py: Python<'py>,
    out: Option<&Bound<'py, PyAny>>,
    name: &str,
    shape: &[usize],
    dtype: &str,
) -> PyResult<Bound<'py, PyArray<T, D>>> {
    let Some(obj) = out else {
        let dims = D::from_dimension(&numpy::IxDyn(shape)).ok_or_else(|| {
            PyValueError::new_err(format!("{name}: internal shape error {shape:?}"))
        })?;
        return Ok(PyArray::<T, D>::zeros(py, dims, false));
    };
    let want = format!(
        "a writeable C-contiguous numpy array of dtype {dtype} and shape {}",
        shape_text(shape)
    );
    let a = obj
        .cast::<PyUntypedArray>()
        .map_err(|_| PyTypeError::new_err(format!("{name} must be {want}")))?;
    if a.shape() != shape {
        return Err(PyValueError::new_err(format!(
            "{name} has shape {}: it must be {want}",
            shape_text(a.shape())
        )));
    }
    let typed = a.cast::<PyArray<T, D>>().map_err(|_| {
        PyTypeError::new_err(format!(
            "{name} has dtype {}: it must be {want}",
            dtype_name(a)
        ))
    })?;
    if !a.is_c_contiguous() {
        return Err(PyValueError::new_err(format!(
            "{name} is not C-contiguous: it must be {want}"
        )));
    }
    if !a.is_aligned() {
        return Err(PyValueError::new_err(format!(
            "{name} is not aligned: it must be {want}"
        )));
    }
    let writeable: bool = a.getattr("flags")?.getattr("writeable")?.extract()?;
    if !writeable {
        return Err(PyValueError::new_err(format!(
            "{name} is read-only: it must be {want}"
        )));
    }
    Ok(typed.clone())
}

/// A mutable borrow of an output array from [`output`].
pub fn write<'py, T: Element, D: numpy::ndarray::Dimension>(
    a: &Bound<'py, PyArray<T, D>>,
    name: &str,
) -> PyResult<PyReadwriteArray<'py, T, D>> {
    a.try_readwrite().map_err(|e| borrow_error(name, e))
}

/// The contiguous elements of a borrowed output array.
pub fn slice<'a, T: Element, D: numpy::ndarray::Dimension>(
    a: &'a mut PyReadwriteArray<'_, T, D>,
    name: &str,
) -> PyResult<&'a mut [T]> {
    a.as_slice_mut()
        .map_err(|_| PyValueError::new_err(format!("{name} is not contiguous")))
}
