#!/usr/bin/env python3
"""Writes the binary sample meshes of this folder (run from here; Python 3 only,
no third-party modules). Same mesh as the hand-written samples: 6 points
(point 2 unreferenced), a line, a triangle and two tetrahedra, the second
negatively oriented, labels 7 and 9."""
import base64
import struct
import zlib

POINTS = [(0, 0, 0), (1, 0, 0), (5, 5, 5), (0, 1, 0), (0, 0, 1), (1, 1, 1)]
CELLS = [(0, 1), (0, 1, 3), (0, 1, 3, 4), (1, 4, 3, 5)]
TYPES = [3, 5, 10, 10]
LABELS = [1, 2, 7, 9]


def legacy_binary():
    out = b"# vtk DataFile Version 3.0\n\nBINARY\nDATASET UNSTRUCTURED_GRID\n"
    out += b"POINTS 6 double\n" + b"".join(struct.pack(">3d", *p) for p in POINTS) + b"\n"
    size = sum(len(c) + 1 for c in CELLS)
    out += b"CELLS 4 %d\n" % size
    out += b"".join(struct.pack(">%di" % (len(c) + 1), len(c), *c) for c in CELLS) + b"\n"
    out += b"CELL_TYPES 4\n" + struct.pack(">4i", *TYPES) + b"\n"
    out += b"CELL_DATA 4\nSCALARS quality float\nLOOKUP_TABLE default\n" + struct.pack(">4f", 1, 1, 0.5, 0.25) + b"\n"
    out += b"SCALARS region int 1\nLOOKUP_TABLE default\n" + struct.pack(">4i", *LABELS) + b"\n"
    return out


def arrays(int_type="Int64"):
    conn = [i for c in CELLS for i in c]
    offsets, o = [], 0
    for c in CELLS:
        o += len(c)
        offsets.append(o)
    code = {"Int64": "q", "Int32": "i"}[int_type]
    return [
        ("Points", "Float64", 3, "d", [x for p in POINTS for x in p], "Points"),
        ("connectivity", int_type, 1, code, conn, "Cells"),
        ("offsets", int_type, 1, code, offsets, "Cells"),
        ("types", "UInt8", 1, "B", TYPES, "Cells"),
        ("temperature", "Float32", 1, "f", [0.5, 1, 2, 3], "CellData"),
        ("CellEntityIds", "Int32", 1, "i", LABELS, "CellData"),
    ]


def block(values, code, header, endian, compress, block_size=16):
    """Header and data bytes of one DataArray; returns (header, data)."""
    data = struct.pack(endian + "%d%s" % (len(values), code), *values)
    h = endian + header
    if not compress:
        return struct.pack(h, len(data)), data
    chunks = [data[i:i + block_size] for i in range(0, len(data), block_size)] or [b""]
    comp = [zlib.compress(c) for c in chunks]
    last = len(chunks[-1]) if len(chunks[-1]) < block_size else 0
    head = struct.pack(endian + header * (3 + len(comp)), len(comp), block_size, last, *[len(c) for c in comp])
    return head, b"".join(comp)


def vtu(fmt, header="I", endian="<", compress=False, split=True, int_type="Int64"):
    """fmt: ascii, binary (inline base64), raw or base64 (appended)."""
    attrs = 'type="UnstructuredGrid" version="1.0" byte_order="%s" header_type="%s"' % (
        "LittleEndian" if endian == "<" else "BigEndian", "UInt32" if header == "I" else "UInt64")
    if compress:
        attrs += ' compressor="vtkZLibDataCompressor"'
    sections = {"Points": [], "Cells": [], "CellData": []}
    appended = b""
    for name, typ, ncomp, code, values, section in arrays(int_type):
        comp = ' NumberOfComponents="3"' if ncomp == 3 else ""
        head = '<DataArray type="%s" Name="%s"%s' % (typ, name, comp)
        if fmt == "ascii":
            body = " ".join(repr(v) for v in values)
            sections[section].append('%s format="ascii">\n  %s\n</DataArray>' % (head, body))
            continue
        h, d = block(values, code, header, endian, compress)
        if fmt == "binary":
            text = (base64.b64encode(h) + base64.b64encode(d)) if split else base64.b64encode(h + d)
            sections[section].append('%s format="binary">\n  %s\n</DataArray>' % (head, text.decode()))
        else:
            sections[section].append('%s format="appended" offset="%d"/>' % (head, len(appended)))
            appended += (h + d) if fmt == "raw" else (base64.b64encode(h) + base64.b64encode(d))
    out = '<?xml version="1.0"?>\n<!-- sample mesh -->\n<VTKFile %s>\n<UnstructuredGrid>\n' % attrs
    out += '<Piece NumberOfPoints="6" NumberOfCells="4">\n<PointData>\n</PointData>\n'
    for s in ("Points", "Cells", "CellData"):
        out += "<%s>\n%s\n</%s>\n" % (s, "\n".join(sections[s]), s)
    out += "</Piece>\n</UnstructuredGrid>\n"
    raw = out.encode()
    if fmt in ("raw", "base64"):
        raw += b'<AppendedData encoding="%s">\n_' % fmt.encode() + appended + b"\n</AppendedData>\n"
    return raw + b"</VTKFile>\n"


FILES = {
    "sample_binary.vtk": legacy_binary(),
    "sample_ascii.vtu": vtu("ascii"),
    "sample_base64_uint32.vtu": vtu("binary", header="I", split=False, int_type="Int32"),
    "sample_base64_uint64.vtu": vtu("binary", header="Q", split=True),
    "sample_base64_bigendian.vtu": vtu("binary", header="Q", endian=">", split=False),
    "sample_zlib_uint32.vtu": vtu("binary", header="I", compress=True),
    "sample_zlib_uint64.vtu": vtu("binary", header="Q", compress=True),
    "sample_appended_raw.vtu": vtu("raw", header="Q"),
    "sample_appended_base64_zlib.vtu": vtu("base64", header="I", compress=True),
}

if __name__ == "__main__":
    for name, data in FILES.items():
        with open(name, "wb") as f:
            f.write(data)
