"""Reads NumPy .npy files (format 1.0 to 3.0) from bytes: as a numpy array, or as nested lists
of Python numbers built with the standard library."""
import ast
import struct
import sys
from array import array as _array

from .optional import require

MAGIC = b"\x93NUMPY"

# dtype descr (without its byte-order mark) -> array module typecode of the same size.
_TYPECODES = {"f4": "f", "f8": "d", "i1": "b", "u1": "B", "i2": "h", "u2": "H",
              "i4": "i", "u4": "I", "i8": "q", "u8": "Q"}


class NpyError(ValueError):
    """The bytes are not a .npy file this reader understands."""


class NpyHeader:
    """What the header says: the dtype (numpy's descr, e.g. '<f4'), the shape and where the
    data start."""

    def __init__(self, descr, shape, data_offset):
        self.descr = descr
        self.shape = shape
        self.data_offset = data_offset

    @property
    def count(self):
        n = 1
        for d in self.shape:
            n *= d
        return n


def parse_header(data):
    if not data.startswith(MAGIC) or len(data) < 10:
        raise NpyError("not a .npy file (no \\x93NUMPY magic)")
    major = data[6]
    if major == 1:
        (length,), start = struct.unpack_from("<H", data, 8), 10
    elif major in (2, 3):
        (length,), start = struct.unpack_from("<I", data, 8), 12
    else:
        raise NpyError("unknown .npy format version %d.%d" % (major, data[7]))
    if len(data) < start + length:
        raise NpyError("the header is cut short")
    text = data[start:start + length].decode("utf-8" if major == 3 else "latin1")
    try:
        header = ast.literal_eval(text)
    except (ValueError, SyntaxError) as e:
        raise NpyError("unreadable header: %s" % e) from None
    if not isinstance(header, dict) or not {"descr", "fortran_order", "shape"} <= header.keys():
        raise NpyError("the header lacks descr, fortran_order or shape")
    shape = header["shape"]
    if not isinstance(shape, tuple) or not all(isinstance(d, int) and d >= 0 for d in shape):
        raise NpyError("bad shape %r" % (shape,))
    result = NpyHeader(header["descr"], shape, start + length)
    if header["fortran_order"]:
        raise NpyError("Fortran-ordered arrays are not supported")
    return result


def _to_lists(flat, shape):
    if not shape:
        return flat[0]
    if len(shape) == 1:
        return list(flat)
    step = len(flat) // shape[0] if shape[0] else 0
    return [_to_lists(flat[i * step:(i + 1) * step], shape[1:]) for i in range(shape[0])]


def _lists(data, h):
    descr = h.descr
    if not isinstance(descr, str) or len(descr) < 3 or descr[0] not in "<>|=":
        raise NpyError("unsupported dtype %r" % (descr,))
    typecode = _TYPECODES.get(descr[1:])
    if typecode is None:
        raise NpyError("unsupported dtype %r (numbers only: %s)" % (descr, ", ".join(_TYPECODES)))
    values = _array(typecode)
    if values.itemsize != int(descr[2:]):
        raise NpyError("dtype %r has no same-sized type on this platform" % descr)
    end = h.data_offset + h.count * values.itemsize
    if len(data) < end:
        raise NpyError("the data are cut short: %d bytes for %d values of %s"
                       % (len(data) - h.data_offset, h.count, descr))
    values.frombytes(data[h.data_offset:end])
    big = descr[0] == ">" or (descr[0] == "=" and sys.byteorder == "big")
    if values.itemsize > 1 and big != (sys.byteorder == "big"):
        values.byteswap()
    return _to_lists(values.tolist(), h.shape)


def load(data, array=True, what="load()"):
    """The array in `data` (the bytes of a .npy file): a numpy array (ImportError naming `what`
    without numpy), or with array=False nested lists."""
    h = parse_header(data)
    if array is False:
        return _lists(data, h)
    numpy = require("numpy", "%s with array=True (the default)" % what,
                    "array=False gives nested lists instead")
    dtype = numpy.dtype(h.descr)
    if len(data) < h.data_offset + h.count * dtype.itemsize:
        raise NpyError("the data are cut short")
    return numpy.frombuffer(data, dtype=dtype, count=h.count,
                            offset=h.data_offset).reshape(h.shape)
