"""numpy arrays across the C ABI.

The ABI's arrays are flat caller-owned buffers of double or int32_t with an
element count. Inputs may be anything numpy can turn into such a buffer of
numbers: copied only when the dtype or layout is wrong (float32, integers,
other byte orders, strided views, Fortran order), refused when the
conversion would change values rather than represent them (TypeError for
complex, bool, strings, objects and floats given for integers; ValueError
for integers outside int32). Outputs are written in place, so an `out=`
array must already be exactly right -- converting it would make C write
into a temporary copy and lose the result.

numpy is imported on first use: the package works without it for everything
that passes no arrays.
"""

import ctypes

_DTYPES = {ctypes.c_double: "float64", ctypes.c_int32: "int32", ctypes.c_int64: "int64"}
# numpy dtype kinds each C type takes from an input without changing values:
# floats and integers for double (integers above 2**53 round, as in C);
# integers alone for int32 (range-checked below).
_INPUT_KINDS = {ctypes.c_double: ("fiu", "real numbers"), ctypes.c_int32: ("iu", "integers"),
                ctypes.c_int64: ("iu", "integers")}


def _numpy():
    try:
        import numpy
    except ImportError as error:  # pragma: no cover - depends on the installation
        raise ImportError("unimesh: numpy is needed for array arguments") from error
    return numpy


def _check_shape(array, shape, name):
    """shape: None (any), or a tuple whose -1 entries match any length."""
    if shape is None:
        return
    if array.ndim != len(shape) or any(want not in (-1, got)
                                       for want, got in zip(shape, array.shape)):
        wanted = "(" + ", ".join("n" if s == -1 else str(s) for s in shape) + ")"
        raise ValueError(f"{name} must have shape {wanted}, not {array.shape}")


def input_array(values, ctype, shape=None, name="array"):
    """values as a C-contiguous array of the dtype matching ctype (c_double,
    c_int32 or c_int64), without a copy when it already is one. shape as for
    _check_shape (entries may also be exact lengths). Keep the result alive
    for as long as C may read the pointer taken from it."""
    numpy = _numpy()
    array = numpy.asarray(values)
    kinds, what = _INPUT_KINDS[ctype]
    if array.dtype.kind not in kinds:
        raise TypeError(f"{name} must hold {what}, not {array.dtype}")
    _check_shape(array, shape, name)
    if ctype in (ctypes.c_int32, ctypes.c_int64) and array.size \
            and not numpy.can_cast(array.dtype, _DTYPES[ctype]):
        limits = numpy.iinfo(_DTYPES[ctype])
        if array.min() < limits.min or array.max() > limits.max:
            raise ValueError(f"{name} holds values outside {_DTYPES[ctype]}: "
                             f"{array.min()}..{array.max()}")
    return numpy.ascontiguousarray(array, dtype=_DTYPES[ctype])


def output_array(ctype, shape, out=None, name="out"):
    """A new C-contiguous array for C to fill, or `out` after checking that C
    can fill it in place (exact dtype, C-contiguous, writeable, shape)."""
    numpy = _numpy()
    dtype = numpy.dtype(_DTYPES[ctype])
    if out is None:
        return numpy.empty(shape, dtype=dtype)
    if not isinstance(out, numpy.ndarray):
        raise TypeError(f"{name} must be a numpy array, not {type(out).__name__}")
    if out.dtype != dtype:
        raise TypeError(f"{name} must have dtype {dtype}, not {out.dtype}")
    if not out.flags.c_contiguous or not out.flags.writeable:
        raise ValueError(f"{name} must be C-contiguous and writeable")
    _check_shape(out, tuple(shape), name)
    return out


def pointer(array, ctype):
    """A ctypes pointer to the first element of array (None passes through
    as NULL). The array must outlive every use of the pointer."""
    if array is None:
        return None
    if array.dtype != _numpy().dtype(_DTYPES[ctype]) or not array.flags.c_contiguous:
        raise TypeError(f"pointer: need a C-contiguous {_DTYPES[ctype]} array")
    return array.ctypes.data_as(ctypes.POINTER(ctype))


def capacity(array):
    """The element count C receives as a buffer's capacity (int64 on the ABI)."""
    return 0 if array is None else int(array.size)
