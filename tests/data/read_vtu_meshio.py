# Reads a .vtu with meshio (an independent VTK XML reader, Debian's
# python3-meshio) and prints what it found, every number as its exact
# binary64 in hex, for tests/mesh/io_vtu_writer.cpp to compare bit for bit.
#   python3 read_vtu.py FILE.vtu > dump.txt
import sys

import meshio

m = meshio.read(sys.argv[1])


def dump(name, values):
    flat = values.reshape(-1)
    kind = "f" if flat.dtype.kind == "f" else "i"
    print(name, kind, len(flat), " ".join(float(v).hex() if kind == "f" else str(int(v)) for v in flat))


dump("points", m.points)
tets = [c for c in m.cells if c.type == "tetra"]
print("cell_blocks", len(m.cells), "tetra_blocks", len(tets))
dump("tetra", tets[0].data)
for name, values in sorted(m.point_data.items()):
    dump("point." + name, values)
for name, blocks in sorted(m.cell_data.items()):
    dump("cell." + name, blocks[0])
