"""Helpers shared by the fgnet interop scripts (run by tests/fgnet_interop.rs).

Field names, order and wire types come from flightgear-python's own
``fdm_v24.fdm_struct`` (walked through construct's subcons), not from the Rust
crate. Values travel as JSON integers so nothing is lost: floats as their IEEE
bit patterns (f64 as 64-bit, f32 as 32-bit), ``u32``/``i32`` as their values,
the 4 padding bytes as a big-endian ``u32``.
"""

import struct

from construct import Array, Bytes, FormatField

from flightgear_python.fdm_v24 import fdm_struct

_FMT_KIND = {'>d': 'f64', '>f': 'f32', '>L': 'u32', '>l': 'i32'}


def _leaf(sc):
    """Returns (kind, count) for one top-level subcon; count is None for scalars."""
    count = None
    while True:
        if isinstance(sc, Array):
            count = sc.count
        if isinstance(sc, FormatField):
            return _FMT_KIND[sc.fmtstr], count
        if isinstance(sc, Bytes):
            if sc.length != 4:
                raise ValueError(f'unexpected Bytes({sc.length})')
            return 'bytes4', count
        sc = sc.subcon


def layout():
    """[(name, kind, count_or_None)] in wire order, from fdm_struct itself."""
    return [(sc.name, *_leaf(sc)) for sc in fdm_struct.subcons]


def to_json_value(kind, value):
    if kind == 'f64':
        return int.from_bytes(struct.pack('>d', value), 'big')
    if kind == 'f32':
        # ``value`` is the Python float construct produced from a binary32; it
        # is exactly representable, so packing it back gives the wire bits
        # (CPython quiets a signalling f32 NaN on unpack; the tests avoid them).
        return int.from_bytes(struct.pack('>f', value), 'big')
    if kind in ('u32', 'i32'):
        return int(value)  # int() also handles construct's EnumIntegerString
    if kind == 'bytes4':
        return int.from_bytes(value, 'big')
    raise ValueError(kind)


def from_json_value(kind, value):
    if kind == 'f64':
        return struct.unpack('>d', value.to_bytes(8, 'big'))[0]
    if kind == 'f32':
        return struct.unpack('>f', value.to_bytes(4, 'big'))[0]
    if kind in ('u32', 'i32'):
        return value
    if kind == 'bytes4':
        return value.to_bytes(4, 'big')
    raise ValueError(kind)


def container_to_json(container):
    """Every field of a parsed fdm_v24 container as {name: {kind, value}}."""
    out = {}
    for name, kind, count in layout():
        v = container[name]
        if count is None:
            out[name] = {'kind': kind, 'value': to_json_value(kind, v)}
        else:
            out[name] = {'kind': kind, 'value': [to_json_value(kind, x) for x in v]}
    return out


def json_to_build_dict(fields):
    """Inverse of container_to_json, for fdm_struct.build()."""
    d = {}
    for name, kind, count in layout():
        v = fields[name]
        if count is None:
            d[name] = from_json_value(kind, v)
        else:
            d[name] = [from_json_value(kind, x) for x in v]
    return d
