#!/usr/bin/env python3
"""Writes the surface samples of this folder with tools independent of softcut
and of CGAL: numpy builds the triangles, meshio (Debian python3-meshio,
python3-numpy) writes the files. Run from here: /usr/bin/python3 make_surfaces.py

  sphere_mm.stl   binary STL, an icosphere (1280 triangles) of radius 30 mm
  torus_m.ply     binary PLY, a torus of radii 0.04 m and 0.015 m (2304 triangles)
  outer_mm.off    ASCII OFF, an icosphere (1280 triangles) of radius 40 mm
  inner_mm.obj    OBJ, an icosphere (320 triangles) of radius 12 mm at (10, 5, 0) mm,
                  inside outer_mm.off: a lesion
  truth.json      per file: the enclosed volume and area of its triangles (file
                  units^3, ^2, by numpy: the divergence theorem), its bounding box

The tests compare softcut's tet meshes of these files with truth.json."""
import json

import meshio
import numpy as np


def icosphere(subdivisions, radius, center=(0.0, 0.0, 0.0)):
    t = (1 + 5 ** 0.5) / 2
    v = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t),
         (0, -1, -t), (0, 1, -t), (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    f = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4),
         (11, 10, 2), (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8),
         (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    pts = [np.array(p, float) / np.linalg.norm(p) for p in v]
    for _ in range(subdivisions):
        mid = {}

        def middle(a, b):
            key = (min(a, b), max(a, b))
            if key not in mid:
                m = pts[a] + pts[b]
                pts.append(m / np.linalg.norm(m))
                mid[key] = len(pts) - 1
            return mid[key]

        g = []
        for a, b, c in f:
            ab, bc, ca = middle(a, b), middle(b, c), middle(c, a)
            g += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        f = g
    return np.array(pts) * radius + np.array(center), np.array(f)


def torus(big, small, around, section):
    u = np.arange(around) * 2 * np.pi / around
    v = np.arange(section) * 2 * np.pi / section
    pts = np.array([((big + small * np.cos(b)) * np.cos(a), (big + small * np.cos(b)) * np.sin(a), small * np.sin(b))
                    for a in u for b in v])
    idx = lambda i, j: (i % around) * section + (j % section)
    tris = []
    for i in range(around):
        for j in range(section):
            tris += [(idx(i, j), idx(i + 1, j), idx(i + 1, j + 1)), (idx(i, j), idx(i + 1, j + 1), idx(i, j + 1))]
    return pts, np.array(tris)


def truth(pts, tris):
    a, b, c = pts[tris[:, 0]], pts[tris[:, 1]], pts[tris[:, 2]]
    volume = np.einsum("ij,ij->i", a, np.cross(b, c)).sum() / 6
    area = np.linalg.norm(np.cross(b - a, c - a), axis=1).sum() / 2
    return {"volume": abs(float(volume)), "area": float(area), "triangles": int(len(tris)),
            "min": pts.min(axis=0).tolist(), "max": pts.max(axis=0).tolist()}


def main():
    out = {}
    for name, (pts, tris), kw in [
        ("sphere_mm.stl", icosphere(3, 30.0), {"binary": True}),
        ("torus_m.ply", torus(0.04, 0.015, 48, 24), {"binary": True}),
        ("outer_mm.off", icosphere(3, 40.0), {}),
        ("inner_mm.obj", icosphere(2, 12.0, (10.0, 5.0, 0.0)), {}),
    ]:
        meshio.write(name, meshio.Mesh(pts, [("triangle", tris.astype(np.int32))]), **kw)
        out[name] = truth(pts, tris)
    with open("truth.json", "w") as f:
        json.dump(out, f, indent=1)
        f.write("\n")


if __name__ == "__main__":
    main()
